#pragma once
/// \file gbuffer.h
/// What the camera sees at each pixel centre: the first surface hit and its
/// geometry. Every later stage (tone, screen-space field, strokes) reads this.
///
/// Storage. Only what the ray returns is stored per pixel: face id, Embree's
/// single-precision barycentrics and the depth (16 bytes a pixel). The surface
/// position and the interpolated shading normal are exact functions of those and
/// the mesh, so position() and normal() rebuild them on demand, bit-identical to
/// storing them (the barycentrics are Embree's floats either way); the stages that
/// need them (tone, screen field) compute them once, in parallel, where they are
/// used, instead of the G-buffer writing and later re-reading 48 bytes a pixel.

#include "field/mesh.h"
#include "renderer/view/camera.h"
#include "renderer/view/crease_normals.h"
#include "renderer/view/embree_scene.h"

#include <memory>
#include <vector>

namespace rosy::renderer {

/// Per-pixel arrays in row-major order, index = y * width + x, y down (raster space).
/// Background pixels have faceId -1 and zero in every other array.
struct GBuffer {
    int width = 0;
    int height = 0;
    std::vector<int> faceId;                  ///< #pixels; mesh face index or -1
    std::vector<Eigen::Vector2f> barycentric; ///< #pixels; (u, v) as Embree returned them (see Hit)
    std::vector<float> depth;                 ///< #pixels; Camera::depth of the hit (world units)

    int index(int x, int y) const { return y * width + x; }
    bool covered(int x, int y) const { return faceId[size_t(index(x, y))] >= 0; }
    size_t nPixels() const { return size_t(width) * size_t(height); }

    /// World-space hit point of covered pixel i, from the mesh's double-precision
    /// corners and the barycentrics. \pre faceId[i] >= 0.
    Vec3 position(size_t i) const;
    /// Unit shading normal of covered pixel i, interpolated from Mesh::vertexNormal
    /// (outward, not flipped toward the viewer); the face normal where that
    /// vanishes (opposite vertex normals on a very sharp crease). \pre faceId[i] >= 0.
    Vec3 normal(size_t i) const;
    /// Unit crease-aware shading normal of covered pixel i (outward), interpolated
    /// from creaseAwareCornerNormals() at kCreaseAngleDeg: smooth across edges whose
    /// faces meet at less than the crease angle, each side's own across sharper ones;
    /// the face normal where the interpolation vanishes. \pre faceId[i] >= 0.
    Vec3 creaseNormal(size_t i) const;

    /// The mesh the face ids index, its vertex normals and its crease-aware corner
    /// normals (3 per face, by halfedge; shared, immutable).
    const field::Mesh *mesh = nullptr;
    std::shared_ptr<const std::vector<Vec3>> vertexNormals;
    std::shared_ptr<const std::vector<Vec3>> cornerNormals;
};

/// Traces one primary ray per pixel centre. Rows run in parallel through
/// rosy::parallelFor; each pixel is written only by its own work item, so the
/// result is identical for any thread count.
/// \param scene built from `mesh` (face ids must match). `mesh` must outlive the
///   G-buffer (position() and normal() read it).
GBuffer renderGBuffer(const RayScene &scene, const field::Mesh &mesh, const Camera &camera);

} // namespace rosy::renderer
