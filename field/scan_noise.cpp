/// \file scan_noise.cpp
/// Fields on noisy scans (scan_noise.h).

#include "field/scan_noise.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>
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

/// Angle-weighted normal at v of the mesh with positions p, unnormalised (each face
/// around v is reached once, by its halfedge out of v; as Mesh::vertexNormal(), which
/// on needle triangles is steadier than weighting by area).
Vec3 normalSum(const Mesh &mesh, const std::vector<Vec3> &p, int v) {
    Vec3 n = Vec3::Zero();
    for (const int *h = mesh.outgoingBegin(v); h != mesh.outgoingEnd(v); ++h) {
        const Vec3 a = p[size_t(mesh.head(*h))] - p[size_t(v)];
        const Vec3 b = p[size_t(mesh.head(Mesh::next(*h)))] - p[size_t(v)];
        const Vec3 c = a.cross(b);
        const double len = c.norm();
        if (len > 0) n += std::atan2(len, a.dot(b)) * (c / len);
    }
    return n;
}

} // namespace

SmoothedSurface smoothAlongNormals(const Mesh &mesh, int rounds) {
    const int n = mesh.nVertices();
    std::vector<Vec3> p = mesh.positions(), q(p.size());
    for (int pass = 0; pass < 2 * std::max(0, rounds); ++pass) {
        const double step = pass % 2 == 0 ? 0.5 : -0.53; // Taubin's λ, then μ
        parallelFor(0, n, [&](int64_t vv) {
            const int v = int(vv);
            q[size_t(v)] = p[size_t(v)];
            if (mesh.isBoundaryVertex(v) || mesh.degree(v) == 0) return;
            Vec3 mean = Vec3::Zero();
            for (const int *h = mesh.outgoingBegin(v); h != mesh.outgoingEnd(v); ++h) mean += p[size_t(mesh.head(*h))];
            mean /= double(mesh.degree(v));
            const Vec3 nrm = normalSum(mesh, p, v);
            const double len = nrm.norm();
            if (!(len > 0)) return;
            const Vec3 unit = nrm / len;
            q[size_t(v)] += step * (mean - p[size_t(v)]).dot(unit) * unit;
        }, 1024);
        std::swap(p, q);
    }
    SmoothedSurface out;
    out.rounds = rounds;
    out.mesh = std::make_unique<Mesh>(Mesh::fromTriangles(std::move(p), mesh.faces(), mesh.name()));
    out.frames = std::make_unique<TangentFrames>(*out.mesh);
    return out;
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
