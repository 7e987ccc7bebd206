// The floor of `rosyhatch render` (issue 17, docs/benchmarks.md): the least any
// renderer of this scene must do. Reads an OFF mesh with a bare parser (no checks,
// no repair), builds Embree's BVH with its defaults and casts one primary ray per
// pixel through a pinhole camera framing the mesh, over rows in parallel (oneTBB,
// like the renderer); writes nothing. Timed as a whole process against the full
// render, the two alternating, by tools/bench.sh ("render against its floor").
//
//   render_floor [MESH.off] [RESOLUTION]    (defaults: data/meshes/bunny00.off, 1024)

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

struct Off {
    std::vector<float> xyz;       // 3 per vertex
    std::vector<unsigned> tri;    // 3 per triangle (polygons fanned)
};

/// The OFF format in its simplest form: header, counts, vertices, faces. Exits on
/// anything it does not understand (this is a benchmark, not a reader).
Off readOff(const char *path) {
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (text.compare(0, 3, "OFF") != 0) {
        std::fprintf(stderr, "render_floor: %s is not an OFF file\n", path);
        std::exit(2);
    }
    const char *p = text.c_str() + 3;
    char *end = nullptr;
    const long nV = std::strtol(p, &end, 10);
    const long nF = std::strtol(end, &end, 10);
    std::strtol(end, &end, 10); // edges
    Off off;
    off.xyz.resize(size_t(3 * nV));
    for (float &c : off.xyz) c = std::strtof(end, &end);
    off.tri.reserve(size_t(3 * nF));
    for (long f = 0; f < nF; ++f) {
        const long n = std::strtol(end, &end, 10);
        std::vector<unsigned> poly(size_t(std::max(0L, n)));
        for (unsigned &v : poly) v = unsigned(std::strtoul(end, &end, 10));
        for (size_t k = 1; k + 1 < poly.size(); ++k) off.tri.insert(off.tri.end(), {poly[0], poly[k], poly[k + 1]});
    }
    return off;
}

} // namespace

int main(int argc, char **argv) {
    const std::string mesh = argc > 1 ? argv[1] : std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off";
    const int res = argc > 2 ? std::atoi(argv[2]) : 1024;
    const Off off = readOff(mesh.c_str());
    const size_t nV = off.xyz.size() / 3, nT = off.tri.size() / 3;

    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto *v = static_cast<float *>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nV));
    std::copy(off.xyz.begin(), off.xyz.end(), v);
    auto *t = static_cast<unsigned *>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nT));
    std::copy(off.tri.begin(), off.tri.end(), t);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);

    // A pinhole on the +z side of the bounding box, 30° field of view, framing it.
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < nV; ++i)
        for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], off.xyz[3 * i + c]), hi[c] = std::max(hi[c], off.xyz[3 * i + c]);
    const float centre[3] = {0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
    const float radius = 0.5f * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                          (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const float halfFov = 0.5f * 30.0f * float(M_PI) / 180.0f, distance = radius / std::sin(halfFov);
    const float tanHalf = std::tan(halfFov);

    const long hits = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, res), 0L,
        [&](const tbb::blocked_range<int> &rows, long count) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            for (int y = rows.begin(); y < rows.end(); ++y)
                for (int x = 0; x < res; ++x) {
                    RTCRayHit rh{};
                    rh.ray.org_x = centre[0];
                    rh.ray.org_y = centre[1];
                    rh.ray.org_z = centre[2] + distance;
                    rh.ray.dir_x = (2.0f * (float(x) + 0.5f) / float(res) - 1.0f) * tanHalf;
                    rh.ray.dir_y = (1.0f - 2.0f * (float(y) + 0.5f) / float(res)) * tanHalf;
                    rh.ray.dir_z = -1.0f;
                    rh.ray.tnear = 0.0f;
                    rh.ray.tfar = INFINITY;
                    rh.ray.mask = ~0u;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(scene, &context, &rh);
                    count += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                }
            return count;
        },
        [](long a, long b) { return a + b; });

    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    // Nothing is written; the hit count only keeps the rays from being optimised away.
    if (std::getenv("ROSY_FLOOR_VERBOSE")) std::fprintf(stderr, "%zu vertices, %zu triangles, %ld of %d hits\n", nV, nT, hits, res * res);
    return hits > 0 ? 0 : 1;
}
