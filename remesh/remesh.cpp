/// \file remesh.cpp
/// Position field and extraction (see remesh.h and docs/remeshing.md). Written
/// from the description in Jakob, Tarini, Panozzo, Sorkine-Hornung 2015; the
/// orientation field is ours (the pipeline's N-RoSy field), only positions are solved.

#include "remesh/remesh.h"

#include "core/error.h"
#include "core/parallel.h"
#include "field/features.h"
#include "field/laplacian.h"
#include "field/mesh/morton.h"
#include "field/mesh/union_find.h"
#include "remesh/aabb_tree.h"
#include "remesh/dislocations.h"
#include "remesh/square_lattice.h"
#include "remesh/polygon_ops.h"

#include <Eigen/Sparse>
#include <OpenMesh/Core/Utils/Noncopyable.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <tbb/task_group.h>

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <queue>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>

namespace rosy::remesh {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// The local lattice of one vertex: origin o, first axis q (unit, tangent), normal n.
/// N = 4: squares spanned by q and n×q; N = 6: triangles spanned by q and q turned by 60°.
struct Lattice {
    int nSym = 4;
    double s = 1; ///< spacing L

    Vec3 second(const Vec3 &q, const Vec3 &n) const {
        const Vec3 w = n.cross(q);
        return nSym == 4 ? w : Vec3(0.5 * q + (std::sqrt(3.0) / 2) * w);
    }
    /// Lattice coordinates (in units of s) of tangent vector d.
    Eigen::Vector2d coords(const Vec3 &d, const Vec3 &q, const Vec3 &n) const {
        const Vec3 w = n.cross(q);
        if (nSym == 4) return {q.dot(d) / s, w.dot(d) / s};
        const double b = w.dot(d) * (2 / std::sqrt(3.0));
        return {(q.dot(d) - 0.5 * b) / s, b / s};
    }
    Vec3 floorPoint(const Vec3 &o, const Vec3 &q, const Vec3 &n, const Vec3 &p) const {
        const Eigen::Vector2d c = coords(p - o, q, n);
        return o + std::floor(c.x()) * s * q + std::floor(c.y()) * s * second(q, n);
    }
    /// The lattice point nearest p. Rounding each coordinate is exact for squares;
    /// for the skewed triangle basis the nearest of the cell's four corners is taken.
    Vec3 roundPoint(const Vec3 &o, const Vec3 &q, const Vec3 &n, const Vec3 &p) const {
        const Eigen::Vector2d c = coords(p - o, q, n);
        const Vec3 b = second(q, n);
        if (nSym == 4) return o + std::round(c.x()) * s * q + std::round(c.y()) * s * b;
        const Vec3 base = o + std::floor(c.x()) * s * q + std::floor(c.y()) * s * b;
        Vec3 best = base;
        double bestD = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 4; ++k) {
            const Vec3 x = base + (k & 1) * s * q + (k >> 1) * s * b;
            const double d = (x - p).squaredNorm();
            if (d < bestD) bestD = d, best = x;
        }
        return best;
    }
    Eigen::Vector2i roundIndex(const Vec3 &d, const Vec3 &q, const Vec3 &n) const {
        const Eigen::Vector2d c = coords(d, q, n);
        return {int(std::lround(c.x())), int(std::lround(c.y()))};
    }
    /// Of the N rotations of q1 about n1, the one closest to q0.
    Vec3 compatOrientation(const Vec3 &q0, const Vec3 &q1, const Vec3 &n1) const {
        const Vec3 w1 = n1.cross(q1);
        static const double c6[6] = {1, 0.5, -0.5, -1, -0.5, 0.5};
        static const double s6[6] = {0, 0.8660254037844386, 0.8660254037844386, 0, -0.8660254037844386,
                                     -0.8660254037844386};
        static const double c4[4] = {1, 0, -1, 0}, s4[4] = {0, 1, 0, -1};
        Vec3 best = q1;
        double bestDot = q0.dot(q1);
        for (int k = 1; k < nSym; ++k) {
            const Vec3 c = nSym == 4 ? Vec3(c4[k] * q1 + s4[k] * w1) : Vec3(c6[k] * q1 + s6[k] * w1);
            const double d = q0.dot(c);
            if (d > bestDot) bestDot = d, best = c;
        }
        return best;
    }
    /// Is integer offset k one lattice edge?
    bool isUnit(const Eigen::Vector2i &k) const {
        const int a = std::abs(k.x()), b = std::abs(k.y());
        if (a + b == 1) return true;
        return nSym == 6 && k.x() == -k.y() && a == 1;
    }
};

struct Level {
    std::vector<Vec3> p, n, q, o; ///< position, normal, orientation, lattice point
    std::vector<double> area;
    std::vector<double> s;  ///< lattice spacing along q (L, or L e^{λφ + μφ_q}, RemeshOptions)
    std::vector<double> s2; ///< lattice spacing along n×q (N = 4; the same as s for N = 6)
    std::vector<int> adjOffset, adj; ///< CSR neighbour lists, sorted
    std::vector<int> toCoarse;        ///< fine vertex -> vertex of the next level
    /// Fine vertex: is its q turned by an odd rotation against its cluster's axes
    /// (its first member's q)? Then its two spacings are swapped in the cluster's mean.
    std::vector<char> oddToCoarse;
    std::vector<char> pinned;
    /// Feature lines (RemeshOptions::featureAngleDeg): a vertex with onLine keeps its
    /// lattice point on the line through lineP along lineD (empty without features).
    std::vector<char> onLine;
    std::vector<Vec3> lineP, lineD;
    /// The finest level only, with features: the feature edges after subdivision,
    /// which vertices are feature corners (pinned at themselves) and which lie on
    /// the input's boundary.
    std::vector<std::array<int, 2>> featureEdges;
    std::vector<char> featureEdgeOnBoundary; ///< per feature edge: a part of one of the input's boundary edges
    std::vector<char> corner, boundary;
    /// The finest level only: its triangles, oriented as the input's.
    std::vector<std::array<int, 3>> tris;
    int size() const { return int(p.size()); }
};

/// Puts x on the line through p along unit d.
inline Vec3 ontoLine(const Vec3 &x, const Vec3 &p, const Vec3 &d) { return p + d * d.dot(x - p); }

/// Closest pair (one corner of each cell around the two tangent planes' middle point)
/// of the lattices (p0, n0, q0, o0) and (p1, n1, q1, o1); q1 already matched to q0.
std::pair<Vec3, Vec3> compatPosition(const Lattice &lat0, const Lattice &lat1, const Vec3 &p0, const Vec3 &n0,
                                     const Vec3 &q0, const Vec3 &o0, const Vec3 &p1, const Vec3 &n1, const Vec3 &q1,
                                     const Vec3 &o1) {
    // The lattice-0 point nearest the middle, and the lattice-1 point nearest to it.
    const Vec3 m = middlePoint(p0, n0, p1, n1);
    const Vec3 c0 = lat0.roundPoint(o0, q0, n0, m);
    return {c0, lat1.roundPoint(o1, q1, n1, c0)};
}

Vec3 perpendicularUnit(const Vec3 &n) {
    Vec3 a = std::abs(n.x()) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    return (a - n * n.dot(a)).normalized();
}

/// Solves A x = b for the scale functions' symmetric positive definite A (both
/// triangles stored) by CHOLMOD's supernodal Cholesky (SuiteSparse; BLAS on one
/// thread, field/sparse_solver.cpp, so the same bits for any thread count): on
/// bunny00 at 1 % (75k unknowns) 0.30 s against 0.49 s for Eigen's simplicial LDLᵀ,
/// which the hierarchy waited for. Empty when A is not positive definite (CHOLMOD's
/// own messages off: the caller falls back to no scaling).
Eigen::VectorXd solveScaleSystem(const Eigen::SparseMatrix<double> &A, const Eigen::VectorXd &b) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
    solver.cholmod().print = 0;
    solver.compute(A);
    if (solver.info() != Eigen::Success) return {};
    Eigen::VectorXd x = solver.solve(b);
    if (solver.info() != Eigen::Success) return {};
    return x;
}

/// The scale function φ of the lattice (spacing L e^φ): the part of the frame
/// field's curl a smooth change of edge length can absorb. With ω₁ = q·dx and
/// ω₂ = (n×q)·dx, lattice coordinates du_k = e^{−φ} ω_k / L close around every
/// triangle when Σ_e e^{−φ_e} ω_k(e) = 0; linearised about the triangle's mean
/// φ̄, Σ_e (φ_e − φ̄) ω_k(e) = Σ_e ω_k(e), φ_e the mean of the edge's ends. Both
/// equations of every triangle (divided by its mean edge) in least squares, plus
/// a small membrane term so the system is definite; sparse Cholesky.
std::vector<double> scaleFunction(const Level &L, const std::vector<std::array<int, 3>> &tris, const Lattice &lat) {
    const int nV = L.size();
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nV);
    double meanEdge = 0;
    for (const auto &t : tris)
        for (int k = 0; k < 3; ++k) meanEdge += (L.p[t[k]] - L.p[t[(k + 1) % 3]]).norm();
    meanEdge /= std::max<double>(1, 3.0 * double(tris.size()));
    const double membrane = 0.1 * meanEdge * meanEdge; // bunny00: 1e-2 CV 0.26, 0.1 CV 0.19, 1 CV 0.12 and no gain // in the units of the squared rows below
    for (const auto &t : tris) {
        Vec3 q[3], w[3];
        for (int k = 0; k < 3; ++k) {
            q[k] = k == 0 ? L.q[t[0]] : lat.compatOrientation(L.q[t[0]], L.q[t[k]], L.n[t[k]]);
            w[k] = L.n[t[k]].cross(q[k]);
        }
        double h = 0;
        for (int k = 0; k < 3; ++k) h += (L.p[t[(k + 1) % 3]] - L.p[t[k]]).norm() / 3;
        if (!(h > 0)) continue;
        for (int family = 0; family < 2; ++family) {
            double om[3], circ = 0; // om[k]: edge k -> k+1
            for (int k = 0; k < 3; ++k) {
                const int k1 = (k + 1) % 3;
                const Vec3 d = family == 0 ? Vec3(q[k] + q[k1]) : Vec3(w[k] + w[k1]);
                om[k] = 0.5 * (L.p[t[k1]] - L.p[t[k]]).dot(d) / h;
                circ += om[k];
            }
            double row[3];
            for (int k = 0; k < 3; ++k) row[k] = 0.5 * (om[k] + om[(k + 2) % 3]) - circ / 3;
            for (int a = 0; a < 3; ++a) {
                rhs[t[a]] += row[a] * circ;
                for (int b = 0; b < 3; ++b) trip.emplace_back(t[a], t[b], row[a] * row[b]);
            }
        }
        for (int k = 0; k < 3; ++k) { // membrane on the triangle's edges
            const int a = t[k], b = t[(k + 1) % 3];
            const double m = membrane / (h * h);
            trip.emplace_back(a, a, m), trip.emplace_back(b, b, m);
            trip.emplace_back(a, b, -m), trip.emplace_back(b, a, -m);
        }
    }
    for (int v = 0; v < nV; ++v) trip.emplace_back(v, v, 1e-8);
    Eigen::SparseMatrix<double> A(nV, nV);
    A.setFromTriplets(trip.begin(), trip.end());
    const Eigen::VectorXd x = solveScaleSystem(A, rhs);
    if (x.size() != nV) return std::vector<double>(nV, 0.0);
    std::vector<double> phi(nV);
    for (int v = 0; v < nV; ++v) phi[v] = std::isfinite(x[v]) ? x[v] : 0.0;
    return phi;
}

/// The two scale functions φ_q, φ_{n×q} of an anisotropic lattice (N = 4): spacing
/// L e^{φ_q} along q and L e^{φ_{n×q}} along n×q. Each family's lattice coordinate
/// du_k = e^{−φ_k} ω_k / L closes around a triangle when Σ_e e^{−φ_k,e} ω_k(e) = 0:
/// the same linearised rows as scaleFunction, but each with its own unknown, so
/// that both rows of every triangle can hold (a nowhere-vanishing 1-form has an
/// integrating factor): the non-integrable part of the curl that one conformal φ
/// leaves is absorbed too. A vertex whose q is matched to the triangle's first by
/// an odd rotation has its two unknowns swapped. Membrane term on both; sparse
/// Cholesky. Returns 2 nV values, φ_q and φ_{n×q} of vertex v at 2v and 2v + 1.
std::vector<double> anisotropicScale(const Level &L, const std::vector<std::array<int, 3>> &tris) {
    const int nV = L.size();
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * nV);
    double meanEdge = 0;
    for (const auto &t : tris)
        for (int k = 0; k < 3; ++k) meanEdge += (L.p[t[k]] - L.p[t[(k + 1) % 3]]).norm();
    meanEdge /= std::max<double>(1, 3.0 * double(tris.size()));
    const double membrane = 0.1 * meanEdge * meanEdge; // as scaleFunction's (0.01: bunny00 CV 0.116, elephant 0.126)
    const Lattice lat{4, 1};
    trip.reserve(42 * tris.size() + 2 * size_t(nV)); // per triangle 2 x 9 rows, 3 x 2 x 4 membrane; the diagonal
    for (const auto &t : tris) {
        Vec3 q[3], w[3];
        int parity[3];
        for (int k = 0; k < 3; ++k) {
            q[k] = k == 0 ? L.q[t[0]] : lat.compatOrientation(L.q[t[0]], L.q[t[k]], L.n[t[k]]);
            parity[k] = k == 0 ? 0 : compatIndex4(L.q[t[0]], L.q[t[k]], L.n[t[k]]) & 1;
            w[k] = L.n[t[k]].cross(q[k]);
        }
        double h = 0;
        for (int k = 0; k < 3; ++k) h += (L.p[t[(k + 1) % 3]] - L.p[t[k]]).norm() / 3;
        if (!(h > 0)) continue;
        for (int family = 0; family < 2; ++family) {
            double om[3], circ = 0;
            int unknown[3];
            for (int k = 0; k < 3; ++k) {
                const int k1 = (k + 1) % 3;
                const Vec3 d = family == 0 ? Vec3(q[k] + q[k1]) : Vec3(w[k] + w[k1]);
                om[k] = 0.5 * (L.p[t[k1]] - L.p[t[k]]).dot(d) / h;
                circ += om[k];
                unknown[k] = 2 * t[k] + (family ^ parity[k]);
            }
            double row[3];
            for (int k = 0; k < 3; ++k) row[k] = 0.5 * (om[k] + om[(k + 2) % 3]) - circ / 3;
            for (int a = 0; a < 3; ++a) {
                rhs[unknown[a]] += row[a] * circ;
                for (int b = 0; b < 3; ++b) trip.emplace_back(unknown[a], unknown[b], row[a] * row[b]);
            }
        }
        for (int k = 0; k < 3; ++k) { // membrane on the triangle's edges, both families
            const int a = t[k], b = t[(k + 1) % 3];
            const int pab = compatIndex4(L.q[a], L.q[b], L.n[b]) & 1;
            const double m = membrane / (h * h);
            for (int family = 0; family < 2; ++family) {
                const int ia = 2 * a + family, ib = 2 * b + (family ^ pab);
                trip.emplace_back(ia, ia, m), trip.emplace_back(ib, ib, m);
                trip.emplace_back(ia, ib, -m), trip.emplace_back(ib, ia, -m);
            }
        }
    }
    for (int v = 0; v < 2 * nV; ++v) trip.emplace_back(v, v, 1e-8);
    Eigen::SparseMatrix<double> A(2 * nV, 2 * nV);
    A.setFromTriplets(trip.begin(), trip.end());
    std::vector<Eigen::Triplet<double>>().swap(trip); // 42 per triangle: freed before the factorisation
    const Eigen::VectorXd x = solveScaleSystem(A, rhs);
    if (x.size() != 2 * nV) return std::vector<double>(2 * size_t(nV), 0.0);
    std::vector<double> phi(2 * size_t(nV));
    for (int v = 0; v < 2 * nV; ++v) phi[size_t(v)] = std::isfinite(x[v]) ? x[v] : 0.0;
    return phi;
}

