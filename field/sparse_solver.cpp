#include "field/sparse_solver.h"

#include <Eigen/SparseCholesky>
#include <Eigen/UmfPackSupport>

#include <stdexcept>
#include <string>

// OpenBLAS (Debian's default BLAS behind UMFPACK when installed) threads its
// kernels, and a different thread count may change rounding, so BLAS runs on one
// thread. Its pool is started by the library's constructor, before main(), and
// an idle worker spins in sched_yield() for about 2^28 cycles (0.1 s) before it
// sleeps: on a two-core machine a core taken from the first 0.1 s of every run
// (the mesh load, measured: 0.1 s of system time per `rosyhatch render`). So the
// pool is shut down when this file's statics are initialized, after OpenBLAS's
// constructor and before main(). Weak: absent with the reference BLAS. (Calling
// openblas_set_num_threads() again after the shutdown would restart the pool.)
extern "C" void openblas_set_num_threads(int) __attribute__((weak));
extern "C" int blas_thread_shutdown_() __attribute__((weak));

namespace rosy::field {
namespace {
bool releaseBlasThreads() {
    if (openblas_set_num_threads) openblas_set_num_threads(1);
    if (blas_thread_shutdown_) blas_thread_shutdown_();
    return true;
}
[[maybe_unused]] const bool kBlasThreadsReleased = releaseBlasThreads();
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
    Eigen::UmfPackLU<SparseMatrixC> lu;
    lu.compute(matrix);
    if (lu.info() != Eigen::Success)
        throw SolverFailure("UMFPACK LU factorization failed (singular system: a component without constraints?)");
    Eigen::VectorXcd x = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !x.allFinite()) throw SolverFailure("UMFPACK solve failed");
    return x;
}

} // namespace rosy::field
