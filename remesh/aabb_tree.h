#pragma once
/// \file aabb_tree.h
/// Closest-point queries on a triangle soup: a median-split bounding-box
/// hierarchy, built once, queried by branch and bound. Used by the remesher (to
/// put output vertices back on the input surface) and by the quality checks
/// (one-sided Hausdorff distances). Deterministic: same input, same answers.

#include "field/mesh.h"
#include "field/mesh/closest_point.h"

#include <array>
#include <vector>

namespace rosy::remesh {

using field::Vec3;

/// The closest point of a triangle soup to a query point.
struct ClosestPoint {
    Vec3 point = Vec3::Zero();
    int triangle = -1;
    double distance2 = 0; ///< squared distance to the query
};

using field::closestPointOnTriangle;

class AabbTree {
public:
    /// Triangles as three corner indices into `points`; both are copied.
    AabbTree(std::vector<Vec3> points, std::vector<std::array<int, 3>> triangles);
    explicit AabbTree(const field::Mesh &mesh);

    /// The closest point of all triangles to p (triangle -1 if there are none).
    /// `hint`, a triangle likely to be near (the answer for a nearby query), only
    /// tightens the search: the distance is the same with or without it (at an
    /// exact tie between two triangles the point returned may be either's).
    ClosestPoint closest(const Vec3 &p, int hint = -1) const;
    int nTriangles() const { return int(m_tris.size()); }

    /// Distance along the ray o + t d (d unit) to the first triangle it crosses with
    /// tMin < t < tMax, or tMax if none (Möller–Trumbore, both sides).
    double firstHit(const Vec3 &o, const Vec3 &d, double tMin, double tMax) const;

private:
    struct Node {
        Vec3 lo, hi;
        int left = -1, right = -1; ///< children, or -1 for a leaf
        int begin = 0, end = 0;    ///< leaf range in m_order
    };
    int build(int begin, int end);
    std::vector<Vec3> m_points;
    std::vector<std::array<int, 3>> m_tris;
    std::vector<int> m_order;
    std::vector<Node> m_nodes;
};

} // namespace rosy::remesh
