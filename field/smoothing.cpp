#include "field/smoothing.h"

#include "core/diagnostics.h"
#include "core/error.h"
#include "core/parallel.h"

#include "field/multilevel.h"
#include "field/sparse_solver.h"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rosy::field {
namespace {

// T(i, j) = ω_ij e^{iNΔθ_ij}: one relaxation step is u ← T u (Eq. 14).
SparseMatrixC transportedWeights(const TangentFrames &frames, int nSym, LaplaceWeights weights) {
    const Mesh &mesh = frames.mesh();
    const Eigen::SparseMatrix<double> W = relaxationWeights(mesh, weights);
    std::vector<Eigen::Triplet<Complex>> trip;
    trip.reserve(2 * mesh.nEdges());
    for (int e = 0; e < mesh.nEdges(); ++e) {
        const int h = mesh.edgeHalfedge(e);
        const int i = mesh.tail(h), j = mesh.head(h);
        const Complex r = std::polar(1.0, nSym * frames.transportAngle(h));
        trip.emplace_back(i, j, W.coeff(i, j) * r);
        trip.emplace_back(j, i, W.coeff(j, i) * std::conj(r));
    }
    SparseMatrixC T(mesh.nVertices(), mesh.nVertices());
    T.setFromTriplets(trip.begin(), trip.end());
    return T;
}

// A deterministic, well-spread start vector for the power iteration.
Eigen::VectorXcd startVector(int n) {
    Eigen::VectorXcd x(n);
    uint64_t s = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < n; ++i) {
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        double a = double(s >> 11) * (2.0 * M_PI / 9007199254740992.0);
        x[i] = std::polar(1.0, a);
    }
    return x;
}

void normalizeMax(Eigen::VectorXcd &u) {
    double m = 0;
    for (int i = 0; i < u.size(); ++i) m = std::max(m, std::abs(u[i]));
    if (m > 0) u /= m;
}

} // namespace

void relaxationSmooth(const TangentFrames &frames, RosyField &field, int iterations, double strength,
                      const std::vector<char> &fixed, LaplaceWeights weights) {
    if (iterations <= 0) return;
    ROSY_CHECK(strength > 0 && strength <= 1);
    const SparseMatrixC T = transportedWeights(frames, field.nSym, weights);
    Eigen::VectorXcd u = field.u;
    const bool anyFixed = std::any_of(fixed.begin(), fixed.end(), [](char c) { return c != 0; });
    const double startMax = u.size() ? u.cwiseAbs().maxCoeff() : 0.0;
    for (int it = 0; it < iterations; ++it) {
        Eigen::VectorXcd next = (1.0 - strength) * u + strength * (T * u);
        if (!fixed.empty())
            for (int v = 0; v < u.size(); ++v)
                if (fixed[v]) next[v] = u[v];
        u.swap(next);
        // Without fixed values nothing holds the level up: the transported average
        // loses magnitude wherever the members disagree (the holonomy of a curved
        // surface), so |u| decays geometrically and 10^5 steps reach exactly zero.
        // Renormalise by a power of two (exact: directions are unchanged to the bit)
        // whenever the largest magnitude has halved.
        if (!anyFixed && startMax > 0) {
            const double now = u.cwiseAbs().maxCoeff();
            if (now > 0 && now < 0.5 * startMax) {
                int e = 0;
                std::frexp(startMax / now, &e);
                u *= std::ldexp(1.0, e - 1);
            }
        }
    }
    if (startMax > 0 && !(u.cwiseAbs().maxCoeff() > 0))
        throw InputError(FileLoc{frames.mesh().name()},
                         "global smoothing reduced the field to zero everywhere (" + std::to_string(iterations) +
                             " iterations)",
                         "use fewer iterations or another field source");
    field.u = u;
}

