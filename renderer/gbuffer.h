#pragma once
/// \file gbuffer.h
/// What the camera sees at each pixel centre: the first surface hit and its
/// geometry. Every later stage (tone, screen-space field, strokes) reads this.

#include "field/mesh.h"
#include "renderer/camera.h"
#include "renderer/embree_scene.h"

#include <vector>

namespace rosy::renderer {

/// Per-pixel arrays in row-major order, index = y * width + x, y down (raster space).
/// Background pixels have faceId -1 and zero in every other array.
struct GBuffer {
    int width = 0;
    int height = 0;
    std::vector<int> faceId;          ///< #pixels; mesh face index or -1
    std::vector<Vec2> barycentric;    ///< #pixels; (u, v) as in Hit
    std::vector<Vec3> position;       ///< #pixels; world-space hit point, from the mesh's
                                      ///< double-precision corners and (u, v)
    std::vector<Vec3> normal;         ///< #pixels; unit shading normal interpolated from
                                      ///< Mesh::vertexNormal (outward, not flipped toward
                                      ///< the viewer); the face normal where that vanishes
    std::vector<double> depth;        ///< #pixels; Camera::depth of the hit (world units)

    int index(int x, int y) const { return y * width + x; }
    bool covered(int x, int y) const { return faceId[size_t(index(x, y))] >= 0; }
    size_t nPixels() const { return size_t(width) * size_t(height); }
};

/// Traces one primary ray per pixel centre. Rows run in parallel through
/// rosy::parallelFor; each pixel is written only by its own work item, so the
/// result is identical for any thread count.
/// \param scene built from `mesh` (face ids must match).
GBuffer renderGBuffer(const RayScene &scene, const field::Mesh &mesh, const Camera &camera);

} // namespace rosy::renderer