/// Sorted, duplicate-free neighbour lists (CSR) from directed pairs (a, b)
/// given by `forEachPair(emit)`, which is called twice (count, then fill): no
/// list per vertex is allocated.
template <typename ForEachPair>
void buildAdjacency(int nV, ForEachPair &&forEachPair, std::vector<int> &offset, std::vector<int> &adj) {
    std::vector<int> start(static_cast<size_t>(nV) + 1, 0);
    forEachPair([&](int a, int) { ++start[size_t(a) + 1]; });
    for (int v = 0; v < nV; ++v) start[size_t(v) + 1] += start[size_t(v)];
    std::vector<int> all(static_cast<size_t>(start[size_t(nV)])), fill(start.begin(), start.end() - 1);
    forEachPair([&](int a, int b) { all[size_t(fill[size_t(a)]++)] = b; });
    offset.assign(1, 0);
    offset.reserve(static_cast<size_t>(nV) + 1);
    adj.clear();
    adj.reserve(all.size() / 2 + 1);
    for (int v = 0; v < nV; ++v) {
        const auto b = all.begin() + start[size_t(v)], e = all.begin() + start[size_t(v) + 1];
        std::sort(b, e);
        adj.insert(adj.end(), b, std::unique(b, e));
        offset.push_back(int(adj.size()));
    }
}

/// The finest level: the input's vertices with the field's first member direction,
/// midpoint-subdivided (in the faces' planes, so the surface is unchanged) until the
/// mean edge is at most kMaxEdge L, so that no edge jumps over a lattice point.
/// With `pinFaces` (a singularity's face and position), the vertices closer than
/// L / 2 to the singularity (on its side of the surface), and always the nearest
/// one, keep the singular point as their lattice point: it is then the lattice
/// point nearest to each of them, so they become one output vertex there.
constexpr double kMaxEdge = 0.5;
/// No finest-level edge is longer than this many L (long edges are bisected).
constexpr double kMaxLongEdge = 1.0;
/// Feature curves shorter than this many L are ignored by the remesher.
constexpr double kMinFeatureLength = 2.0;
/// Thin parts (RemeshOptions::thinParts): the lattice spacing where the surface is
/// thinner than about L, or faces another part across a gap that narrow, is this
/// fraction of the thickness (a tube of diameter D then has about four edges round
/// it), never below kMinThinSpacing L, and grows by at most kThinGrading times the
/// distance away from there.
constexpr double kThinSpacing = 0.75;
constexpr double kMinThinSpacing = 0.25;
constexpr double kThinGrading = 0.25;
/// A connected thin spot of less area than this many L² is not a part (thinPartSpacing).
constexpr double kMinThinArea = 1.0;
/// The four side rays of the thickness measure are tilted this much from the normal.
constexpr double kThinRayTilt = 30.0 * M_PI / 180.0;

/// The spacing cap of every input vertex for thin parts, at most 2 L (the largest
/// spacing, so no cap): kThinSpacing times the nearer of the surface's distances
/// inward (the part's thickness) and outward (a gap to another part or a fold),
/// each the median of five rays (along the normal and tilted kThinRayTilt to four
/// sides; none where the one along the normal finds nothing within reach); connected spots thinner than L of less than kMinThinArea L² dropped;
/// then graded along the edges (each vertex at most its neighbour's plus
/// kThinGrading times their distance, by Dijkstra's search: the least such caps). `thin` counts the vertices whose own cap is
/// below L.
std::vector<double> thinPartSpacing(const field::TangentFrames &frames, const AabbTree &surface, double L,
                                    int &thin) {
    const field::Mesh &mesh = frames.mesh();
    const int n = mesh.nVertices();
    const double none = 2.0 * L, tMin = 1e-4 * L, reach = L / kThinSpacing;
    std::vector<double> cap(size_t(n), none);
    parallelFor(0, n, [&](int64_t v) {
        const Vec3 p = mesh.position(int(v)), nv = frames.normal(int(v));
        if (!(nv.squaredNorm() > 0.5)) return;
        // The median of five rays, along ±n and tilted 30° toward four tangent
        // directions, so that one ray grazing a neighbouring face does not count;
        // the four only where the one along ±n hits within reach (most vertices
        // are not thin: one ray each way there).
        const Vec3 t1 = perpendicularUnit(nv), t2 = nv.cross(t1);
        const double c = std::cos(kThinRayTilt), sn = std::sin(kThinRayTilt);
        auto median = [&](const Vec3 &axis) {
            std::array<double, 5> hit;
            hit[0] = surface.firstHit(p, axis, tMin, reach);
            if (!(hit[0] < reach)) return reach;
            const Vec3 side[4] = {t1, -t1, t2, -t2};
            for (int k = 0; k < 4; ++k) hit[size_t(k) + 1] = surface.firstHit(p, c * axis + sn * side[k], tMin, reach);
            std::nth_element(hit.begin(), hit.begin() + 2, hit.end());
            return hit[2];
        };
        const double t = std::min(median(-nv), median(nv));
        if (t < reach) cap[size_t(v)] = std::max(kMinThinSpacing * L, kThinSpacing * t);
    }, 1024);
    // A thin spot smaller than kMinThinArea L² (one or two vertices where a ray
    // grazes a fold, or where two parts touch, which no spacing resolves) is not a
    // part: its caps are dropped.
    {
        const Eigen::VectorXd area = field::vertexAreas(mesh);
        std::vector<int> component(size_t(n), -1), queue;
        for (int root = 0; root < n; ++root) {
            if (component[size_t(root)] >= 0 || !(cap[size_t(root)] < L)) continue;
            queue.assign(1, root);
            component[size_t(root)] = root;
            double sum = 0;
            for (size_t k = 0; k < queue.size(); ++k) {
                const int v = queue[k];
                sum += area[v];
                for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it)
                    for (int w : {mesh.head(*it), mesh.tail(field::Mesh::prev(*it))})
                        if (component[size_t(w)] < 0 && cap[size_t(w)] < L) {
                            component[size_t(w)] = root;
                            queue.push_back(w);
                        }
            }
            if (sum < kMinThinArea * L * L)
                for (int v : queue) cap[size_t(v)] = none;
        }
    }
    thin = int(std::count_if(cap.begin(), cap.end(), [&](double c) { return c < L; }));
    if (thin == 0) return cap;
    // Dijkstra from every capped vertex at once: the smallest cap first (ties by
    // vertex), each neighbour offered the cap plus kThinGrading times the edge.
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> front;
    for (int v = 0; v < n; ++v)
        if (cap[size_t(v)] < none) front.push({cap[size_t(v)], v});
    while (!front.empty()) {
        const auto [c, v] = front.top();
        front.pop();
        if (c > cap[size_t(v)]) continue; // superseded
        for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it)
            for (int w : {mesh.head(*it), mesh.tail(field::Mesh::prev(*it))}) {
                const double cw = c + kThinGrading * (mesh.position(v) - mesh.position(w)).norm();
                if (cw < cap[size_t(w)]) {
                    cap[size_t(w)] = cw;
                    front.push({cw, w});
                }
            }
    }
    return cap;
}

/// A vertex made by subdivision: the midpoint of a and b; odd: b's q turned by an
/// odd rotation against a's (N = 4), so b's two scale functions are swapped.
struct Midpoint {
    int a, b;
    bool odd;
};

/// The finest level without its spacings (finestSpacings gives them). `atInput` is
/// called with the input's vertices (p, n, q) and triangles before subdivision (the
/// scale functions are solved there, while this goes on); `midpoints` lists the
/// subdivision's vertices in the order they are made.
Level finestLevel(const field::TangentFrames &frames, const field::RosyField &field, const Lattice &lat,
                  const std::vector<std::pair<int, Vec3>> &pinFaces, long long maxVertices,
                  const field::FeatureCurves *curves,
                  const std::function<void(const Level &, const std::vector<std::array<int, 3>> &)> &atInput,
                  std::vector<Midpoint> &midpoints, int &subdivisions, int &longEdgesSplit,
                  std::vector<double> &sizing) {
    const field::Mesh &mesh = frames.mesh();
    const int nV0 = mesh.nVertices();
    Level L;
    L.p = mesh.positions();
    L.n.resize(nV0);
    L.q.resize(nV0);
    for (int v = 0; v < nV0; ++v) {
        L.n[v] = frames.normal(v);
        const double a = std::abs(field.u[v]) > 0 ? field::memberAngle(field.u[v], field.nSym) : 0.0;
        Vec3 q = frames.tangentOfAngle(v, a);
        q -= L.n[v] * L.n[v].dot(q);
        L.q[v] = q.norm() > 1e-12 ? Vec3(q.normalized()) : perpendicularUnit(L.n[v]);
    }
    // Feature edges (key: smaller vertex << 32 | larger) -> a boundary edge; curve
    // vertices get their tangent's rotation nearest their field direction as q.
    std::unordered_map<long long, char> featureEdge;
    auto edgeKey = [](int a, int b) { return (long long)std::min(a, b) << 32 | (long long)std::max(a, b); };
    std::vector<Vec3> tangent; // per vertex on a curve (not a corner), else zero
    if (curves) {
        for (const auto &e : curves->edges)
            featureEdge.emplace(edgeKey(e[0], e[1]), char(mesh.isBoundaryVertex(e[0]) && mesh.isBoundaryVertex(e[1])));
        for (int h = 0; h < mesh.nHalfedges(); ++h) // an edge between two boundary vertices may be inside
            if (!mesh.isBoundaryHalfedge(h)) {
                const auto it = featureEdge.find(edgeKey(mesh.tail(h), mesh.head(h)));
                if (it != featureEdge.end()) it->second = 0;
            }
        L.corner.assign(size_t(nV0), 0);
        L.boundary.assign(size_t(nV0), 0);
        tangent.assign(size_t(nV0), Vec3::Zero());
        for (int v = 0; v < nV0; ++v) {
            L.corner[size_t(v)] = curves->corner[size_t(v)];
            L.boundary[size_t(v)] = char(mesh.isBoundaryVertex(v));
            if (!curves->onCurve(v) || curves->corner[size_t(v)]) continue;
            Vec3 t = curves->tangent[size_t(v)];
            t -= L.n[v] * L.n[v].dot(t);
            if (t.norm() < 1e-9) continue;
            tangent[size_t(v)] = t.normalized();
            L.q[v] = lat.compatOrientation(L.q[v], tangent[size_t(v)], L.n[v]);
        }
    }
    std::vector<std::array<int, 3>> tris(mesh.faces().begin(), mesh.faces().end());
    atInput(L, tris);
    midpoints.clear();
    auto meanEdge = [&] {
        double sum = 0;
        for (const auto &t : tris)
            for (int k = 0; k < 3; ++k) sum += (L.p[t[k]] - L.p[t[(k + 1) % 3]]).norm();
        return tris.empty() ? 0.0 : sum / (3.0 * double(tris.size()));
    };
    subdivisions = 0;
    // Refuse before allocating: each subdivision halves the edges and about
    // quadruples the vertices.
    const double ratio = meanEdge() / (kMaxEdge * lat.s);
    const int needed = ratio > 1 ? int(std::ceil(std::log2(ratio))) : 0;
    if (needed > 15 || double(L.p.size()) * std::pow(4.0, needed) > double(maxVertices))
        throw InputError(FileLoc{"--edge"},
                         "the edge length is too short for this mesh: the remesher would need more than " +
                             std::to_string(maxVertices) + " vertices",
                         "give a longer --edge");
    // Midpoints of edges (key: smaller vertex << 32 | larger) made in this round.
    std::unordered_map<long long, int> mid;
    auto midpoint = [&](int a, int b) {
        const long long key = (long long)std::min(a, b) << 32 | (long long)std::max(a, b);
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        const int id = int(L.p.size());
        const Vec3 n = (L.n[a] + L.n[b]).norm() > 1e-12 ? Vec3((L.n[a] + L.n[b]).normalized()) : L.n[a];
        Vec3 q = L.q[a] + lat.compatOrientation(L.q[a], L.q[b], L.n[b]);
        q -= n * n.dot(q);
        L.p.push_back(0.5 * (L.p[a] + L.p[b]));
        L.n.push_back(n);
        L.q.push_back(q.norm() > 1e-12 ? Vec3(q.normalized()) : perpendicularUnit(n));
        if (curves) {
            const auto fe = featureEdge.find(key);
            Vec3 t = Vec3::Zero();
            if (fe != featureEdge.end()) {
                t = L.p[b] - L.p[a];
                t -= n * n.dot(t);
                if (t.norm() > 1e-12) {
                    t.normalize();
                    L.q.back() = lat.compatOrientation(L.q.back(), t, n);
                } else {
                    t = Vec3::Zero();
                }
            }
            tangent.push_back(t);
            L.corner.push_back(0);
            L.boundary.push_back(fe != featureEdge.end() ? fe->second : 0);
        }
        midpoints.push_back({a, b, lat.nSym == 4 && (compatIndex4(L.q[a], L.q[b], L.n[b]) & 1)}); // (q is near a's)
        sizing.push_back(0.5 * (sizing[size_t(a)] + sizing[size_t(b)]));
        mid.emplace(key, id);
        return id;
    };
    // After a round, each feature edge split in it (in `mid`) becomes its two halves.
    auto halveFeatureEdges = [&] {
        std::unordered_map<long long, char> halves;
        for (const auto &[key, isBoundary] : featureEdge) {
            const auto m = mid.find(key);
            if (m == mid.end()) {
                halves.emplace(key, isBoundary);
                continue;
            }
            halves.emplace(edgeKey(int(key >> 32), m->second), isBoundary);
            halves.emplace(edgeKey(m->second, int(key & 0xffffffff)), isBoundary);
        }
        featureEdge.swap(halves);
    };
    while (meanEdge() > kMaxEdge * lat.s) {
        if (4 * (long long)(L.p.size()) > 4 * maxVertices)
            throw InputError(FileLoc{"--edge"},
                             "the edge length is too short for this mesh: the remesher would need more than " +
                                 std::to_string(maxVertices) + " vertices",
                             "give a longer --edge");
        ++subdivisions;
        mid.clear();
        mid.reserve(3 * tris.size());
        std::vector<std::array<int, 3>> next;
        next.reserve(4 * tris.size());
        for (const auto &t : tris) {
            const int m0 = midpoint(t[0], t[1]), m1 = midpoint(t[1], t[2]), m2 = midpoint(t[2], t[0]);
            next.push_back({t[0], m0, m2});
            next.push_back({m0, t[1], m1});
            next.push_back({m2, m1, t[2]});
            next.push_back({m0, m1, m2});
        }
        tris.swap(next);
        if (curves) halveFeatureEdges();
    }
    // The rounds above bound the mean edge; on a coarse or very uneven input some
    // edges stay much longer (helmet's slivers: 3.5 L after four rounds, turbine's
    // 4.6 L), jump over lattice points and leave holes in the output. Such edges are
    // bisected, each triangle with a marked edge also at its longest edge (so new
    // angles stay at least half the old ones) and split conformingly into 2, 3 or 4,
    // until every edge is at most kMaxLongEdge L, and at most the spacing of thin
    // parts (`sizing`) where that is smaller.
    longEdgesSplit = 0;
    auto length2 = [&](int a, int b) { return (L.p[a] - L.p[b]).squaredNorm(); };
    auto tooLong = [&](int a, int b) {
        const double m = std::min({kMaxLongEdge * lat.s, sizing[size_t(a)], sizing[size_t(b)]});
        return length2(a, b) > m * m;
    };
    for (int round = 0;; ++round) {
        std::unordered_set<long long> marked;
        for (const auto &t : tris)
            for (int k = 0; k < 3; ++k)
                if (tooLong(t[k], t[(k + 1) % 3])) marked.insert(edgeKey(t[k], t[(k + 1) % 3]));
        if (marked.empty()) break;
        if (round >= 40 || double(L.p.size() + marked.size()) > double(maxVertices))
            throw InputError(FileLoc{"--edge"},
                             "the edge length is too short for this mesh: the remesher would need more than " +
                                 std::to_string(maxVertices) + " vertices",
                             "give a longer --edge (or --thin-parts off, whose finer lattice in thin parts "
                             "needs more)");
        // The longest edge of each triangle (ties by key, so the choice is fixed).
        auto longest = [&](const std::array<int, 3> &t) {
            int best = 0;
            for (int k = 1; k < 3; ++k) {
                const double lk = length2(t[k], t[(k + 1) % 3]), lb = length2(t[best], t[(best + 1) % 3]);
                if (lk > lb || (lk == lb && edgeKey(t[k], t[(k + 1) % 3]) > edgeKey(t[best], t[(best + 1) % 3])))
                    best = k;
            }
            return best;
        };
        for (bool changed = true; changed;) { // closure: a triangle with a marked edge has its longest marked
            changed = false;
            for (const auto &t : tris) {
                const int k = longest(t);
                const long long key = edgeKey(t[k], t[(k + 1) % 3]);
                if (marked.count(key)) continue;
                for (int e = 0; e < 3; ++e)
                    if (marked.count(edgeKey(t[e], t[(e + 1) % 3]))) {
                        marked.insert(key);
                        changed = true;
                        break;
                    }
            }
        }
        // Midpoints in a fixed order (sorted keys), so vertex ids do not depend on hashing.
        std::vector<long long> order(marked.begin(), marked.end());
        std::sort(order.begin(), order.end());
        mid.clear();
        for (long long key : order) midpoint(int(key >> 32), int(key & 0xffffffff));
        longEdgesSplit += int(order.size());
        std::vector<std::array<int, 3>> next;
        next.reserve(tris.size() + 3 * order.size());
        for (const auto &t : tris) {
            const int k = longest(t);
            const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
            const auto m = mid.find(edgeKey(a, b));
            if (m == mid.end()) {
                next.push_back(t);
                continue;
            }
            const auto m1 = mid.find(edgeKey(b, c)), m2 = mid.find(edgeKey(c, a));
            if (m2 == mid.end()) next.push_back({a, m->second, c});
            else next.push_back({a, m->second, m2->second}), next.push_back({m2->second, m->second, c});
            if (m1 == mid.end()) next.push_back({m->second, b, c});
            else next.push_back({m->second, b, m1->second}), next.push_back({m->second, m1->second, c});
        }
        tris.swap(next);
        if (curves) halveFeatureEdges();
    }
    const int nV = int(L.p.size());
    L.area.assign(nV, 0.0);
    for (const auto &t : tris) {
        const double area = 0.5 * (L.p[t[1]] - L.p[t[0]]).cross(L.p[t[2]] - L.p[t[0]]).norm();
        for (int k = 0; k < 3; ++k) L.area[t[k]] += area / 3;
    }
    buildAdjacency(
        nV,
        [&](auto &&emit) {
            for (const auto &t : tris)
                for (int k = 0; k < 3; ++k) emit(t[k], t[(k + 1) % 3]), emit(t[(k + 1) % 3], t[k]);
        },
        L.adjOffset, L.adj);
    L.o = L.p;
    L.pinned.assign(nV, 0);
    if (curves) {
        // Corners are pinned at themselves; curve vertices keep their lattice point on
        // the line along their tangent (the lattice's q, so the rounding keeps it there).
        L.onLine.assign(size_t(nV), 0);
        L.lineP.assign(size_t(nV), Vec3::Zero());
        L.lineD.assign(size_t(nV), Vec3::Zero());
        for (int v = 0; v < nV; ++v) {
            if (L.corner[size_t(v)]) L.pinned[v] = 1;
            else if (tangent[size_t(v)] != Vec3::Zero())
                L.onLine[size_t(v)] = 1, L.lineP[size_t(v)] = L.p[v], L.lineD[size_t(v)] = tangent[size_t(v)];
        }
        std::vector<long long> keys;
        for (const auto &[key, isBoundary] : featureEdge) keys.push_back(key);
        std::sort(keys.begin(), keys.end()); // a fixed order (the map's is not)
        for (long long key : keys) {
            L.featureEdges.push_back({int(key >> 32), int(key & 0xffffffff)});
            L.featureEdgeOnBoundary.push_back(featureEdge.at(key));
        }
    }
    // Pinning by distance, not by the singular face's corners: an input face larger
    // than L would otherwise put vertices more than L apart on one lattice point
    // (measured: worse near singularities with pinning than without, docs/remeshing.md).
    for (const auto &[face, target] : pinFaces) {
        const auto &tri = mesh.face(face);
        const Vec3 fn = (mesh.position(tri[1]) - mesh.position(tri[0]))
                            .cross(mesh.position(tri[2]) - mesh.position(tri[0]))
                            .normalized();
        int nearest = -1;
        double nearestD = std::numeric_limits<double>::infinity();
        for (int v = 0; v < nV; ++v) {
            if (L.n[v].dot(fn) < 0.5) continue; // the other side of a thin part
            if (!L.onLine.empty() && (L.onLine[size_t(v)] || L.corner[size_t(v)])) continue; // features first
            const double d = (L.p[v] - target).norm();
            if (d < nearestD) nearestD = d, nearest = v;
            if (d < 0.5 * lat.s && !L.pinned[v]) {
                L.pinned[v] = 1;
                L.o[v] = target - L.n[v] * L.n[v].dot(target - L.p[v]);
            }
        }
        if (nearest >= 0 && !L.pinned[nearest]) {
            L.pinned[nearest] = 1;
            L.o[nearest] = target - L.n[nearest] * L.n[nearest].dot(target - L.p[nearest]);
        }
    }
    L.tris = std::move(tris);
    return L;
}

