#include "field/separatrices.h"

#include "core/json.h"
#include "core/parallel.h"

#include <unsupported/Eigen/Polynomials>

#include <algorithm>
#include <cmath>

namespace rosy::field {

Eigen::Matrix2d faceJacobian(const TangentFrames &frames, const RosyField &field, int face) {
    const Mesh &mesh = frames.mesh();
    Vec2 q[3];
    for (int c = 0; c < 3; ++c) q[c] = frames.toFace2D(face, mesh.position(mesh.face(face)[c]));
    Eigen::Matrix2d m;
    m.col(0) = q[1] - q[0];
    m.col(1) = q[2] - q[0];
    const double det = m.determinant();
    if (!(std::abs(det) > 1e-14 * m.squaredNorm())) return Eigen::Matrix2d::Zero();
    const Eigen::Matrix2d inv = m.inverse();
    std::array<Complex, 3> u = frames.faceValues(face, field);
    // u(p) = u0 + (u1 − u0) b1 + (u2 − u0) b2 with (b1, b2) = M⁻¹ (p − q0).
    const Complex du1 = u[1] - u[0], du2 = u[2] - u[0];
    Eigen::Matrix2d dB; // d(value)/d(b1, b2): rows Re, Im
    dB << du1.real(), du2.real(), du1.imag(), du2.imag();
    return dB * inv;
}

namespace {

/// Left side of Eq. 9.
double eq9(const Eigen::Matrix2d &j, int nSym, double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    return std::sin(nSym * theta) * (j(0, 0) * c + j(0, 1) * s) -
           std::cos(nSym * theta) * (j(1, 0) * c + j(1, 1) * s);
}

/// Coefficients (lowest degree first) of Eq. 9 divided by cos^{N+1} θ, in t = tan θ:
/// S_N(t) (a + b t) − C_N(t) (c + d t), with C_N + i S_N = (1 + i t)^N = Σ_k binom(N,k) (it)^k
/// (Eq. 10–11: cos Nθ and sin Nθ as sums of cos^{N−k} sin^k).
std::vector<double> eq9Polynomial(const Eigen::Matrix2d &j, int nSym) {
    std::vector<double> cN(nSym + 1, 0.0), sN(nSym + 1, 0.0);
    double binom = 1;
    for (int k = 0; k <= nSym; ++k) {
        // i^k cycles through 1, i, −1, −i.
        const int r = k % 4;
        if (r == 0) cN[k] = binom;
        else if (r == 1) sN[k] = binom;
        else if (r == 2) cN[k] = -binom;
        else sN[k] = -binom;
        binom = binom * (nSym - k) / (k + 1);
    }
    std::vector<double> p(nSym + 2, 0.0);
    for (int k = 0; k <= nSym; ++k) {
        p[k] += sN[k] * j(0, 0) - cN[k] * j(1, 0);
        p[k + 1] += sN[k] * j(0, 1) - cN[k] * j(1, 1);
    }
    return p;
}

} // namespace

std::vector<SeparatrixDirection> separatrixDirections(const Eigen::Matrix2d &jacobian, int nSym) {
    std::vector<SeparatrixDirection> out;
    const double scale = jacobian.norm();
    if (!(scale > 0) || !jacobian.allFinite() || nSym < 1) return out;
    const Eigen::Matrix2d j = jacobian / scale; // Eq. 9 is homogeneous in J
    // Eq. 9 vanishing identically (N = 1 with J ∝ I, a pure source or sink): every ray
    // is a trajectory and none is distinguished.
    std::vector<double> poly = eq9Polynomial(j, nSym);
    double maxCoef = 0;
    for (double c : poly) maxCoef = std::max(maxCoef, std::abs(c));
    if (maxCoef < 1e-10) return out;

    std::vector<double> roots; // θ in [0, π)
    // θ = π/2 (cos θ = 0, t = ∞) is not a root of the polynomial: it shows as a vanishing
    // leading coefficient, so it is tested on Eq. 9 directly.
    if (std::abs(eq9(j, nSym, 0.5 * M_PI)) < 1e-9) roots.push_back(0.5 * M_PI);
    int degree = int(poly.size()) - 1;
    while (degree > 0 && std::abs(poly[degree]) < 1e-12 * maxCoef) --degree;
    if (degree > 0) {
        Eigen::VectorXd coeffs(degree + 1);
        for (int k = 0; k <= degree; ++k) coeffs[k] = poly[k] / maxCoef;
        Eigen::PolynomialSolver<double, Eigen::Dynamic> solver(coeffs);
        for (int r = 0; r < solver.roots().size(); ++r) {
            const Complex t = solver.roots()[r];
            // Companion eigenvalues of clustered roots carry imaginary noise; accept
            // loosely here and let the polished value of Eq. 9 decide.
            if (std::abs(t.imag()) > 1e-4 * (1 + std::abs(t))) continue;
            double theta = std::atan(t.real());
            for (int it = 0; it < 8; ++it) { // Newton on Eq. 9 in θ to undo the tan distortion
                const double h = 1e-7;
                const double f = eq9(j, nSym, theta);
                const double df = (eq9(j, nSym, theta + h) - eq9(j, nSym, theta - h)) / (2 * h);
                if (!(std::abs(df) > 1e-14)) break;
                const double stepRad = f / df;
                theta -= std::clamp(stepRad, -0.05, 0.05);
                if (std::abs(stepRad) < 1e-14) break;
            }
            if (std::abs(eq9(j, nSym, theta)) > 1e-8) continue;
            theta = std::fmod(theta, M_PI);
            if (theta < 0) theta += M_PI;
            roots.push_back(theta);
        }
    }
    std::sort(roots.begin(), roots.end());
    std::vector<double> unique;
    for (double r : roots) {
        // Roots near 0 and near π are the same line.
        if (!unique.empty() && r - unique.back() < 1e-7) continue;
        if (!unique.empty() && unique.front() + M_PI - r < 1e-7) continue;
        unique.push_back(r);
    }

    for (double theta : unique) {
        const Vec2 v(std::cos(theta), std::sin(theta));
        const Vec2 w = j * v;
        if (!(w.norm() > 1e-9)) continue; // a kernel direction of J has no field direction
        const double dot = std::cos(nSym * theta) * w.x() + std::sin(nSym * theta) * w.y();
        // Angles in [0, 2π); a root that rounded to just below π lands at 0, not 2π.
        auto wrap = [](double a) { return a >= 2 * M_PI - 1e-12 ? 0.0 : a; };
        if (nSym % 2 == 0) {
            out.push_back({wrap(dot > 0 ? theta : theta + M_PI), false});
        } else {
            out.push_back({theta, dot < 0});
            out.push_back({wrap(theta + M_PI), dot < 0});
        }
    }
    std::sort(out.begin(), out.end(),
              [](const SeparatrixDirection &a, const SeparatrixDirection &b) { return a.angleRad < b.angleRad; });
    return out;
}

std::vector<Separatrix> traceSeparatrices(const TangentFrames &frames, const RosyField &field,
                                          const std::vector<Singularity> &singularities,
                                          const SeparatrixOptions &options) {
    const Mesh &mesh = frames.mesh();
    const std::vector<int> faceIndex = faceIndexNumerators(frames, field);
    StreamlineOptions opt = options.streamline;
    if (!(opt.maxLength > 0)) {
        Vec3 lo, hi;
        mesh.bounds(lo, hi);
        opt.maxLength = options.maxLengthRelative * (hi - lo).norm();
    }
    // Resolved once here: the mean edge length is a pass over the whole mesh, far more
    // than tracing one short separatrix costs.
    if (!(opt.stepLength > 0)) opt.stepLength = 0.5 * mesh.meanEdgeLength();
    opt.leaveStartFaceStraight = true;
    opt.bothDirections = false;
    opt.stopAtSingularFaces = true;

    // One slot per singularity, concatenated in index order afterwards, so the
    // output does not depend on the thread count.
    std::vector<std::vector<Separatrix>> perSingularity(singularities.size());
    rosy::parallelFor(0, int64_t(singularities.size()), [&](int64_t i) {
        const Singularity &s = singularities[i];
        if (s.face < 0 || s.face >= mesh.nFaces()) return;
        const Eigen::Matrix2d j = faceJacobian(frames, field, s.face);
        for (const SeparatrixDirection &d : separatrixDirections(j, field.nSym)) {
            Separatrix sep;
            sep.singularity = int(i);
            sep.angleRad = d.angleRad;
            sep.incoming = d.incoming;
            sep.direction3D = frames.faceDirection(s.face, d.angleRad);
            StreamlineOptions o = opt;
            o.reverseField = d.incoming; // outwards along an incoming separatrix is against the flow
            sep.line = traceStreamline(frames, field, s.face, s.barycentric, sep.direction3D, o, &faceIndex);
            perSingularity[i].push_back(std::move(sep));
        }
    }, 1);
    std::vector<Separatrix> out;
    for (auto &v : perSingularity)
        for (auto &s : v) out.push_back(std::move(s));
    return out;
}

void writeSeparatricesJson(rosy::JsonWriter &json, const std::vector<Separatrix> &separatrices) {
    json.key("separatrices").beginArray();
    for (const Separatrix &s : separatrices) {
        json.beginObject();
        json.field("singularity", s.singularity);
        json.key("direction").beginArray();
        for (int k = 0; k < 3; ++k) json.value(s.direction3D[k]);
        json.endArray();
        json.field("incoming", s.incoming);
        json.key("polyline").beginArray();
        for (const Vec3 &p : s.line.points) {
            json.beginArray();
            for (int k = 0; k < 3; ++k) json.value(p[k]);
            json.endArray();
        }
        json.endArray();
        json.endObject();
    }
    json.endArray();
}

} // namespace rosy::field
