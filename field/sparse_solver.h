#pragma once
/// \file sparse_solver.h
/// Sparse direct solvers for the complex systems of field design, behind one
/// small interface so the choice is made (and measured) in one place.
///
/// Hermitian positive definite systems (connection Laplacians, Dirichlet
/// problems, the smoothest field's inverse iteration) use Eigen's
/// SimplicialLDLT: on bunny00 it factors in 115 ms against 197 ms for CHOLMOD's
/// supernodal and 111 ms for CHOLMOD's simplicial Cholesky (complex, one BLAS
/// thread), so CHOLMOD is not worth a dependency there. General systems (the
/// paper's mean-value relaxation, whose rows are normalised and so not
/// symmetric) use UMFPACK's LU from Debian's libsuitesparse-dev, about 2.4×
/// faster than Eigen's SparseLU on bunny00. BLAS runs on one thread, so results
/// are bit-identical for any thread count.
///
/// These factorizations are the fallbacks and references: the product's
/// solves go through the two-level Krylov solvers of multilevel.h, which beat
/// any factorization here (a factorization of bunny00 alone costs about as
/// much as the whole iterative solve).

#include "core/error.h"
#include "field/rosy.h"

#include <Eigen/Sparse>

#include <memory>
#include <stdexcept>
#include <string>

namespace rosy::field {

using SparseMatrixC = Eigen::SparseMatrix<Complex>;

/// A factorization or iterative solve failed (Eigen's info(), non-finite values,
/// no convergence). Thrown only by the solvers of this file and multilevel.h, so a
/// caller can tell a failed solve (degenerate input) from any other error (a bug).
class SolverFailure : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The user-facing error for a failed solve: `WHAT failed on this mesh (CAUSE)` at
/// `where`, with the hint to repair the geometry. `what` names the solve ("the field
/// solver", "cannot cancel #1 … and #2 …: the solve on its region of 40 vertices").
[[noreturn]] void throwDegenerateGeometry(const FileLoc &where, const std::string &what,
                                          const SolverFailure &cause);

/// Relative residual ‖b − Kx‖ ≤ kFieldTolerance ‖b‖ at which the field solves
/// stop. Chosen from the accuracy a direction field needs, measured against a
/// direct LDLT solve of the curvature-aligned 4-RoSy system: at 1e-4 the member
/// directions differ by at most 0.012° (bunny00), 0.023° (armadillo) and 0.021°
/// (fandisk), the median by 1e-4°, and every singularity (face and index) is the
/// same; 1e-6 costs a third more iterations (52 instead of 39 on bunny00) for
/// differences nobody can see. Tests: Solver.DefaultToleranceMatchesTheConvergedField*.
constexpr double kFieldTolerance = 1e-4;

/// The same for the design relaxation (Eq. 14–15 with Dirichlet elements), which
/// is worse conditioned: with three elements on bunny00 and no guide, 1e-4 moves
/// directions by 2° and shifts singularities to neighbouring faces, 1e-5 by 0.24°,
/// 1e-6 by 0.026° with every singularity in place (against a solve to 1e-10).
constexpr double kRelaxationTolerance = 1e-6;

/// Factorization of a Hermitian positive definite matrix (only its lower
/// triangle is read), reused for many right-hand sides.
class HermitianSolver {
public:
    /// \throws SolverFailure if the factorization fails (Eigen's info(); the
    ///   matrix is not numerically positive definite).
    explicit HermitianSolver(const SparseMatrixC &matrix);
    ~HermitianSolver();
    HermitianSolver(const HermitianSolver &) = delete;
    HermitianSolver &operator=(const HermitianSolver &) = delete;
    /// \throws SolverFailure if the solve fails or produces non-finite values.
    Eigen::VectorXcd solve(const Eigen::VectorXcd &rhs) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Solves a general square sparse system once (LU). \throws SolverFailure.
Eigen::VectorXcd solveGeneral(const SparseMatrixC &matrix, const Eigen::VectorXcd &rhs);

} // namespace rosy::field