/// The finest level's spacings L e^{λφ + μφ_q} and L e^{λφ + μφ_{n×q}} (RemeshOptions)
/// from the scale functions of the input's vertices, `phi` (nV0 values) and `phiA`
/// (2 nV0: φ_q, φ_{n×q} of vertex v at 2v, 2v + 1), carried to the subdivision's
/// vertices (the mean of their edge's ends, in the order they were made).
void finestSpacings(Level &L, std::vector<double> phi, std::vector<double> phiA, const std::vector<Midpoint> &midpoints,
                    const Lattice &lat, double scaleStrength, double anisotropy, const std::vector<double> &sizing) {
    const bool aniso = anisotropy > 0 && lat.nSym == 4;
    for (const Midpoint &m : midpoints) {
        const size_t a = size_t(m.a), b = size_t(m.b), pb = aniso && m.odd ? 1 : 0;
        phi.push_back(0.5 * (phi[a] + phi[b]));
        phiA.push_back(0.5 * (phiA[2 * a] + phiA[2 * b + pb]));
        phiA.push_back(0.5 * (phiA[2 * a + 1] + phiA[2 * b + 1 - pb]));
    }
    const int nV = L.size();
    {
        // Spacings L e^{λφ + μφ_q} and L e^{λφ + μφ_{n×q}}, clamped to [L/2, 2L],
        // scaled so that the number of lattice cells (Σ area / (s s2)) stays what L
        // everywhere gives.
        L.s.resize(nV);
        L.s2.resize(nV);
        double cells = 0, area = 0;
        for (int v = 0; v < nV; ++v) {
            L.s[v] = std::clamp(std::exp(scaleStrength * phi[v] + anisotropy * phiA[2 * size_t(v)]), 1e-3, 1e3);
            L.s2[v] = aniso ? std::clamp(std::exp(scaleStrength * phi[v] + anisotropy * phiA[2 * size_t(v) + 1]), 1e-3, 1e3)
                            : L.s[v];
            cells += L.area[v] / (L.s[v] * L.s2[v]), area += L.area[v];
        }
        const double k = cells > 0 && area > 0 ? std::sqrt(cells / area) : 1.0;
        for (int v = 0; v < nV; ++v) { // thin parts' caps last (they are at most 2 L)
            L.s[v] = std::min(lat.s * std::clamp(k * L.s[v], 0.5, 2.0), sizing[size_t(v)]);
            L.s2[v] = std::min(lat.s * std::clamp(k * L.s2[v], 0.5, 2.0), sizing[size_t(v)]);
        }
    }
}

/// Pairs neighbours (best aligned normals and similar areas first) into the next level.
/// The coarse level's spacings are left to coarsenSpacings (they wait for the scale
/// functions, its topology does not).
Level coarsen(Level &fine) {
    const int n = fine.size();
    struct Cand {
        double score;
        int i, j;
    };
    std::vector<Cand> cands;
    cands.reserve(fine.adj.size() / 2);
    for (int i = 0; i < n; ++i)
        for (int k = fine.adjOffset[i]; k < fine.adjOffset[i + 1]; ++k) {
            const int j = fine.adj[k];
            if (j <= i) continue;
            const double ratio = std::min(fine.area[i], fine.area[j]) / std::max(1e-300, std::max(fine.area[i], fine.area[j]));
            cands.push_back({fine.n[i].dot(fine.n[j]) * ratio, i, j});
        }
    std::sort(cands.begin(), cands.end(), [](const Cand &a, const Cand &b) {
        if (a.score != b.score) return a.score > b.score;
        return a.i != b.i ? a.i < b.i : a.j < b.j;
    });
    std::vector<int> mate(n, -1);
    for (const Cand &c : cands)
        if (mate[c.i] < 0 && mate[c.j] < 0) mate[c.i] = c.j, mate[c.j] = c.i;
    // Every neighbour of a vertex left unmatched is matched (else they would be a
    // pair): it joins its best-scored neighbour's pair, so each level at least halves.
    std::vector<int> rep(n);
    for (int i = 0; i < n; ++i) rep[i] = mate[i] >= 0 ? std::min(i, mate[i]) : -1;
    for (const Cand &c : cands) {
        if (mate[c.i] < 0 && rep[c.i] < 0) rep[c.i] = rep[c.j];
        if (mate[c.j] < 0 && rep[c.j] < 0) rep[c.j] = rep[c.i];
    }
    for (int i = 0; i < n; ++i)
        if (rep[i] < 0) rep[i] = i; // isolated
    fine.toCoarse.assign(n, -1);
    fine.oddToCoarse.assign(size_t(n), 0);
    Level coarse;
    std::vector<int> idOfRep(n, -1);
    std::vector<Vec3> sumP, sumN;
    for (int i = 0; i < n; ++i) {
        int &id = idOfRep[rep[i]];
        if (id < 0) {
            id = coarse.size();
            coarse.p.push_back(Vec3::Zero());
            coarse.n.push_back(Vec3::Zero());
            coarse.q.push_back(fine.q[rep[i]]);
            coarse.area.push_back(0);
        }
        fine.toCoarse[i] = id;
        coarse.p[id] += fine.p[i] * fine.area[i];
        coarse.n[id] += fine.n[i] * fine.area[i];
        coarse.area[id] += fine.area[i];
        // the cluster's axes are its first member's
        fine.oddToCoarse[i] = char(compatIndex4(fine.q[rep[i]], fine.q[i], fine.n[i]) & 1);
    }
    for (int c = 0; c < coarse.size(); ++c) {
        Vec3 &p = coarse.p[c], &nn = coarse.n[c], &q = coarse.q[c];
        p = coarse.area[c] > 0 ? Vec3(p / coarse.area[c]) : fine.p[c];
        nn = nn.norm() > 1e-300 ? Vec3(nn.normalized()) : Vec3(0, 0, 1);
        q -= nn * nn.dot(q);
        q = q.norm() > 1e-12 ? Vec3(q.normalized()) : perpendicularUnit(nn);
    }
    buildAdjacency(
        coarse.size(),
        [&](auto &&emit) {
            for (int i = 0; i < n; ++i)
                for (int k = fine.adjOffset[i]; k < fine.adjOffset[i + 1]; ++k) {
                    const int ci = fine.toCoarse[i], cj = fine.toCoarse[fine.adj[k]];
                    if (ci != cj) emit(ci, cj);
                }
        },
        coarse.adjOffset, coarse.adj);
    coarse.pinned.assign(coarse.size(), 0);
    coarse.o.assign(coarse.size(), Vec3::Zero());
    for (int i = 0; i < n; ++i)
        if (fine.pinned[i] && !coarse.pinned[fine.toCoarse[i]]) {
            const int c = fine.toCoarse[i];
            coarse.pinned[c] = 1;
            coarse.o[c] = fine.o[i] - coarse.n[c] * coarse.n[c].dot(fine.o[i] - coarse.p[c]);
        }
    if (!fine.onLine.empty()) {
        // A cluster holding a line vertex (and no pinned one) keeps the first one's
        // line, put in its tangent plane.
        coarse.onLine.assign(size_t(coarse.size()), 0);
        coarse.lineP.assign(size_t(coarse.size()), Vec3::Zero());
        coarse.lineD.assign(size_t(coarse.size()), Vec3::Zero());
        for (int i = 0; i < n; ++i) {
            const int c = fine.toCoarse[i];
            if (!fine.onLine[size_t(i)] || coarse.pinned[c] || coarse.onLine[size_t(c)]) continue;
            const Vec3 &nc = coarse.n[c];
            Vec3 d = fine.lineD[size_t(i)] - nc * nc.dot(fine.lineD[size_t(i)]);
            if (d.norm() < 1e-6) continue;
            coarse.onLine[size_t(c)] = 1;
            coarse.lineD[size_t(c)] = d.normalized();
            coarse.lineP[size_t(c)] = fine.lineP[size_t(i)] - nc * nc.dot(fine.lineP[size_t(i)] - coarse.p[c]);
        }
    }
    return coarse;
}

/// The spacings of `coarse` (made by coarsen(fine)): each cluster's area-weighted
/// means of its members' (a member turned by an odd rotation against the cluster's
/// axes has its two swapped).
void coarsenSpacings(const Level &fine, Level &coarse) {
    coarse.s.assign(size_t(coarse.size()), 0.0);
    coarse.s2.assign(size_t(coarse.size()), 0.0);
    for (int i = 0; i < fine.size(); ++i) {
        const int id = fine.toCoarse[i];
        const bool swapped = fine.s[i] != fine.s2[i] && fine.oddToCoarse[size_t(i)];
        coarse.s[id] += (swapped ? fine.s2[i] : fine.s[i]) * fine.area[i];
        coarse.s2[id] += (swapped ? fine.s[i] : fine.s2[i]) * fine.area[i];
    }
    for (int c = 0; c < coarse.size(); ++c) {
        coarse.s[c] = coarse.area[c] > 0 ? coarse.s[c] / coarse.area[c] : fine.s[c];
        coarse.s2[c] = coarse.area[c] > 0 ? coarse.s2[c] / coarse.area[c] : fine.s2[c];
    }
}

/// Greedy colouring in vertex order (each vertex takes the smallest colour none of
/// its lower-numbered neighbours has): vertices of one colour are never
/// neighbours, so they can be updated at the same time. Vertices grouped by
/// colour, each group in index order.
std::vector<std::vector<int>> colourClasses(const Level &L) {
    std::vector<int> colour(L.size(), -1);
    std::vector<std::vector<int>> classes;
    std::vector<char> taken;
    for (int i = 0; i < L.size(); ++i) {
        taken.assign(classes.size() + 1, 0);
        for (int k = L.adjOffset[i]; k < L.adjOffset[i + 1]; ++k)
            if (colour[L.adj[k]] >= 0) taken[colour[L.adj[k]]] = 1;
        int c = 0;
        while (taken[c]) ++c;
        colour[i] = c;
        if (c == int(classes.size())) classes.emplace_back();
        classes[c].push_back(i);
    }
    return classes;
}

/// x rounded to the nearest integer (ties to even) without a libm call or a
/// branch: the baseline x86-64 target has no SSE4.1 rounding instruction, and
/// the sweeps round four times per neighbour, at coordinates whose fractions are
/// as likely below as above one half. Exact for |x| < 2^51; std::round (ties away
/// from zero) differs only at exact ties.
inline double roundNearest(double x) {
    constexpr double kShift = 6755399441055744.0; // 1.5 · 2^52
    if (!(std::abs(x) < 2251799813685248.0)) return std::nearbyint(x);
    const double shifted = x + kShift; // IEEE arithmetic: not folded without -ffast-math
    return shifted - kShift;
}

/// The point of the square lattice (origin o, axes q and w = n×q, spacing s,
/// invS = 1 / s) nearest p: Lattice::roundPoint for N = 4, with w given.
/// With spacings s along q and s2 along w (invS2 = 1 / s2).
inline Vec3 roundSquare(const Vec3 &o, const Vec3 &q, const Vec3 &w, double s, double invS, double s2, double invS2,
                        const Vec3 &p) {
    const Vec3 d = p - o;
    const double cx = q.dot(d) * invS, cy = w.dot(d) * invS2;
    return o + roundNearest(cx) * s * q + roundNearest(cy) * s2 * w;
}

/// One Gauss–Seidel sweep of the position field over a level, colour by colour;
/// within a colour the vertices are independent (parallel, same result for any
/// thread count). The general path (N = 6); sweepSquares below is N = 4.
void smoothPositions(Level &L, const Lattice &lat, const std::vector<std::vector<int>> &classes) {
    for (const std::vector<int> &cls : classes)
        parallelFor(0, int64_t(cls.size()), [&](int64_t idx) {
            const int i = cls[size_t(idx)];
            if (L.pinned[i]) return;
            const Vec3 &n = L.n[i], &q = L.q[i], &p = L.p[i];
            const Lattice li{lat.nSym, L.s[i]};
            Vec3 o = L.o[i];
            double weight = 0;
            for (int k = L.adjOffset[i]; k < L.adjOffset[i + 1]; ++k) {
                const int j = L.adj[k];
                const Vec3 qj = lat.compatOrientation(q, L.q[j], L.n[j]);
                const auto [oi, oj] = compatPosition(li, {lat.nSym, L.s[j]}, p, n, q, o, L.p[j], L.n[j], qj, L.o[j]);
                o = (oi * weight + oj) / (weight + 1);
                weight += 1;
                o -= n * n.dot(o - p);
            }
            if (!L.onLine.empty() && L.onLine[size_t(i)]) o = ontoLine(o, L.lineP[size_t(i)], L.lineD[size_t(i)]);
            L.o[i] = li.roundPoint(o, q, n, p);
        }, 512);
}

