#include "field/sparse_solver.h"

#include <Eigen/SparseCholesky>
#include <Eigen/UmfPackSupport>

#include <mutex>
#include <stdexcept>
#include <string>

// OpenBLAS (Debian's default BLAS behind CHOLMOD when installed) threads its
// kernels; a different thread count may change rounding. Pin it to one thread
// when it is the BLAS in use (weak: absent with the reference BLAS).
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

namespace rosy::field {
namespace {
void pinBlasThreads() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (openblas_set_num_threads) openblas_set_num_threads(1);
    });
}
} // namespace

void throwDegenerateGeometry(const FileLoc &where, const std::string &what, const SolverFailure &cause) {
    throw InputError(where, what + " failed on this mesh (" + cause.what() + ")",
                     "its geometry is too degenerate (needle or nearly zero-area faces make the "
                     "system singular); repair or remesh it");
}

struct HermitianSolver::Impl {
    Eigen::SimplicialLDLT<SparseMatrixC, Eigen::Lower> ldlt;
};

HermitianSolver::HermitianSolver(const SparseMatrixC &matrix) : m_impl(std::make_unique<Impl>()) {
    m_impl->ldlt.compute(matrix);
    if (m_impl->ldlt.info() != Eigen::Success)
        throw SolverFailure("sparse LDLT factorization failed (matrix of size " +
                                 std::to_string(matrix.rows()) + " not positive definite?)");
}

HermitianSolver::~HermitianSolver() = default;

Eigen::VectorXcd HermitianSolver::solve(const Eigen::VectorXcd &rhs) const {
    Eigen::VectorXcd x = m_impl->ldlt.solve(rhs);
    if (m_impl->ldlt.info() != Eigen::Success || !x.allFinite())
        throw SolverFailure("sparse LDLT solve failed");
    return x;
}

Eigen::VectorXcd solveGeneral(const SparseMatrixC &matrix, const Eigen::VectorXcd &rhs) {
    pinBlasThreads();
    Eigen::UmfPackLU<SparseMatrixC> lu;
    lu.compute(matrix);
    if (lu.info() != Eigen::Success)
        throw SolverFailure("UMFPACK LU factorization failed (singular system: a component without constraints?)");
    Eigen::VectorXcd x = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !x.allFinite()) throw SolverFailure("UMFPACK solve failed");
    return x;
}

} // namespace rosy::field
