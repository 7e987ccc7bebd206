#include "field/curvature.h"

#include "core/parallel.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace rosy::field {

namespace {

// The per-element structs below are deliberately left uninitialized: every
// element is written by its pass, and zero-filling the large arrays first was a
// measurable part of the run time.

/// A symmetric 2×2 tensor [[e, f], [f, g]] in some orthonormal tangent frame.
struct Tensor2 {
    double e, f, g;
};

/// An orthonormal frame (u, n × u, n); only u and n are stored.
struct Frame {
    Vec3 u, n;
    Vec3 v() const { return n.cross(u); }
};

/// Per-face result of the least-squares fit, in the face's own frame.
struct FaceFit {
    Frame frame;
    Tensor2 second;
};

// Faces flatter than this (2·area / longest edge², i.e. height over length) are
// skipped: the normal equations then have a condition number above ~1e12, so the
// fit is noise, and such a face carries a negligible share of the area anyway.
constexpr double kSliverAspect = 1e-6;

/// The smallest rotation taking unit vector a to unit vector b. Rodrigues in the
/// form R x = c x + w × x + w (w·x) / (1 + c), with c = a·b and w = a × b, needs
/// no normalized axis and stays accurate for small angles.
class MinimalRotation {
public:
    MinimalRotation(const Vec3 &a, const Vec3 &b)
        : m_c(a.dot(b)), m_w(a.cross(b)), m_halfTurnAxis(Vec3::Zero()) {
        if (m_c > -1.0 + 1e-12) {
            m_k = 1.0 / (1.0 + m_c);
        } else {
            // Opposite normals (a folded surface): any half-turn about an axis
            // perpendicular to a is minimal; pick one deterministically.
            m_halfTurnAxis = a.unitOrthogonal();
            m_k = 0;
        }
    }
    Vec3 operator()(const Vec3 &x) const {
        if (m_k == 0) return 2.0 * m_halfTurnAxis * m_halfTurnAxis.dot(x) - x;
        return m_c * x + m_w.cross(x) + m_w * (m_k * m_w.dot(x));
    }

private:
    double m_c;
    Vec3 m_w;
    double m_k;
    Vec3 m_halfTurnAxis;
};

/// True if the face with these edge vectors is too flat to fit (see kSliverAspect).
bool isSliver(const Vec3 &nArea, const std::array<Vec3, 3> &edges) {
    const double longest = std::max({edges[0].squaredNorm(), edges[1].squaredNorm(),
                                     edges[2].squaredNorm()});
    return !(nArea.norm() > kSliverAspect * longest);
}

/// Max-weighted normal at v: Σ (a × b) / (|a|² |b|²) over the corners (a, b the
/// two edges leaving v). Exact on a sphere, which makes the curvature fit exact
/// there too. Zero if no corner qualifies.
Vec3 maxWeightedNormal(const Mesh &mesh, int v) {
    Vec3 n = Vec3::Zero();
    const Vec3 &p = mesh.position(v);
    for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it) {
        const Vec3 a = mesh.position(mesh.head(*it)) - p;
        const Vec3 b = mesh.position(mesh.tail(Mesh::prev(*it))) - p;
        const Vec3 nArea = a.cross(b);
        if (isSliver(nArea, {a, b, b - a})) continue;
        n += nArea / (a.squaredNorm() * b.squaredNorm());
    }
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

/// Re-expresses tensor t, given in frame `from`, in the tangent frame `to`.
/// Following Rusinkiewicz §3, `to`'s axes are first rotated into `from`'s
/// tangent plane (normal onto normal), which keeps the tensor's eigenvalues.
/// The rotated frame is then `from` turned by some angle φ in its plane, so only
/// cos φ and sin φ are needed: the rotated v axis is n × (rotated u).
Tensor2 transportTensor(const Frame &from, const Tensor2 &t, const Frame &to) {
    const Vec3 u = MinimalRotation(to.n, from.n)(to.u);
    const double c = u.dot(from.u), s = u.dot(from.v());
    const double cc = c * c, ss = s * s, cs = c * s;
    // R(φ)ᵀ II R(φ) written out.
    return {cc * t.e + 2 * cs * t.f + ss * t.g,
            cs * (t.g - t.e) + (cc - ss) * t.f,
            ss * t.e - 2 * cs * t.f + cc * t.g};
}

/// Tangent frame of vertex v around normal n: u is the first outgoing edge that is
/// not parallel to n, projected onto the tangent plane. Tying u to the mesh (not to
/// world axes) keeps the frame well defined whatever the normal.
Frame vertexFrame(const Mesh &mesh, int v, const Vec3 &n) {
    Frame fr;
    fr.n = n;
    for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it) {
        const Vec3 e = mesh.vector(*it);
        const Vec3 t = e - n * n.dot(e);
        const double len = t.norm();
        if (len > 1e-9 * e.norm()) {
            fr.u = t / len;
            return fr;
        }
    }
    fr.u = n.unitOrthogonal();
    return fr;
}

