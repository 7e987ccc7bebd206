#include "field/multilevel.h"

#include "core/parallel.h"

#include <fmt/format.h>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace rosy::field {
namespace {

constexpr int64_t kBlock = 8192;
constexpr int kDirectBelow = 4096; // unknowns: general systems this small go to LU // fixed summation blocks: the same sums for any thread count

// Aggregates of about two rings, grown by BFS from roots taken in vertex order.
// Returns the aggregate of every free row and the transport angle from the
// aggregate's root frame to the row's vertex frame.
int buildAggregates(const TangentFrames &frames, const std::vector<int> &freeId, int nFree,
                    std::vector<int> &aggregate, std::vector<double> &angle) {
    const Mesh &mesh = frames.mesh();
    aggregate.assign(nFree, -1);
    angle.assign(nFree, 0.0);
    std::vector<int> depth(mesh.nVertices(), -1), queue;
    int nAgg = 0;
    constexpr int kRadius = 2;
    for (int root = 0; root < mesh.nVertices(); ++root) {
        if (freeId[root] < 0 || aggregate[freeId[root]] >= 0) continue;
        const int id = nAgg++;
        queue.assign(1, root);
        aggregate[freeId[root]] = id;
        depth[root] = 0;
        for (size_t q = 0; q < queue.size(); ++q) {
            const int v = queue[q];
            if (depth[v] >= kRadius) continue;
            for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it) {
                // The head of each outgoing halfedge and the tail of the previous
                // halfedge (which covers the last neighbour of a boundary vertex).
                for (int h : {*it, Mesh::prev(*it)}) {
                    const bool outgoing = h == *it;
                    const int w = outgoing ? mesh.head(h) : mesh.tail(h);
                    if (freeId[w] < 0 || aggregate[freeId[w]] >= 0) continue;
                    aggregate[freeId[w]] = id;
                    depth[w] = depth[v] + 1;
                    // transportAngle(g) moves head(g)'s frame to tail(g)'s; we need v -> w.
                    const double t = outgoing ? -frames.transportAngle(h) : frames.transportAngle(h);
                    angle[freeId[w]] = angle[freeId[v]] + t;
                    queue.push_back(w);
                }
            }
        }
    }
    return nAgg;
}

// Pᴴ K P for P with one entry per row, P(i, aggregate[i]) = phase[i], in K's own
// storage order: Gustavson's row-by-row product over each aggregate's members.
template <int Options>
Eigen::SparseMatrix<Complex, Options> galerkinProduct(const Eigen::SparseMatrix<Complex, Options> &K,
                                                      const std::vector<int> &aggregate,
                                                      const Eigen::VectorXcd &phase, int nAgg,
                                                      const std::vector<int> &memberStart,
                                                      const std::vector<int> &members) {
    using Matrix = Eigen::SparseMatrix<Complex, Options>;
    std::vector<int> outer(nAgg + 1, 0), inner, slot(nAgg, -1), touched;
    std::vector<Complex> value;
    inner.reserve(size_t(K.nonZeros()) / 2);
    value.reserve(size_t(K.nonZeros()) / 2);
    for (int c = 0; c < nAgg; ++c) {
        touched.clear();
        for (int m = memberStart[c]; m < memberStart[c + 1]; ++m)
            for (typename Matrix::InnerIterator it(K, members[m]); it; ++it) {
                const int a = aggregate[it.index()];
                const Complex x = std::conj(phase[it.row()]) * it.value() * phase[it.col()];
                if (slot[a] < 0) {
                    slot[a] = int(value.size());
                    touched.push_back(a);
                    inner.push_back(a);
                    value.push_back(x);
                } else {
                    value[slot[a]] += x;
                }
            }
        // Sort this outer slice by inner index (Eigen's compressed format).
        const int begin = outer[c];
        std::vector<std::pair<int, Complex>> tmp;
        tmp.reserve(touched.size());
        for (int a : touched) tmp.push_back({a, value[slot[a]]});
        std::sort(tmp.begin(), tmp.end(), [](const auto &p, const auto &q) { return p.first < q.first; });
        for (size_t t = 0; t < tmp.size(); ++t) {
            inner[begin + t] = tmp[t].first;
            value[begin + t] = tmp[t].second;
            slot[tmp[t].first] = -1;
        }
        outer[c + 1] = begin + int(tmp.size());
    }
    Matrix Kc(nAgg, nAgg);
    Kc.resizeNonZeros(Eigen::Index(outer[nAgg]));
    std::copy(outer.begin(), outer.end(), Kc.outerIndexPtr());
    std::copy(inner.begin(), inner.begin() + outer[nAgg], Kc.innerIndexPtr());
    std::copy(value.begin(), value.begin() + outer[nAgg], Kc.valuePtr());
    return Kc;
}

} // namespace