namespace {

// Vertex components through the rings (ids in order of their smallest vertex).
std::vector<int> components(const Mesh &mesh, int &nComp) {
    std::vector<int> comp(mesh.nVertices(), -1), queue;
    nComp = 0;
    for (int root = 0; root < mesh.nVertices(); ++root) {
        if (comp[root] >= 0) continue;
        comp[root] = nComp;
        queue.assign(1, root);
        for (size_t q = 0; q < queue.size(); ++q) {
            const int v = queue[q];
            for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it)
                for (int w : {mesh.head(*it), mesh.tail(Mesh::prev(*it))})
                    if (comp[w] < 0) {
                        comp[w] = nComp;
                        queue.push_back(w);
                    }
        }
        ++nComp;
    }
    return comp;
}

// Inverse power iteration on one sparse factorization of A + εM (the fallback).
Eigen::VectorXcd inverseIteration(const SparseMatrixC &A, const Eigen::VectorXd &m, double eps, int &iterations) {
    const int n = int(A.rows());
    SparseMatrixC K = A;
    for (int i = 0; i < n; ++i) K.coeffRef(i, i) += eps * m[i];
    const HermitianSolver solver(K);
    Eigen::VectorXcd x = startVector(n);
    double lambda = 0, previous = -1;
    int it = 0;
    for (; it < 500; ++it) {
        Eigen::VectorXcd y = solver.solve(m.cast<Complex>().cwiseProduct(x));
        const double norm = std::sqrt(std::real(y.dot(m.cast<Complex>().cwiseProduct(y))));
        x = y / norm;
        lambda = std::real(x.dot(A * x));
        if (previous >= 0 && std::abs(lambda - previous) <= 1e-8 * std::max(lambda, eps)) break;
        previous = lambda;
    }
    iterations = it + 1;
    return x;
}