/// Mixed Voronoi areas of the three corners of face f (Meyer et al. 2003, Fig. 4):
/// the Voronoi region inside a non-obtuse triangle, else half the area to the
/// obtuse corner and a quarter to each other one. They always sum to the area.
std::array<double, 3> cornerAreas(const Mesh &mesh, int f) {
    const Face &t = mesh.face(f);
    const Vec3 &p0 = mesh.position(t[0]), &p1 = mesh.position(t[1]), &p2 = mesh.position(t[2]);
    const double area = mesh.faceArea(f);
    if (!(area > 0)) return {0, 0, 0};
    const Vec3 e0 = p2 - p1, e1 = p0 - p2, e2 = p1 - p0; // opposite corner 0, 1, 2
    // dot_k = cos(angle_k) · |adjacent edges|; cot(angle_k) = dot_k / (2 area).
    const double d0 = -e1.dot(e2), d1 = -e2.dot(e0), d2 = -e0.dot(e1);
    if (d0 < 0) return {0.5 * area, 0.25 * area, 0.25 * area};
    if (d1 < 0) return {0.25 * area, 0.5 * area, 0.25 * area};
    if (d2 < 0) return {0.25 * area, 0.25 * area, 0.5 * area};
    // A_i = (1/8) Σ |e_j|² cot(angle_j) over the two edges e_j at corner i.
    const double s = 1.0 / (16.0 * area);
    const double l0 = e0.squaredNorm(), l1 = e1.squaredNorm(), l2 = e2.squaredNorm();
    return {s * (l2 * d2 + l1 * d1), s * (l0 * d0 + l2 * d2), s * (l1 * d1 + l0 * d0)};
}

/// Least-squares second fundamental form of face f (Rusinkiewicz §3, eq. 4):
/// find II with II·(e·u, e·v) = (Δn·u, Δn·v) for the three edges e.
/// Returns false for zero-area and sliver faces, which then get no weight.
bool fitFace(const Mesh &mesh, int f, const std::vector<Vec3> &normals, FaceFit &fit) {
    const Face &t = mesh.face(f);
    const Vec3 &p0 = mesh.position(t[0]), &p1 = mesh.position(t[1]), &p2 = mesh.position(t[2]);
    const Vec3 nArea = (p1 - p0).cross(p2 - p0);
    const std::array<Vec3, 3> edges = {p2 - p1, p0 - p2, p1 - p0};
    if (isSliver(nArea, edges)) return false;

    fit.frame.n = nArea.normalized();
    fit.frame.u = edges[2].normalized();
    const Vec3 frameV = fit.frame.v();

    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atb = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
        // Edge k runs from corner k+1 to corner k+2.
        const Vec3 dn = normals[t[(k + 2) % 3]] - normals[t[(k + 1) % 3]];
        const double x = edges[k].dot(fit.frame.u), y = edges[k].dot(frameV);
        const double dx = dn.dot(fit.frame.u), dy = dn.dot(frameV);
        // Rows [x y 0]·(e f g) = dx and [0 x y]·(e f g) = dy.
        ata(0, 0) += x * x;
        ata(0, 1) += x * y;
        ata(1, 1) += x * x + y * y;
        ata(1, 2) += x * y;
        ata(2, 2) += y * y;
        atb(0) += x * dx;
        atb(1) += y * dx + x * dy;
        atb(2) += y * dy;
    }
    ata(1, 0) = ata(0, 1);
    ata(2, 1) = ata(1, 2);
    const Eigen::Vector3d efg = ata.ldlt().solve(atb);
    if (!efg.allFinite()) return false;
    fit.second = {efg(0), efg(1), efg(2)};
    return true;
}

/// Principal curvatures and directions of tensor t in frame fr.
void diagonalize(const Frame &fr, const Tensor2 &t, VertexCurvature &out) {
    const double mean = 0.5 * (t.e + t.g);
    const double halfDiff = 0.5 * (t.e - t.g);
    const double radius = std::sqrt(halfDiff * halfDiff + t.f * t.f);
    out.kMax = mean + radius;
    out.kMin = mean - radius;
    // II(cos θ, sin θ) = mean + halfDiff cos 2θ + f sin 2θ is largest at
    // 2θ = atan2(f, halfDiff); atan2(0, 0) = 0 picks u at umbilics.
    const double theta = 0.5 * std::atan2(t.f, halfDiff);
    out.dirMax = std::cos(theta) * fr.u + std::sin(theta) * fr.v();
    out.dirMin = fr.n.cross(out.dirMax);
    out.normal = fr.n;
}

} // namespace