/// What a sweep reads of one vertex, in two cache lines (a Level's separate
/// arrays cost a cache miss each per neighbour on the large levels).
struct alignas(64) SweepNode {
    Vec3 p, n, q, o; ///< position, normal, orientation, lattice point
    double s, s2;    ///< lattice spacings along q and n×q
};


/// What sweepSquares needs of a level's topology, in the Morton order of its
/// positions: made in the hierarchy stage, before the spacings are known.
struct SweepPlan {
    std::vector<std::pair<uint64_t, int>> order; ///< slot -> (Morton code, vertex)
    std::vector<int> offset, adj;                ///< neighbour lists by slot, in the level's order
    std::vector<char> lineOn;                    ///< feature lines by slot (empty without features)
    std::vector<std::array<Vec3, 2>> line;
    std::vector<std::vector<int>> slotClasses; ///< the colour classes' unpinned vertices by slot, sorted
};

SweepPlan planSweeps(const Level &L, const std::vector<std::vector<int>> &classes) {
    SweepPlan plan;
    const int n = L.size();
    if (n == 0) return plan;
    Vec3 lo = L.p[0], hi = L.p[0];
    for (const Vec3 &p : L.p) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const double extent = (hi - lo).maxCoeff();
    const double scale = extent > 0 ? 1 / extent : 1.0;
    std::vector<std::pair<uint64_t, int>> &order = plan.order;
    order.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) order[size_t(i)] = {field::mortonCode(L.p[i], lo, scale), i};
    std::sort(order.begin(), order.end());
    std::vector<int> slot(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) slot[size_t(order[size_t(k)].second)] = k;
    std::vector<int> &offset = plan.offset, &adj = plan.adj;
    offset.assign(size_t(n) + 1, 0);
    adj.resize(L.adj.size());
    for (int k = 0; k < n; ++k) {
        const int i = order[size_t(k)].second;
        offset[size_t(k) + 1] = offset[size_t(k)] + (L.adjOffset[i + 1] - L.adjOffset[i]);
        for (int a = L.adjOffset[i], b = offset[size_t(k)]; a < L.adjOffset[i + 1]; ++a, ++b) // neighbour order kept
            adj[size_t(b)] = slot[size_t(L.adj[a])];
    }
    // Feature lines by slot (read only for the vertex being updated).
    std::vector<char> &lineOn = plan.lineOn;
    std::vector<std::array<Vec3, 2>> &line = plan.line;
    if (!L.onLine.empty()) {
        lineOn.assign(size_t(n), 0);
        line.resize(size_t(n));
        for (int k = 0; k < n; ++k) {
            const int i = order[size_t(k)].second;
            lineOn[size_t(k)] = L.onLine[size_t(i)];
            line[size_t(k)] = {L.lineP[size_t(i)], L.lineD[size_t(i)]};
        }
    }
    for (const std::vector<int> &cls : classes) {
        std::vector<int> c;
        for (int i : cls)
            if (!L.pinned[i]) c.push_back(slot[size_t(i)]);
        std::sort(c.begin(), c.end());
        plan.slotClasses.push_back(std::move(c));
    }
    return plan;
}

/// `sweeps` Gauss–Seidel sweeps of the position field for N = 4, the same
/// arithmetic as smoothPositions (Lattice's general path) with the rotations of
/// q written out and n×q kept per vertex. The result depends only on the plan's colour classes
/// (vertices of one colour are not neighbours, so the order within a colour does
/// not matter); the data are stored, and each colour visited, in the Morton
/// order of the positions, so that neighbours are mostly near in memory: on
/// bunny00's largest levels (13 and 29 MB) the neighbour loads were most of the time.
void sweepSquares(Level &L, const SweepPlan &plan, int sweeps, std::vector<SweepNode> &nodes) {
    const int n = L.size();
    if (sweeps <= 0 || n == 0) return;
    const auto &order = plan.order;
    const std::vector<int> &offset = plan.offset, &adj = plan.adj;
    const std::vector<char> &lineOn = plan.lineOn;
    const std::vector<std::array<Vec3, 2>> &line = plan.line;
    const std::vector<std::vector<int>> &slotClasses = plan.slotClasses;
    nodes.resize(static_cast<size_t>(n));
    parallelFor(0, n, [&](int64_t k) {
        const int i = order[size_t(k)].second;
        nodes[size_t(k)] = {L.p[i], L.n[i], L.q[i], L.o[i], L.s[i], L.s2[i]};
    }, 4096);
    // Two vertices of a colour are updated side by side, neighbour by neighbour:
    // each update is one long chain of dependent arithmetic (latency bound), and
    // the two chains are independent, so the processor overlaps them.
    struct Update {
        SweepNode *a;
        Vec3 o, w;
        double weight, invS, invS2;
        int k, end;
    };
    auto start = [&](int i) {
        SweepNode &a = nodes[size_t(i)];
        return Update{&a, a.o, a.n.cross(a.q), 0.0, 1 / a.s, 1 / a.s2, offset[size_t(i)], offset[size_t(i) + 1]};
    };
    auto step = [&](Update &u) {
        const SweepNode &a = *u.a;
        const SweepNode &b = nodes[size_t(adj[size_t(u.k++)])];
        if (u.k + 1 < u.end) { // the node after next: its two cache lines are on their way when it is read
            const char *next = reinterpret_cast<const char *>(&nodes[size_t(adj[size_t(u.k + 1)])]);
            __builtin_prefetch(next);
            __builtin_prefetch(next + 64);
        }
        const Vec3 &nrm = a.n, &q = a.q;
        // Lattice::compatOrientation: of b.q, b.w, −b.q, −b.w the first closest to q
        const Vec3 bw = b.n.cross(b.q);
        const double d0 = q.dot(b.q), d1 = q.dot(bw);
        int best = 0;
        double bestDot = d0;
        if (d1 > bestDot) bestDot = d1, best = 1;
        if (-d0 > bestDot) bestDot = -d0, best = 2;
        if (-d1 > bestDot) best = 3;
        const Vec3 qj = best == 0 ? b.q : best == 1 ? bw : best == 2 ? Vec3(-b.q) : Vec3(-bw);
        const Vec3 wj = b.n.cross(qj);
        const double sj = best & 1 ? b.s2 : b.s, sj2 = best & 1 ? b.s : b.s2; // along qj, wj
        // compatPosition: our lattice point nearest the planes' middle point, theirs nearest that
        const Vec3 c0 = roundSquare(u.o, q, u.w, a.s, u.invS, a.s2, u.invS2, middlePoint(a.p, nrm, b.p, b.n));
        const Vec3 cj = roundSquare(b.o, qj, wj, sj, 1 / sj, sj2, 1 / sj2, c0);
        u.o = (c0 * u.weight + cj) / (u.weight + 1);
        u.weight += 1;
        u.o -= nrm * nrm.dot(u.o - a.p);
    };
    auto finish = [&](Update &u) {
        while (u.k < u.end) step(u);
        if (!lineOn.empty()) {
            const size_t k = size_t(u.a - nodes.data());
            if (lineOn[k]) u.o = ontoLine(u.o, line[k][0], line[k][1]);
        }
        u.a->o = roundSquare(u.o, u.a->q, u.w, u.a->s, u.invS, u.a->s2, u.invS2, u.a->p);
    };
    for (int it = 0; it < sweeps; ++it)
        for (const std::vector<int> &cls : slotClasses)
            parallelFor(0, int64_t(cls.size() + 1) / 2, [&](int64_t pair) {
                // the next pair's first two neighbours each, on their way
                for (size_t x = size_t(2 * pair + 2); x < std::min(cls.size(), size_t(2 * pair + 4)); ++x)
                    for (int k = offset[size_t(cls[x])]; k < std::min(offset[size_t(cls[x]) + 1], offset[size_t(cls[x])] + 2); ++k) {
                        const char *b = reinterpret_cast<const char *>(&nodes[size_t(adj[size_t(k)])]);
                        __builtin_prefetch(b);
                        __builtin_prefetch(b + 64);
                    }
                Update u = start(cls[size_t(2 * pair)]);
                if (size_t(2 * pair + 1) == cls.size()) {
                    finish(u);
                    return;
                }
                Update v = start(cls[size_t(2 * pair + 1)]);
                while (u.k < u.end && v.k < v.end) step(u), step(v);
                finish(u);
                finish(v);
            }, 256);
    parallelFor(0, n, [&](int64_t k) { L.o[size_t(order[size_t(k)].second)] = nodes[size_t(k)].o; }, 4096);
}

/// The finest level's lattices for square_lattice.h.
SquareLattices squareLattices(const Level &F) { return {F.p, F.n, F.q, F.o, F.s, F.s2}; }

/// N = 4: two triangles sharing an edge become one quad (their union), greedily in
/// face order. Polygons are rewritten in place (merged ones removed).
void mergeTrianglePairs(std::vector<std::vector<int>> &polygons, const std::vector<Vec3> &positions, int nSym,
                        std::map<std::string, int> &repairs) {
    int merged = 0;
    if (nSym == 4) {
        std::map<std::pair<int, int>, int> triByEdge; // directed edge -> triangle
        for (int f = 0; f < int(polygons.size()); ++f)
            if (polygons[f].size() == 3)
                for (int k = 0; k < 3; ++k) triByEdge[{polygons[f][k], polygons[f][(k + 1) % 3]}] = f;
        std::vector<char> gone(polygons.size(), 0), touched(polygons.size(), 0);
        for (int f = 0; f < int(polygons.size()); ++f) {
            if (polygons[f].size() != 3 || touched[f]) continue;
            // the longest edge first: two half-squares share their diagonal
            int order[3] = {0, 1, 2};
            auto len = [&](int k) {
                return (positions[polygons[f][k]] - positions[polygons[f][(k + 1) % 3]]).squaredNorm();
            };
            std::sort(order, order + 3, [&](int x, int y) { return len(x) > len(y) || (len(x) == len(y) && x < y); });
            for (int k : order) {
                const int a = polygons[f][k], b = polygons[f][(k + 1) % 3], c = polygons[f][(k + 2) % 3];
                auto it = triByEdge.find({b, a});
                if (it == triByEdge.end() || touched[it->second] || it->second == f) continue;
                const std::vector<int> &g = polygons[it->second];
                int d = -1;
                for (int x : g)
                    if (x != a && x != b) d = x;
                if (d < 0 || d == c) continue;
                gone[it->second] = touched[it->second] = touched[f] = 1;
                polygons[f] = {a, d, b, c};
                ++merged;
                break;
            }
        }
        removeMarked(polygons, gone);
    }
    repairs["triangle_pairs_merged"] = merged;
    // N = 6: quads split along their shorter diagonal (unless it is already an edge).
    int splitQuads = 0;
    if (nSym == 6) {
        std::set<std::pair<int, int>> edges;
        for (const auto &poly : polygons)
            for (size_t k = 0; k < poly.size(); ++k) {
                const int a = poly[k], b = poly[(k + 1) % poly.size()];
                edges.insert({std::min(a, b), std::max(a, b)});
            }
        std::vector<std::vector<int>> out;
        for (auto &poly : polygons) {
            if (poly.size() != 4) {
                out.push_back(std::move(poly));
                continue;
            }
            const int s0 = (positions[poly[0]] - positions[poly[2]]).squaredNorm() <=
                                   (positions[poly[1]] - positions[poly[3]]).squaredNorm()
                               ? 0
                               : 1;
            bool done = false;
            for (int k : {s0, 1 - s0}) {
                const int a = poly[k], b = poly[k + 2];
                if (edges.count({std::min(a, b), std::max(a, b)})) continue;
                edges.insert({std::min(a, b), std::max(a, b)});
                out.push_back({poly[k], poly[k + 1], poly[k + 2]});
                out.push_back({poly[k + 2], poly[(k + 3) % 4], poly[k]});
                ++splitQuads;
                done = true;
                break;
            }
            if (!done) out.push_back(std::move(poly));
        }
        polygons.swap(out);
    }
    repairs["quads_split"] = splitQuads;
}

/// All ways to cut polygon `poly` (an even number of corners) into quads by
/// diagonals, appended to `out` (each a list of quads).
void quadrangulations(const std::vector<int> &poly, std::vector<std::vector<std::vector<int>>> &out) {
    const int m = int(poly.size());
    if (m == 4) {
        out.push_back({poly});
        return;
    }
    // The quad on the side (poly[0], poly[m-1]) is (poly[0], poly[a], poly[b], poly[m-1]); the three
    // pieces between its corners are either single sides or polygons of an even number of corners.
    auto piece = [&](int i, int j) { // corners i..j
        return std::vector<int>(poly.begin() + i, poly.begin() + j + 1);
    };
    for (int a = 1; a < m - 2; a += 2)
        for (int b = a + 1; b < m - 1; b += 2) {
            std::vector<std::vector<std::vector<int>>> parts[3];
            const std::vector<int> pieces[3] = {piece(0, a), piece(a, b), piece(b, m - 1)};
            bool ok = true;
            for (int k = 0; k < 3 && ok; ++k) {
                if (pieces[k].size() == 2) parts[k].push_back({});
                else if (pieces[k].size() % 2 == 0) quadrangulations(pieces[k], parts[k]);
                else ok = false;
            }
            if (!ok) continue;
            for (const auto &x : parts[0])
                for (const auto &y : parts[1])
                    for (const auto &z : parts[2]) {
                        std::vector<std::vector<int>> quads{{poly[0], poly[a], poly[b], poly[m - 1]}};
                        quads.insert(quads.end(), x.begin(), x.end());
                        quads.insert(quads.end(), y.begin(), y.end());
                        quads.insert(quads.end(), z.begin(), z.end());
                        out.push_back(std::move(quads));
                    }
        }
}


