#include "field/mesh/refine.h"

#include "core/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace rosy::field {

namespace {

uint64_t edgeKey(int a, int b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(uint32_t(a)) << 32) | uint64_t(uint32_t(b));
}

/// The faces beside an edge: one on a boundary, two inside (the mesh is manifold).
struct EdgeFaces {
    int f[2] = {-1, -1};
    void replace(int from, int to) { (f[0] == from ? f[0] : f[1]) = to; }
    void add(int face) {
        ROSY_CHECK_LT(f[1], 0); // a third face: Mesh::fromTriangles() admits none
        (f[0] < 0 ? f[0] : f[1]) = face;
    }
};

/// Opposite angles summing to at most π plus this (radians) count as Delaunay
/// (flipCoplanarToDelaunay()).
constexpr double kCocircularSlack = 1e-9;

/// The faces beside every edge of `faces`, keyed by edgeKey(); `keys` (if given)
/// receives each edge's key once, in the order the faces first reach it.
using EdgeMap = std::unordered_map<uint64_t, EdgeFaces>;
EdgeMap facesBesideEdges(const std::vector<Face> &faces, std::vector<uint64_t> *keys = nullptr) {
    EdgeMap edges;
    edges.reserve(faces.size() * 2);
    for (int f = 0; f < int(faces.size()); ++f)
        for (int k = 0; k < 3; ++k) {
            const uint64_t key = edgeKey(faces[size_t(f)][k], faces[size_t(f)][(k + 1) % 3]);
            auto [it, fresh] = edges.try_emplace(key);
            it->second.add(f);
            if (fresh && keys) keys->push_back(key);
        }
    return edges;
}

} // namespace

Mesh refineLongEdges(const Mesh &mesh, double maxEdge, long long maxVertices, Refinement *report) {
    ROSY_CHECK(maxEdge > 0 && std::isfinite(maxEdge));
    std::vector<Vec3> positions = mesh.positions();
    std::vector<Face> faces = mesh.faces();
    std::vector<uint64_t> keys;
    EdgeMap edges = facesBesideEdges(faces, &keys);
    // Longest first; equal lengths by their vertex pair, so the order (and the
    // result) never depends on hashing.
    using Entry = std::tuple<double, int, int>; // length, a < b
    std::priority_queue<Entry> queue;
    auto length = [&](int a, int b) { return (positions[size_t(a)] - positions[size_t(b)]).norm(); };
    auto push = [&](int a, int b) {
        const double l = length(a, b);
        if (l > maxEdge) queue.emplace(l, std::min(a, b), std::max(a, b));
    };
    double longest = 0;
    for (const uint64_t key : keys) {
        const int a = int(key >> 32), b = int(key & 0xffffffffu);
        longest = std::max(longest, length(a, b));
        push(a, b);
    }
    int bisections = 0;
    while (!queue.empty()) {
        const auto [l, a, b] = queue.top();
        queue.pop();
        const auto found = edges.find(edgeKey(a, b));
        if (found == edges.end()) continue; // bisected already
        if ((long long)positions.size() >= maxVertices)
            throw InputError(FileLoc{mesh.name()},
                             fmt::format("refining the mesh to edges of at most {:.4g} would take more than {} "
                                         "vertices",
                                         maxEdge, maxVertices),
                             "use a longer edge length, or raise the vertex limit");
        const EdgeFaces beside = found->second;
        edges.erase(found);
        const int m = int(positions.size());
        positions.push_back(0.5 * (positions[size_t(a)] + positions[size_t(b)]));
        ++bisections;
        for (int f : beside.f) {
            if (f < 0) continue;
            // f = (p, q, c) with p -> q the bisected edge in f's winding: f becomes
            // (p, m, c) and a new face g = (m, q, c).
            const Face old = faces[size_t(f)];
            int k = 0;
            while (edgeKey(old[k], old[(k + 1) % 3]) != edgeKey(a, b)) ++k;
            const int p = old[k], q = old[(k + 1) % 3], c = old[(k + 2) % 3];
            const int g = int(faces.size());
            faces[size_t(f)] = {p, m, c};
            faces.push_back({m, q, c});
            edges[edgeKey(q, c)].replace(f, g);
            edges[edgeKey(p, m)].add(f);
            edges[edgeKey(m, q)].add(g);
            EdgeFaces &mc = edges[edgeKey(m, c)];
            mc.add(f);
            mc.add(g);
            push(m, c);
        }
        push(a, m);
        push(m, b);
    }
    if (report) *report = {bisections, longest};
    if (bisections == 0) return mesh;
    return Mesh::fromTriangles(std::move(positions), std::move(faces), mesh.name());
}