std::vector<VertexCurvature> computeCurvature(const Mesh &mesh, const CurvatureOptions &options) {
    const int nV = mesh.nVertices(), nF = mesh.nFaces();
    std::vector<VertexCurvature> result(nV);
    if (nV == 0) return result;

    // Every pass below writes only its own index and reads earlier passes, so the
    // results do not depend on scheduling; sums run over each ring in its fixed order.
    std::vector<Vec3> normals(nV);
    parallelFor(0, nV, [&](int64_t v) {
        Vec3 n = Vec3::Zero();
        if (options.normals == NormalWeighting::Max) n = maxWeightedNormal(mesh, int(v));
        // Angle weights also back up Max ones where every corner is a sliver.
        if (n.squaredNorm() == 0) n = mesh.vertexNormal(int(v));
        normals[v] = n.squaredNorm() > 0 ? n : Vec3::UnitZ();
    }, 1024);

    std::vector<FaceFit> fits(nF);
    std::vector<uint8_t> fitted(nF);
    std::vector<double> areas(3 * size_t(nF)); // per halfedge h = 3f + k: corner k of f
    parallelFor(0, nF, [&](int64_t f) {
        fitted[f] = fitFace(mesh, int(f), normals, fits[f]);
        const std::array<double, 3> a = cornerAreas(mesh, int(f));
        for (int k = 0; k < 3; ++k) areas[3 * f + k] = a[k];
    }, 1024);

    // Without smoothing each vertex is finished in this pass; with it the frames
    // and tensors are kept for the rounds below.
    const int nRounds = std::max(0, options.smoothingRounds);
    std::vector<Frame> frames(nRounds > 0 ? nV : 0);
    std::vector<Tensor2> tensors(nRounds > 0 ? nV : 0);
    parallelFor(0, nV, [&](int64_t vi) {
        const int v = int(vi);
        const Frame frame = vertexFrame(mesh, v, normals[v]);
        Tensor2 sum{0, 0, 0};
        double wSum = 0;
        double area = 0;
        for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it) {
            const double w = areas[*it];
            area += w;
            if (!(w > 0) || !fitted[Mesh::faceOf(*it)]) continue;
            const FaceFit &fit = fits[Mesh::faceOf(*it)];
            const Tensor2 t = transportTensor(fit.frame, fit.second, frame);
            sum.e += w * t.e;
            sum.f += w * t.f;
            sum.g += w * t.g;
            wSum += w;
        }
        // Vertices whose faces are all degenerate keep a zero tensor (flat).
        const Tensor2 mean = wSum > 0 ? Tensor2{sum.e / wSum, sum.f / wSum, sum.g / wSum}
                                      : Tensor2{0, 0, 0};
        // The reported area is the full mixed area, slivers included.
        result[v].area = area;
        if (nRounds > 0) {
            frames[v] = frame;
            tensors[v] = mean;
        } else {
            diagonalize(frame, mean, result[v]);
        }
    }, 1024);
    if (nRounds == 0) return result;

    // Optional 1-ring averaging, double-buffered so each round reads only the
    // previous one (deterministic), weighted by vertex area so dense patches of a
    // nonuniform mesh do not dominate.
    std::vector<Tensor2> next(nV);
    for (int round = 0; round < nRounds; ++round) {
        parallelFor(0, nV, [&](int64_t vi) {
            const int v = int(vi);
            double wSum = result[v].area;
            Tensor2 sum{wSum * tensors[v].e, wSum * tensors[v].f, wSum * tensors[v].g};
            auto add = [&](int j) {
                const double w = result[j].area;
                if (!(w > 0)) return;
                const Tensor2 t = transportTensor(frames[j], tensors[j], frames[v]);
                sum.e += w * t.e;
                sum.f += w * t.f;
                sum.g += w * t.g;
                wSum += w;
            };
            for (const int *it = mesh.outgoingBegin(v); it != mesh.outgoingEnd(v); ++it) {
                add(mesh.head(*it));
                // On a boundary the last neighbour is reached only through prev().
                const int p = Mesh::prev(*it);
                if (mesh.isBoundaryHalfedge(p)) add(mesh.tail(p));
            }
            next[v] = wSum > 0 ? Tensor2{sum.e / wSum, sum.f / wSum, sum.g / wSum} : tensors[v];
        }, 1024);
        tensors.swap(next);
    }

    parallelFor(0, nV, [&](int64_t v) { diagonalize(frames[v], tensors[v], result[v]); }, 1024);
    return result;
}

double curvatureAnisotropy(const std::vector<VertexCurvature> &curvature) {
    // Sequential sums in vertex order: the same bits for any thread count.
    double anisotropy = 0, magnitude = 0;
    for (const VertexCurvature &c : curvature) {
        anisotropy += c.area * std::abs(c.kMax - c.kMin);
        magnitude += c.area * (std::abs(c.kMax) + std::abs(c.kMin));
    }
    // A plane (0 / 0) has no direction either; never NaN.
    if (!(magnitude > 0)) return 0;
    const double ratio = anisotropy / magnitude;
    return ratio >= 0 ? std::min(ratio, 1.0) : 0; // an overflowed inf / inf counts as none
}

} // namespace rosy::field