/// Dislocation pairs. The position field leaves dislocations, each a triangle
/// with a valence-5 corner where the lattice gains a row; two of opposite sign a
/// quad or two apart cancel. For each triangle, the triangles reachable through
/// at most kMaxQuads quads are tried: the union of the chain of faces (a polygon
/// of an even number of corners, no vertex inside) is cut into quads again, in
/// the way that lowers Σ (valence − 4)² over its corners the most, counting each
/// triangle removed as 1 and keeping every new corner convex and between
/// kMinQuadCorner and 180° − kMinQuadCorner about the union's normal. Greedy in face
/// order (the same result for any thread count); the faces replaced cover the
/// same polygon, so the mesh stays closed, manifold and oriented. N = 4 only.
void cancelDislocationPairs(std::vector<std::vector<int>> &polygons, const std::vector<Vec3> &positions,
                            std::map<std::string, int> &repairs) {
    constexpr int kMaxQuads = 3;
    const int nV = int(positions.size());
    const auto key = directedEdgeKey;
    std::unordered_map<uint64_t, int> faceOfEdge; // directed edge -> face
    std::vector<std::set<int>> nb(nV);
    std::vector<char> alive(polygons.size(), 1);
    auto link = [&](int f, bool add) {
        const auto &P = polygons[f];
        for (size_t k = 0; k < P.size(); ++k) {
            const int a = P[k], b = P[(k + 1) % P.size()];
            if (add) {
                faceOfEdge[key(a, b)] = f;
                nb[a].insert(b);
                nb[b].insert(a);
            } else {
                faceOfEdge.erase(key(a, b));
                if (!faceOfEdge.count(key(b, a))) nb[a].erase(b), nb[b].erase(a);
            }
        }
    };
    for (int f = 0; f < int(polygons.size()); ++f) link(f, true);
    const auto cost = valenceCost;
    auto position = [&](int v) -> const Vec3 & { return positions[size_t(v)]; };
    auto goodQuad = [&](const std::vector<int> &P, const Vec3 &nrm) { return worstCornerDeviation(P, position, nrm) >= 0; };
    // The boundary of a set of faces as one loop, or empty if it is not one simple
    // loop through all their corners.
    auto unionLoop = [&](const std::vector<int> &faces) {
        std::map<int, int> next;
        std::set<int> corners;
        std::set<uint64_t> inside;
        for (int f : faces)
            for (size_t k = 0; k < polygons[f].size(); ++k)
                inside.insert(key(polygons[f][k], polygons[f][(k + 1) % polygons[f].size()]));
        for (int f : faces)
            for (size_t k = 0; k < polygons[f].size(); ++k) {
                const int a = polygons[f][k], b = polygons[f][(k + 1) % polygons[f].size()];
                corners.insert(a);
                if (inside.count(key(b, a))) continue;
                if (next.count(a)) return std::vector<int>{};
                next[a] = b;
            }
        if (next.size() != corners.size()) return std::vector<int>{};
        std::vector<int> loop{next.begin()->first};
        while (int(loop.size()) <= int(next.size())) {
            const int b = next[loop.back()];
            if (b == loop.front()) break;
            loop.push_back(b);
        }
        if (loop.size() != next.size()) return std::vector<int>{};
        return loop;
    };
    int cancelled = 0;
    for (int t = 0; t < int(polygons.size()); ++t) {
        if (!alive[t] || polygons[t].size() != 3) continue;
        // Chains t, q1, .., qk, t2 through quads (breadth first, in edge order).
        std::vector<std::vector<int>> chains{{t}}, found;
        for (size_t c = 0; c < chains.size(); ++c) {
            const std::vector<int> chain = chains[c];
            const std::vector<int> &last = polygons[chain.back()];
            for (size_t k = 0; k < last.size(); ++k) {
                const auto it = faceOfEdge.find(key(last[(k + 1) % last.size()], last[k]));
                if (it == faceOfEdge.end() || !alive[it->second]) continue;
                const int g = it->second;
                if (std::find(chain.begin(), chain.end(), g) != chain.end()) continue;
                std::vector<int> longer = chain;
                longer.push_back(g);
                if (polygons[g].size() == 3 && chain.size() >= 2) found.push_back(longer);
                else if (polygons[g].size() == 4 && int(chain.size()) <= kMaxQuads) chains.push_back(longer);
            }
        }
        double bestGain = 0;
        std::vector<int> bestChain;
        std::vector<std::vector<int>> bestQuads;
        for (const std::vector<int> &chain : found) {
            const std::vector<int> loop = unionLoop(chain);
            if (loop.size() < 6 || loop.size() % 2) continue;
            // Valences without the union's inner edges, and the cost before.
            std::map<int, int> outer;
            double before = 0;
            for (int v : loop) {
                int inner = 0;
                for (int u : nb[v])
                    if (faceOfEdge.count(key(v, u)) && faceOfEdge.count(key(u, v)) &&
                        std::find(chain.begin(), chain.end(), faceOfEdge[key(v, u)]) != chain.end() &&
                        std::find(chain.begin(), chain.end(), faceOfEdge[key(u, v)]) != chain.end())
                        ++inner;
                outer[v] = int(nb[v].size()) - inner;
                before += cost(int(nb[v].size()));
            }
            Vec3 nrm = Vec3::Zero();
            for (size_t i = 0; i < loop.size(); ++i)
                nrm += positions[loop[i]].cross(positions[loop[(i + 1) % loop.size()]]);
            if (!(nrm.norm() > 0)) continue;
            nrm.normalize();
            std::vector<std::vector<std::vector<int>>> options;
            quadrangulations(loop, options);
            for (const auto &quads : options) {
                std::map<int, int> added;
                bool ok = true;
                for (const auto &q : quads) {
                    if (!goodQuad(q, nrm)) ok = false;
                    for (int k = 0; k < 4 && ok; ++k) {
                        const int a = q[k], b = q[(k + 1) % 4];
                        // a side of q that is not a side of the loop is a diagonal (counted from both quads)
                        const size_t ia = size_t(std::find(loop.begin(), loop.end(), a) - loop.begin());
                        if (loop[(ia + 1) % loop.size()] == b) continue;
                        if (nb[a].count(b) && outer[a] == int(nb[a].size())) ok = false; // already an outer edge
                        ++added[a];
                    }
                }
                if (!ok) continue;
                double after = 0;
                for (int v : loop) after += cost(outer[v] + added[v]);
                if (before - after > std::max(bestGain, 0.5)) bestGain = before - after, bestChain = chain, bestQuads = quads;
            }
        }
        if (bestChain.empty()) continue;
        for (int f : bestChain) link(f, false);
        for (size_t k = 0; k < bestChain.size(); ++k) {
            const int f = bestChain[k];
            if (k < bestQuads.size()) {
                polygons[f] = bestQuads[k];
                link(f, true);
            } else {
                alive[f] = 0;
                polygons[f].clear();
            }
        }
        ++cancelled;
    }
    std::vector<std::vector<int>> kept;
    for (size_t f = 0; f < polygons.size(); ++f)
        if (alive[f]) kept.push_back(std::move(polygons[f]));
    polygons.swap(kept);
    repairs["dislocation_pairs_cancelled"] = cancelled;
}