// Block LOBPCG (Knyazev 2001, Alg. 4.1) for the smallest eigenpairs of
// A u = λ M u, started from the columns of X0 (n x blockSize). Single-vector
// LOBPCG converges at a rate set by the gap λ2 − λ1; on noisy scans many small
// eigenvalues cluster (each noise-made singularity pair is a nearly free mode),
// and a block of k converges at the rate of the gap to λ_{k+1} instead. Every
// Rayleigh–Ritz basis [X W P] is M-orthonormalised explicitly (twice, dropping
// directions that vanish), as in the single-vector loop, since near convergence
// W and P become almost dependent on X. Returns true with x the first Ritz
// vector (M-normalised) once its residual ‖A x − λ M x‖_{M⁻¹} ≤ `tolerance`.
bool blockLobpcg(const SparseMatrixC &A, const Eigen::VectorXd &m, const TwoLevelPreconditioner &pre,
                 const Eigen::MatrixXcd &X0, double tolerance, int maxIterations, Eigen::VectorXcd &x,
                 int &iterations, double &residual) {
    const int n = int(A.rows());
    const Eigen::VectorXd invM = m.cwiseInverse();
    std::vector<Eigen::VectorXcd> basis, images; // M-orthonormal columns and A times them
    auto add = [&](Eigen::VectorXcd v, Eigen::VectorXcd Av, bool haveImage) {
        const double before = std::sqrt(std::real(blockDot(v, m, v)));
        for (int pass = 0; pass < 2; ++pass)
            for (size_t b = 0; b < basis.size(); ++b) {
                const Complex c = blockDot(basis[b], m, v);
                v -= c * basis[b];
                if (haveImage) Av -= c * images[b];
            }
        const double after = std::sqrt(std::real(blockDot(v, m, v)));
        if (!(after > 1e-10 * before) || !(after > 0)) return;
        v /= after;
        if (haveImage) Av /= after;
        else multiplyHermitian(A, v, Av);
        basis.push_back(std::move(v));
        images.push_back(std::move(Av));
    };
    for (int j = 0; j < X0.cols(); ++j) add(X0.col(j), Eigen::VectorXcd(), false);
    const int k = int(basis.size());
    if (k == 0) return false;
    std::vector<Eigen::VectorXcd> X, AX, P, AP;
    Eigen::VectorXcd r, w;
    for (int it = 0; it <= maxIterations; ++it) {
        // Rayleigh–Ritz on the orthonormal basis: the projected A, Hermitian.
        const int nb = int(basis.size());
        Eigen::MatrixXcd G(nb, nb);
        for (int a = 0; a < nb; ++a)
            for (int b = a; b < nb; ++b) {
                G(a, b) = blockDot(basis[a], images[b]);
                G(b, a) = std::conj(G(a, b));
            }
        for (int a = 0; a < nb; ++a) G(a, a) = G(a, a).real();
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> ritz(G);
        const Eigen::MatrixXcd &C = ritz.eigenvectors();
        X.assign(size_t(k), Eigen::VectorXcd::Zero(n));
        AX.assign(size_t(k), Eigen::VectorXcd::Zero(n));
        P.assign(size_t(k), Eigen::VectorXcd::Zero(n));
        AP.assign(size_t(k), Eigen::VectorXcd::Zero(n));
        for (int j = 0; j < k; ++j)
            for (int a = 0; a < nb; ++a) {
                X[size_t(j)] += C(a, j) * basis[size_t(a)];
                AX[size_t(j)] += C(a, j) * images[size_t(a)];
                if (a >= k) {
                    // The part of the update outside the old X: the next search direction.
                    P[size_t(j)] += C(a, j) * basis[size_t(a)];
                    AP[size_t(j)] += C(a, j) * images[size_t(a)];
                }
            }
        // Residuals; convergence is judged on the smallest pair only.
        basis.clear();
        images.clear();
        for (int j = 0; j < k; ++j) {
            basis.push_back(X[size_t(j)]);
            images.push_back(AX[size_t(j)]);
        }
        std::vector<Eigen::VectorXcd> W;
        for (int j = 0; j < k; ++j) {
            r = AX[size_t(j)] - ritz.eigenvalues()[j] * m.cast<Complex>().cwiseProduct(X[size_t(j)]);
            if (j == 0) {
                residual = std::sqrt(std::real(blockDot(r, invM, r)));
                iterations = it;
                if (!std::isfinite(residual)) return false;
                if (residual <= tolerance) {
                    x = X[0];
                    return true;
                }
            }
            pre.apply(r, w);
            W.push_back(w);
        }
        for (int j = 0; j < k; ++j) add(W[size_t(j)], Eigen::VectorXcd(), false);
        if (it > 0)
            for (int j = 0; j < k; ++j) add(P[size_t(j)], AP[size_t(j)], true);
    }
    return false;
}

/// LOBPCG's element-by-element vector updates run over chunks of at least this many
/// entries on both cores (core/parallel.h's parallelForRange): each chunk the same Eigen
/// expression on its segment, so every entry gets the same arithmetic and the same
/// bits for any thread count and any chunking.
constexpr int64_t kUpdateGrain = 4096;

