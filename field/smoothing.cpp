#include "field/smoothing.h"

#include "core/error.h"

#include "field/multilevel.h"
#include "field/sparse_solver.h"

#include <cmath>

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
    for (int it = 0; it < iterations; ++it) {
        Eigen::VectorXcd next = (1.0 - strength) * u + strength * (T * u);
        if (!fixed.empty())
            for (int v = 0; v < u.size(); ++v)
                if (fixed[v]) next[v] = u[v];
        u.swap(next);
    }
    field.u = u;
}

SmoothestResult smoothestField(const TangentFrames &frames, int nSym) {
    const Mesh &mesh = frames.mesh();
    const int n = mesh.nVertices();
    SmoothestResult out;
    out.field.nSym = nSym;
    if (n == 0) return out;
    const SparseMatrixC A = connectionLaplacian(frames, nSym);
    const Eigen::VectorXd m = vertexAreas(mesh);
    // Shift by a tiny multiple of M so the factorization exists when A is singular
    // (e.g. a flat torus, whose smoothest field has eigenvalue exactly 0).
    const double scale = A.diagonal().real().sum() / m.sum();
    const double eps = 1e-8 * scale;
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
    out.eigenvalue = lambda;
    out.iterations = it + 1;
    normalizeMax(x);
    out.field.u = x;
    return out;
}

RosyField alignedField(const TangentFrames &frames, const RosyField &guide, double smoothingLength,
                       const std::vector<char> &fixed, const Eigen::VectorXcd &fixedValues) {
    const Mesh &mesh = frames.mesh();
    const int n = mesh.nVertices();
    ROSY_CHECK(smoothingLength > 0);
    RosyField out;
    out.nSym = guide.nSym;
    out.u = Eigen::VectorXcd::Zero(n);
    if (n == 0) return out;
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    const double len = smoothingLength * std::max((hi - lo).norm(), 1e-300);
    const double s = 1.0 / (len * len);
    const SparseMatrixC A = connectionLaplacian(frames, guide.nSym);
    const Eigen::VectorXd m = vertexAreas(mesh);

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
    std::vector<Eigen::Triplet<Complex>> trip;
    trip.reserve(A.nonZeros());
    for (int k = 0; k < A.outerSize(); ++k)
        for (SparseMatrixC::InnerIterator it(A, k); it; ++it) {
            const int i = int(it.row()), j = int(it.col());
            if (freeId[i] < 0) continue;
            if (freeId[j] >= 0) {
                trip.emplace_back(freeId[i], freeId[j], it.value());
            } else {
                rhs[freeId[i]] -= it.value() * out.u[j];
            }
        }
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) trip.emplace_back(freeId[v], freeId[v], Complex(s * m[v], 0));
    SparseMatrixC K(nFree, nFree);
    K.setFromTriplets(trip.begin(), trip.end());
    // The guide restricted to the free vertices is a good start for CG.
    Eigen::VectorXcd guess(nFree);
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) guess[freeId[v]] = guide.u[v];
    const Eigen::VectorXcd x = solveHermitianSystem(frames, guide.nSym, freeId, K, rhs, guess);
    for (int v = 0; v < n; ++v)
        if (freeId[v] >= 0) out.u[v] = x[freeId[v]];
    return out;
}

} // namespace rosy::field
