#pragma once
/// \file features.h
/// Feature curves of a triangle mesh and the field constraint that aligns an
/// N-RoSy field to them (docs/remeshing.md, "Sharp features and boundaries").
///
/// An edge is a feature edge when the normals of its two faces differ by more
/// than an angle D (a crease, dihedral angle below 180° − D) or when it has one
/// face (a boundary edge). Feature edges form feature curves; a vertex where
/// more than two of them meet, or where a curve turns by more than
/// kFeatureCornerTurnDeg, is a feature corner. At every other vertex of a curve
/// the curve has a tangent (the mean of its two edges' directions; at a curve's
/// end, its one edge's), and the
/// constraint asks the field to have a member along it: u_v = e^{iNθ_v}, θ_v the
/// tangent's angle in v's frame (for N = 4 the other members are then along and
/// across the curve). Corners are left free.

#include "field/frames.h"
#include "field/mesh.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace rosy::field {

/// A curve vertex whose two feature edges turn by more than this (degrees) is a corner.
inline constexpr double kFeatureCornerTurnDeg = 45.0;

struct FeatureCurves {
    std::vector<std::array<int, 2>> edges; ///< feature edges (smaller vertex first), in edge order
    std::vector<int> degree;               ///< per vertex: feature edges meeting there
    std::vector<char> corner;              ///< per vertex: a feature corner
    std::vector<Vec3> tangent;             ///< per vertex inside a curve: unit tangent; else zero
    int boundaryEdges = 0;                 ///< how many of `edges` are boundary edges
    bool empty() const { return edges.empty(); }
    bool onCurve(int v) const { return degree[size_t(v)] > 0; }
};

/// The feature edges (crease angle above `angleDeg`, in (0, 180), and every
/// boundary edge), corners and tangents of `mesh`. With minCurveLength > 0, the
/// crease curves (edges joined through vertices that are not corners) shorter
/// than it are dropped, and the rest classified again. \throws InputError naming
/// the mesh when angleDeg is outside (0, 180).
FeatureCurves findFeatureCurves(const Mesh &mesh, double angleDeg, double minCurveLength = 0);

/// Dirichlet constraints for an N-RoSy field aligned to `curves`: every curve
/// vertex that is not a corner and not already fixed gets fixed[v] = 1 and
/// values[v] = e^{iNθ_v} (θ_v its tangent's angle in v's frame). `fixed` and
/// `values` are sized to the mesh if empty. Returns how many vertices it fixed.
int addFeatureConstraints(const TangentFrames &frames, int nSym, const FeatureCurves &curves,
                          std::vector<char> &fixed, Eigen::VectorXcd &values);

} // namespace rosy::field
