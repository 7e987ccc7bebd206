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

#include "field/rosy.h"

#include <Eigen/Sparse>

#include <memory>

namespace rosy::field {

using SparseMatrixC = Eigen::SparseMatrix<Complex>;

/// Factorization of a Hermitian positive definite matrix (only its lower
/// triangle is read), reused for many right-hand sides.
class HermitianSolver {
public:
    /// \throws std::runtime_error with CHOLMOD's status if the matrix is not
    ///   positive definite or the factorization fails.
    explicit HermitianSolver(const SparseMatrixC &matrix);
    ~HermitianSolver();
    HermitianSolver(const HermitianSolver &) = delete;
    HermitianSolver &operator=(const HermitianSolver &) = delete;
    /// \throws std::runtime_error if the solve fails or produces non-finite values.
    Eigen::VectorXcd solve(const Eigen::VectorXcd &rhs) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Solves a general square sparse system once (LU). \throws std::runtime_error.
Eigen::VectorXcd solveGeneral(const SparseMatrixC &matrix, const Eigen::VectorXcd &rhs);

} // namespace rosy::field
