#include "renderer/strokes/quad_lines.h"

#include "core/error.h"
#include "core/parallel.h"
#include "renderer/strokes/hatching.h"

#include <algorithm>
#include <cmath>

namespace rosy::renderer {

int quadLineLevel(double density, const styles::HatchStyle &style) {
    if (!(density > 0) || !(density >= style.highlightDensity)) return 0;
    const double w = style.strokeWidthPx, L = std::max(style.quadEdgePx, 1e-9);
    const double c1 = std::min(1.0, w / (2 * L)), c2 = std::min(1.0, w / L);
    if (density < style.crossDensity) return std::abs(density - c1) <= std::abs(density - c2) ? 1 : 2;
    const double c3 = 1 - (1 - c2) * (1 - c1), c4 = 1 - (1 - c2) * (1 - c2);
    return std::abs(density - c3) <= std::abs(density - c4) ? 3 : 4;
}

namespace {

/// Pieces a segment is cut into on screen: at most this many pixels long, each kept
/// or dropped by what is at its midpoint.
constexpr double kPiecePx = 1.0;
constexpr int kSmoothingRounds = 2;

bool drawn(int family, int parity, int level) {
    return family == 0 ? level >= (parity == 0 ? 1 : 2) : level >= (parity == 0 ? 3 : 4);
}

/// The line with its kinks eased: kSmoothingRounds of p_i ← (p_{i−1} + 2 p_i + p_{i+1}) / 4
/// at every point but an open line's ends (normals alike, renormalised). The mesh's
/// vertices sit on a lattice that wobbles by a few per cent of the edge from one
/// vertex to the next (the position field's rounding), which a pen line would show
/// as a zigzag; the eased line stays within that wobble of the surface.
SurfaceLine smoothed(const SurfaceLine &line) {
    SurfaceLine out = line;
    const size_t n = line.points.size();
    if (n < 3) return out;
    std::vector<Vec3> p(n), q(n);
    for (int round = 0; round < kSmoothingRounds; ++round) {
        p = out.points;
        q = out.normals;
        for (size_t i = 0; i < n; ++i) {
            if (!line.closed && (i == 0 || i + 1 == n)) continue;
            const size_t a = (i + n - 1) % n, b = (i + 1) % n;
            out.points[i] = 0.25 * (p[a] + 2.0 * p[i] + p[b]);
            const Vec3 m = q[a] + 2.0 * q[i] + q[b];
            if (m.norm() > 0) out.normals[i] = m.normalized();
        }
    }
    return out;
}

/// The strokes of one line, in order along it (ids unset).
std::vector<Stroke> lineStrokes(const SurfaceLine &line, const ScreenField &screen,
                                const std::vector<float> &targetDensity, const GBuffer &g, const Camera &camera,
                                const styles::HatchStyle &style) {
    std::vector<Stroke> out;
    Stroke run;
    int runFamily = -1;
    auto finish = [&] {
        double length = 0;
        for (size_t k = 1; k < run.points.size(); ++k) length += (run.points[k] - run.points[k - 1]).norm();
        if (run.points.size() >= 2 && length >= std::max(style.minLengthPx, 1e-9)) {
            run.kind = StrokeKind::Hatch;
            run.family = runFamily;
            out.push_back(std::move(run));
        }
        run = Stroke();
        runFamily = -1;
    };
    const size_t n = line.points.size();
    const size_t nSegments = line.closed ? n : n - 1;
    for (size_t s = 0; s < nSegments; ++s) {
        const Vec3 &a = line.points[s], &b = line.points[(s + 1) % n];
        const Vec3 &na = line.normals[s], &nb = line.normals[(s + 1) % n];
        const int family = line.families[s];
        if (runFamily >= 0 && family != runFamily) finish(); // the run ended at this segment's start
        if (!(camera.depth(a) > 0) || !(camera.depth(b) > 0)) {
            finish();
            continue;
        }
        const Vec2 pa = camera.project(a), pb = camera.project(b);
        const Vec2 along = pb - pa;
        const int pieces = std::clamp(int(std::ceil(along.norm() / kPiecePx)), 1, 1 << 16);
        // Depth slack: a few pixel footprints and a quarter of the edge, which lies on
        // a chord below (convex) or above (concave) the surface the G-buffer saw.
        const Eigen::Matrix<double, 2, 3> J = camera.projectJacobian(0.5 * (a + b));
        const double pxPerWorld = J.norm() / std::sqrt(2.0);
        const double slack = (pxPerWorld > 0 ? 3.0 / pxPerWorld : 0.0) + 0.25 * (b - a).norm();
        bool pending = false; // the run's last point is the current piece's end, not yet pushed
        for (int k = 0; k < pieces; ++k) {
            const double tm = (k + 0.5) / pieces;
            const Vec3 pm = a + tm * (b - a);
            const Vec3 nm = (1 - tm) * na + tm * nb;
            const Vec2 rm = pa + tm * along;
            const int px = int(std::floor(rm.x())), py = int(std::floor(rm.y()));
            bool keep = px >= 0 && py >= 0 && px < g.width && py < g.height && nm.dot(camera.toViewer(pm)) > 0;
            size_t i = 0;
            if (keep) {
                i = size_t(g.index(px, py));
                keep = g.faceId[i] >= 0 && screen.valid(i) && camera.depth(pm) <= g.depth[i] + slack;
            }
            if (keep) {
                const float d = targetDensity[i];
                keep = drawn(family, line.parity, quadLineLevel(d == d ? std::clamp(d, 0.f, 1.f) : 0.f, style));
            }
            if (!keep) {
                if (pending) run.points.push_back(pa + (double(k) / pieces) * along);
                pending = false;
                finish();
                continue;
            }
            if (run.points.empty()) {
                run.points.push_back(pa + (double(k) / pieces) * along);
                runFamily = family;
            }
            pending = true;
        }
        // The segment's end: a corner of the line (the next segment turns).
        if (pending) run.points.push_back(pb);
    }
    finish();
    return out;
}

} // namespace

StrokeList quadLineHatches(const std::vector<SurfaceLine> &lines, const ScreenField &screen,
                           const std::vector<float> &targetDensity, const GBuffer &gbuffer, const Camera &camera,
                           const styles::HatchStyle &style, uint32_t seed) {
    ROSY_CHECK_EQ(screen.width, gbuffer.width);
    ROSY_CHECK_EQ(screen.height, gbuffer.height);
    ROSY_CHECK_EQ(targetDensity.size(), gbuffer.nPixels());
    std::vector<std::vector<Stroke>> perLine(lines.size());
    parallelFor(0, int64_t(lines.size()), [&](int64_t l) {
        const SurfaceLine &line = lines[size_t(l)];
        const size_t nSegments = line.closed ? line.points.size() : line.points.size() - 1;
        if (line.points.size() < 2 || line.normals.size() != line.points.size() || line.families.size() != nSegments)
            return;
        perLine[size_t(l)] = lineStrokes(smoothed(line), screen, targetDensity, gbuffer, camera, style);
    }, 16);
    StrokeList out;
    out.width = gbuffer.width;
    out.height = gbuffer.height;
    for (std::vector<Stroke> &strokes : perLine)
        for (Stroke &s : strokes) {
            s.id = uint32_t(out.strokes.size());
            out.strokes.push_back(std::move(s));
        }
    parallelFor(0, int64_t(out.strokes.size()), [&](int64_t k) { finishStroke(out.strokes[size_t(k)], style, seed); },
                64);
    return out;
}

} // namespace rosy::renderer
