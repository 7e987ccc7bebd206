#include "field/mesh/mesh.h"

#include <cstdio>

#include "core/error.h"
#include "core/parallel.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

namespace rosy::field {

Mesh Mesh::fromTriangles(std::vector<Vec3> positions, std::vector<Face> faces,
                         const std::string &name) {
    Mesh m;
    m.m_name = name;
    const int nV = int(positions.size());
    const int nF = int(faces.size());
    const FileLoc loc{name};
    for (int v = 0; v < nV; ++v)
        if (!positions[v].allFinite())
            throw InputError(loc, "vertex " + std::to_string(v) + " has a non-finite coordinate",
                             "fix or remove that vertex");
    // A mesh far smaller than any real object: areas (d²) and their products (d⁴ in
    // the curvature and the solvers) would underflow toward the denormals, and the
    // fuzzer's disk scaled to 1e-73 made the smoothest-field solve fail. Loaded
    // coordinates are floats, so nothing real is below 1e-15 across.
    if (nF > 0) {
        Vec3 lo = positions[0], hi = positions[0];
        for (const Vec3 &p : positions) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        const double diagonal = (hi - lo).norm();
        if (!(diagonal >= kMinMeshSize)) {
            char size[32];
            std::snprintf(size, sizeof size, "%.3g", diagonal);
            throw InputError(loc, std::string("the mesh is ") + size + " units across, below the limit of 1e-15",
                             "rescale the mesh (e.g. mesh.transform.scale in a scene); the picture does not "
                             "depend on its scale");
        }
    }
    for (int f = 0; f < nF; ++f) {
        const Face &t = faces[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] < 0 || t[k] >= nV)
                throw InputError(loc, "face " + std::to_string(f) + " uses vertex index " +
                                          std::to_string(t[k]) + " outside [0, " +
                                          std::to_string(nV) + ")");
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            throw InputError(loc, "face " + std::to_string(f) + " repeats a vertex");
    }

    // Twins from the outgoing halfedges of each vertex, bucketed by tail (a
    // counting sort) and sorted by (head, halfedge) within each bucket. Each
    // directed edge must be unique: a repeat means an edge with more than two
    // faces or two faces that disagree on orientation.
    const int nH = 3 * nF;
    auto tailOf = [&](int h) { return faces[h / 3][h % 3]; };
    auto headOf = [&](int h) { return faces[h / 3][(h % 3 + 1) % 3]; };
    std::vector<int> outStart(size_t(nV) + 1, 0);
    for (int h = 0; h < nH; ++h) ++outStart[size_t(tailOf(h)) + 1];
    for (int v = 0; v < nV; ++v) outStart[v + 1] += outStart[v];
    std::vector<std::pair<int, int>> out(nH); // (head, halfedge)
    {
        std::vector<int> fill(outStart.begin(), outStart.end() - 1);
        for (int h = 0; h < nH; ++h) out[fill[tailOf(h)]++] = {headOf(h), h};
    }
    // Buckets sorted in parallel; a repeated edge is then named for the first vertex
    // that has one, as a loop in vertex order would.
    std::atomic<bool> repeated{false};
    parallelFor(0, nV, [&](int64_t v) {
        const auto first = out.begin() + outStart[v], last = out.begin() + outStart[v + 1];
        std::sort(first, last);
        for (auto it = first; it + 1 < last; ++it)
            if (it->first == (it + 1)->first) repeated = true;
    }, 1024);
    for (int v = 0; repeated && v < nV; ++v) {
        const auto first = out.begin() + outStart[v], last = out.begin() + outStart[v + 1];
        for (auto it = first; it + 1 < last; ++it)
            if (it->first == (it + 1)->first)
                throw InputError(loc,
                                 "edge (" + std::to_string(v) + ", " + std::to_string(it->first) +
                                     ") is used in the same direction by faces " + std::to_string(it->second / 3) +
                                     " and " + std::to_string((it + 1)->second / 3),
                                 "the surface is non-manifold or inconsistently oriented there; "
                                 "load it through loadMesh() to repair it");
    }
    m.m_twin.assign(nH, -1);
    parallelFor(0, nH, [&](int64_t h) {
        // The twin of a -> b is b -> a: look for head a among b's outgoing halfedges.
        const int a = tailOf(int(h)), b = headOf(int(h));
        const auto first = out.begin() + outStart[b], last = out.begin() + outStart[b + 1];
        const auto it = std::lower_bound(first, last, std::pair<int, int>(a, -1));
        if (it != last && it->first == a) m.m_twin[size_t(h)] = it->second;
    }, 4096);

    // Edges: one id per halfedge pair, numbered in halfedge order (deterministic).
    m.m_halfedgeEdge.assign(nH, -1);
    for (int h = 0; h < nH; ++h) {
        if (m.m_halfedgeEdge[h] >= 0) continue;
        int e = int(m.m_edgeHalfedge.size());
        m.m_edgeHalfedge.push_back(h);
        m.m_halfedgeEdge[h] = e;
        if (m.m_twin[h] >= 0) m.m_halfedgeEdge[m.m_twin[h]] = e;
    }

