#include "renderer/strokes/screen_field.h"
#include "renderer/output/large_buffer.h"

#include "core/error.h"
#include "core/parallel.h"
#include "field/singularities.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rosy::renderer {

namespace {

/// A screen vector folded into the half-plane of angles [0, π) (lines have no
/// orientation), normalized.
Vec2 foldLine(const Vec2 &v) {
    const Vec2 u = v.normalized();
    return (u.y() < 0 || (u.y() == 0 && u.x() < 0)) ? Vec2(-u) : u;
}

float lineAngle(const Eigen::Vector2f &folded) {
    const float a = std::atan2(folded.y(), folded.x());
    // Rounding to float can land on π itself, which is the same line as 0.
    return a >= 0.f && a < float(M_PI) ? a : 0.f;
}

/// Bilinear footprint of raster point p over pixel centres (at +0.5).
struct Footprint {
    int x0, y0;
    double fx, fy;
};

Footprint footprint(const Vec2 &p) {
    const double x = p.x() - 0.5, y = p.y() - 0.5;
    const double fx0 = std::floor(x), fy0 = std::floor(y);
    return {int(fx0), int(fy0), x - fx0, y - fy0};
}

/// Doubled-angle vector (cos 2a, sin 2a) of a unit line direction (cos a, sin a).
Vec2 doubled(const Eigen::Vector2f &d) {
    return Vec2(double(d.x()) * d.x() - double(d.y()) * d.y(), 2.0 * double(d.x()) * d.y());
}

/// Back from the doubled-angle sum to a unit line direction; false when it cancels.
bool undouble(const Vec2 &s, Vec2 &dir) {
    const double n = s.norm();
    if (!(n > 1e-9)) return false;
    // Half-angle from the cosine, avoiding atan2: (cos a, sin a) with cos 2a = c.
    const double c = s.x() / n;
    double cx = std::sqrt(std::max(0.0, 0.5 * (1 + c)));
    double sy = std::sqrt(std::max(0.0, 0.5 * (1 - c)));
    if (s.y() < 0) sy = -sy;
    dir = Vec2(cx, sy);
    return true;
}

/// |z| as sqrt(re² + im²): std::abs of a complex calls hypot(), which guards against
/// overflow and underflow at several times the cost; field values are O(1).
double modulus(const field::Complex &z) { return std::sqrt(z.real() * z.real() + z.imag() * z.imag()); }

/// 3D direction of the first member vector, angle arg(u)/N in face f's frame. For
/// N = 1, 2, 4 principal square roots give exactly that angle without trigonometry
/// (arg of the principal root is half the argument).
Vec3 memberDirection(const field::TangentFrames &frames, int f, field::Complex u, int nSym) {
    field::Complex r;
    switch (nSym) {
    case 1: r = u; break;
    case 2: r = std::sqrt(u); break;
    case 4: r = std::sqrt(std::sqrt(u)); break;
    default: return frames.faceDirection(f, std::arg(u) / nSym);
    }
    const double n = modulus(r);
    return (r.real() / n) * frames.faceAxisX(f) + (r.imag() / n) * frames.faceAxisY(f);
}

} // namespace

// Bilinear average of the line directions pick(i) of the valid pixels around p,
// in the doubled-angle representation (a line direction and its opposite agree).
// Returns false where no valid pixel contributes or the directions cancel.
template <typename Pick>
static bool sampleLines(const ScreenField &field, const Vec2 &p, Pick &&pick, Vec2 &dir) {
    const Footprint fp = footprint(p);
    Vec2 sum = Vec2::Zero();
    double wSum = 0;
    for (int k = 0; k < 4; ++k) {
        const int x = fp.x0 + (k & 1), y = fp.y0 + (k >> 1);
        if (x < 0 || y < 0 || x >= field.width || y >= field.height) continue;
        const size_t i = size_t(field.index(x, y));
        if (!field.valid(i)) continue;
        const double w = ((k & 1) ? fp.fx : 1 - fp.fx) * ((k >> 1) ? fp.fy : 1 - fp.fy);
        if (w <= 0) continue;
        sum += w * doubled(pick(i));
        wSum += w;
    }
    if (!(wSum > 1e-12)) return false;
    return undouble(sum, dir);
}

bool ScreenField::lineNear(const Vec2 &p, const Vec2 &heading, Vec2 &dir) const {
    // Per pixel the heading chooses the direction, so label swaps between
    // neighbouring pixels (cross fields have no global labels) do not mix lines.
    auto closest = [&](size_t i) -> const Eigen::Vector2f & {
        const Eigen::Vector2f &d0 = lines[i].d[0], &d1 = lines[i].d[1];
        const double c0 = std::abs(heading.x() * d0.x() + heading.y() * d0.y());
        const double c1 = std::abs(heading.x() * d1.x() + heading.y() * d1.y());
        return c0 >= c1 ? d0 : d1;
    };
    Vec2 d;
    if (!sampleLines(*this, p, closest, d)) return false;
    dir = d.dot(heading) < 0 ? Vec2(-d) : d;
    return true;
}