// Smallest eigenvector of A u = λ M u (M = diag(m)), M-normalised, by LOBPCG
// (Knyazev 2001) with block size one and the two-level preconditioner of
// A + σM, σ the coarse (Galerkin) eigenvalue. Start: the coarse eigenvector by
// inverse iteration on the coarse factorization, prolonged. Stops when
// ‖A x − λ M x‖_{M⁻¹} ≤ 1e-3 · max(λ, 1e-8 scale), x M-normalised (the eigenvalue
// error is quadratic in the residual, ~1e-6 λ²/gap; the test checks it against a
// dense solve with the Kato–Temple bound). Falls back
// to inverse iteration on a sparse factorization if it stalls.
Eigen::VectorXcd lowestEigenvector(const TangentFrames &frames, int nSym, const std::vector<int> &freeId,
                                   const SparseMatrixC &A, const Eigen::VectorXd &m, const SmoothestOptions &options,
                                   EigenSolveReport &report) {
    const int n = int(A.rows());
    // A component whose faces all have zero area has no mass matrix: the
    // generalized eigenproblem is undefined (and the scale below divides by 0).
    if (!(m.sum() > 0) || !std::isfinite(m.sum()))
        throw InputError(FileLoc{"mesh"}, "a mesh component has zero total area, so it has no smoothest field",
                         "remove the degenerate faces (the mesh loaders do this with a warning) or the component");
    const double scale = A.diagonal().real().sum() / m.sum();
    const double eps = 1e-8 * scale;
    if (n <= 48) { // tiny component: dense solve
        const Eigen::MatrixXcd Ad = Eigen::MatrixXcd(A);
        const Eigen::MatrixXcd Md = m.cast<Complex>().asDiagonal();
        Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> es(Ad, Md);
        report = {"dense", 1, 0, {}};
        return es.eigenvectors().col(0);
    }
    auto shifted = [&](double sigma) {
        SparseMatrixC K = A;
        for (int i = 0; i < n; ++i) K.coeffRef(i, i) += sigma * m[i];
        return K;
    };
    auto mDot = [&](const Eigen::VectorXcd &a, const Eigen::VectorXcd &b) { return blockDot(a, m, b); };
    const Eigen::VectorXd invM = m.cwiseInverse();
    try {
        // Coarse eigenproblem Pᴴ A P y = λ Pᴴ M P y by inverse iteration.
        Eigen::VectorXcd x;
        double sigma = 0;
        {
            const TwoLevelPreconditioner coarse(frames, nSym, freeId, shifted(eps));
            const Eigen::VectorXd mc = coarse.coarseSum(m);
            const SparseMatrixC Ac = coarse.galerkin(A);
            Eigen::VectorXcd y = startVector(coarse.coarseSize());
            double lc = 0, previous = -1;
            for (int it = 0; it < 200; ++it) {
                y = coarse.coarseSolve(mc.cast<Complex>().cwiseProduct(y));
                y /= std::sqrt(std::real(y.dot(mc.cast<Complex>().cwiseProduct(y))));
                lc = std::real(y.dot(Ac * y));
                if (previous >= 0 && std::abs(lc - previous) <= 1e-6 * std::max(lc, eps)) break;
                previous = lc;
            }
            x = coarse.prolong(y);
            // Damped Jacobi steps remove the jumps between aggregates from the start.
            const int steps = 10;
            const Eigen::VectorXd invDiag = A.diagonal().real().cwiseInverse();
            Eigen::VectorXcd Ax0;
            for (int k = 0; k < steps; ++k) {
                multiplyHermitian(A, x, Ax0);
                x -= (2.0 / 3.0) * invDiag.cast<Complex>().cwiseProduct(Ax0);
            }
            multiplyHermitian(A, x, Ax0);
            const double rq = std::real(blockDot(x, Ax0)) / std::real(mDot(x, x));
            sigma = std::max(std::min(rq, lc), 1e-6 * scale);
        }
        const TwoLevelPreconditioner pre(frames, nSym, freeId, shifted(sigma));
        x /= std::sqrt(std::real(mDot(x, x)));
        Eigen::VectorXcd Ax, w, Aw, p, Ap, r;
        multiplyHermitian(A, x, Ax);
        double lambda = std::real(blockDot(x, Ax));
        bool haveP = false;
        double rNorm = 0;
        const int switchAt = options.lobpcgIterations;
        for (int it = 0; it <= switchAt; ++it) {
            if (it == switchAt) {
                if (options.blockSize <= 0 || it == 0) break;
                // Stalled: a block continues from x and the last search direction, the
                // other columns smooth deterministic vectors (preconditioned M-weighted
                // unit phasors), so the result is the same for any thread count.
                Eigen::MatrixXcd X0(n, options.blockSize);
                X0.col(0) = x;
                int filled = 1;
                if (haveP && filled < options.blockSize) X0.col(filled++) = p;
                for (int j = 0; filled < options.blockSize; ++j) {
                    const Eigen::VectorXcd seed =
                        m.cast<Complex>().cwiseProduct(startVector(n).array().pow(double(j + 2)).matrix());
                    pre.apply(seed, w);
                    X0.col(filled++) = w;
                }
                int blockIterations = 0;
                double blockResidual = 0;
                const double tolerance = 1e-3 * std::max(lambda, eps);
                if (blockLobpcg(A, m, pre, X0, tolerance, options.blockIterations, x, blockIterations,
                                blockResidual)) {
                    report.method = "block-lobpcg";
                    report.iterations = it + blockIterations;
                    return x;
                }
                report.lobpcgIterations = it + blockIterations;
                report.fallbackReason = fmt::format(
                    "LOBPCG did not converge in {} single-vector and {} block-of-{} iterations (residual {:.3g}, "
                    "target {:.3g})",
                    it, blockIterations, options.blockSize, blockResidual, tolerance);
                break;
            }
            r.resize(n);
            parallelForRange(0, n, [&](int64_t lo, int64_t hi) {
                const Eigen::Index len = Eigen::Index(hi - lo);
                r.segment(lo, len) =
                    Ax.segment(lo, len) - lambda * (m.segment(lo, len).cast<Complex>().cwiseProduct(x.segment(lo, len)));
            }, kUpdateGrain);
            rNorm = std::sqrt(std::real(blockDot(r, invM, r)));
            report.lobpcgIterations = it + 1;
            if (!std::isfinite(rNorm)) {
                report.fallbackReason = fmt::format("LOBPCG's residual became non-finite at iteration {}", it + 1);
                break;
            }
            if (rNorm <= 1e-3 * std::max(lambda, eps)) {
                report.method = "lobpcg";
                report.iterations = it + 1;
                return x;
            }
            pre.apply(r, w);
            // M-orthonormal basis [x, p, w] (p, w orthogonalised twice for stability).
            std::vector<Eigen::VectorXcd *> basis{&x}, images{&Ax};
            auto orthonormalize = [&](Eigen::VectorXcd &v, Eigen::VectorXcd *Av) {
                const double before = std::sqrt(std::real(mDot(v, v)));
                for (int pass = 0; pass < 2; ++pass)
                    for (size_t k = 0; k < basis.size(); ++k) {
                        const Complex c = mDot(*basis[k], v);
                        parallelForRange(0, n, [&](int64_t lo, int64_t hi) {
                            const Eigen::Index len = Eigen::Index(hi - lo);
                            v.segment(lo, len) -= c * basis[k]->segment(lo, len);
                            if (Av) Av->segment(lo, len) -= c * images[k]->segment(lo, len);
                        }, kUpdateGrain);
                    }
                const double after = std::sqrt(std::real(mDot(v, v)));
                if (!(after > 1e-10 * before) || !(after > 0)) return false;
                parallelForRange(0, n, [&](int64_t lo, int64_t hi) {
                    const Eigen::Index len = Eigen::Index(hi - lo);
                    v.segment(lo, len) /= after;
                    if (Av) Av->segment(lo, len) /= after;
                }, kUpdateGrain);
                return true;
            };
            if (haveP && orthonormalize(p, &Ap)) {
                basis.push_back(&p);
                images.push_back(&Ap);
            }
            if (orthonormalize(w, nullptr)) {
                multiplyHermitian(A, w, Aw);
                basis.push_back(&w);
                images.push_back(&Aw);
            }
            const int k = int(basis.size());
            Eigen::MatrixXcd G(k, k);
            for (int a = 0; a < k; ++a)
                for (int b = a; b < k; ++b) {
                    G(a, b) = blockDot(*basis[a], *images[b]);
                    G(b, a) = std::conj(G(a, b));
                }
            for (int a = 0; a < k; ++a) G(a, a) = G(a, a).real();
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> es(G);
            const Eigen::VectorXcd c = es.eigenvectors().col(0);
            // New search direction: the part of the update outside x.
            Eigen::VectorXcd pNew(n), ApNew(n);
            parallelForRange(0, n, [&](int64_t lo, int64_t hi) {
                const Eigen::Index len = Eigen::Index(hi - lo);
                pNew.segment(lo, len).setZero();
                ApNew.segment(lo, len).setZero();
                for (int a = 1; a < k; ++a) {
                    pNew.segment(lo, len) += c[a] * basis[size_t(a)]->segment(lo, len);
                    ApNew.segment(lo, len) += c[a] * images[size_t(a)]->segment(lo, len);
                }
                x.segment(lo, len) = c[0] * x.segment(lo, len) + pNew.segment(lo, len);
                Ax.segment(lo, len) = c[0] * Ax.segment(lo, len) + ApNew.segment(lo, len);
            }, kUpdateGrain);
            p.swap(pNew);
            Ap.swap(ApNew);
            haveP = k > 1;
            const double xNorm = std::sqrt(std::real(mDot(x, x)));
            parallelForRange(0, n, [&](int64_t lo, int64_t hi) {
                const Eigen::Index len = Eigen::Index(hi - lo);
                x.segment(lo, len) /= xNorm;
                Ax.segment(lo, len) /= xNorm;
            }, kUpdateGrain);
            lambda = std::real(blockDot(x, Ax));
        }
        if (report.fallbackReason.empty())
            report.fallbackReason =
                fmt::format("LOBPCG did not converge in {} iterations (residual {:.3g}, target {:.3g})",
                            switchAt, rNorm, 1e-3 * std::max(lambda, eps));
    } catch (const SolverFailure &failure) {
        report.fallbackReason = std::string("LOBPCG's preconditioner failed: ") + failure.what();
    }
    report.method = "inverse-iteration";
    Eigen::VectorXcd x = inverseIteration(A, m, eps, report.iterations);
    return x;
}

} // namespace

