/// \file display_mesh.cpp
/// Vertex clustering for the studio's display mesh (display_mesh.h).

#include "studio/display_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace rosy::studio {

using field::Vec3;

namespace {

/// One clustering with cells of side h.
DisplayMesh cluster(const field::Mesh &mesh, const Vec3 &lo, double h) {
    const int nV = mesh.nVertices();
    std::unordered_map<uint64_t, int> cellOf;
    cellOf.reserve(size_t(nV));
    std::vector<int> clusterOf(static_cast<size_t>(nV));
    std::vector<Vec3> sum;
    std::vector<int> count;
    for (int v = 0; v < nV; ++v) {
        const Vec3 q = (mesh.position(v) - lo) / h;
        uint64_t key = 0;
        for (int c = 0; c < 3; ++c) key = (key << 21) | (uint64_t(std::max(0.0, std::floor(q[c]))) & 0x1fffff);
        const auto [it, fresh] = cellOf.try_emplace(key, int(sum.size()));
        if (fresh) sum.push_back(Vec3::Zero()), count.push_back(0);
        clusterOf[v] = it->second;
        sum[it->second] += mesh.position(v);
        ++count[it->second];
    }
    // Faces between three clusters, each once (by their sorted corners), in mesh order.
    std::vector<std::pair<std::array<int, 3>, int>> keyed;
    keyed.reserve(size_t(mesh.nFaces()));
    for (int f = 0; f < mesh.nFaces(); ++f) {
        std::array<int, 3> c;
        for (int k = 0; k < 3; ++k) c[k] = clusterOf[mesh.face(f)[k]];
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        std::array<int, 3> s = c;
        std::sort(s.begin(), s.end());
        keyed.push_back({s, f});
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<int> kept;
    for (size_t i = 0; i < keyed.size(); ++i)
        if (i == 0 || keyed[i].first != keyed[i - 1].first) kept.push_back(keyed[i].second);
    std::sort(kept.begin(), kept.end());
    // Representatives: per used cluster, the vertex nearest to the cluster's mean.
    std::vector<int> rep(sum.size(), -1);
    std::vector<double> repD(sum.size(), std::numeric_limits<double>::infinity());
    for (int v = 0; v < nV; ++v) {
        const int k = clusterOf[v];
        const double d = (mesh.position(v) - sum[k] / count[k]).squaredNorm();
        if (d < repD[k]) repD[k] = d, rep[k] = v;
    }
    DisplayMesh out;
    out.cellSize = h;
    std::vector<int> displayOf(sum.size(), -1);
    out.faces.reserve(kept.size());
    for (int f : kept) {
        field::Face face;
        for (int k = 0; k < 3; ++k) {
            const int c = clusterOf[mesh.face(f)[k]];
            if (displayOf[c] < 0) displayOf[c] = int(out.fullVertex.size()), out.fullVertex.push_back(rep[c]);
            face[k] = displayOf[c];
        }
        out.faces.push_back(face);
    }
    return out;
}

} // namespace

DisplayMesh makeDisplayMesh(const field::Mesh &mesh, int maxFaces) {
    DisplayMesh out;
    if (mesh.nFaces() <= maxFaces || maxFaces < 1) {
        out.faces = mesh.faces();
        out.fullVertex.resize(size_t(mesh.nVertices()));
        for (int v = 0; v < mesh.nVertices(); ++v) out.fullVertex[v] = v;
        return out;
    }
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    double edges = 0.0;
    for (const field::Face &f : mesh.faces())
        for (int k = 0; k < 3; ++k) edges += (mesh.position(f[(k + 1) % 3]) - mesh.position(f[k])).norm();
    const double meanEdge = edges / (3.0 * mesh.nFaces());
    // Cells no smaller than 2^-20 of the extent: every cell coordinate fits 21 bits.
    const double minCell = std::max((hi - lo).maxCoeff(), 1e-30) / double(1 << 20);
    double h = std::max(minCell, meanEdge * std::sqrt(double(mesh.nFaces()) / maxFaces));
    for (;;) {
        out = cluster(mesh, lo, h);
        if (int(out.faces.size()) <= maxFaces) return out;
        h *= 1.25;
    }
}

} // namespace rosy::studio
