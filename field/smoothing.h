#pragma once
/// \file smoothing.h
/// Global smoothing of N-RoSy fields, two ways:
///  - relaxationSmooth: the paper's smoothing (Palacios & Zhang 2007, Sec. 5.1),
///    repeated transported Laplace relaxation steps with a strength, constrained
///    vertices kept;
///  - smoothestField / alignedField: the globally smoothest field of Knöppel et
///    al. 2013 (smallest eigenvector of the connection Laplacian), optionally
///    pulled toward a guide field such as the curvature field.

#include "field/laplacian.h"
#include "field/rosy.h"
#include "field/sparse_solver.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rosy::field {

/// `iterations` Jacobi steps u_i ← (1 − strength) u_i + strength Σ_j ω_ij T_ij u_j
/// (strength in (0, 1]). Vertices with fixed[v] != 0 keep their value (fixed may be
/// empty). Deterministic and parallel. Strength is preserved per vertex only where
/// the neighbours agree: smoothing shrinks |u| near singularities, as it should.
/// Without fixed vertices the whole field also shrinks from step to step (by the
/// transport's holonomy on curved surfaces), so it is renormalised by a power of
/// two whenever max |u| falls below half its starting value: a power of two scales
/// exactly, so relative magnitudes and directions are those of the plain iteration
/// (bit for bit, while it stays clear of underflow), but 10^5 steps no longer decay
/// to exactly zero.
/// \throws InputError naming the mesh if the field still ends exactly zero
///   everywhere (it started nonzero), rather than hatching a zero field.
void relaxationSmooth(const TangentFrames &frames, RosyField &field, int iterations,
                      double strength, const std::vector<char> &fixed = {},
                      LaplaceWeights weights = LaplaceWeights::MeanValue);

/// How smoothestField() found its eigenvector: data, not an exception, since a
/// fallback still gives the right field, only slower.
struct EigenSolveReport {
    /// "dense" (tiny components), "lobpcg", "block-lobpcg" (single-vector LOBPCG
    /// stalled and a block of SmoothestOptions::blockSize continued it), or
    /// "inverse-iteration" (the slow fallback); with several components, the
    /// slowest one's.
    std::string method;
    int iterations = 0;       ///< of the method that produced the field (max over components)
    int lobpcgIterations = 0; ///< LOBPCG's, also when it gave up (max over components)
    /// Why LOBPCG gave up (no convergence with its residual, a failed coarse
    /// factorization, a non-finite residual); empty when it did not.
    std::string fallbackReason;
};

/// Iteration limits of smoothestField()'s eigen-solve (tests and benchmarks
/// lower them to exercise the later stages on small meshes).
struct SmoothestOptions {
    /// Single-vector LOBPCG iterations before it counts as stalled.
    int lobpcgIterations = 400;
    /// Block size of the block LOBPCG that continues a stalled solve from where it
    /// stopped (0: go straight to inverse iteration), and its iteration limit.
    int blockSize = 2;
    int blockIterations = 400;
};

struct SmoothestResult {
    RosyField field;  ///< unit-M-norm eigenvector, rescaled so max |u_v| = 1
    double eigenvalue = 0; ///< Rayleigh quotient uᴴAu / uᴴMu (0 for a flat torus)
    int iterations = 0;    ///< = solver.iterations
    EigenSolveReport solver;
};

/// Globally smoothest N-RoSy (Knöppel et al. 2013): smallest eigenvector of the
/// generalized problem A u = λ M u, per mesh component, by LOBPCG with the
/// two-level preconditioner (started from the coarse eigenvector), stopped at a
/// residual of 1e-3 λ (eigenvalue error quadratic in it, ~1e-6 λ²/gap). If it
/// stalls (clustered small eigenvalues on noisy scans), block LOBPCG continues
/// from its last iterate; inverse power iteration on one sparse factorization is
/// the last fallback, never
/// silently: a `smoothest-fallback` warning names the mesh and the reason, and
/// SmoothestResult::solver records it.
/// \throws InputError for a component of zero total area; SolverFailure
/// naming the cause if a factorization fails.
SmoothestResult smoothestField(const TangentFrames &frames, int nSym, const SmoothestOptions &options = {});

/// The accepted smoothing lengths of alignedField() (0, the raw guide, is handled
/// by the caller): below 1e-6 s = 1 / (ℓ d)² leaves double range.
inline constexpr double kMinSmoothingLength = 1e-6;
inline constexpr double kMaxSmoothingLength = 10.0;

/// Smooth field aligned to a guide (Knöppel 2013, Sec. 6 in spirit): solves
/// (A + s M) u = s M q, where q is the guide field and s = 1 / (ℓ d)², d the
/// bounding-box diagonal and ℓ = smoothingLength the relative length below which
/// guide detail is smoothed away (0.02–0.1 typical). Where |q| is small
/// (umbilics, flat parts), the smoothness term decides.
/// Vertices with fixed[v] != 0 keep `fixedValues[v]` (Dirichlet rows; fixed may be empty).
/// The solve stops at a relative residual of `tolerance`; by default kFieldTolerance,
/// or kRelaxationTolerance when vertices are fixed (design elements make the system
/// worse conditioned: at 1e-4 directions moved by 0.22° on bunny00 with two elements).
/// \throws InputError naming the mesh if smoothingLength is outside
///   [kMinSmoothingLength, kMaxSmoothingLength].
RosyField alignedField(const TangentFrames &frames, const RosyField &guide, double smoothingLength,
                       const std::vector<char> &fixed = {},
                       const Eigen::VectorXcd &fixedValues = {},
                       std::optional<double> tolerance = std::nullopt);

/// alignedField() with its two mesh-only inputs given: `laplacian` =
/// connectionLaplacian(frames, guide.nSym) and `areas` = vertexAreas(frames.mesh())
/// (a FieldCache keeps them between calls; the result is the same to the bit).
RosyField alignedField(const TangentFrames &frames, const SparseMatrixC &laplacian, const Eigen::VectorXd &areas,
                       const RosyField &guide, double smoothingLength, const std::vector<char> &fixed = {},
                       const Eigen::VectorXcd &fixedValues = {}, std::optional<double> tolerance = std::nullopt);

/// alignedField() without fixed vertices in two halves: the system, K = A + s M and
/// its two-level preconditioner, which needs no guide; then solve() for a guide. So
/// buildField() builds the system beside the curvature that gives the guide. The
/// field is alignedField()'s to the bit (alignedField() itself goes through here).
class AlignedSystem {
public:
    /// `laplacian` = connectionLaplacian(frames, nSym), `areas` = vertexAreas(frames.mesh());
    /// none of the three is referred to afterwards.
    /// \throws InputError naming the mesh if smoothingLength is outside
    ///   [kMinSmoothingLength, kMaxSmoothingLength].
    AlignedSystem(const TangentFrames &frames, const SparseMatrixC &laplacian, const Eigen::VectorXd &areas,
                  int nSym, double smoothingLength);
    ~AlignedSystem();
    AlignedSystem(AlignedSystem &&) noexcept;
    AlignedSystem &operator=(AlignedSystem &&) noexcept;

    /// The field following `guide` (guide.nSym must be the system's N; checked), to a
    /// relative residual of `tolerance`.
    RosyField solve(const RosyField &guide, double tolerance = kFieldTolerance) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace rosy::field