SmoothestResult smoothestField(const TangentFrames &frames, int nSym, const SmoothestOptions &options) {
    const Mesh &mesh = frames.mesh();
    const int n = mesh.nVertices();
    SmoothestResult out;
    out.field.nSym = nSym;
    if (n == 0) return out;
    const SparseMatrixC A = connectionLaplacian(frames, nSym);
    const Eigen::VectorXd m = vertexAreas(mesh);
    // Components do not interact: each gets its own smallest eigenvector
    // (M-normalised), so none is left near zero.
    int nComp = 0;
    const std::vector<int> comp = components(mesh, nComp);
    // vertexAreas() floors zero areas (so M stays invertible elsewhere), which hides
    // a component without any area: measure the faces themselves, against the
    // component's own size so the test is scale-invariant.
    std::vector<double> faceArea(nComp, 0.0);
    std::vector<Vec3> lo(nComp, Vec3::Constant(std::numeric_limits<double>::infinity()));
    std::vector<Vec3> hi(nComp, Vec3::Constant(-std::numeric_limits<double>::infinity()));
    for (int f = 0; f < mesh.nFaces(); ++f) faceArea[comp[mesh.face(f)[0]]] += mesh.faceArea(f);
    for (int v = 0; v < n; ++v) {
        lo[comp[v]] = lo[comp[v]].cwiseMin(mesh.position(v));
        hi[comp[v]] = hi[comp[v]].cwiseMax(mesh.position(v));
    }
    for (int c = 0; c < nComp; ++c)
        if (!(faceArea[c] > 1e-12 * (hi[c] - lo[c]).squaredNorm()))
            throw InputError(FileLoc{mesh.name()},
                             "a mesh component has (almost) zero total area, so it has no smoothest field",
                             "remove the degenerate faces (the mesh loaders do this with a warning) or the component");
    Eigen::VectorXcd x(n);
    for (int c = 0; c < nComp; ++c) {
        std::vector<int> freeId(n, -1);
        int nFree = 0;
        for (int v = 0; v < n; ++v)
            if (comp[v] == c) freeId[v] = nFree++;
        Eigen::VectorXcd unused;
        const SparseMatrixC Ac = nComp == 1 ? A : freeBlock(A, freeId, nFree, {}, unused);
        Eigen::VectorXd mc(nFree);
        for (int v = 0; v < n; ++v)
            if (freeId[v] >= 0) mc[freeId[v]] = m[v];
        EigenSolveReport component;
        const Eigen::VectorXcd xc = lowestEigenvector(frames, nSym, freeId, Ac, mc, options, component);
        // The report keeps the slowest component's method and every fallback reason.
        if (out.solver.method.empty() || component.method == "inverse-iteration" ||
            (component.method == "lobpcg" && out.solver.method == "dense"))
            out.solver.method = component.method;
        out.solver.iterations = std::max(out.solver.iterations, component.iterations);
        out.solver.lobpcgIterations = std::max(out.solver.lobpcgIterations, component.lobpcgIterations);
        if (!component.fallbackReason.empty())
            out.solver.fallbackReason +=
                (out.solver.fallbackReason.empty() ? "" : "; ") +
                (nComp > 1 ? fmt::format("component {}: ", c) : std::string()) + component.fallbackReason;
        for (int v = 0; v < n; ++v)
            if (freeId[v] >= 0) x[v] = xc[freeId[v]];
    }
    out.iterations = out.solver.iterations;
    if (!out.solver.fallbackReason.empty())
        warn(mesh.name(), "smoothest-fallback",
             out.solver.fallbackReason + "; used inverse iteration on a sparse factorization instead (" +
                 std::to_string(out.solver.iterations) + " iterations, slower)");
    out.eigenvalue = std::real(x.dot(A * x)) / std::real(x.dot(m.cast<Complex>().cwiseProduct(x)));
    normalizeMax(x);
    out.field.u = x;
    return out;
}

