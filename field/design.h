#pragma once
/// \file design.h
/// Design elements and transported relaxation (Palacios & Zhang 2007, Sec. 5.1).
///
/// An element of order L ∈ {−1, 0, +1} sits at a point on the surface. It is
/// snapped to the nearest face f and fixes the representation vectors of f's
/// three vertices from Eq. 13 evaluated in f's plane:
///   V(ρ, θ) = strength · (cos(Lθ + Nθ₀), sin(Lθ + Nθ₀)),
/// with (ρ, θ) the polar coordinates of the vertex around the element centre.
/// For L ≠ 0 the centre is f's centroid, so the singularity of index L/N lies in f;
/// for L = 0, θ₀ is the angle of the element's direction in f's plane.
/// The rest of the field solves the transported Laplace equation (Eq. 14–15)
/// with these vertices as Dirichlet rows. Several elements on one vertex add up
/// (Eq. 13 sums basis fields).

#include "field/laplacian.h"
#include "field/rosy.h"
#include "field/sparse_solver.h"

#include <string>
#include <vector>

namespace rosy::field {

struct DesignElement {
    Vec3 position = Vec3::Zero();     ///< world units; snapped to the nearest face
    int order = 0;                    ///< L ∈ {−1, 0, +1}
    Vec3 direction = Vec3::UnitX();   ///< for L = 0: a direction, projected into the face plane
    double phaseRad = 0;              ///< θ₀ for L ≠ 0
    double strength = 1;              ///< > 0
    std::string label;                ///< where it came from, for messages ("scene.yaml:12:5")
};

/// Where an element landed.
struct SnappedElement {
    int face = -1;
    Vec3 point = Vec3::Zero();  ///< closest point on that face
    double distance = 0;        ///< from the element's position to `point`
};

/// Nearest face to p (closest point on triangles; ties broken by the lower face id).
SnappedElement snapToSurface(const Mesh &mesh, const Vec3 &p);

struct DesignOptions {
    LaplaceWeights weights = LaplaceWeights::MeanValue;
    /// Optional guide field (e.g. curvature): its values enter every free row as a
    /// soft constraint (1 + g) u_i − Σ ω_ij T_ij u_j = g q_i. Null: pure relaxation.
    const RosyField *guide = nullptr;
    double guideWeight = 0.05; ///< g, dimensionless per vertex
    /// Elements farther than this fraction of the bounding-box diagonal from the
    /// surface are rejected as "off the mesh".
    double maxSnapDistance = 0.05;
    /// Relative residual of the relaxation solve (see kRelaxationTolerance).
    double solverTolerance = kRelaxationTolerance;
    /// snapToSurface() of each element's position when the caller knows it (a
    /// FieldCache), so designField() need not search the faces again; null: searched.
    const std::vector<SnappedElement> *snapped = nullptr;
};

/// The Dirichlet values an element set fixes: vertex ids and representation vectors
/// (in vertex frames). \throws InputError (using element.label) if the element is off
/// the mesh, has an order outside {−1, 0, 1}, a non-positive or non-finite strength,
/// a zero direction for L = 0, or lands in a degenerate face. `snapped`, when given,
/// holds snapToSurface() of each element's position (else each is searched).
void elementConstraints(const TangentFrames &frames, int nSym,
                        const std::vector<DesignElement> &elements, std::vector<char> &fixed,
                        Eigen::VectorXcd &values, const std::vector<SnappedElement> *snapped = nullptr);

/// Relaxed N-RoSy field from design elements (plus an optional guide).
/// Components that hold no element and have no guide get the globally smoothest
/// field there, with a warning. \throws InputError for bad elements or an empty list
/// without a guide.
RosyField designField(const TangentFrames &frames, int nSym,
                      const std::vector<DesignElement> &elements,
                      const DesignOptions &options = {});

/// Solves the transported Laplace system of Eq. 14–15 with Dirichlet rows at
/// fixed vertices (and the optional guide term). Exposed for topological editing,
/// which relaxes inside a region with the region's boundary fixed.
/// \throws SolverFailure with the solver's message on failure.
Eigen::VectorXcd solveRelaxation(const TangentFrames &frames, int nSym,
                                 const std::vector<char> &fixed, const Eigen::VectorXcd &values,
                                 const DesignOptions &options);

} // namespace rosy::field