namespace {
template <typename Term>
Complex blockSum(int64_t n, Term term) {
    const int64_t nBlocks = (n + kBlock - 1) / kBlock;
    std::vector<Complex> part(size_t(std::max<int64_t>(nBlocks, 1)), Complex(0, 0));
    parallelFor(0, nBlocks, [&](int64_t k) {
        Complex s(0, 0);
        const int64_t end = std::min(n, (k + 1) * kBlock);
        for (int64_t i = k * kBlock; i < end; ++i) s += term(i);
        part[size_t(k)] = s;
    }, 1);
    Complex s(0, 0);
    for (const Complex &p : part) s += p;
    return s;
}
} // namespace

Complex blockDot(const Eigen::VectorXcd &a, const Eigen::VectorXcd &b) {
    return blockSum(a.size(), [&](int64_t i) { return std::conj(a[i]) * b[i]; });
}

Complex blockDot(const Eigen::VectorXcd &a, const Eigen::VectorXd &w, const Eigen::VectorXcd &b) {
    return blockSum(a.size(), [&](int64_t i) { return std::conj(a[i]) * (w[i] * b[i]); });
}

// Row i of a Hermitian K is the conjugate of column i, so each work item reads
// one column and writes one entry (no transposed copy needed).
void multiplyHermitian(const SparseMatrixC &K, const Eigen::VectorXcd &x, Eigen::VectorXcd &y) {
    y.resize(K.rows());
    const int *outer = K.outerIndexPtr(), *inner = K.innerIndexPtr();
    const Complex *value = K.valuePtr();
    parallelFor(0, K.cols(), [&](int64_t i) {
        Complex s(0, 0);
        for (int k = outer[i]; k < outer[i + 1]; ++k) s += std::conj(value[k]) * x[inner[k]];
        y[i] = s;
    }, 4096);
}

namespace {
void multiplyRows(const SparseMatrixRowC &K, const Eigen::VectorXcd &x, Eigen::VectorXcd &y) {
    y.resize(K.rows());
    const int *outer = K.outerIndexPtr(), *inner = K.innerIndexPtr();
    const Complex *value = K.valuePtr();
    parallelFor(0, K.rows(), [&](int64_t i) {
        Complex s(0, 0);
        for (int k = outer[i]; k < outer[i + 1]; ++k) s += value[k] * x[inner[k]];
        y[i] = s;
    }, 4096);
}
} // namespace

struct TwoLevelPreconditioner::Impl {
    int n = 0, nAgg = 0;
    std::vector<int> aggregate, memberStart, members;
    Eigen::VectorXcd phase; // P(i, aggregate[i]) = phase[i]
    Eigen::VectorXd invDiag;
    Eigen::SimplicialLDLT<SparseMatrixC, Eigen::Lower> ldlt;
    Eigen::SparseLU<SparseMatrixC> lu;
    bool hermitian = true;

    void setup(const TangentFrames &frames, int nSym, const std::vector<int> &freeId, int rows) {
        n = rows;
        std::vector<double> angle;
        nAgg = buildAggregates(frames, freeId, n, aggregate, angle);
        phase.resize(n);
        for (int i = 0; i < n; ++i) phase[i] = std::polar(1.0, nSym * angle[i]);
        memberStart.assign(nAgg + 1, 0);
        for (int i = 0; i < n; ++i) ++memberStart[aggregate[i] + 1];
        for (int a = 0; a < nAgg; ++a) memberStart[a + 1] += memberStart[a];
        members.resize(n);
        std::vector<int> fill(memberStart.begin(), memberStart.end() - 1);
        for (int i = 0; i < n; ++i) members[fill[aggregate[i]]++] = i;
    }
};

TwoLevelPreconditioner::TwoLevelPreconditioner(const TangentFrames &frames, int nSym,
                                               const std::vector<int> &freeId, const SparseMatrixC &K)
    : m_impl(std::make_unique<Impl>()) {
    Impl &d = *m_impl;
    d.setup(frames, nSym, freeId, int(K.rows()));
    d.invDiag.resize(d.n);
    for (int i = 0; i < d.n; ++i) d.invDiag[i] = 1.0 / K.coeff(i, i).real();
    d.ldlt.compute(galerkinProduct(K, d.aggregate, d.phase, d.nAgg, d.memberStart, d.members));
    if (d.ldlt.info() != Eigen::Success) throw SolverFailure("two-level: coarse factorization failed");
}

