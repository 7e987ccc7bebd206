/// \file scan_noise.cpp
/// Fields on noisy scans (scan_noise.h).

#include "field/scan_noise.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace rosy::field {

double singularityDensity(const Mesh &mesh, size_t nSingularities) {
    double area = 0;
    for (int f = 0; f < mesh.nFaces(); ++f) area += mesh.faceArea(f);
    if (!(area > 0)) return 0.0;
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    const double disc = kScanNoiseScale * (hi - lo).norm();
    return double(nSingularities) * disc * disc / area;
}

bool fieldIsScanNoise(const Mesh &mesh, size_t nSingularities) {
    // Cheap first: far too few singularities for any mesh to pass the density.
    if (nSingularities < 64) return false;
    return singularityDensity(mesh, nSingularities) > kScanNoiseDensity;
}

namespace {

/// A = I + t L on the interior vertices, L the uniform graph Laplacian (deg(v) x_v −
/// Σ neighbours), boundary vertices held (their terms moved to the right-hand side):
/// symmetric positive definite. Vectors are per vertex (Vec3: the three coordinates
/// solved at once), zero at boundary vertices.
struct Implicit {
    const Mesh &mesh;
    double t;
    std::vector<uint8_t> held; // boundary or isolated: not an unknown
};

/// Vertices per block of the conjugate-gradient passes: each block's per-coordinate
/// sums are taken in vertex order and the blocks' sums in block order, so every dot
/// product has the same bits for any thread count.
constexpr int64_t kBlock = 8192;

/// Runs `body(begin, end)` on the blocks in parallel and returns the per-coordinate sum
/// of what each returns (a fixed-size Eigen matrix: Vec3, or several sums side by side),
/// added in block order.
template <typename Body>
auto blockSums(int64_t n, Body &&body) {
    using Sum = std::decay_t<decltype(body(int64_t(0), int64_t(0)))>;
    const int64_t nBlocks = (n + kBlock - 1) / kBlock;
    std::vector<Sum> partial(size_t(nBlocks), Sum::Zero());
    parallelFor(0, nBlocks, [&](int64_t k) { partial[size_t(k)] = body(k * kBlock, std::min(n, (k + 1) * kBlock)); }, 1);
    Sum total = Sum::Zero();
    for (const Sum &p : partial) total += p;
    return total;
}

/// Solves A x = b (x zero at held vertices, b too) by conjugate gradients with the
/// diagonal as preconditioner, the three coordinates side by side, to a relative
/// residual of 1e-8 or kMaxIterations. Three passes over the vertices per iteration
/// (q = A p with p·q; x, r and z = D⁻¹ r updated with r·z and r·r; p), the vectors
/// read once each where the textbook loop reads them up to four times: the solve is
/// bound by memory traffic.
std::vector<Vec3> solveImplicit(const Implicit &A, const std::vector<Vec3> &b) {
    constexpr int kMaxIterations = 4000;
    const int64_t n = int64_t(b.size());
    const Mesh &mesh = A.mesh;
    std::vector<double> inverseDiagonal(size_t(n), 0.0);
    for (int64_t v = 0; v < n; ++v)
        if (!A.held[size_t(v)]) inverseDiagonal[size_t(v)] = 1.0 / (1.0 + A.t * mesh.degree(int(v)));
    const size_t m = static_cast<size_t>(n);
    std::vector<Vec3> x(m, Vec3::Zero()), r = b, z(m), p(m), q(m);
    const Vec3 bb = blockSums(n, [&](int64_t i0, int64_t i1) {
        Vec3 sum = Vec3::Zero();
        for (int64_t i = i0; i < i1; ++i) sum += b[size_t(i)].cwiseProduct(b[size_t(i)]);
        return sum;
    });
    // z = D⁻¹ r and r·z; r·r is b·b here.
    Vec3 rz = blockSums(n, [&](int64_t i0, int64_t i1) {
        Vec3 sum = Vec3::Zero();
        for (int64_t i = i0; i < i1; ++i) {
            z[size_t(i)] = inverseDiagonal[size_t(i)] * r[size_t(i)];
            sum += r[size_t(i)].cwiseProduct(z[size_t(i)]);
        }
        return sum;
    });
    p = z;
    Vec3 rr = bb;
    for (int it = 0; it < kMaxIterations; ++it) {
        bool done = true;
        for (int c = 0; c < 3; ++c) done = done && !(rr[c] > 1e-16 * bb[c]);
        if (done) break;
        // q = A p, with p·q.
        const Vec3 pq = blockSums(n, [&](int64_t i0, int64_t i1) {
            Vec3 sum = Vec3::Zero();
            for (int64_t i = i0; i < i1; ++i) {
                const int v = int(i);
                if (A.held[size_t(v)]) {
                    q[size_t(v)] = Vec3::Zero();
                } else {
                    Vec3 around = Vec3::Zero();
                    for (const int *h = mesh.outgoingBegin(v); h != mesh.outgoingEnd(v); ++h)
                        around += p[size_t(mesh.head(*h))];
                    q[size_t(v)] = (1.0 + A.t * mesh.degree(v)) * p[size_t(v)] - A.t * around;
                }
                sum += p[size_t(v)].cwiseProduct(q[size_t(v)]);
            }
            return sum;
        });
        Vec3 alpha;
        for (int c = 0; c < 3; ++c) alpha[c] = pq[c] > 0 ? rz[c] / pq[c] : 0.0;
        // x += α p, r −= α q, z = D⁻¹ r, with r·z and r·r (the next iteration's test).
        // Column 0: r·z, column 1: r·r.
        const Eigen::Matrix<double, 3, 2> sums = blockSums(n, [&](int64_t i0, int64_t i1) {
            Eigen::Matrix<double, 3, 2> sum = Eigen::Matrix<double, 3, 2>::Zero();
            for (int64_t i = i0; i < i1; ++i) {
                x[size_t(i)] += alpha.cwiseProduct(p[size_t(i)]);
                r[size_t(i)] -= alpha.cwiseProduct(q[size_t(i)]);
                z[size_t(i)] = inverseDiagonal[size_t(i)] * r[size_t(i)];
                sum.col(0) += r[size_t(i)].cwiseProduct(z[size_t(i)]);
                sum.col(1) += r[size_t(i)].cwiseProduct(r[size_t(i)]);
            }
            return sum;
        });
        const Vec3 rzNext = sums.col(0), rrNext = sums.col(1);
        Vec3 beta;
        for (int c = 0; c < 3; ++c) beta[c] = rz[c] > 0 ? rzNext[c] / rz[c] : 0.0;
        rz = rzNext;
        rr = rrNext;
        parallelFor(0, n, [&](int64_t v) { p[size_t(v)] = z[size_t(v)] + beta.cwiseProduct(p[size_t(v)]); }, kBlock);
    }
    return x;
}

} // namespace

