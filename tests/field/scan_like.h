#pragma once
/// \file scan_like.h
/// Scan-like test meshes (field/scan_noise.h's tests, the pipeline's): needle
/// triangles beside normal ones and noise along the normals, made here from a clean
/// mesh with a hash of the vertex id (no library generator, the same on every machine).

#include "field/mesh.h"

#include <cstdint>
#include <vector>

namespace rosy::test {

/// The scan-like ellipsoid of the noisy-scan tests (field/scan_noise.h's and the
/// pipeline's): makeEllipsoid(kScanEllipsoidLevel, 1.0, 0.7, 0.5) through
/// makeScanLike(…, kScanEllipsoidNoise), 136k faces with noise of half an edge.
/// Under the sanitizers, whose -O1 build leaves the smoothing's and the field's small
/// Eigen expressions uninlined (40-50 s per test at level 6), one level coarser (34k
/// faces) with noise of 0.7 edges, so that its field is still judged noise
/// (singularity density 23.6 against field::kScanNoiseDensity's 20).
#ifdef ROSY_SANITIZED
inline constexpr int kScanEllipsoidLevel = 5;
inline constexpr double kScanEllipsoidNoise = 0.7;
#else
inline constexpr int kScanEllipsoidLevel = 6;
inline constexpr double kScanEllipsoidNoise = 0.5;
#endif

/// A uniform number in [-1, 1) from (v, salt).
inline double hashedUniform(uint64_t v, uint64_t salt) {
    uint64_t x = v * 0x9E3779B97F4A7C15ull + salt;
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBull;
    x ^= x >> 31;
    return double(x >> 11) / double(1ull << 52) - 1.0;
}

/// `mesh` with every `every`-th triangle (from the first) split 1-to-3 at a point
/// `fromEdge` of the way from its first edge's midpoint to the opposite corner: needle
/// triangles beside normal ones, as tools/make_scan_mesh.py's slivers.
inline field::Mesh withNeedles(const field::Mesh &mesh, int every, double fromEdge) {
    using field::Vec3;
    std::vector<Vec3> p = mesh.positions();
    std::vector<field::Face> faces;
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const field::Face &t = mesh.face(f);
        if (f % every != 0) {
            faces.push_back(t);
            continue;
        }
        const Vec3 mid = 0.5 * (p[size_t(t[0])] + p[size_t(t[1])]);
        const int c = int(p.size());
        p.push_back(mid + fromEdge * (p[size_t(t[2])] - mid));
        faces.push_back({t[0], t[1], c});
        faces.push_back({t[1], t[2], c});
        faces.push_back({t[2], t[0], c});
    }
    return field::Mesh::fromTriangles(std::move(p), std::move(faces), mesh.name());
}

/// withNeedles(mesh, 3, 0.02), then every vertex moved along its normal by uniform
/// noise of `noise` times the mean edge length.
inline field::Mesh makeScanLike(const field::Mesh &mesh, double noise) {
    const field::Mesh split = withNeedles(mesh, 3, 0.02);
    std::vector<field::Vec3> p = split.positions();
    const double e = split.meanEdgeLength();
    for (int v = 0; v < split.nVertices(); ++v)
        p[size_t(v)] += noise * e * hashedUniform(uint64_t(v), 17) * split.vertexNormal(v);
    return field::Mesh::fromTriangles(p, split.faces(), mesh.name());
}

} // namespace rosy::test