TwoLevelPreconditioner::TwoLevelPreconditioner(const TangentFrames &frames, int nSym,
                                               const std::vector<int> &freeId, const SparseMatrixRowC &K)
    : m_impl(std::make_unique<Impl>()) {
    Impl &d = *m_impl;
    d.hermitian = false;
    d.setup(frames, nSym, freeId, int(K.rows()));
    d.invDiag.resize(d.n);
    for (int i = 0; i < d.n; ++i) {
        const double diag = K.coeff(i, i).real();
        d.invDiag[i] = diag != 0 ? 1.0 / diag : 0.0;
    }
    const SparseMatrixC Kc = galerkinProduct(K, d.aggregate, d.phase, d.nAgg, d.memberStart, d.members);
    d.lu.analyzePattern(Kc);
    d.lu.factorize(Kc);
    if (d.lu.info() != Eigen::Success) throw SolverFailure("two-level: coarse LU failed");
}

TwoLevelPreconditioner::~TwoLevelPreconditioner() = default;

int TwoLevelPreconditioner::coarseSize() const { return m_impl->nAgg; }

Eigen::VectorXcd TwoLevelPreconditioner::restrictTo(const Eigen::VectorXcd &r) const {
    const Impl &d = *m_impl;
    Eigen::VectorXcd rc(d.nAgg);
    parallelFor(0, d.nAgg, [&](int64_t a) {
        Complex s(0, 0);
        for (int m = d.memberStart[a]; m < d.memberStart[a + 1]; ++m)
            s += std::conj(d.phase[d.members[m]]) * r[d.members[m]];
        rc[a] = s;
    }, 2048);
    return rc;
}

Eigen::VectorXcd TwoLevelPreconditioner::prolong(const Eigen::VectorXcd &xc) const {
    const Impl &d = *m_impl;
    Eigen::VectorXcd x(d.n);
    for (int i = 0; i < d.n; ++i) x[i] = d.phase[i] * xc[d.aggregate[i]];
    return x;
}

Eigen::VectorXcd TwoLevelPreconditioner::coarseSolve(const Eigen::VectorXcd &rc) const {
    const Impl &d = *m_impl;
    return d.hermitian ? Eigen::VectorXcd(d.ldlt.solve(rc)) : Eigen::VectorXcd(d.lu.solve(rc));
}

Eigen::VectorXd TwoLevelPreconditioner::coarseSum(const Eigen::VectorXd &w) const {
    const Impl &d = *m_impl;
    Eigen::VectorXd s = Eigen::VectorXd::Zero(d.nAgg);
    for (int i = 0; i < d.n; ++i) s[d.aggregate[i]] += w[i];
    return s;
}

SparseMatrixC TwoLevelPreconditioner::galerkin(const SparseMatrixC &B) const {
    const Impl &d = *m_impl;
    return galerkinProduct(B, d.aggregate, d.phase, d.nAgg, d.memberStart, d.members);
}

void TwoLevelPreconditioner::apply(const Eigen::VectorXcd &r, Eigen::VectorXcd &z) const {
    const Impl &d = *m_impl;
    z.resize(d.n);
    const Eigen::VectorXcd rc = restrictTo(r);
    const Eigen::VectorXcd ec = coarseSolve(rc);
    parallelFor(0, d.n, [&](int64_t i) { z[i] = d.invDiag[i] * r[i] + d.phase[i] * ec[d.aggregate[i]]; }, 8192);
}

namespace {
// Rows per block of the fused PCG loops below. Each block's partial dot
// product is summed in block order, so the result does not depend on the
// thread count; 2048 rows give 2 threads enough blocks to balance on bunny00.
constexpr int64_t kFusedBlock = 2048;

// Calls body(begin, end) for every fixed block of rows in parallel and returns
// the sum of the blocks' results in block order.
template <typename Body>
Complex fusedBlocks(int64_t n, Body body) {
    const int64_t nBlocks = (n + kFusedBlock - 1) / kFusedBlock;
    std::vector<Complex> part(size_t(std::max<int64_t>(nBlocks, 1)), Complex(0, 0));
    parallelFor(0, nBlocks, [&](int64_t k) {
        part[size_t(k)] = body(k * kFusedBlock, std::min(n, (k + 1) * kFusedBlock));
    }, 1);
    Complex s(0, 0);
    for (const Complex &p : part) s += p;
    return s;
}
} // namespace