    // One-rings in CCW order: the CCW successor of outgoing h is twin(prev(h)).
    std::vector<int> count(nV + 1, 0);
    for (int h = 0; h < nH; ++h) ++count[faces[h / 3][h % 3] + 1];
    m.m_ringOffset.assign(nV + 1, 0);
    for (int v = 0; v < nV; ++v) m.m_ringOffset[v + 1] = m.m_ringOffset[v] + count[v + 1];
    std::vector<int> anyOut(nV, -1), boundaryOut(nV, -1);
    for (int h = 0; h < nH; ++h) {
        int v = faces[h / 3][h % 3];
        if (anyOut[v] < 0) anyOut[v] = h;
        if (m.m_twin[h] < 0) {
            if (boundaryOut[v] >= 0)
                throw InputError(loc, "vertex " + std::to_string(v) +
                                          " is non-manifold (it joins two boundary fans)",
                                 "load it through loadMesh() to split it");
            boundaryOut[v] = h;
        }
    }
    m.m_ring.resize(nH);
    m.m_boundaryVertex.assign(nV, 0);
    // Each vertex's ring in parallel; the first vertex in order that fails is named.
    std::atomic<int> firstBad{nV};
    parallelFor(0, nV, [&](int64_t vi) {
        const int v = int(vi);
        if (anyOut[v] < 0) {
            for (int seen = firstBad.load(); v < seen && !firstBad.compare_exchange_weak(seen, v);) {}
            return;
        }
        int start = boundaryOut[v] >= 0 ? boundaryOut[v] : anyOut[v];
        m.m_boundaryVertex[v] = boundaryOut[v] >= 0;
        int n = 0, h = start;
        const int expected = m.m_ringOffset[v + 1] - m.m_ringOffset[v];
        do {
            if (n >= expected) break;
            m.m_ring[m.m_ringOffset[v] + n++] = h;
            h = m.m_twin[prev(h)];
        } while (h >= 0 && h != start);
        if (n != expected)
            for (int seen = firstBad.load(); v < seen && !firstBad.compare_exchange_weak(seen, v);) {}
    }, 1024);
    if (const int v = firstBad.load(); v < nV) {
        if (anyOut[v] < 0)
            throw InputError(loc, "vertex " + std::to_string(v) + " is not used by any face",
                             "remove isolated vertices or load through loadMesh()");
        throw InputError(loc, "vertex " + std::to_string(v) +
                                  " is non-manifold (its faces form more than one fan)",
                         "load it through loadMesh() to split it");
    }
    m.m_positions = std::move(positions);
    m.m_faces = std::move(faces);
    return m;
}

Vec3 Mesh::faceNormalArea(int f) const {
    const Face &t = m_faces[f];
    return (m_positions[t[1]] - m_positions[t[0]]).cross(m_positions[t[2]] - m_positions[t[0]]);
}

Vec3 Mesh::faceNormal(int f) const {
    Vec3 n = faceNormalArea(f);
    double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double Mesh::cornerAngle(int h) const {
    Vec3 a = vector(h);
    Vec3 b = position(tail(prev(h))) - position(tail(h));
    // atan2 of |cross| and dot is accurate for tiny and near-pi angles alike.
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

namespace {

/// `slot` filled once with value(i) for i in [0, n), in parallel; then as it is.
/// Isolated: while its loop waits, this thread must not pick up a task that asks for
/// the same values (it would wait on its own once_flag).
template <typename T, typename Value>
const std::vector<T> &computedOnce(std::once_flag &once, std::vector<T> &slot, int n, Value &&value) {
    std::call_once(once, [&] {
        tbb::this_task_arena::isolate([&] {
            std::vector<T> v(static_cast<size_t>(n));
            parallelFor(0, n, [&](int64_t i) { v[size_t(i)] = value(int(i)); }, 4096);
            slot = std::move(v);
        });
    });
    return slot;
}

} // namespace

const std::vector<double> &Mesh::cornerAngles() const {
    static const std::vector<double> kNone;
    if (!m_derived) return kNone; // a moved-from mesh: no halfedges either
    return computedOnce(m_derived->anglesOnce, m_derived->cornerAngles, nHalfedges(),
                        [&](int h) { return cornerAngle(h); });
}

const std::vector<Vec3> &Mesh::faceNormals() const {
    static const std::vector<Vec3> kNone;
    if (!m_derived) return kNone; // a moved-from mesh: no faces either
    return computedOnce(m_derived->normalsOnce, m_derived->faceNormals, nFaces(), [&](int f) { return faceNormal(f); });
}

Vec3 Mesh::vertexNormal(int v) const {
    Vec3 n = Vec3::Zero();
    for (const int *it = outgoingBegin(v); it != outgoingEnd(v); ++it)
        n += cornerAngle(*it) * faceNormal(faceOf(*it));
    double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

void Mesh::bounds(Vec3 &lo, Vec3 &hi) const {
    lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const Vec3 &p : m_positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
}

double Mesh::meanEdgeLength() const {
    if (m_edgeHalfedge.empty()) return 0;
    double sum = 0;
    for (int h : m_edgeHalfedge) sum += vector(h).norm();
    return sum / double(m_edgeHalfedge.size());
}

} // namespace rosy::field
