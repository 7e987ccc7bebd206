#include "renderer/view/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace rosy::renderer {

struct RayScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    // Embree reads vertices with 16-byte loads, so the last vertex needs one float of
    // slack after it; we own the buffers and share them with Embree.
    std::vector<float> vertices;
    std::vector<unsigned> indices;
    std::mutex errorMutex;
    std::string lastError;
    /// Embree sees the scene scaled by this power of two (radius in [1, 2)): its
    /// single-precision tests carry tolerances that are not relative to the scene's
    /// size, so a mesh a billionth of a unit across drew differently from the same
    /// mesh at unit size. A power of two scales every float exactly, so the hits
    /// are those of the scaled scene to the bit, at any size.
    double toEmbree = 1.0;

    void check(const char *what) {
        RTCError code = rtcGetDeviceError(device);
        if (code == RTC_ERROR_NONE) return;
        std::string message;
        {
            std::lock_guard<std::mutex> lock(errorMutex);
            message = lastError;
        }
        if (message.empty()) message = "error code " + std::to_string(int(code));
        throw std::runtime_error(std::string("Embree failed in ") + what + ": " + message);
    }

    static void errorCallback(void *userPtr, RTCError, const char *str) {
        auto *impl = static_cast<Impl *>(userPtr);
        std::lock_guard<std::mutex> lock(impl->errorMutex);
        impl->lastError = str ? str : "";
    }

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

/// `ray` in Embree's scaled space (Impl::toEmbree): origin and parameter range
/// scale, the direction does not (p = o + t d scales with o and t).
void toRtcRay(const Ray &ray, double toEmbree, RTCRay &r) {
    r.org_x = float(ray.origin.x() * toEmbree);
    r.org_y = float(ray.origin.y() * toEmbree);
    r.org_z = float(ray.origin.z() * toEmbree);
    r.dir_x = float(ray.dir.x());
    r.dir_y = float(ray.dir.y());
    r.dir_z = float(ray.dir.z());
    r.tnear = float(ray.tMin * toEmbree);
    r.tfar = std::isinf(ray.tMax) ? std::numeric_limits<float>::infinity() : float(ray.tMax * toEmbree);
    r.time = 0.0f;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
}

/// Up to 8 rays in Embree's packet layout; lanes past `count` repeat ray 0 and are
/// switched off in `valid`.
void toRtcRay8(const Ray *rays, int count, double toEmbree, int *valid, RTCRay8 &r8) {
    for (int k = 0; k < 8; ++k) {
        valid[k] = k < count ? -1 : 0;
        RTCRay r;
        toRtcRay(rays[k < count ? k : 0], toEmbree, r);
        r8.org_x[k] = r.org_x;
        r8.org_y[k] = r.org_y;
        r8.org_z[k] = r.org_z;
        r8.dir_x[k] = r.dir_x;
        r8.dir_y[k] = r.dir_y;
        r8.dir_z[k] = r.dir_z;
        r8.tnear[k] = r.tnear;
        r8.tfar[k] = r.tfar;
        r8.time[k] = 0.0f;
        r8.mask[k] = ~0u;
        r8.id[k] = unsigned(k);
        r8.flags[k] = 0;
    }
}
} // namespace