SmoothedSurface smoothAtScale(const Mesh &mesh, double radius) {
    const int n = mesh.nVertices();
    const double e = mesh.meanEdgeLength();
    Implicit A{mesh, e > 0 ? (radius / e) * (radius / e) : 0.0, std::vector<uint8_t>(size_t(n), 0)};
    for (int v = 0; v < n; ++v) A.held[size_t(v)] = mesh.isBoundaryVertex(v) || mesh.degree(v) == 0;
    const std::vector<Vec3> &x0 = mesh.positions();
    // Right-hand side of A x = x0 on the unknowns: x0 plus t times the held neighbours.
    std::vector<Vec3> b(size_t(n), Vec3::Zero());
    parallelFor(0, n, [&](int64_t vv) {
        const int v = int(vv);
        if (A.held[size_t(v)]) return;
        Vec3 rhs = x0[size_t(v)];
        for (const int *h = mesh.outgoingBegin(v); h != mesh.outgoingEnd(v); ++h)
            if (A.held[size_t(mesh.head(*h))]) rhs += A.t * x0[size_t(mesh.head(*h))];
        b[size_t(v)] = rhs;
    }, 4096);
    std::vector<Vec3> x1 = solveImplicit(A, b);
    // The low-pass of the displacement is the shape's shrinkage: taken back out, so that
    // the filter is 1 − (tk / (1 + tk))², flat to second order where the shape is.
    std::vector<Vec3> d(size_t(n), Vec3::Zero());
    parallelFor(0, n, [&](int64_t v) {
        if (!A.held[size_t(v)]) d[size_t(v)] = x1[size_t(v)] - x0[size_t(v)];
    }, 8192);
    const std::vector<Vec3> shrink = solveImplicit(A, d);
    std::vector<Vec3> p(static_cast<size_t>(n));
    parallelFor(0, n, [&](int64_t v) {
        p[size_t(v)] = A.held[size_t(v)] ? x0[size_t(v)] : Vec3(x1[size_t(v)] - shrink[size_t(v)]);
    }, 8192);
    SmoothedSurface out;
    out.radius = radius;
    out.mesh = std::make_unique<Mesh>(Mesh::fromTriangles(std::move(p), mesh.faces(), mesh.name()));
    out.frames = std::make_unique<TangentFrames>(*out.mesh);
    return out;
}

SmoothedSurface smoothAtScale(const Mesh &mesh) {
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    return smoothAtScale(mesh, std::max(kScanSmoothingRadius * (hi - lo).norm(), kScanSmoothingEdges * mesh.meanEdgeLength()));
}

RosyField carryField(const TangentFrames &from, const RosyField &field, const TangentFrames &to) {
    ROSY_CHECK_EQ(from.mesh().nVertices(), to.mesh().nVertices());
    ROSY_CHECK_EQ(int(field.u.size()), from.mesh().nVertices());
    RosyField out = field;
    const int nSym = field.nSym;
    parallelFor(0, int64_t(field.u.size()), [&](int64_t vv) {
        const int v = int(vv);
        const Complex u = field.u[v];
        const double a = std::sqrt(u.real() * u.real() + u.imag() * u.imag());
        if (!(a > 0)) return;
        const Vec3 d = from.tangentOfAngle(v, std::arg(u) / nSym);
        const Vec3 &nrm = to.normal(v);
        const Vec3 t = d - d.dot(nrm) * nrm;
        out.u[v] = t.squaredNorm() > 1e-12 ? std::polar(a, nSym * to.angleOfTangent(v, t)) : Complex(0, 0);
    }, 1024);
    return out;
}

SingularityReport placedOn(SingularityReport report, const Mesh &onto) {
    for (Singularity &s : report.singularities) {
        const Face &t = onto.face(s.face);
        s.position = s.barycentric[0] * onto.position(t[0]) + s.barycentric[1] * onto.position(t[1]) +
                     s.barycentric[2] * onto.position(t[2]);
    }
    return report;
}

} // namespace rosy::field