void TwoLevelPreconditioner::applyWithDot(const Eigen::VectorXcd &r, Eigen::VectorXcd &z, Complex &rz) const {
    const Impl &d = *m_impl;
    z.resize(d.n);
    const Eigen::VectorXcd ec = coarseSolve(restrictTo(r));
    rz = fusedBlocks(d.n, [&](int64_t begin, int64_t end) {
        Complex s(0, 0);
        for (int64_t i = begin; i < end; ++i) {
            z[i] = d.invDiag[i] * r[i] + d.phase[i] * ec[d.aggregate[i]];
            s += std::conj(r[i]) * z[i];
        }
        return s;
    });
}

// Each iteration makes five passes over the vectors (the textbook loop makes
// eight): Ap = K p fused with ⟨p, Ap⟩; the x and r updates fused with ‖r‖²;
// Pᴴ r; z = M⁻¹ r fused with ⟨r, z⟩; and p = z + β p.
Eigen::VectorXcd solvePcg(const SparseMatrixC &K, const TwoLevelPreconditioner &pre, const Eigen::VectorXcd &b,
                          const Eigen::VectorXcd &guess, double tolerance, int maxIterations, PcgReport *report) {
    const int n = int(b.size());
    Eigen::VectorXcd x = guess.size() == n ? guess : Eigen::VectorXcd::Zero(n);
    Eigen::VectorXcd r(n), z(n), p(n), Ap(n);
    multiplyHermitian(K, x, Ap);
    r = b - Ap;
    const double bNorm = std::sqrt(std::real(blockDot(b, b)));
    const double target = tolerance * (bNorm > 0 ? bNorm : 1.0);
    double rNorm = std::sqrt(std::real(blockDot(r, r)));
    const int *outer = K.outerIndexPtr(), *inner = K.innerIndexPtr();
    const Complex *value = K.valuePtr();
    int it = 0;
    if (rNorm > target) {
        Complex rz;
        pre.applyWithDot(r, z, rz);
        p = z;
        for (; it < maxIterations; ++it) {
            // Row i of the Hermitian K is the conjugate of its column i.
            const Complex pAp = fusedBlocks(n, [&](int64_t begin, int64_t end) {
                Complex s(0, 0);
                for (int64_t i = begin; i < end; ++i) {
                    Complex y(0, 0);
                    for (int k = outer[i]; k < outer[i + 1]; ++k) y += std::conj(value[k]) * p[inner[k]];
                    Ap[i] = y;
                    s += std::conj(p[i]) * y;
                }
                return s;
            });
            const Complex alpha = rz / pAp;
            const double rr = std::real(fusedBlocks(n, [&](int64_t begin, int64_t end) {
                double s = 0;
                for (int64_t i = begin; i < end; ++i) {
                    x[i] += alpha * p[i];
                    r[i] -= alpha * Ap[i];
                    s += std::norm(r[i]);
                }
                return Complex(s, 0);
            }));
            rNorm = std::sqrt(rr);
            if (rNorm <= target) {
                ++it;
                break;
            }
            Complex rzNew;
            pre.applyWithDot(r, z, rzNew);
            const Complex beta = rzNew / rz;
            parallelFor(0, n, [&](int64_t i) { p[i] = z[i] + beta * p[i]; }, 8192);
            rz = rzNew;
        }
    }
    if (report) *report = {it, bNorm > 0 ? rNorm / bNorm : rNorm, pre.coarseSize()};
    if (!(rNorm <= target) || !x.allFinite())
        throw SolverFailure("two-level PCG did not converge in " + std::to_string(maxIterations) +
                            " iterations (relative residual " + fmt::format("{:.3g}", rNorm / bNorm) + ")");
    return x;
}

Eigen::VectorXcd solveTwoLevelPcg(const TangentFrames &frames, int nSym, const std::vector<int> &freeId,
                                  const SparseMatrixC &K, const Eigen::VectorXcd &b,
                                  const Eigen::VectorXcd &guess, double tolerance, int maxIterations,
                                  PcgReport *report) {
    const TwoLevelPreconditioner pre(frames, nSym, freeId, K);
    return solvePcg(K, pre, b, guess, tolerance, maxIterations, report);
}