Mesh flipCoplanarToDelaunay(const Mesh &mesh, int *flips) {
    std::vector<Face> faces = mesh.faces();
    const std::vector<Vec3> &x = mesh.positions();
    std::vector<uint64_t> keys;
    EdgeMap edges = facesBesideEdges(faces, &keys);
    std::sort(keys.begin(), keys.end());
    std::deque<uint64_t> work(keys.begin(), keys.end());
    auto normal = [&](const Face &f) { return Vec3((x[size_t(f[1])] - x[size_t(f[0])]).cross(x[size_t(f[2])] - x[size_t(f[0])])); };
    // The angle at b of the triangle (a, b, c).
    auto angleAt = [&](int a, int b, int c) {
        const Vec3 u = x[size_t(a)] - x[size_t(b)], w = x[size_t(c)] - x[size_t(b)];
        return std::atan2(u.cross(w).norm(), u.dot(w));
    };
    const double minCos = std::cos(kCoplanarAngle);
    int count = 0;
    while (!work.empty()) {
        const uint64_t key = work.front();
        work.pop_front();
        const auto found = edges.find(key);
        if (found == edges.end()) continue; // flipped away
        const EdgeFaces beside = found->second;
        if (beside.f[0] < 0 || beside.f[1] < 0) continue; // boundary
        const Face A = faces[size_t(beside.f[0])], B = faces[size_t(beside.f[1])];
        // A = (p, q, c) with p -> q the edge in A's winding; B runs q -> p, d its third corner.
        int k = 0;
        while (edgeKey(A[k], A[(k + 1) % 3]) != key) ++k;
        const int p = A[k], q = A[(k + 1) % 3], c = A[(k + 2) % 3];
        int d = -1;
        for (int v : B)
            if (v != p && v != q) d = v;
        ROSY_CHECK_GE(d, 0);
        if (c == d || edges.count(edgeKey(c, d))) continue; // the new diagonal exists already
        const Vec3 nA = normal(A), nB = normal(B);
        const double lA = nA.norm(), lB = nB.norm();
        if (!(lA > 0 && lB > 0) || nA.dot(nB) < minCos * lA * lB) continue; // not one plane
        // Delaunay already (or cocircular, up to rounding: both diagonals may not flip back and forth).
        if (angleAt(p, c, q) + angleAt(p, d, q) <= M_PI + kCocircularSlack) continue;
        const Face newA = {p, d, c}, newB = {q, c, d};
        if (!(normal(newA).dot(nA) > 0 && normal(newB).dot(nA) > 0)) continue; // would fold
        const int fa = beside.f[0], fb = beside.f[1];
        edges.erase(found);
        faces[size_t(fa)] = newA;
        faces[size_t(fb)] = newB;
        // Edges (q, c) moves from A to newB, (p, d) from B to newA; (c, d) is new.
        edges[edgeKey(q, c)].replace(fa, fb);
        edges[edgeKey(p, d)].replace(fb, fa);
        EdgeFaces &cd = edges[edgeKey(c, d)];
        cd.add(fa);
        cd.add(fb);
        ++count;
        for (const uint64_t around : {edgeKey(p, c), edgeKey(c, q), edgeKey(q, d), edgeKey(d, p)}) work.push_back(around);
    }
    if (flips) *flips = count;
    if (count == 0) return mesh;
    return Mesh::fromTriangles(mesh.positions(), std::move(faces), mesh.name());
}

} // namespace rosy::field