RosyField alignedField(const TangentFrames &frames, const RosyField &guide, double smoothingLength,
                       const std::vector<char> &fixed, const Eigen::VectorXcd &fixedValues,
                       std::optional<double> tolerance) {
    return alignedField(frames, connectionLaplacian(frames, guide.nSym), vertexAreas(frames.mesh()), guide,
                        smoothingLength, fixed, fixedValues, tolerance);
}

namespace {

/// s = 1 / (ℓ d)² of alignedField(), ℓ checked first.
double alignmentWeight(const Mesh &mesh, double smoothingLength) {
    // s = 1 / (ℓ d)² overflows to infinity for tiny ℓ (1e-200), which the solver
    // would then report as degenerate geometry: name the setting instead.
    if (!(smoothingLength >= kMinSmoothingLength && smoothingLength <= kMaxSmoothingLength))
        throw InputError(FileLoc{mesh.name()},
                         "the smoothing length " + (std::ostringstream() << smoothingLength).str() +
                             " is outside [" + (std::ostringstream() << kMinSmoothingLength).str() + ", " +
                             (std::ostringstream() << kMaxSmoothingLength).str() + "]",
                         "use 0 for the raw curvature directions or a fraction of the bounding-box diagonal "
                         "such as 0.08");
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    const double len = smoothingLength * std::max((hi - lo).norm(), 1e-300);
    return 1.0 / (len * len);
}

} // namespace