float ScreenField::angle(int family, size_t i) const {
    return lineAngle(dir(family, i));
}

bool ScreenField::lineOfFamily(const Vec2 &p, int family, Vec2 &dir) const {
    return sampleLines(*this, p, [&](size_t i) -> const Eigen::Vector2f & { return lines[i].d[family]; }, dir);
}

ScreenField computeScreenField(const GBuffer &gbuffer, const field::TangentFrames &frames,
                               const field::RosyField &field, const field::SingularityReport &report,
                               const Camera &camera) {
    const field::Mesh &mesh = frames.mesh();
    ROSY_CHECK_EQ(int(field.u.size()), mesh.nVertices());
    ROSY_CHECK(field.nSym >= 1);
    ScreenField out;
    out.width = gbuffer.width;
    out.height = gbuffer.height;
    out.nSym = field.nSym;
    const size_t n = gbuffer.nPixels();
    assignLarge(out.lines, n, ScreenField::Lines{{Eigen::Vector2f::Zero(), Eigen::Vector2f::Zero()}});
    assignLarge(out.strength, n, 0.f);
    if (n == 0) return out;

    // Corner values per face once: faces cover many pixels at high resolution.
    std::vector<std::array<field::Complex, 3>> corner(size_t(mesh.nFaces()));
    const std::vector<Vec3> &faceNormal = mesh.faceNormals();
    parallelFor(0, mesh.nFaces(), [&](int64_t f) { corner[size_t(f)] = frames.faceValues(int(f), field); });

    const int nSym = field.nSym;
    parallelFor(0, gbuffer.height, [&](int64_t y) {
        for (int x = 0; x < gbuffer.width; ++x) {
            const size_t i = size_t(gbuffer.index(x, int(y)));
            const int f = gbuffer.faceId[i];
            if (f < 0) continue;
            const Vec2 b = gbuffer.barycentric[i].cast<double>();
            const auto &c = corner[size_t(f)];
            // Representation vectors add linearly (P&Z Eq. 3), so interpolating them is
            // interpolating the N-RoSy; the member angle is taken afterwards.
            const field::Complex u = (1 - b.x() - b.y()) * c[0] + b.x() * c[1] + b.y() * c[2];
            const double strength = modulus(u);
            out.strength[i] = float(strength);
            if (!(strength > 1e-12)) continue;
            // The member lies in face f's plane; projected from there, one surface
            // direction jumps at every edge where faces bend against each other (on
            // coarse meshes by 20-40°), and lines stop or restart at each jump. Taken
            // into the tangent plane of the crease-aware shading normal instead, it turns
            // smoothly across such edges and still follows each side of a sharp crease.
            Vec3 m0 = memberDirection(frames, f, u, nSym);
            Vec3 nrm = faceNormal[size_t(f)];
            const Vec3 ns = gbuffer.creaseNormal(i);
            const Vec3 inPlane = m0 - m0.dot(ns) * ns;
            if (inPlane.norm() > 1e-6) {
                m0 = inPlane.normalized();
                nrm = ns;
            }
            const Vec3 m1 = nrm.cross(m0);
            const Eigen::Matrix<double, 2, 3> J = camera.projectJacobian(gbuffer.position(i));
            const Vec2 s0 = J * m0, s1 = J * m1;
            // Edge-on faces project their tangents to (nearly) nothing: no direction there.
            const double scale = J.norm();
            if (!(s0.norm() > 1e-6 * scale) || !(s1.norm() > 1e-6 * scale)) continue;
            const Vec2 l0 = foldLine(s0), l1 = foldLine(s1);
            out.lines[i].d[0] = l0.cast<float>();
            out.lines[i].d[1] = l1.cast<float>();
        }
    }, 1);

    out.singularities.reserve(report.singularities.size());
    for (const field::Singularity &s : report.singularities) {
        ScreenSingularity ss;
        ss.pWorld = s.position;
        ss.index = s.index();
        ss.face = s.face;
        ss.pRaster = camera.project(s.position);
        const double depth = camera.depth(s.position);
        const int px = int(std::floor(ss.pRaster.x())), py = int(std::floor(ss.pRaster.y()));
        if (depth > 0 && px >= 0 && py >= 0 && px < gbuffer.width && py < gbuffer.height &&
            gbuffer.covered(px, py)) {
            // Half a pixel of a steep face changes depth by a few per cent at most; a
            // hidden singularity lies behind by at least the object's thickness there.
            const double seen = gbuffer.depth[size_t(gbuffer.index(px, py))];
            ss.visible = std::abs(seen - depth) <= 0.02 * depth;
        }
        out.singularities.push_back(ss);
    }
    return out;
}

} // namespace rosy::renderer