RayScene::RayScene(const field::Mesh &mesh) : m_impl(std::make_unique<Impl>()) {
    Vec3 centre;
    boundingSphere(mesh, centre, m_sceneRadius);
    Impl &im = *m_impl;
    im.device = rtcNewDevice(nullptr);
    if (!im.device) {
        RTCError code = rtcGetDeviceError(nullptr);
        throw std::runtime_error("Embree could not create a device (error code " +
                                 std::to_string(int(code)) + ")");
    }
    rtcSetDeviceErrorFunction(im.device, Impl::errorCallback, &im);
    im.scene = rtcNewScene(im.device);
    im.check("rtcNewScene");
    rtcSetSceneFlags(im.scene, RTC_SCENE_FLAG_ROBUST);
    im.check("rtcSetSceneFlags");

    if (std::isfinite(m_sceneRadius) && m_sceneRadius > 0.0)
        im.toEmbree = std::ldexp(1.0, -std::ilogb(m_sceneRadius));
    if (mesh.nFaces() > 0) {
        int nV = mesh.nVertices(), nF = mesh.nFaces();
        im.vertices.assign(3 * size_t(nV) + 1, 0.0f);
        for (int v = 0; v < nV; ++v)
            for (int k = 0; k < 3; ++k) im.vertices[3 * size_t(v) + k] = float(mesh.position(v)[k] * im.toEmbree);
        im.indices.resize(3 * size_t(nF));
        for (int f = 0; f < nF; ++f)
            for (int k = 0; k < 3; ++k) im.indices[3 * size_t(f) + k] = unsigned(mesh.face(f)[k]);

        RTCGeometry geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        im.check("rtcNewGeometry");
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                   im.vertices.data(), 0, 3 * sizeof(float), size_t(nV));
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                   im.indices.data(), 0, 3 * sizeof(unsigned), size_t(nF));
        rtcCommitGeometry(geom);
        // geomID 0: the only geometry, so hit.geomID needs no lookup table.
        rtcAttachGeometry(im.scene, geom);
        rtcReleaseGeometry(geom);
        im.check("building the triangle geometry");
    }
    rtcCommitScene(im.scene);
    im.check("rtcCommitScene");
}

RayScene::~RayScene() = default;

Hit RayScene::intersect(const Ray &ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    toRtcRay(ray, m_impl->toEmbree, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->scene, &context, &rh);
    Hit hit;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.faceId = int(rh.hit.primID);
    hit.t = rh.ray.tfar / m_impl->toEmbree;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    return hit;
}

void RayScene::intersect8(const Ray *rays, int count, Hit *hits) const {
    alignas(32) int valid[8];
    alignas(32) RTCRayHit8 rh;
    toRtcRay8(rays, count, m_impl->toEmbree, valid, rh.ray);
    for (int k = 0; k < 8; ++k) {
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect8(valid, m_impl->scene, &context, &rh);
    for (int k = 0; k < count; ++k) {
        Hit &hit = hits[k];
        hit = Hit();
        if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
        hit.faceId = int(rh.hit.primID[k]);
        hit.t = rh.ray.tfar[k] / m_impl->toEmbree;
        hit.u = rh.hit.u[k];
        hit.v = rh.hit.v[k];
    }
}

bool RayScene::occluded(const Ray &ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    toRtcRay(ray, m_impl->toEmbree, r);
    rtcOccluded1(m_impl->scene, &context, &r);
    // Embree marks an occluded ray by setting tfar to -inf.
    return r.tfar < 0.0f;
}

void RayScene::occluded8(const Ray *rays, int count, bool *out) const {
    alignas(32) int valid[8];
    alignas(32) RTCRay8 r8;
    toRtcRay8(rays, count, m_impl->toEmbree, valid, r8);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcOccluded8(valid, m_impl->scene, &context, &r8);
    // Embree marks an occluded ray by setting tfar to -inf.
    for (int k = 0; k < count; ++k) out[k] = r8.tfar[k] < 0.0f;
}

void RayScene::occludedMany(const Ray *rays, int count, bool *out) const {
    constexpr int kChunk = 64;
    RTCRay r[kChunk];
    for (int k0 = 0; k0 < count; k0 += kChunk) {
        const int m = std::min(kChunk, count - k0);
        for (int k = 0; k < m; ++k) toRtcRay(rays[k0 + k], m_impl->toEmbree, r[k]);
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        rtcOccluded1M(m_impl->scene, &context, r, unsigned(m), sizeof(RTCRay));
        for (int k = 0; k < m; ++k) out[k0 + k] = r[k].tfar < 0.0f;
    }
}

} // namespace rosy::renderer
