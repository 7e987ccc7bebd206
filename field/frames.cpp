#include "field/frames.h"

#include "core/parallel.h"

#include <algorithm>
#include <cmath>

namespace rosy::field {
namespace {
constexpr double kTwoPi = 2.0 * M_PI;

double wrap2Pi(double a) {
    a = fmodTwoPi(a);
    return a < 0 ? a + kTwoPi : a;
}

// Any unit vector orthogonal to n (for degenerate projections).
Vec3 anyOrthogonal(const Vec3 &n) {
    Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    Vec3 t = a - a.dot(n) * n;
    return t.normalized();
}
} // namespace

TangentFrames::TangentFrames(const Mesh &mesh) : m_mesh(&mesh) {
    const int nV = mesh.nVertices(), nF = mesh.nFaces(), nH = mesh.nHalfedges();
    // Sized only: every element is written below, in parallel (the one-rings cover every
    // halfedge once), so the pages are first touched there rather than by one thread here.
    m_angleOut.resize(nH);
    m_angleIn.resize(nH);
    m_transport.resize(nH);
    m_scale.resize(nV);
    m_faceHolonomy.resize(nF);
    m_normal.resize(nV);
    m_projAngle.resize(nH);
    m_projTotal.resize(nV);
    m_angleTotal.resize(nV);
    m_faceX.resize(nF);
    m_faceY.resize(nF);
    m_vertexToFace.resize(nH);

    // Corner angles and face normals once each (kept by the mesh): the vertex normals
    // below are Mesh::vertexNormal() summed from them (the same terms in the same order).
    const std::vector<double> &corner = mesh.cornerAngles();
    const std::vector<Vec3> &faceNormal = mesh.faceNormals();

    const int *ring0 = nV > 0 ? mesh.outgoingBegin(0) : nullptr;
    // Scratch space per chunk, not thread_local: a thread_local with a destructor
    // registers itself through __cxa_thread_atexit, which takes the dynamic loader's
    // lock, so every TBB worker stalled here while rosyhatch's image module was being
    // dlopen()ed on its background thread (frames took 150 ms instead of 40).
    parallelForRange(0, nV, [&](int64_t lo, int64_t hi) {
      std::vector<Vec3> dirs;
      std::vector<double> psi;
      for (int64_t vi = lo; vi < hi; ++vi) {
        const int v = int(vi);
        const int *begin = mesh.outgoingBegin(v), *end = mesh.outgoingEnd(v);
        const int d = int(end - begin);
        double total = 0;
        for (int k = 0; k < d; ++k) total += corner[begin[k]];
        const bool boundary = mesh.isBoundaryVertex(v);
        // Interior vertices are rescaled to a flat cone of 2π. Boundary vertices keep
        // their true angle sum: rescaling them to π would move the boundary's turning
        // into the boundary faces and show up as spurious ±1/N singularities at sharp
        // corners. A collapsed fan (all corners zero) keeps scale 1.
        const double s = (!boundary && total > 1e-300) ? kTwoPi / total : 1.0;
        m_scale[v] = s;
        double acc = 0;
        for (int k = 0; k < d; ++k) {
            m_angleOut[begin[k]] = acc;
            acc += s * corner[begin[k]];
        }

        // Extrinsic embedding: projected wedge angles around the vertex normal.
        Vec3 n = Vec3::Zero();
        for (int k = 0; k < d; ++k) n += corner[begin[k]] * faceNormal[size_t(Mesh::faceOf(begin[k]))];
        const double nLength = n.norm();
        n = nLength > 0 ? Vec3(n / nLength) : Vec3::Zero();
        if (n.squaredNorm() == 0) n = Vec3::UnitZ();
        m_normal[v] = n;
        auto projected = [&](const Vec3 &e) {
            Vec3 t = e - e.dot(n) * n;
            double len = t.norm();
            return len > 0 ? Vec3(t / len) : Vec3::Zero();
        };
        dirs.resize(d + 1);
        psi.assign(d + 1, 0.0);
        for (int k = 0; k < d; ++k) dirs[k] = projected(mesh.vector(begin[k]));
        // The closing direction: the first edge again inside, the last boundary edge outside.
        dirs[d] = boundary ? projected(mesh.position(mesh.tail(Mesh::prev(begin[d - 1]))) -
                                       mesh.position(v))
                           : dirs[0];
        for (int k = 0; k < d; ++k) {
            double beta = 0;
            if (dirs[k].squaredNorm() > 0 && dirs[k + 1].squaredNorm() > 0)
                beta = std::atan2(dirs[k].cross(dirs[k + 1]).norm(), dirs[k].dot(dirs[k + 1]));
            psi[k + 1] = psi[k] + beta;
        }
        // Inside, force the projected wedges to close at exactly 2π so the map is a
        // homeomorphism of the circle even where the projection folds (saddles).
        if (!boundary && psi[d] > 1e-300)
            for (int k = 0; k <= d; ++k) psi[k] *= kTwoPi / psi[d];
        const int base = int(begin - ring0);
        for (int k = 0; k < d; ++k) m_projAngle[base + k] = psi[k];
        m_projTotal[v] = psi[d];
        m_angleTotal[v] = boundary ? total : kTwoPi;
      }
    }, 1024);

    // Reverse angles and transport need the angles of neighbouring vertices.
    parallelFor(0, nH, [&](int64_t hi) {
        const int h = int(hi);
        const int hn = Mesh::next(h); // leaves head(h); its corner ends at head(h) → tail(h)
        m_angleIn[h] = wrap2Pi(m_angleOut[hn] + m_scale[mesh.tail(hn)] * corner[hn]);
        m_transport[h] = wrapAngle(m_angleOut[h] - m_angleIn[h] - M_PI);
    }, 4096);

    parallelFor(0, nF, [&](int64_t fi) {
        const int f = int(fi);
        double k = -M_PI;
        for (int c = 0; c < 3; ++c) k += m_scale[mesh.face(f)[c]] * corner[3 * f + c];
        m_faceHolonomy[f] = k;
        const Vec3 &n = faceNormal[size_t(f)];
        Vec3 x = mesh.vector(3 * f);
        if (x.squaredNorm() == 0 || n.squaredNorm() == 0) { // degenerate: default frame
            m_faceX[f] = Vec3::UnitX();
            m_faceY[f] = Vec3::UnitY();
            for (int c = 0; c < 3; ++c) m_vertexToFace[3 * f + c] = 0.0;
            return;
        }
        x.normalize();
        m_faceX[f] = x;
        m_faceY[f] = n.cross(x);
        for (int c = 0; c < 3; ++c) {
            const int h = 3 * f + c;
            Vec3 e = mesh.vector(h);
            double faceAngle = std::atan2(e.dot(m_faceY[f]), e.dot(m_faceX[f]));
            m_vertexToFace[h] = wrapAngle(faceAngle - m_angleOut[h]);
        }
    }, 4096);
}

// Knots of the piecewise linear map between intrinsic angles phi and projected
// angles psi at a vertex: one per outgoing halfedge, then the closing knot at
// (2π, 2π) inside; on the boundary the last edge (Θ, Ψ) and a virtual exterior
// wedge closing at (2π, 2π), so directions pointing off the surface map too.
void TangentFrames::knots(int v, std::vector<double> &phi, std::vector<double> &psi) const {
    const Mesh &mesh = *m_mesh;
    const int *begin = mesh.outgoingBegin(v), *end = mesh.outgoingEnd(v);
    const int deg = int(end - begin);
    const double *proj = m_projAngle.data() + (begin - mesh.outgoingBegin(0));
    phi.clear();
    psi.clear();
    for (int k = 0; k < deg; ++k) {
        phi.push_back(m_angleOut[begin[k]]);
        psi.push_back(proj[k]);
    }
    if (mesh.isBoundaryVertex(v)) {
        phi.push_back(std::min(m_angleTotal[v], kTwoPi));
        psi.push_back(std::min(m_projTotal[v], kTwoPi));
    }
    phi.push_back(kTwoPi);
    psi.push_back(kTwoPi);
}

// Unit vectors spanning v's tangent plane: e1 along the projected first edge.
void TangentFrames::tangentBasis(int v, Vec3 &e1, Vec3 &e2) const {
    const Mesh &mesh = *m_mesh;
    const Vec3 &n = m_normal[v];
    e1 = mesh.degree(v) > 0 ? mesh.vector(*mesh.outgoingBegin(v)) : Vec3::UnitX();
    e1 -= e1.dot(n) * n;
    e1 = e1.squaredNorm() > 0 ? Vec3(e1.normalized()) : anyOrthogonal(n);
    e2 = n.cross(e1);
}

static double interpolateKnots(const std::vector<double> &from, const std::vector<double> &to,
                               double x) {
    // from is non-decreasing from 0 to 2π; find the segment holding x.
    int k = int(std::upper_bound(from.begin(), from.end(), x) - from.begin()) - 1;
    k = std::clamp(k, 0, int(from.size()) - 2);
    double a = from[k], b = from[k + 1];
    double t = b > a ? std::clamp((x - a) / (b - a), 0.0, 1.0) : 0.0;
    return to[k] + t * (to[k + 1] - to[k]);
}

double TangentFrames::angleOfTangent(int v, const Vec3 &d) const {
    const Vec3 &n = m_normal[v];
    Vec3 t = d - d.dot(n) * n;
    if (t.squaredNorm() == 0 || m_mesh->degree(v) == 0) return 0.0;
    Vec3 e1, e2;
    tangentBasis(v, e1, e2);
    // Per-thread knot buffers: these run per vertex in parallel loops (field export,
    // the studio's directions), where two allocations a call were most of the cost.
    static thread_local std::vector<double> phi, psi;
    knots(v, phi, psi);
    return interpolateKnots(psi, phi, wrap2Pi(std::atan2(t.dot(e2), t.dot(e1))));
}

Vec3 TangentFrames::tangentOfAngle(int v, double phiRad) const {
    Vec3 e1, e2;
    tangentBasis(v, e1, e2);
    if (m_mesh->degree(v) == 0) return e1;
    static thread_local std::vector<double> phi, psi; // as in angleOfTangent()
    knots(v, phi, psi);
    double p = interpolateKnots(phi, psi, wrap2Pi(phiRad));
    return std::cos(p) * e1 + std::sin(p) * e2;
}

std::array<Complex, 3> TangentFrames::faceValues(int f, const RosyField &field) const {
    const Face &t = m_mesh->face(f);
    std::array<Complex, 3> out;
    for (int c = 0; c < 3; ++c)
        out[c] = field.u[t[c]] * std::polar(1.0, field.nSym * m_vertexToFace[3 * f + c]);
    return out;
}

Vec2 TangentFrames::toFace2D(int f, const Vec3 &p) const {
    Vec3 d = p - m_mesh->position(m_mesh->face(f)[0]);
    return Vec2(d.dot(m_faceX[f]), d.dot(m_faceY[f]));
}

} // namespace rosy::field
