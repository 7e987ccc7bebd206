#pragma once
/// \file winding_number.h
/// The generalized winding number of a triangle mesh around a point (Jacobson,
/// Kavan and Sorkine-Hornung 2013, "Robust Inside-Outside Segmentation using
/// Generalized Winding Numbers"): tells inside from outside for closed meshes and
/// degrades gracefully on open ones.

#include "field/mesh.h"

#include <array>
#include <vector>

namespace rosy::field {

/// Sum of the signed solid angles that the triangles of `mesh` subtend at `p`
/// (world units), each by Van Oosterom and Strackee's formula, over 4π. About ±1
/// inside a closed mesh (the sign follows the face orientation), 0 outside, and
/// in between near holes of an open mesh. An empty mesh gives 0. O(#F).
double windingNumber(const Mesh &mesh, const Vec3 &p);

/// The same for the triangles `triangles` (indices into `positions`), e.g. a polygon
/// mesh's fan triangles, without building a Mesh. O(#triangles).
double windingNumber(const std::vector<Vec3> &positions, const std::vector<std::array<int, 3>> &triangles,
                     const Vec3 &p);

} // namespace rosy::field