struct AlignedSystem::Impl {
    int nSym = 0;
    Eigen::VectorXd weight; ///< s m_v per vertex: K's added diagonal, the right-hand side's factor
    SparseMatrixC K;
    /// Absent when its set-up failed (SolverFailure): solveHermitianSystem() then factors K.
    std::optional<TwoLevelPreconditioner> pre;
};

AlignedSystem::AlignedSystem(const TangentFrames &frames, const SparseMatrixC &laplacian,
                             const Eigen::VectorXd &areas, int nSym, double smoothingLength)
    : m_impl(std::make_unique<Impl>()) {
    Impl &im = *m_impl;
    const Mesh &mesh = frames.mesh();
    const int n = mesh.nVertices();
    im.nSym = nSym;
    const double s = alignmentWeight(mesh, smoothingLength);
    im.weight = s * areas.head(n);
    if (n == 0) return;
    // K = (A + sM), every vertex free.
    im.K = laplacian;
    for (int v = 0; v < n; ++v) im.K.coeffRef(v, v) += im.weight[v];
    std::vector<int> freeId(static_cast<size_t>(n));
    for (int v = 0; v < n; ++v) freeId[size_t(v)] = v;
    try {
        im.pre.emplace(frames, nSym, freeId, im.K);
    } catch (const SolverFailure &) {
    }
}