Eigen::VectorXcd solveTwoLevelBicgstab(const TangentFrames &frames, int nSym, const std::vector<int> &freeId,
                                       const SparseMatrixRowC &K, const Eigen::VectorXcd &b,
                                       const Eigen::VectorXcd &guess, double tolerance, int maxIterations,
                                       PcgReport *report) {
    const int n = int(b.size());
    const TwoLevelPreconditioner pre(frames, nSym, freeId, K);
    Eigen::VectorXcd x = guess.size() == n ? guess : Eigen::VectorXcd::Zero(n);
    Eigen::VectorXcd r(n), rHat(n), p = Eigen::VectorXcd::Zero(n), v = Eigen::VectorXcd::Zero(n), y(n), z(n),
        sv(n), t(n);
    multiplyRows(K, x, t);
    r = b - t;
    rHat = r;
    const double bNorm = std::sqrt(std::real(blockDot(b, b)));
    const double target = tolerance * (bNorm > 0 ? bNorm : 1.0);
    double rNorm = std::sqrt(std::real(blockDot(r, r)));
    Complex rho(1, 0), alpha(1, 0), omega(1, 0);
    int it = 0;
    for (; it < maxIterations && rNorm > target; ++it) {
        const Complex rhoNew = blockDot(rHat, r);
        if (std::abs(rhoNew) == 0 || std::abs(omega) == 0) break; // breakdown: let the caller fall back
        const Complex beta = (rhoNew / rho) * (alpha / omega);
        rho = rhoNew;
        parallelFor(0, n, [&](int64_t i) { p[i] = r[i] + beta * (p[i] - omega * v[i]); }, 8192);
        pre.apply(p, y);
        multiplyRows(K, y, v);
        alpha = rho / blockDot(rHat, v);
        parallelFor(0, n, [&](int64_t i) { sv[i] = r[i] - alpha * v[i]; }, 8192);
        pre.apply(sv, z);
        multiplyRows(K, z, t);
        const double tt = std::real(blockDot(t, t));
        omega = tt > 0 ? blockDot(t, sv) / tt : Complex(0, 0);
        parallelFor(0, n, [&](int64_t i) {
            x[i] += alpha * y[i] + omega * z[i];
            r[i] = sv[i] - omega * t[i];
        }, 8192);
        rNorm = std::sqrt(std::real(blockDot(r, r)));
    }
    if (report) *report = {it, bNorm > 0 ? rNorm / bNorm : rNorm, pre.coarseSize()};
    if (!(rNorm <= target) || !x.allFinite())
        throw SolverFailure("two-level BiCGSTAB did not converge in " + std::to_string(maxIterations) +
                            " iterations (relative residual " + fmt::format("{:.3g}", rNorm / bNorm) + ")");
    return x;
}

Eigen::VectorXcd solveHermitianSystem(const TangentFrames &frames, int nSym, const std::vector<int> &freeId,
                                      const SparseMatrixC &K, const Eigen::VectorXcd &b,
                                      const Eigen::VectorXcd &guess, double tolerance) {
    std::optional<TwoLevelPreconditioner> pre;
    try {
        pre.emplace(frames, nSym, freeId, K);
    } catch (const SolverFailure &) {
    }
    return solveHermitianSystem(K, pre ? &*pre : nullptr, b, guess, tolerance);
}

Eigen::VectorXcd solveHermitianSystem(const SparseMatrixC &K, const TwoLevelPreconditioner *pre,
                                      const Eigen::VectorXcd &b, const Eigen::VectorXcd &guess, double tolerance) {
    if (pre) {
        try {
            return solvePcg(K, *pre, b, guess, tolerance, 1000);
        } catch (const SolverFailure &) {
        }
    }
    // A factorization always works for positive definite K; it is only slower.
    return HermitianSolver(K).solve(b);
}

Eigen::VectorXcd solveGeneralSystem(const TangentFrames &frames, int nSym, const std::vector<int> &freeId,
                                    const SparseMatrixRowC &K, const Eigen::VectorXcd &b,
                                    const Eigen::VectorXcd &guess, double tolerance) {
    // Small systems (editing regions, small meshes) are solved exactly by LU,
    // which is faster there than setting up the two-level solver.
    if (K.rows() < kDirectBelow) return solveGeneral(SparseMatrixC(K), b);
    try {
        return solveTwoLevelBicgstab(frames, nSym, freeId, K, b, guess, tolerance, 1000);
    } catch (const SolverFailure &) {
        return solveGeneral(SparseMatrixC(K), b);
    }
}

} // namespace rosy::field