/// Optional rounds of tangential smoothing: each vertex moves halfway to the mean of
/// its neighbours within its tangent plane (the normal part of that step removed, so
/// that a tip or a ridge is not pulled inward), then back onto the input surface.
void relaxVertices(const std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions, const AabbTree &tree,
                   int rounds, std::map<std::string, int> &repairs,
                   const std::function<void(size_t, Vec3 &)> &constrain = {}) {
    std::vector<std::vector<int>> nb(positions.size());
    for (const auto &poly : polygons)
        for (size_t k = 0; k < poly.size(); ++k) {
            nb[poly[k]].push_back(poly[(k + 1) % poly.size()]);
            nb[poly[(k + 1) % poly.size()]].push_back(poly[k]);
        }
    for (auto &list : nb) {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    for (int r = 0; r < rounds; ++r) {
        // Vertex normals: the polygons' vector areas (Newell) summed at their corners.
        std::vector<Vec3> normal(positions.size(), Vec3::Zero());
        for (const auto &poly : polygons) {
            const Vec3 area = vectorArea(poly, positions);
            for (int v : poly) normal[v] += area;
        }
        std::vector<Vec3> next = positions;
        for (size_t v = 0; v < positions.size(); ++v) {
            if (nb[v].empty()) continue;
            Vec3 mean = Vec3::Zero();
            for (int u : nb[v]) mean += positions[u];
            mean /= double(nb[v].size());
            Vec3 step = 0.5 * (mean - positions[v]);
            const double nn = normal[v].norm();
            if (nn > 0) step -= normal[v] * (normal[v].dot(step) / (nn * nn));
            next[v] = tree.closest(positions[v] + step).point;
            if (constrain) constrain(v, next[v]);
        }
        positions.swap(next);
    }
    repairs["relaxation_rounds"] = rounds;
}

/// Input vertices farther than this many L from the output surface are protrusions.
constexpr double kSnapDistance = 0.25;
/// A snapped vertex keeps its edges at most this many L long.
constexpr double kSnapMaxEdge = 1.5;
/// ... and turns none of its polygons by more than this angle's cosine (60°).
constexpr double kSnapMinCos = 0.5;

/// Output vertices snapped onto the input's protrusions. A tip or a thin ridge about
/// L wide (an ear's tip, a tail) is cut off by the faces spanning it when no lattice
/// point falls on it, however well the rest is placed. Each input vertex farther than
/// kSnapDistance L from the output (farthest first, ties by index) pulls a corner of
/// the output triangle nearest to it onto itself: the nearest corner that is free (not
/// moved already, not `fixed`) and whose move turns none of its polygons by more than
/// 60° (Newell normals before and after), keeps its edges at most kSnapMaxEdge L and
/// leaves none of the input vertices whose nearest triangle it is a corner of farther
/// from its polygons than they were from the output (or than the reach); input
/// vertices the moves have already brought within reach (checked
/// against the polygons around the nearest triangle's corners) are passed over. The
/// output stays on the input surface: vertices move onto input vertices.
void snapToProtrusions(const std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                       const field::Mesh &input, double L, const std::function<bool(size_t)> &fixed,
                       std::map<std::string, int> &repairs) {
    std::vector<std::array<int, 3>> tris;
    for (const auto &poly : polygons)
        for (size_t k = 1; k + 1 < poly.size(); ++k) tris.push_back({poly[0], poly[k], poly[k + 1]});
    int snapped = 0;
    if (tris.empty()) {
        repairs["protrusion_vertices_snapped"] = snapped;
        return;
    }
    const AabbTree out(positions, tris);
    const int nIn = input.nVertices();
    std::vector<double> dist(size_t(nIn), 0.0);
    std::vector<int> nearTri(size_t(nIn), -1);
    const double reach = kSnapDistance * L;
    parallelFor(0, nIn, [&](int64_t i) {
        const ClosestPoint c = out.closest(input.position(int(i)));
        dist[size_t(i)] = std::sqrt(c.distance2);
        nearTri[size_t(i)] = c.triangle;
    }, 256);
    std::vector<int> far;
    for (int i = 0; i < nIn; ++i)
        if (dist[size_t(i)] > reach && nearTri[size_t(i)] >= 0) far.push_back(i);
    std::sort(far.begin(), far.end(), [&](int a, int b) {
        return dist[size_t(a)] != dist[size_t(b)] ? dist[size_t(a)] > dist[size_t(b)] : a < b;
    });
    std::vector<std::vector<int>> around(positions.size()); // polygons at each vertex
    for (size_t f = 0; f < polygons.size(); ++f)
        for (int v : polygons[f]) around[size_t(v)].push_back(int(f));
    auto distanceToPolygonsAt = [&](const Vec3 &x, int v) {
        double best = std::numeric_limits<double>::infinity();
        for (int f : around[size_t(v)]) {
            const auto &poly = polygons[size_t(f)];
            for (size_t k = 1; k + 1 < poly.size(); ++k)
                best = std::min(best, (x - closestPointOnTriangle(x, positions[poly[0]], positions[poly[k]],
                                                                 positions[poly[k + 1]]))
                                          .norm());
        }
        return best;
    };
    // The input vertices whose nearest output triangle has corner v: a move of v must
    // not leave any of them farther than it was (or than the reach).
    std::vector<std::vector<int>> near(positions.size());
    for (int i = 0; i < nIn; ++i)
        if (nearTri[size_t(i)] >= 0)
            for (int c : tris[size_t(nearTri[size_t(i)])]) near[size_t(c)].push_back(i);
    std::vector<char> moved(positions.size(), 0);
    for (int i : far) {
        const Vec3 x = input.position(i);
        const std::array<int, 3> &t = tris[size_t(nearTri[size_t(i)])];
        bool reached = false;
        for (int c : t)
            if (moved[size_t(c)] && distanceToPolygonsAt(x, c) <= reach) reached = true;
        if (reached) continue;
        // The triangle's corners nearest first; the first that can move does.
        std::array<int, 3> corners = t;
        std::sort(corners.begin(), corners.end(), [&](int a, int b) {
            const double da = (positions[a] - x).squaredNorm(), db = (positions[b] - x).squaredNorm();
            return da != db ? da < db : a < b;
        });
        int w = -1;
        for (int c : corners) {
            if (moved[size_t(c)] || (fixed && fixed(size_t(c)))) continue;
            const Vec3 old = positions[c];
            std::vector<Vec3> before;
            for (int f : around[size_t(c)]) before.push_back(vectorArea(polygons[size_t(f)], positions));
            positions[c] = x;
            bool ok = true;
            for (size_t k = 0; ok && k < around[size_t(c)].size(); ++k) {
                const auto &poly = polygons[size_t(around[size_t(c)][k])];
                const Vec3 after = vectorArea(poly, positions);
                if (after.dot(before[k]) <= kSnapMinCos * after.norm() * before[k].norm()) ok = false;
                for (size_t j = 0; ok && j < poly.size(); ++j)
                    if (poly[j] == c && ((positions[poly[(j + 1) % poly.size()]] - x).norm() > kSnapMaxEdge * L ||
                                         (positions[poly[(j + poly.size() - 1) % poly.size()]] - x).norm() >
                                             kSnapMaxEdge * L))
                        ok = false;
            }
            for (size_t k = 0; ok && k < near[size_t(c)].size(); ++k) {
                const int j = near[size_t(c)][k];
                if (distanceToPolygonsAt(input.position(j), c) > std::max(dist[size_t(j)], reach)) ok = false;
            }
            if (ok) {
                w = c;
                break;
            }
            positions[c] = old;
        }
        if (w < 0) continue;
        moved[size_t(w)] = 1;
        ++snapped;
    }
    repairs["protrusion_vertices_snapped"] = snapped;
}

/// Rounds of the distance repair.
constexpr int kFarRounds = 4;
/// A fan triangle whose apex is closer than this many L to its base edge is not made.
constexpr double kFanMinHeight = 0.1;
/// A flipped polygon's diagonal shorter than this many L is collapsed
/// (collapseFoldedDiagonals): a quad folded over a thin part (elk: 0.22 L).
constexpr double kFoldedDiagonal = 0.5;

/// Where the line through p along unit n meets the input surface nearest to p:
/// marching out from p both ways in steps of L/20 up to 1.5 L, the closest input
/// point of the first march point within L/20 of the input (else nothing).
std::optional<Vec3> surfaceAlong(const AabbTree &inputTree, const Vec3 &p, const Vec3 &n, double L) {
    for (int k = 0; k <= 30; ++k)
        for (int sign : {-1, 1}) {
            if (k == 0 && sign > 0) continue;
            const ClosestPoint cp = inputTree.closest(p + n * (sign * k * L / 20));
            if (cp.triangle >= 0 && cp.distance2 < L * L / 400) return cp.point;
        }
    return std::nullopt;
}

/// The cut of polygon H by a diagonal from its corner i into two parts whose corners
/// are nearest 90° (a triangle's 60°), each facing the input and none farther from
/// it than `limit`; empty if there is none.
std::vector<std::vector<int>> cutFrom(const std::vector<int> &H, int i, const std::vector<Vec3> &positions,
                                      const field::Mesh &input, const AabbTree &inputTree, double L, double limit) {
    const int n = int(H.size());
    double bestCost = std::numeric_limits<double>::infinity();
    std::vector<std::vector<int>> best;
    for (int d = 2; d <= n - 2; ++d) {
        std::vector<int> A, B;
        for (int k = 0; k <= d; ++k) A.push_back(H[size_t((i + k) % n)]);
        for (int k = d; k <= n; ++k) B.push_back(H[size_t((i + k) % n)]);
        double cost = 0;
        bool ok = true;
        for (const auto *part : {&A, &B}) {
            const auto &poly = *part;
            ok = ok && facesInput(poly, positions, input, inputTree) &&
                 farthestFromInput(poly, positions, inputTree, L) <= limit;
            const size_t m = poly.size();
            const double ideal = m == 3 ? 60 : 90;
            for (size_t k = 0; k < m; ++k) {
                const Vec3 u = positions[poly[(k + m - 1) % m]] - positions[poly[k]],
                           v = positions[poly[(k + 1) % m]] - positions[poly[k]];
                const double c = u.dot(v) / std::max(u.norm() * v.norm(), 1e-300);
                cost = std::max(cost, std::abs(std::acos(std::clamp(c, -1.0, 1.0)) * 180 / std::numbers::pi - ideal));
            }
        }
        if (ok && cost < bestCost) bestCost = cost, best = {A, B};
    }
    return best;
}



/// The two-sided distance held: after the snapping, what is still farther than
/// kFarDistance L from the other surface gets a vertex of its own, in rounds:
/// 1. **Edges over a groove.** An output edge whose midpoint is far from the input
///    spans a groove or a crease the lattice stepped over; the point where the line
///    through the midpoint along the edge's normal (its faces' vector areas) meets
///    the input is put into the edge, farthest first, in both its faces, when neither
///    then faces away from the input (the report's flipped test) and neither passes
///    six sides. A quad split on two opposite sides is cut into two quads across the
///    groove, so a row of quads over it gains a row of vertices along its bottom.
/// 2. **Points inside a face.** An input vertex far from the output (a dimple, a tip
///    the snap could not reach), or a far sample of an output triangle (step L/3, as
///    the report samples; its point is where the line along the triangle's normal
///    meets the input), goes into the output polygon nearest to it (for a sample: its
///    own), which is replaced by the fan of triangles from the point to its sides —
///    if no fan triangle faces away from the input and none is thinner than
///    kFanMinHeight L. The farthest point of each polygon, farthest first, one per
///    polygon and round.
///    A far quad no fan mends is cut along a diagonal instead (no new vertex): a quad
///    folded over a rim or a ridge narrower than the lattice, its diagonal along the
///    ridge and its other corners down either side, leaves its middle inside the part;
///    its two triangles lie on the two sides (bunny00's ear at L = 0.98 %).
/// Both keep the mesh closed, manifold and oriented (the new faces cover the old).
void holdDistance(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions, const field::Mesh &input,
                  const AabbTree &inputTree, double L, const std::function<bool(size_t)> &fixed,
                  std::map<std::string, int> &repairs,
                  const std::function<bool(int, int)> &alongFeature = {}) {
    // An edge between two feature vertices is a piece of a feature curve — not split,
    // not joined across — unless `alongFeature` says it runs off the curves (a chord
    // across a tip between two of its creases); without it every such edge is one.
    auto featureEdge = [&](int a, int b) {
        return fixed && fixed(size_t(a)) && fixed(size_t(b)) && (!alongFeature || alongFeature(a, b));
    };
    const double reach = kFarDistance * L;
    int edgesSplit = 0, fanned = 0, quadsCut = 0, left = 0, cornersMoved = 0, fannedWithNeighbour = 0;
    const auto key = directedEdgeKey;
    for (int round = 0; round < kFarRounds; ++round) {
        int made = 0;
        // --- 1. edges over a groove
        std::unordered_map<uint64_t, int> edgePoly; // directed edge -> polygon
        std::vector<std::pair<int, int>> edges;     // undirected, a < b, first seen order
        for (size_t f = 0; f < polygons.size(); ++f)
            for (size_t k = 0; k < polygons[f].size(); ++k) {
                const int a = polygons[f][k], b = polygons[f][(k + 1) % polygons[f].size()];
                edgePoly[key(a, b)] = int(f);
                if (a < b) edges.push_back({a, b});
            }
        // Each edge's farthest point from the input, sampled at most L/3 apart (as the
        // report samples the faces), the midpoint first: a groove under one end of a
        // long edge leaves its midpoint near.
        std::vector<double> edgeDist(edges.size(), 0.0), edgeAt(edges.size(), 0.5);
        parallelFor(0, int64_t(edges.size()), [&](int64_t e) {
            const auto [a, b] = edges[size_t(e)];
            const Vec3 &pa = positions[a], d = positions[b] - positions[a];
            edgeDist[size_t(e)] = std::sqrt(inputTree.closest(pa + 0.5 * d).distance2);
            const int k = std::clamp(int(std::ceil(d.norm() / (L / 3))), 2, 64);
            for (int i = 1; i < k; ++i) {
                if (2 * i == k) continue; // the midpoint, done
                const double t = double(i) / k;
                const double dist = std::sqrt(inputTree.closest(pa + t * d).distance2);
                if (dist > edgeDist[size_t(e)]) edgeDist[size_t(e)] = dist, edgeAt[size_t(e)] = t;
            }
        }, 256);
        std::vector<int> farEdges;
        for (size_t e = 0; e < edges.size(); ++e)
            if (edgeDist[e] > reach && edgePoly.count(key(edges[e].second, edges[e].first)) &&
                !featureEdge(edges[e].first, edges[e].second))
                farEdges.push_back(int(e));
        std::sort(farEdges.begin(), farEdges.end(), [&](int a, int b) {
            return edgeDist[size_t(a)] != edgeDist[size_t(b)] ? edgeDist[size_t(a)] > edgeDist[size_t(b)] : a < b;
        });
        std::vector<char> touched(polygons.size(), 0);
        auto at = [](const std::vector<int> &poly, int u, int v) {
            for (size_t k = 0; k < poly.size(); ++k)
                if (poly[k] == u && poly[(k + 1) % poly.size()] == v) return int(k);
            return -1;
        };
        for (int e : farEdges) {
            const auto [a, b] = edges[size_t(e)];
            const int fab = edgePoly[key(a, b)], fba = edgePoly[key(b, a)];
            if (fab == fba || touched[size_t(fab)] || touched[size_t(fba)]) continue;
            const std::vector<int> &P = polygons[size_t(fab)], &Q = polygons[size_t(fba)];
            const int kp = at(P, a, b), kq = at(Q, b, a);
            if (kp < 0 || kq < 0) continue;
            const Vec3 n = vectorArea(P, positions) + vectorArea(Q, positions);
            if (!(n.squaredNorm() > 0)) continue;
            const std::optional<Vec3> h =
                surfaceAlong(inputTree, positions[a] + edgeAt[size_t(e)] * (positions[b] - positions[a]), n.normalized(), L);
            if (!h) continue;
            // The new vertex x goes into both faces, each then cut by a diagonal from
            // x (so x has four edges); the parts must come nearer the input.
            const double before = std::max(farthestFromInput(P, positions, inputTree, L),
                                           farthestFromInput(Q, positions, inputTree, L));
            const double limit = std::max(reach, 0.9 * before);
            const int x = int(positions.size());
            positions.push_back(*h);
            std::vector<int> P2 = P, Q2 = Q;
            P2.insert(P2.begin() + kp + 1, x);
            Q2.insert(Q2.begin() + kq + 1, x);
            const auto cutP = cutFrom(P2, kp + 1, positions, input, inputTree, L, limit);
            const auto cutQ = cutFrom(Q2, kq + 1, positions, input, inputTree, L, limit);
            if (cutP.empty() || cutQ.empty()) {
                positions.pop_back();
                continue;
            }
            polygons[size_t(fab)] = cutP[0], polygons[size_t(fba)] = cutQ[0];
            polygons.push_back(cutP[1]), polygons.push_back(cutQ[1]);
            touched[size_t(fab)] = touched[size_t(fba)] = 1;
            touched.push_back(1), touched.push_back(1);
            ++edgesSplit, ++made;
        }

        // --- 2. points inside a face
        std::vector<std::array<int, 3>> tris;
        std::vector<int> polyOf;
        for (size_t f = 0; f < polygons.size(); ++f)
            for (size_t k = 1; k + 1 < polygons[f].size(); ++k) {
                tris.push_back({polygons[f][0], polygons[f][k], polygons[f][k + 1]});
                polyOf.push_back(int(f));
            }
        if (tris.empty()) break;
        const AabbTree out(positions, tris);
        const int nIn = input.nVertices();
        std::vector<double> inDist(size_t(nIn), 0.0);
        std::vector<int> inPoly(size_t(nIn), -1);
        parallelForRange(0, nIn, [&](int64_t lo, int64_t hi) {
            int hint = -1;
            for (int64_t i = lo; i < hi; ++i) {
                const ClosestPoint c = out.closest(input.position(int(i)), hint);
                hint = c.triangle;
                inDist[size_t(i)] = std::sqrt(c.distance2);
                inPoly[size_t(i)] = c.triangle >= 0 ? polyOf[size_t(c.triangle)] : -1;
            }
        });
        std::vector<double> outDist(tris.size(), 0.0);
        std::vector<Vec3> outSample(tris.size(), Vec3::Zero()), outClosest(tris.size(), Vec3::Zero());
        parallelFor(0, int64_t(tris.size()), [&](int64_t t) {
            const auto &tri = tris[size_t(t)];
            int hint = -1;
            forEachSample(positions[tri[0]], positions[tri[1]], positions[tri[2]], L, [&](const Vec3 &p) {
                const ClosestPoint cp = inputTree.closest(p, hint);
                hint = cp.triangle;
                const double d = std::sqrt(cp.distance2);
                if (d > outDist[size_t(t)])
                    outDist[size_t(t)] = d, outSample[size_t(t)] = p, outClosest[size_t(t)] = cp.point;
            });
        }, 16);
        std::vector<double> worst(polygons.size(), 0.0);
        std::vector<std::vector<Vec3>> target(polygons.size()); // points to try, in order
        std::vector<char> outputFar(polygons.size(), 0);          // its worst: a sample of its own
        for (int i = 0; i < nIn; ++i) {
            const int f = inPoly[size_t(i)];
            if (f >= 0 && inDist[size_t(i)] > reach && inDist[size_t(i)] > worst[size_t(f)])
                worst[size_t(f)] = inDist[size_t(i)], target[size_t(f)] = {input.position(i)};
        }
        for (size_t t = 0; t < tris.size(); ++t) {
            const size_t f = size_t(polyOf[t]);
            if (!(outDist[t] > reach) || !(outDist[t] > worst[f])) continue;
            const Vec3 &a = positions[tris[t][0]], &b = positions[tris[t][1]], &c = positions[tris[t][2]];
            const Vec3 nt = (b - a).cross(c - a);
            if (!(nt.squaredNorm() > 0)) continue;
            worst[f] = outDist[t];
            outputFar[f] = 1;
            target[f].clear();
            if (const std::optional<Vec3> h = surfaceAlong(inputTree, outSample[t], nt.normalized(), L))
                target[f].push_back(*h);
            target[f].push_back(outClosest[t]); // a rim the normal's line runs past
        }
        std::vector<int> order;
        for (size_t f = 0; f < polygons.size(); ++f)
            if (worst[f] > 0) order.push_back(int(f));
        std::sort(order.begin(), order.end(), [&](int a, int b) {
            return worst[size_t(a)] != worst[size_t(b)] ? worst[size_t(a)] > worst[size_t(b)] : a < b;
        });
        left = 0;
        for (int f : order) {
            if (touched[size_t(f)]) {
                ++left;
                continue;
            }
            const std::vector<int> poly = polygons[size_t(f)];
            const int xi = int(positions.size());
            std::vector<std::vector<int>> fan;
            bool ok = false;
            // A far sample of the polygon's own must come nearer; a far input point
            // (a gap on the other side) is mended by faces no farther than the polygon was.
            const double limit =
                std::max(reach, (outputFar[size_t(f)] ? 0.9 : 1.0) * farthestFromInput(poly, positions, inputTree, L));
            // First a corner moved onto the point (no new vertex, no new face).
            {
                int moved = -1;
                std::vector<int> around;
                for (const Vec3 &x : target[size_t(f)]) {
                    moved = moveCornerOnto(poly, x, polygons, positions, input, inputTree, L, limit, fixed,
                                           [&](int g) { return !touched[size_t(g)]; }, around);
                    if (moved >= 0) break;
                }
                if (moved >= 0) {
                    for (int g : around) touched[size_t(g)] = 1;
                    ++cornersMoved, ++made;
                    continue;
                }
            }
            for (const Vec3 &x : target[size_t(f)]) {
                positions.push_back(x);
                fan = soundFan(poly, xi, positions, input, inputTree, L, kFanMinHeight * L, limit);
                ok = !fan.empty();
                if (ok) break;
                positions.pop_back();
            }
            // No fan: a far quad is cut along a diagonal if that brings it nearer (no new
            // vertex). Only for a sample of its own: a cut leaving the quad's own samples
            // near would be taken without bringing a far input vertex nearer.
            bool cut = false;
            if (!ok && outputFar[size_t(f)]) {
                fan = cutFarQuad(poly, positions, input, inputTree, L, kFanMinHeight * L, limit);
                cut = !fan.empty();
            }
            if (!ok && !cut) { // the far region may lie across a side: fanned with the neighbour there
                const JoinedFan joined = fanAcrossSide(
                    f, target[size_t(f)], polygons, positions,
                    [&](int a, int b) { // a crease's side stays (both ends on a feature curve)
                        if (featureEdge(a, b)) return -1;
                        const auto it = edgePoly.find(key(a, b));
                        return it == edgePoly.end() ? -1 : it->second;
                    },
                    [&](int g) { return !touched[size_t(g)]; }, input, inputTree, L, kFanMinHeight * L, limit);
                if (joined.neighbour < 0) {
                    ++left;
                    continue;
                }
                touched[size_t(f)] = touched[size_t(joined.neighbour)] = 1;
                polygons[size_t(f)] = joined.faces[0];
                polygons[size_t(joined.neighbour)] = joined.faces[1];
                for (size_t k = 2; k < joined.faces.size(); ++k) polygons.push_back(joined.faces[k]), touched.push_back(1);
                ++fannedWithNeighbour, ++made;
                continue;
            }
            touched[size_t(f)] = 1;
            polygons[size_t(f)] = fan[0];
            for (size_t k = 1; k < fan.size(); ++k) polygons.push_back(fan[k]), touched.push_back(1);
            ++(cut ? quadsCut : fanned), ++made;
        }
        if (made == 0) break;
    }
    repairs["far_edges_split"] = edgesSplit;
    repairs["far_points_fanned"] = fanned;
    repairs["far_points_corner_moved"] = cornersMoved;
    repairs["far_points_left"] = left;
    repairs["far_quads_cut"] = quadsCut;
    repairs["far_points_fanned_with_neighbour"] = fannedWithNeighbour;
}

// `move`, the default, is DislocationOptions' own defaults: one set of numbers, held
// together here (RemeshOptions cannot name DislocationOptions in its public header).
static_assert(RemeshOptions{}.dislocationReach == DislocationOptions{}.reach &&
                  RemeshOptions{}.dislocationConePenalty == DislocationOptions{}.conePenalty &&
                  RemeshOptions{}.dislocationConeReach == DislocationOptions{}.coneReach &&
                  RemeshOptions{}.dislocationAnchor == DislocationOptions{}.anchor,
              "RemeshOptions' dislocation defaults (`move`) must be DislocationOptions' defaults");

} // namespace

void setDislocationMode(RemeshOptions &options, DislocationMode mode) {
    const RemeshOptions defaults;
    options.dislocationReach = mode == DislocationMode::Keep     ? 0.0
                               : mode == DislocationMode::Remove ? kDislocationReachRemove
                                                                 : kDislocationReachMove;
    const bool remove = mode == DislocationMode::Remove;
    options.dislocationConePenalty = remove ? kDislocationConePenaltyRemove : defaults.dislocationConePenalty;
    options.dislocationConeReach = remove ? kDislocationConeReachRemove : defaults.dislocationConeReach;
    options.dislocationAnchor = remove ? kDislocationAnchorRemove : defaults.dislocationAnchor;
}

