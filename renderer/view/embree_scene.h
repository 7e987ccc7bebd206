#pragma once
/// \file embree_scene.h
/// Ray queries against a field::Mesh through Embree. Embree's types stay in the
/// .cpp file; callers see only our Ray and Hit.

#include "field/mesh.h"
#include "renderer/view/camera.h"

#include <memory>

namespace rosy::renderer {

/// The closest intersection along a ray.
struct Hit {
    /// Face index into the mesh, -1 when the ray hit nothing.
    int faceId = -1;
    /// Ray parameter of the hit (world units for unit-length directions).
    double t = 0.0;
    /// Barycentrics: p = (1 - u - v) p0 + u p1 + v p2 with p0..p2 the face's corners.
    double u = 0.0, v = 0.0;
    bool valid() const { return faceId >= 0; }
};

/// An acceleration structure over one mesh. Immutable after construction, so
/// intersect() and occluded() may be called from many threads at once.
/// Embree works in single precision: positions are converted to float.
class RayScene {
public:
    /// Builds the BVH (robust mode: watertight-leaning traversal over speed).
    /// An empty mesh gives a scene every ray misses.
    /// \throws std::runtime_error with Embree's message if Embree fails.
    explicit RayScene(const field::Mesh &mesh);
    ~RayScene();
    RayScene(const RayScene &) = delete;
    RayScene &operator=(const RayScene &) = delete;

    /// Closest hit with t in [ray.tMin, ray.tMax], or an invalid Hit.
    Hit intersect(const Ray &ray) const;
    /// Closest hits of up to 8 rays at once (Embree's packet traversal, faster for
    /// coherent rays such as neighbouring primary rays); hits[k] is exactly what
    /// intersect(rays[k]) would return. count in [0, 8].
    void intersect8(const Ray *rays, int count, Hit *hits) const;
    /// True if anything lies on the ray with t in [ray.tMin, ray.tMax].
    bool occluded(const Ray &ray) const;
    /// occluded() of up to 8 rays at once (Embree's packet traversal, for coherent
    /// rays such as the shadow rays of neighbouring pixels toward one light);
    /// out[k] == occluded(rays[k]). count in [0, 8].
    void occluded8(const Ray *rays, int count, bool *out) const;
    /// occluded() of `count` rays at once through Embree's stream call
    /// (rtcOccluded1M, incoherent rays such as ambient-occlusion samples):
    /// out[k] == occluded(rays[k]).
    void occludedMany(const Ray *rays, int count, bool *out) const;
    /// Radius of the mesh's bounding sphere: the scale for ray offsets (world units).
    double sceneRadius() const { return m_sceneRadius; }

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    double m_sceneRadius = 1.0;
};

} // namespace rosy::renderer
