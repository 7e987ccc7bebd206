#pragma once
/// \file singularities.h
/// Singularities of a vertex-based N-RoSy field (Palacios & Zhang 2007, Sec. 4.1
/// and 4.3) and the Poincaré–Hopf check.
///
/// Face index. Walking around face f counter-clockwise, each edge i → j adds the
/// angle change of the representation vector, arg(T_ij u_j) − arg(u_i) wrapped to
/// (−π, π]; adding N K_f (the face's holonomy, see frames.h) makes the total an
/// integer multiple k of 2π. The face's index is k / N. Each edge's change is
/// computed once and used with opposite signs by its two faces, so on a closed
/// mesh Σ_f k_f = N χ exactly (Σ_f K_f = 2πχ).
///
/// Boundary convention. Boundary vertices are not rescaled (frames.h), so face
/// indices near the boundary are the field's own singularities (a constant field
/// in a flat square has none, also at the corners). The rest of Poincaré–Hopf is
/// the boundary term
///   boundaryIndex = T / 2π − Σ_boundary edges (change) / (2πN),
/// T = Σ_boundary vertices (π − Θ_v) the boundary's geodesic turning, so that
/// Σ_f k_f / N + boundaryIndex = χ on every mesh. It equals the number of turns
/// of the boundary tangent relative to the field (χ for a field that does not
/// turn along the boundary, e.g. a constant field on a planar disk).

#include "field/frames.h"
#include "field/rosy.h"

#include <vector>

namespace rosy::field {

struct Singularity {
    int face = -1;
    int indexNumerator = 0;  ///< k: the index is k / N (first order: ±1)
    int nSym = 4;
    Vec3 barycentric = Vec3::Constant(1.0 / 3.0); ///< in face's corner order
    Vec3 position = Vec3::Zero();                ///< world
    double index() const { return double(indexNumerator) / nSym; }
};

struct SingularityReport {
    std::vector<Singularity> singularities; ///< sorted by face id
    int indexNumeratorSum = 0;              ///< Σ k_f
    double boundaryIndex = 0;               ///< 0 on closed meshes
    /// (indexNumeratorSum / N) + boundaryIndex, equal to χ by Poincaré–Hopf.
    double totalIndex(int nSym) const { return double(indexNumeratorSum) / nSym + boundaryIndex; }
};

/// Integer k_f for every face (#F). Faces touching a zero vector still get a
/// well-defined integer (arg(0) = 0), so the sum identity holds everywhere.
std::vector<int> faceIndexNumerators(const TangentFrames &frames, const RosyField &field);

/// All faces with k_f ≠ 0, with the zero of the linearly interpolated
/// representation vectors in the face as position (clamped into the triangle;
/// the centroid when the interpolation has no isolated zero).
SingularityReport findSingularities(const TangentFrames &frames, const RosyField &field);

} // namespace rosy::field