RemeshResult remesh(const field::TangentFrames &frames, const field::RosyField &field,
                    const field::SingularityReport &singularities, const RemeshOptions &options) {
    if (field.nSym != 4 && field.nSym != 6)
        throw InputError(FileLoc{"--symmetry"},
                         "remeshing needs a 4-RoSy (quads) or 6-RoSy (triangles) field, got N = " +
                             std::to_string(field.nSym),
                         "use --symmetry 4 or 6");
    if (!(options.edgeLength > 0) || !std::isfinite(options.edgeLength))
        throw InputError(FileLoc{"--edge"}, "the edge length must be positive and finite", "e.g. --edge 0.01");
    const field::Mesh &mesh = frames.mesh();
    RemeshResult result;
    result.nSym = field.nSym;
    const Lattice lat{field.nSym, options.edgeLength};

    // --- hierarchy
    auto t0 = Clock::now();
    std::vector<Level> levels;
    std::vector<std::pair<int, Vec3>> pinFaces;
    if (options.separatrices)
        for (const field::Singularity &sg : singularities.singularities)
            if (std::abs(sg.indexNumerator) == 1) pinFaces.emplace_back(sg.face, sg.position);
    int subdivisions = 0, longEdgesSplit = 0;
    field::FeatureCurves curves;
    if (options.featureAngleDeg > 0) {
        // creases shorter than 2 L are noise at this scale (elephant at 1 %: 448 corners
        // of mostly one- or two-edge creases without it)
        curves = field::findFeatureCurves(mesh, options.featureAngleDeg, kMinFeatureLength * options.edgeLength);
        result.repairs["feature_edges"] = int(curves.edges.size());
        result.repairs["feature_boundary_edges"] = curves.boundaryEdges;
        result.repairs["feature_corners"] = int(std::count(curves.corner.begin(), curves.corner.end(), 1));
    }
    // The scale functions are solved on the input's vertices (a sparse Cholesky
    // factorisation: one thread) while this thread subdivides, coarsens, colours and
    // builds the closest-point tree, none of which reads them: the subdivision's
    // vertices take the mean of their edge's ends afterwards, and the spacings are
    // set level by level once the functions are known. The same arithmetic in the
    // same order as one after the other, so the same bytes for any thread count.
    Level input; // the input's p, n, q, copied: the subdivision grows the finest level's arrays
    std::vector<std::array<int, 3>> inputTris;
    std::vector<double> phi, phiA;
    std::vector<Midpoint> midpoints;
    std::vector<std::vector<std::vector<int>>> classesOf; // colour classes per level
    std::vector<SweepPlan> plans;                         // per level (N = 4)
    std::optional<AabbTree> surface;
    surface.emplace(mesh);
    // Spacing caps of thin parts, per input vertex; finestLevel carries them to its
    // own vertices.
    int thinVertices = 0;
    const auto tt = Clock::now();
    std::vector<double> sizing = options.thinParts
                                     ? thinPartSpacing(frames, *surface, lat.s, thinVertices)
                                     : std::vector<double>(size_t(mesh.nVertices()), 2.0 * lat.s);
    result.repairs["thin_part_vertices"] = thinVertices;
    result.timingsMs["thin_parts"] = msSince(tt); // part of the hierarchy's
    {
        tbb::task_group scaleSolve;
        auto startScaleSolve = [&](const Level &in, const std::vector<std::array<int, 3>> &tris) {
            input.p = in.p, input.n = in.n, input.q = in.q;
            inputTris = tris;
            scaleSolve.run([&] {
                const size_t nV0 = input.p.size();
                phi = options.scaleStrength > 0 ? scaleFunction(input, inputTris, lat) : std::vector<double>(nV0, 0.0);
                phiA = options.anisotropicScale > 0 && lat.nSym == 4 ? anisotropicScale(input, inputTris)
                                                                     : std::vector<double>(2 * nV0, 0.0);
            });
        };
        try {
            levels.push_back(finestLevel(frames, field, lat, pinFaces, options.maxVertices,
                                         curves.empty() ? nullptr : &curves, startScaleSolve, midpoints, subdivisions,
                                         longEdgesSplit, sizing));
            while (levels.back().size() > 64 && levels.size() < 40) {
                Level next = coarsen(levels.back());
                if (next.size() > 0.95 * levels.back().size()) {
                    levels.back().toCoarse.clear();
                    break;
                }
                levels.push_back(std::move(next));
            }
            for (const Level &L : levels) {
                classesOf.push_back(colourClasses(L));
                plans.push_back(lat.nSym == 4 ? planSweeps(L, classesOf.back()) : SweepPlan{});
            }
        } catch (...) {
            scaleSolve.wait(); // it reads this function's locals
            throw;
        }
        scaleSolve.wait();
    }
    result.repairs["input_subdivisions"] = subdivisions;
    result.repairs["long_edges_split"] = longEdgesSplit;
    finestSpacings(levels[0], std::move(phi), std::move(phiA), midpoints, lat, options.scaleStrength,
                   options.anisotropicScale, sizing);
    for (size_t l = 0; l + 1 < levels.size(); ++l) coarsenSpacings(levels[l], levels[l + 1]);
    result.timingsMs["hierarchy"] = msSince(t0);

    // --- position field, coarse to fine
    t0 = Clock::now();
    Level &top = levels.back();
    for (int i = 0; i < top.size(); ++i)
        if (!top.pinned[i]) top.o[i] = top.p[i];
    std::vector<SweepNode> nodeBuffer; // reused level to level (fresh pages cost a fault each)
    for (int l = int(levels.size()) - 1; l >= 0; --l) {
        Level &L = levels[l];
        if (l + 1 < int(levels.size())) {
            const Level &C = levels[l + 1];
            parallelFor(0, L.size(), [&](int64_t i) {
                if (L.pinned[i]) return;
                const Vec3 &oc = C.o[L.toCoarse[i]];
                L.o[i] = oc - L.n[i] * L.n[i].dot(oc - L.p[i]);
            }, 4096);
        }
        const int sweeps = l == 0 ? options.finestSweeps : options.sweepsPerLevel;
        const std::vector<std::vector<int>> &classes = classesOf[size_t(l)];
        if (lat.nSym == 4) sweepSquares(L, plans[size_t(l)], sweeps, nodeBuffer);
        else
            for (int it = 0; it < sweeps; ++it) smoothPositions(L, lat, classes);
    }
    result.timingsMs["position"] = msSince(t0);

    // --- dislocations moved (N = 4): the offsets made consistent where it costs little
    if (lat.nSym == 4 && options.dislocationReach > 0) {
        const auto td = Clock::now();
        Level &Fm = levels[0];
        DislocationOptions dopt;
        dopt.reach = options.dislocationReach;
        dopt.conePenalty = options.dislocationConePenalty;
        dopt.coneReach = options.dislocationConeReach;
        dopt.anchor = options.dislocationAnchor;
        const DislocationStats ds = moveDislocations(
            DislocationInput{Fm.p, Fm.n, Fm.q, Fm.o, Fm.s, Fm.s2, Fm.adjOffset, Fm.adj, Fm.tris, Fm.pinned, Fm.onLine,
                             Fm.corner, lat.s},
            dopt);
        result.repairs["dislocations_before"] = ds.before;
        result.repairs["dislocations_moved"] = ds.moved;
        result.repairs["dislocations_left"] = ds.left;
        result.repairs["dislocations_beside_cones_before"] = ds.conesWithOneBefore;
        result.repairs["dislocations_beside_cones"] = ds.conesWithOne;
        result.repairs["dislocation_solve_iterations"] = ds.iterations;
        result.timingsMs["dislocations"] = msSince(td);
    }

    // --- extraction: collapse edges within one lattice point, keep unit edges
    t0 = Clock::now();
    const Level &F = levels[0];
    const int nV = F.size();
    field::UnionFind uf(nV);
    std::vector<std::pair<int, int>> unitEdges;
    // Each edge's lattice offset on its own (in parallel: 0 same point, 1 unit
    // edge, 2 neither), then united and listed in edge order as before.
    std::vector<char> edgeKind(F.adj.size(), 2);
    const SquareLattices lattices = squareLattices(F);
    parallelFor(0, nV, [&](int64_t iv) {
        const int i = int(iv);
        for (int k = F.adjOffset[i]; k < F.adjOffset[i + 1]; ++k) {
            const int j = F.adj[k];
            if (j <= i) continue;
            const Eigen::Vector2i d = lat.nSym == 4 ? squareOffset(lattices, i, j) : [&] {
                const Vec3 qj = lat.compatOrientation(F.q[i], F.q[j], F.n[j]);
                const Lattice li{lat.nSym, F.s[i]}, lj{lat.nSym, F.s[j]};
                const auto [oi, oj] = compatPosition(li, lj, F.p[i], F.n[i], F.q[i], F.o[i], F.p[j], F.n[j], qj, F.o[j]);
                return Eigen::Vector2i(lj.roundIndex(F.o[j] - oj, qj, F.n[j]) - li.roundIndex(F.o[i] - oi, F.q[i], F.n[i]));
            }();
            edgeKind[size_t(k)] = d.x() == 0 && d.y() == 0 ? 0 : lat.isUnit(d) ? 1 : 2;
        }
    }, 1024);
    for (int i = 0; i < nV; ++i)
        for (int k = F.adjOffset[i]; k < F.adjOffset[i + 1]; ++k) {
            const int j = F.adj[k];
            if (j <= i) continue;
            if (edgeKind[size_t(k)] == 0) uf.unite(i, j);
            else if (edgeKind[size_t(k)] == 1) unitEdges.emplace_back(i, j);
        }
    // Output vertices: one per cluster, numbered by their smallest member.
    std::vector<int> cluster(nV, -1);
    std::vector<Vec3> cp, cn, cq;
    std::vector<int> count;
    for (int i = 0; i < nV; ++i) {
        const int r = uf.find(i);
        if (cluster[r] < 0) {
            cluster[r] = int(cp.size());
            cp.push_back(Vec3::Zero());
            cn.push_back(Vec3::Zero());
            cq.push_back(F.q[i]);
            count.push_back(0);
        }
        const int c = cluster[i] = cluster[r];
        cp[c] += F.o[i];
        cn[c] += F.n[i] * F.area[i];
        ++count[c];
    }
    const int nC = int(cp.size());
    const AabbTree &tree = *surface;
    parallelFor(0, nC, [&](int64_t c) { cp[c] = tree.closest(cp[c] / count[c]).point; });
    // Features: an output vertex holding a feature corner goes onto it; one holding
    // vertices of a feature line goes to the mean of their lattice points (on their
    // lines) put on the nearest feature edge next to them; one holding input boundary
    // vertices is on the boundary (its opening is left open below).
    const bool features = !F.featureEdges.empty();
    std::vector<char> cKind(features ? size_t(nC) : 0, 0), cBoundary(features ? size_t(nC) : 0, 0);
    std::vector<int> cCorner(features ? size_t(nC) : 0, -1);
    std::vector<std::vector<int>> cSegments(features ? size_t(nC) : 0);
    // The point of feature edge e nearest x.
    auto onFeatureEdge = [&](const Vec3 &x, size_t e) {
        const Vec3 &a = F.p[F.featureEdges[e][0]], d = F.p[F.featureEdges[e][1]] - a;
        const double t = std::clamp((x - a).dot(d) / std::max(1e-300, d.squaredNorm()), 0.0, 1.0);
        return Vec3(a + t * d);
    };
    auto ontoSegments = [&](const Vec3 &x, const std::vector<int> &segs) {
        Vec3 best = x;
        double bestD = std::numeric_limits<double>::infinity();
        for (int e : segs) {
            const Vec3 y = onFeatureEdge(x, size_t(e));
            const double dist = (y - x).squaredNorm();
            if (dist < bestD) bestD = dist, best = y;
        }
        return best;
    };
    if (features) {
        std::vector<std::vector<int>> incident(static_cast<size_t>(nV));
        for (int e = 0; e < int(F.featureEdges.size()); ++e)
            for (int v : F.featureEdges[size_t(e)]) incident[size_t(v)].push_back(e);
        std::vector<Vec3> lineSum(static_cast<size_t>(nC), Vec3::Zero());
        std::vector<int> lineCount(static_cast<size_t>(nC), 0);
        for (int i = 0; i < nV; ++i) {
            const size_t c = size_t(cluster[i]);
            if (F.boundary[size_t(i)]) cBoundary[c] = 1;
            if (F.corner[size_t(i)] && cCorner[c] < 0) cCorner[c] = i;
            if (F.onLine[size_t(i)]) lineSum[c] += F.o[i], ++lineCount[c];
            for (int e : incident[size_t(i)]) cSegments[c].push_back(e);
        }
        for (int c = 0; c < nC; ++c) {
            std::vector<int> &segs = cSegments[size_t(c)];
            std::sort(segs.begin(), segs.end());
            segs.erase(std::unique(segs.begin(), segs.end()), segs.end());
            if (cCorner[size_t(c)] >= 0) cKind[size_t(c)] = 2, cp[c] = F.p[cCorner[size_t(c)]];
            else if (lineCount[size_t(c)] > 0)
                cKind[size_t(c)] = 1, cp[c] = ontoSegments(lineSum[size_t(c)] / lineCount[size_t(c)], segs);
        }
        result.repairs["feature_vertices"] = int(std::count(cKind.begin(), cKind.end(), 1));
        result.repairs["feature_corner_vertices"] = int(std::count(cKind.begin(), cKind.end(), 2));
    }
    for (int c = 0; c < nC; ++c) {
        cn[c] = cn[c].norm() > 0 ? Vec3(cn[c].normalized()) : Vec3(0, 0, 1);
        cq[c] -= cn[c] * cn[c].dot(cq[c]);
        cq[c] = cq[c].norm() > 1e-12 ? Vec3(cq[c].normalized()) : perpendicularUnit(cn[c]);
    }
    std::vector<std::set<int>> graph(nC);
    for (const auto &[i, j] : unitEdges) {
        const int a = cluster[i], b = cluster[j];
        if (a == b) continue;
        graph[a].insert(b);
        graph[b].insert(a);
    }
    if (features) {
        // A boundary corner sharper than the lattice (45° for squares) can have one
        // lattice neighbour X that holds boundary vertices of both sides: it would be
        // removed as a dangling edge and the corner cut off. X lies on one side; along
        // the other, the first output vertex past X with two or more neighbours is
        // joined to the corner, so that the boundary runs through it.
        std::vector<std::vector<int>> along(static_cast<size_t>(nV));
        for (size_t e = 0; e < F.featureEdges.size(); ++e)
            if (F.featureEdgeOnBoundary[e]) {
                const auto [a, b] = F.featureEdges[e];
                along[size_t(a)].push_back(b);
                along[size_t(b)].push_back(a);
            }
        int joined = 0;
        for (int c = 0; c < nC; ++c) {
            if (cKind[size_t(c)] != 2 || !cBoundary[size_t(c)] || graph[size_t(c)].size() != 1) continue;
            const int x = *graph[size_t(c)].begin(), start = cCorner[size_t(c)];
            if (along[size_t(start)].size() != 2) continue;
            // X's distance to each side's line, and the walk along the farther side
            double off[2];
            for (int k = 0; k < 2; ++k) {
                const Vec3 d = (F.p[along[size_t(start)][size_t(k)]] - F.p[start]).normalized();
                const Vec3 r = cp[x] - F.p[start];
                off[k] = (r - d * d.dot(r)).norm();
            }
            int prev = start, cur = along[size_t(start)][off[0] > off[1] ? 0 : 1];
            while (cur != start && (cluster[cur] == c || cluster[cur] == x || graph[size_t(cluster[cur])].size() < 2)) {
                const std::vector<int> &next = along[size_t(cur)];
                if (next.size() != 2) break;
                const int n = next[0] == prev ? next[1] : next[0];
                prev = cur, cur = n;
            }
            const int y = cluster[cur];
            if (cur == start || y == c || y == x || graph[size_t(y)].size() < 2) continue;
            graph[size_t(c)].insert(y);
            graph[size_t(y)].insert(c);
            ++joined;
        }
        result.repairs["boundary_corners_joined"] = joined;
    }
    int uncrossed = 0;
    // Clean the graph: no dangling edges, no vertex of degree 2 (it would be a
    // valence-2 vertex between two faces): its two edges become one. Then sort
    // each vertex's neighbours counter-clockwise about its normal and trace the
    // faces (from u -> v the next vertex is u's clockwise neighbour around v: the
    // face is on the left). An edge with the same face on both sides (a bridge)
    // is removed and everything is done again.
    int dangling = 0, dissolved = 0, bridges = 0;
    // A face traced along the input's boundary (the opening there, see below): it has
    // boundary vertices and either only them and more sides than a face may have, or
    // half of them and a centroid off the surface, or more than half of its sides
    // between two boundary vertices with the outside on their left (docs/remeshing.md,
    // "Openings with few sides": the mouth of a hole about L wide has few sides and a
    // centroid near its rim).
    const int maxSides = field.nSym == 4 ? 6 : 5;
    auto alongBoundary = [&](const std::vector<int> &f) {
        int onBoundary = 0;
        Vec3 c = Vec3::Zero();
        for (int x : f) onBoundary += cBoundary[size_t(x)], c += cp[x];
        if (onBoundary == 0) return false;
        if (onBoundary == int(f.size()) && int(f.size()) > maxSides) return true;
        c /= double(f.size());
        if (2 * onBoundary >= int(f.size()) && (tree.closest(c).point - c).norm() > 0.5 * options.edgeLength) return true;
        // The face is on the left of its edges: for an opening, the left of its sides
        // between two boundary vertices is off the surface (probe a third of L away).
        int sides = 0, offSides = 0;
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            if (!cBoundary[size_t(a)] || !cBoundary[size_t(b)]) continue;
            const Vec3 d = cp[b] - cp[a], nrm = cn[a] + cn[b];
            const Vec3 left = nrm.cross(d);
            if (!(left.norm() > 0)) continue;
            const Vec3 probe = 0.5 * (cp[a] + cp[b]) + left.normalized() * (options.edgeLength / 3);
            ++sides;
            offSides += (tree.closest(probe).point - probe).norm() > options.edgeLength / 6;
        }
        return sides >= 2 && 2 * offSides > sides;
    };
    // A feature corner on the input's boundary (a corner of an open square) has two
    // lattice neighbours, one along each side: dissolving it would cut the corner by
    // a diagonal. It stays, a vertex of one face and of the opening beside it; if
    // neither of its two traced faces is an opening (a ragged boundary, where the
    // lattice does not follow the sides) it is released and dissolved after all.
    // A feature corner inside the surface (a pyramid's apex, a star's tips) whose
    // lattice reached it from two sides only stays too: dissolving it would cut the tip
    // off (pyramid at 1 %: the apex 1.26 % of the diagonal from the output). Its two
    // faces are cut by diagonals from it once traced (`corner_faces_cut` below), so it
    // is no valence-2 vertex.
    std::vector<char> released(features ? size_t(nC) : 0, 0);
    auto keepCorner = [&](int v) {
        return features && cKind[size_t(v)] == 2 && !released[size_t(v)];
    };
    std::vector<std::vector<int>> ring(nC), faces;
    auto slotOf = [&](int v, int u) {
        return int(std::find(ring[v].begin(), ring[v].end(), u) - ring[v].begin());
    };
    for (int round = 0; round < 16; ++round) {
        for (bool changed = true; changed;) {
            changed = false;
            for (int v = 0; v < nC; ++v) {
                if (graph[v].size() == 1) {
                    const int a = *graph[v].begin();
                    graph[a].erase(v);
                    graph[v].clear();
                    ++dangling;
                    changed = true;
                } else if (graph[v].size() == 2 && !keepCorner(v)) {
                    const int a = *graph[v].begin(), b = *graph[v].rbegin();
                    graph[a].erase(v);
                    graph[b].erase(v);
                    graph[v].clear();
                    graph[a].insert(b);
                    graph[b].insert(a);
                    ++dissolved;
                    changed = true;
                }
            }
        }
        for (int v = 0; v < nC; ++v) {
            const Vec3 w = cn[v].cross(cq[v]);
            std::vector<std::pair<double, int>> byAngle;
            for (int u : graph[v]) {
                const Vec3 d = cp[u] - cp[v];
                byAngle.emplace_back(std::atan2(w.dot(d), cq[v].dot(d)), u);
            }
            std::sort(byAngle.begin(), byAngle.end());
            ring[v].clear();
            for (const auto &[angle, u] : byAngle) ring[v].push_back(u);
        }
        std::vector<std::vector<int>> faceOf(nC);
        for (int v = 0; v < nC; ++v) faceOf[v].assign(ring[v].size(), -1);
        faces.clear();
        for (int v0 = 0; v0 < nC; ++v0)
            for (int s0 = 0; s0 < int(ring[v0].size()); ++s0) {
                if (faceOf[v0][s0] >= 0) continue;
                const int id = int(faces.size());
                std::vector<int> face;
                int v = v0, s = s0;
                while (faceOf[v][s] < 0) {
                    faceOf[v][s] = id;
                    face.push_back(v);
                    const int u = v;
                    v = ring[u][s];
                    const int back = slotOf(v, u);
                    const int deg = int(ring[v].size());
                    s = (back + deg - 1) % deg;
                }
                faces.push_back(std::move(face));
            }
        std::vector<std::pair<int, int>> bridge;
        for (int v = 0; v < nC; ++v)
            for (int s = 0; s < int(ring[v].size()); ++s) {
                const int u = ring[v][s];
                if (v < u && faceOf[v][s] == faceOf[u][slotOf(u, v)]) bridge.emplace_back(v, u);
            }
        int releasedNow = 0;
        for (int v = 0; v < nC; ++v)
            if (ring[v].size() == 2 && keepCorner(v)) {
                const int f0 = faceOf[v][0], f1 = faceOf[v][1];
                if (!cBoundary[size_t(v)]) { // inside: kept where its two faces are two
                    if (f0 != f1) continue;
                    released[size_t(v)] = 1;
                    ++releasedNow;
                    continue;
                }
                auto simple = [&](int f) { // through no vertex twice
                    std::vector<int> sorted = faces[size_t(f)];
                    std::sort(sorted.begin(), sorted.end());
                    return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
                };
                if (f0 != f1 && simple(f0) && simple(f1) &&
                    (alongBoundary(faces[size_t(f0)]) || alongBoundary(faces[size_t(f1)])))
                    continue;
                released[size_t(v)] = 1;
                ++releasedNow;
            }
        // Faces traced over each other where two edges cross (removeCrossingEdges): a
        // face that does not face the input, or a hole (more sides than a face may
        // have: where a tangle's faces overlap, the loop around them), has its crossing
        // edges removed, and the faces are traced again.
        // Only faces at a crossing are looked at (a closest-point query each).
        int uncrossedNow = 0;
        {
            const std::vector<EdgeCrossing> crossings = findCrossingEdges(graph, cp, cn);
            std::vector<char> crossing(static_cast<size_t>(nC), 0), turned(static_cast<size_t>(nC), 0);
            for (const auto &[a, b, c, d] : crossings)
                for (int x : {a, b, c, d}) crossing[size_t(x)] = 1;
            bool anyTurned = false;
            for (size_t k = 0; k < faces.size() && !crossings.empty(); ++k) {
                const std::vector<int> &f = faces[k];
                if (std::none_of(f.begin(), f.end(), [&](int x) { return crossing[size_t(x)] != 0; })) continue;
                if (int(f.size()) > maxSides || !facesInput(f, cp, mesh, tree)) {
                    for (int x : f) turned[size_t(x)] = 1;
                    anyTurned = true;
                }
            }
            // cKind (0: no feature) is empty without features, as removeCrossingEdges takes it.
            if (anyTurned)
                uncrossedNow = removeCrossingEdges(graph, crossings, cp, cKind, options.edgeLength, &turned);
            uncrossed += uncrossedNow;
        }
        if (bridge.empty() && releasedNow == 0 && uncrossedNow == 0) break;
        for (const auto &[v, u] : bridge) {
            graph[v].erase(u);
            graph[u].erase(v);
            ++bridges;
        }
    }
    result.repairs["dangling_edges_removed"] = dangling;
    result.repairs["valence2_dissolved"] = dissolved;
    result.repairs["bridges_removed"] = bridges;
    result.repairs["crossing_edges_removed"] = uncrossed;

    int holes = 0, dropped = 0, split = 0, openings = 0;
    // With features, a face traced along the input's boundary (alongBoundary) is the
    // opening there, not a face: left open, if no vertex of it is on an opening left
    // open before (two openings through one vertex would make it non-manifold: the
    // later one is filled as before).
    std::vector<char> onOpening(features ? size_t(nC) : 0, 0);
    auto isOpening = [&](const std::vector<int> &f) {
        if (!features) return false;
        for (int x : f)
            if (onOpening[size_t(x)]) return false;
        return alongBoundary(f);
    };
    std::vector<std::vector<int>> polygons;
    std::vector<Vec3> positions = cp;
    // The sides a hole's ears may not take: the graph's edges and the ears' cuts so far.
    int holesByEars = 0;
    std::set<std::pair<int, int>> holeDiagonals;
    const std::function<bool(int, int)> joined = [&](int a, int b) {
        return graph[size_t(a)].count(b) > 0 || holeDiagonals.count({std::min(a, b), std::max(a, b)}) > 0;
    };
    for (const std::vector<int> &face : faces) {
            // A face through a vertex twice is two loops meeting there: split it.
            std::vector<std::vector<int>> loops{face};
            for (size_t k = 0; k < loops.size(); ++k) {
                for (size_t i = 0; i < loops[k].size(); ++i) {
                    std::vector<int> &f = loops[k];
                    const auto again = std::find(f.begin() + long(i) + 1, f.end(), f[i]);
                    if (again == f.end()) continue;
                    std::vector<int> sub(f.begin() + long(i), again);
                    f.erase(f.begin() + long(i), again);
                    loops.push_back(std::move(sub)); // f is not used after this
                    ++split;
                    i = size_t(-1); // rescan what is left
                }
            }
            for (const std::vector<int> &f : loops) {
                if (f.size() < 3) {
                    ++dropped;
                    continue;
                }
                if (isOpening(f)) {
                    for (int x : f) onOpening[size_t(x)] = 1;
                    ++openings;
                    continue;
                }
                if (int(f.size()) <= maxSides) {
                    polygons.push_back(f);
                    continue;
                }
                // A hole: a fan of triangles around its centroid put on the surface,
                // or cut into ears where that fan would turn over (fillHole).
                bool byEars = false;
                for (std::vector<int> &t : fillHole(f, positions, mesh, tree, joined, byEars)) {
                    if (byEars) holeDiagonals.insert({std::min(t[0], t[2]), std::max(t[0], t[2])});
                    polygons.push_back(std::move(t));
                }
                ++holes;
                holesByEars += byEars;
            }
        }
    result.repairs["faces_split"] = split;
    mergeTrianglePairs(polygons, positions, result.nSym, result.repairs);
    // A feature corner inside the surface kept with two neighbours (keepCorner) has
    // two faces: each is cut by a diagonal from it (no face farther from the input than
    // it was), so the corner gets four edges and stays a vertex of the output.
    int cornerFacesCut = 0;
    if (features) {
        const size_t nPolygons = polygons.size();
        for (size_t f = 0; f < nPolygons; ++f) {
            const std::vector<int> P = polygons[f];
            if (P.size() < 4) continue;
            for (size_t i = 0; i < P.size(); ++i) {
                const int v = P[i];
                if (v >= nC || cKind[size_t(v)] != 2 || cBoundary[size_t(v)] || graph[size_t(v)].size() != 2) continue;
                const double limit = std::max(kFarDistance * options.edgeLength,
                                              farthestFromInput(P, positions, tree, options.edgeLength));
                const auto cut = cutFrom(P, int(i), positions, mesh, tree, options.edgeLength, limit);
                if (cut.empty()) break;
                polygons[f] = cut[0];
                polygons.push_back(cut[1]);
                ++cornerFacesCut;
                break;
            }
        }
    }
    result.repairs["corner_faces_cut"] = cornerFacesCut;
    dissolveValence2(polygons, int(positions.size()), maxSides, result.repairs);
    // A later step that leaves vertices with two neighbours dissolves them too; the
    // count (which dissolveValence2 sets) then adds up over the passes.
    auto dissolveValence2Again = [&] {
        const int dissolvedBefore = result.repairs["valence2_dissolved_in_faces"];
        dissolveValence2(polygons, int(positions.size()), maxSides, result.repairs);
        result.repairs["valence2_dissolved_in_faces"] += dissolvedBefore;
    };
    if (result.nSym == 4) {
        const auto tc = Clock::now();
        cancelDislocationPairs(polygons, positions, result.repairs);
        result.timingsMs["dislocation_pairs"] = msSince(tc);
        // A re-cut can leave a vertex between two quads that share both its edges
        // (homer: 2 with features, 1 at μ = 0): dissolved like the others.
        dissolveValence2Again();
    }
    const auto onFeature = [&](size_t v) { return features && v < size_t(nC) && cKind[v] != 0; };
    std::function<void(size_t, Vec3 &)> constrain;
    if (features) // feature vertices move along their curve only, corners not at all
        constrain = [&](size_t v, Vec3 &x) {
            if (v >= size_t(nC) || !cKind[v]) return;
            x = cKind[v] == 2 ? F.p[cCorner[v]] : ontoSegments(x, cSegments[v]);
        };
    // Stars re-cut around their centre where that leaves fewer irregular vertices
    // (a cone drawn as a vertex with its spokes one corner off, "Stars re-cut").
    if (result.nSym == 4)
        result.repairs["stars_respoked"] = respokeVertices(polygons, positions, tree, options.edgeLength, onFeature);
    relaxVertices(polygons, positions, tree, options.relaxRounds, result.repairs, constrain);
    snapToProtrusions(polygons, positions, mesh, options.edgeLength,
                      onFeature, result.repairs);
    // An edge between two feature vertices runs along a feature curve when its middle
    // is within L/4 of one (brute force over the curves' pieces: called for far edges
    // and sides only).
    std::function<bool(int, int)> alongFeature;
    if (features)
        alongFeature = [&](int a, int b) {
            const Vec3 x = 0.5 * (positions[size_t(a)] + positions[size_t(b)]);
            const double reach2 = 0.0625 * options.edgeLength * options.edgeLength;
            for (size_t e = 0; e < F.featureEdges.size(); ++e)
                if ((onFeatureEdge(x, e) - x).squaredNorm() <= reach2) return true;
            return false;
        };
    const auto th = Clock::now();
    holdDistance(polygons, positions, mesh, tree, options.edgeLength,
                 onFeature, result.repairs, alongFeature);
    result.timingsMs["distance_repair"] = msSince(th);
    if (features) result.repairs["boundary_openings_left_open"] = openings;
    result.repairs["holes_filled"] = holes;
    result.repairs["holes_filled_by_ears"] = holesByEars;
    result.repairs["faces_dropped"] = dropped;

    // A face traced through a vertex twice was split there into two loops, which
    // pinches the surface at that vertex (two fans of faces meeting at one point):
    // OpenMesh would refuse faces at it, leaving holes. Each fan gets its own vertex.
    result.repairs["pinched_vertices_split"] = splitPinchedVertices(polygons, positions, 0.25 * options.edgeLength);
    result.repairs["flipped_corners_moved"] =
        untangleFlipped(polygons, positions, mesh, tree, options.edgeLength,
                        onFeature);
    result.repairs["flipped_triangles_absorbed"] = absorbFlippedTriangles(polygons, positions, mesh, tree, maxSides);
    // The absorbed triangle's third corner may be left between two faces (hand at 1 %).
    if (result.repairs["flipped_triangles_absorbed"] > 0) dissolveValence2Again();
    result.repairs["folded_diagonals_collapsed"] = collapseFoldedDiagonals(
        polygons, positions, mesh, tree, kFoldedDiagonal * options.edgeLength,
        onFeature);
    if (result.repairs["folded_diagonals_collapsed"] > 0) // a corner between the ends may have two neighbours left
        dissolveValence2Again();
    // A corner of a refilled patch may be left with two neighbours; dissolving it can
    // turn a triangle over again (joint at 1 %: one), which a second pass mends.
    int refilled = 0;
    for (int pass = 0; pass < 2; ++pass) {
        const int now = refillFlippedPatches(polygons, positions, mesh, tree, options.edgeLength, onFeature);
        refilled += now;
        if (now == 0) break;
        dissolveValence2Again();
    }
    result.repairs["flipped_patches_refilled"] = refilled;
    // The flip repairs move corners and refill patches without looking at the distance
    // (camel at 1 %: a refilled patch 0.65 % from the input): held once more where they
    // changed anything, and kept only if that turns no face over (its fans and cuts face
    // the input, but a valence-2 vertex dissolved after them may not: femur, 2 faces).
    result.repairs["distance_held_again"] = 0;
    result.repairs["distance_held_again_undone"] = 0;
    if (result.repairs["flipped_corners_moved"] + result.repairs["flipped_triangles_absorbed"] +
            result.repairs["folded_diagonals_collapsed"] + refilled > 0) {
        auto turnedOver = [&] {
            int n = 0;
            for (const auto &poly : polygons) n += !facesInput(poly, positions, mesh, tree);
            return n;
        };
        const int before = turnedOver();
        std::vector<std::vector<int>> keptPolygons = polygons;
        std::vector<Vec3> keptPositions = positions;
        const std::map<std::string, int> keptRepairs = result.repairs;
        std::map<std::string, int> again;
        holdDistance(polygons, positions, mesh, tree, options.edgeLength, onFeature, again, alongFeature);
        for (const auto &[name, count] : again)
            result.repairs[name] = name == "far_points_left" ? count : result.repairs[name] + count;
        dissolveValence2Again();
        result.repairs["distance_held_again"] = 1;
        if (turnedOver() > before) {
            polygons.swap(keptPolygons);
            positions.swap(keptPositions);
            result.repairs = keptRepairs;
            result.repairs["distance_held_again_undone"] = 1;
        }
    }
    result.repairs["stray_pieces_removed"] =
        removeStrayPieces(polygons, positions, mesh, tree, options.edgeLength);

    intoPolyMesh(positions, polygons, result);
    result.timingsMs["extraction"] = msSince(t0);
    return result;
}

