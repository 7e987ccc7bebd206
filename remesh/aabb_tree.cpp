/// \file aabb_tree.cpp
#include "remesh/aabb_tree.h"

#include <algorithm>
#include <limits>

namespace rosy::remesh {


AabbTree::AabbTree(std::vector<Vec3> points, std::vector<std::array<int, 3>> triangles)
    : m_points(std::move(points)), m_tris(std::move(triangles)) {
    m_order.resize(m_tris.size());
    for (size_t i = 0; i < m_order.size(); ++i) m_order[i] = int(i);
    if (!m_tris.empty()) {
        m_nodes.reserve(2 * m_tris.size());
        build(0, int(m_tris.size()));
    }
}

AabbTree::AabbTree(const field::Mesh &mesh)
    : AabbTree(mesh.positions(), std::vector<std::array<int, 3>>(mesh.faces().begin(), mesh.faces().end())) {}

int AabbTree::build(int begin, int end) {
    Node node;
    node.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    node.hi = -node.lo;
    for (int k = begin; k < end; ++k)
        for (int c : m_tris[m_order[k]]) {
            node.lo = node.lo.cwiseMin(m_points[c]);
            node.hi = node.hi.cwiseMax(m_points[c]);
        }
    const int id = int(m_nodes.size());
    m_nodes.push_back(node);
    if (end - begin <= 4) {
        m_nodes[id].begin = begin;
        m_nodes[id].end = end;
        return id;
    }
    // Split at the median centroid along the longest axis (ties by index: deterministic).
    int axis = 0;
    (node.hi - node.lo).maxCoeff(&axis);
    auto centroid = [&](int t) {
        const auto &f = m_tris[t];
        return m_points[f[0]][axis] + m_points[f[1]][axis] + m_points[f[2]][axis];
    };
    const int mid = (begin + end) / 2;
    std::nth_element(m_order.begin() + begin, m_order.begin() + mid, m_order.begin() + end, [&](int x, int y) {
        const double cx = centroid(x), cy = centroid(y);
        return cx < cy || (cx == cy && x < y);
    });
    const int left = build(begin, mid);
    const int right = build(mid, end);
    m_nodes[id].left = left;
    m_nodes[id].right = right;
    return id;
}

namespace {
double boxDistance2(const Vec3 &p, const Vec3 &lo, const Vec3 &hi) {
    const Vec3 d = (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero());
    return d.squaredNorm();
}
} // namespace

ClosestPoint AabbTree::closest(const Vec3 &p, int hint) const {
    ClosestPoint best;
    best.distance2 = std::numeric_limits<double>::infinity();
    if (m_nodes.empty()) return best;
    if (hint >= 0 && hint < int(m_tris.size())) {
        const auto &f = m_tris[size_t(hint)];
        best.point = closestPointOnTriangle(p, m_points[f[0]], m_points[f[1]], m_points[f[2]]);
        best.distance2 = (best.point - p).squaredNorm();
        best.triangle = hint;
    }
    // Each stacked node with its box's distance, computed once when it was pushed.
    int stack[128];
    double stackDistance2[128];
    int top = 0;
    stackDistance2[top] = boxDistance2(p, m_nodes[0].lo, m_nodes[0].hi);
    stack[top++] = 0;
    while (top > 0) {
        --top;
        if (stackDistance2[top] >= best.distance2) continue;
        const Node &node = m_nodes[size_t(stack[top])];
        if (node.left < 0) {
            for (int k = node.begin; k < node.end; ++k) {
                const auto &f = m_tris[m_order[k]];
                const Vec3 q = closestPointOnTriangle(p, m_points[f[0]], m_points[f[1]], m_points[f[2]]);
                const double d2 = (q - p).squaredNorm();
                if (d2 < best.distance2 || (d2 == best.distance2 && m_order[k] < best.triangle)) {
                    best.distance2 = d2;
                    best.point = q;
                    best.triangle = m_order[k];
                }
            }
            continue;
        }
        // Nearer child last, so it is popped first.
        const Node &l = m_nodes[node.left], &r = m_nodes[node.right];
        const double dl = boxDistance2(p, l.lo, l.hi), dr = boxDistance2(p, r.lo, r.hi);
        if (dl < dr) {
            stackDistance2[top] = dr, stack[top++] = node.right;
            stackDistance2[top] = dl, stack[top++] = node.left;
        } else {
            stackDistance2[top] = dl, stack[top++] = node.left;
            stackDistance2[top] = dr, stack[top++] = node.right;
        }
    }
    return best;
}

double AabbTree::firstHit(const Vec3 &o, const Vec3 &d, double tMin, double tMax) const {
    if (m_nodes.empty()) return tMax;
    const Vec3 inv(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
    // Entry distance of the ray into a box (slabs), or +inf if it misses before `best`.
    auto enter = [&](const Node &n, double best) {
        double t0 = tMin, t1 = best;
        for (int k = 0; k < 3; ++k) {
            double a = (n.lo[k] - o[k]) * inv[k], b = (n.hi[k] - o[k]) * inv[k];
            if (a > b) std::swap(a, b);
            if (a != a || b != b) { // d[k] == 0 with o on a slab plane: inside iff within it
                if (o[k] < n.lo[k] || o[k] > n.hi[k]) return std::numeric_limits<double>::infinity();
                continue;
            }
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
        }
        return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
    };
    double best = tMax;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node &node = m_nodes[size_t(stack[--top])];
        if (enter(node, best) >= best) continue;
        if (node.left < 0) {
            for (int k = node.begin; k < node.end; ++k) {
                const auto &f = m_tris[size_t(m_order[size_t(k)])];
                const Vec3 e1 = m_points[f[1]] - m_points[f[0]], e2 = m_points[f[2]] - m_points[f[0]];
                const Vec3 pv = d.cross(e2);
                const double det = e1.dot(pv);
                if (std::abs(det) < 1e-300) continue;
                const Vec3 tv = o - m_points[f[0]];
                const double u = tv.dot(pv) / det;
                if (u < 0 || u > 1) continue;
                const Vec3 qv = tv.cross(e1);
                const double v = d.dot(qv) / det;
                if (v < 0 || u + v > 1) continue;
                const double t = e2.dot(qv) / det;
                if (t > tMin && t < best) best = t;
            }
            continue;
        }
        stack[top++] = node.left;
        stack[top++] = node.right;
    }
    return best;
}

} // namespace rosy::remesh