AlignedSystem::~AlignedSystem() = default;
AlignedSystem::AlignedSystem(AlignedSystem &&) noexcept = default;
AlignedSystem &AlignedSystem::operator=(AlignedSystem &&) noexcept = default;

RosyField AlignedSystem::solve(const RosyField &guide, double tolerance) const {
    const Impl &im = *m_impl;
    const int n = int(im.weight.size());
    ROSY_CHECK_EQ(guide.nSym, im.nSym);
    ROSY_CHECK_EQ(int(guide.u.size()), n);
    RosyField out;
    out.nSym = guide.nSym;
    out.u = Eigen::VectorXcd::Zero(n);
    if (n == 0) return out;
    Eigen::VectorXcd rhs(n);
    for (int v = 0; v < n; ++v) rhs[v] = im.weight[v] * guide.u[v];
    // The guide is a good start for CG.
    out.u = solveHermitianSystem(im.K, im.pre ? &*im.pre : nullptr, rhs, guide.u, tolerance);
    return out;
}

RosyField alignedField(const TangentFrames &frames, const SparseMatrixC &laplacian, const Eigen::VectorXd &areas,
                       const RosyField &guide, double smoothingLength, const std::vector<char> &fixed,
                       const Eigen::VectorXcd &fixedValues, std::optional<double> tolerance) {
    const Mesh &mesh = frames.mesh();
    const int n = mesh.nVertices();
    if (std::none_of(fixed.begin(), fixed.end(), [](char c) { return c != 0; }))
        return AlignedSystem(frames, laplacian, areas, guide.nSym, smoothingLength)
            .solve(guide, tolerance.value_or(kFieldTolerance));
    const double s = alignmentWeight(mesh, smoothingLength);
    RosyField out;
    out.nSym = guide.nSym;
    out.u = Eigen::VectorXcd::Zero(n);
    if (n == 0) return out;
    const Eigen::VectorXd &m = areas;

    std::vector<int> freeId(n, -1);
    int nFree = 0;
    for (int v = 0; v < n; ++v)
        if (fixed.empty() || !fixed[v]) freeId[v] = nFree++;
    for (int v = 0; v < n; ++v)
        if (freeId[v] < 0) out.u[v] = fixedValues[v];
    if (nFree == 0) return out;

    Eigen::VectorXcd rhs(nFree);
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) rhs[freeId[v]] = s * m[v] * guide.u[v];
    // K = (A + sM) on the free vertices, built in place (no triplets).
    SparseMatrixC K = nFree < n ? freeBlock(laplacian, freeId, nFree, out.u, rhs) : laplacian;
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) K.coeffRef(freeId[v], freeId[v]) += s * m[v];
    // The guide restricted to the free vertices is a good start for CG.
    Eigen::VectorXcd guess(nFree);
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) guess[freeId[v]] = guide.u[v];
    const Eigen::VectorXcd x = solveHermitianSystem(
        frames, guide.nSym, freeId, K, rhs, guess,
        tolerance.value_or(nFree < n ? kRelaxationTolerance : kFieldTolerance));
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) out.u[v] = x[freeId[v]];
    return out;
}

} // namespace rosy::field