void intoPolyMesh(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                  RemeshResult &result) {
    // Compact away the vertices no polygon uses.
    std::vector<int> newId(positions.size(), -1);
    for (const auto &poly : polygons)
        for (int x : poly)
            if (newId[x] < 0) newId[x] = 0;
    for (size_t x = 0; x < positions.size(); ++x)
        if (newId[x] == 0) {
            newId[x] = int(result.positions.size());
            result.positions.push_back(positions[x]);
        }
    std::vector<field::PolyMesh::VertexHandle> handles;
    for (const Vec3 &p : result.positions) handles.push_back(result.poly.add_vertex({p.x(), p.y(), p.z()}));
    int refused = 0;
    omerr().disable();
    for (const auto &poly : polygons) {
        std::vector<field::PolyMesh::VertexHandle> vh;
        std::vector<int> ids;
        for (int x : poly) vh.push_back(handles[newId[x]]), ids.push_back(newId[x]);
        // A polygon through one vertex twice is no face OpenMesh can hold (its add_face
        // asserts on some of them rather than refusing).
        std::vector<int> sorted = ids;
        std::sort(sorted.begin(), sorted.end());
        const bool repeats = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
        if (!repeats && result.poly.add_face(vh).is_valid()) result.polygons.push_back(ids);
        else ++refused;
    }
    omerr().enable();
    result.repairs["faces_refused_by_openmesh"] = refused;
}

} // namespace rosy::remesh
