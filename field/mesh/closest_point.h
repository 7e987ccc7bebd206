#pragma once
/// \file closest_point.h
/// The closest point of a triangle to a query point: the one implementation used by
/// design elements (snapping a point onto the mesh) and the remesher's AABB tree.
#include "field/mesh/mesh.h"

namespace rosy::field {

/// Closest point to `p` on triangle (a, b, c), by the Voronoi regions of its
/// vertices, edges and face (Ericson, Real-Time Collision Detection, §5.1.5).
/// Degenerate triangles (collinear or coincident corners) give the closest point of
/// their three edges, never NaN.
Vec3 closestPointOnTriangle(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c);

} // namespace rosy::field
