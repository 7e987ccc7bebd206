// Screen-space field and Jobard–Lefer hatching against analytic expectations:
// projected directions from finite differences of Camera::project, spacings from
// the coverage formulas, directions from the exact cylinder.

#include "field/design.h"
#include "field/field_builder.h"
#include "field/frames.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "renderer/view/camera.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"
#include "renderer/strokes/hatching.h"
#include "renderer/strokes/screen_field.h"

#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <memory>

using namespace rosy;
using namespace rosy::renderer;

namespace {


/// A mesh, its field and everything the hatcher needs, rendered once.
struct Scene {
    field::Mesh mesh;
    std::unique_ptr<field::TangentFrames> frames;
    field::RosyField field;
    Camera camera;
    GBuffer gbuffer;
    ScreenField screen;

    Scene(field::Mesh m, const Camera &cam) : mesh(std::move(m)), camera(cam) {
        frames = std::make_unique<field::TangentFrames>(mesh);
    }
    void render() {
        RayScene rs(mesh);
        gbuffer = renderGBuffer(rs, mesh, camera);
        screen = computeScreenField(gbuffer, *frames, field, field::findSingularities(*frames, field), camera);
    }
    std::vector<float> uniformDensity(float d) const { return std::vector<float>(gbuffer.nPixels(), d); }
};

/// A 2-RoSy on the z = 0 plane along world x, from one order-0 design element.
field::RosyField constantField(const field::TangentFrames &frames, int nSym) {
    field::DesignElement e;
    e.position = field::Vec3(0.1, 0.05, 0);
    e.order = 0;
    e.direction = field::Vec3::UnitX();
    return field::designField(frames, nSym, {e});
}

/// Screen direction (unit) of world tangent t at p, by central differences of project().
Vec2 projectedDirection(const Camera &cam, const Vec3 &p, const Vec3 &t) {
    const double eps = 1e-5;
    return (cam.project(p + eps * t) - cam.project(p - eps * t)).normalized();
}

/// Angle in degrees between two screen lines (mod π).
double lineAngleDeg(const Vec2 &a, const Vec2 &b) {
    const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
    return std::acos(c) / test::kDeg;
}

Scene tiltedPlane(int size) {
    // Seen at 45° about the world x axis: lines along x stay parallel on screen.
    Camera cam = Camera::perspective(Vec3(0, -3, 3), Vec3(0, 0, 0), Vec3(0, 1, 0), 35.0, size, size);
    Scene s(field::makeGrid(8), cam);
    s.field = constantField(*s.frames, 2);
    s.render();
    return s;
}

Scene cylinder(int size) {
    Camera cam = Camera::perspective(Vec3(4.5, 0.8, 1.6), Vec3(0, 0, 0), Vec3(0, 0, 1), 35.0, size, size);
    Scene s(field::makeCylinder(1.0, 3.0, 256, 24), cam);
    s.field = field::buildField(*s.frames, field::FieldSpec{}).field;
    s.render();
    return s;
}

/// Smallest screen distance from a stroke segment of `list` to any singularity of
/// `sing`, projected through `cam`.
double nearestStrokeToSingularities(const StrokeList &list, const field::SingularityReport &sing, const Camera &cam) {
    double nearest = 1e9;
    for (const Stroke &stroke : list.strokes)
        for (size_t k = 0; k + 1 < stroke.points.size(); ++k)
            for (const field::Singularity &sg : sing.singularities) {
                const Vec2 c = cam.project(sg.position);
                const Vec2 a = stroke.points[k], ab = stroke.points[k + 1] - a;
                const double t = std::clamp((c - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
                nearest = std::min(nearest, (c - (a + t * ab)).norm());
            }
    return nearest;
}

} // namespace

TEST(HatchSpacing, MatchesCoverageFormulas) {
    styles::HatchStyle st;
    // One family of width w at spacing s covers w / s.
    EXPECT_NEAR(hatchSpacingPx(0.2, 1, st), st.strokeWidthPx / 0.2, 1e-12);
    // Two crossing families: 1 − (1 − w/s)² = ρ.
    const double s2 = hatchSpacingPx(0.5, 2, st);
    EXPECT_NEAR(1.0 - std::pow(1.0 - st.strokeWidthPx / s2, 2), 0.5, 1e-12);
    EXPECT_DOUBLE_EQ(hatchSpacingPx(0.9, 1, st), st.minSpacingPx);
    EXPECT_DOUBLE_EQ(hatchSpacingPx(0.0, 1, st), st.maxSpacingPx);
    EXPECT_EQ(hatchFamilies(0.01, st), 0);
    EXPECT_EQ(hatchFamilies(0.2, st), 1);
    EXPECT_EQ(hatchFamilies(0.7, st), 2);
    EXPECT_EQ(hatchFamilies(std::nan(""), st), 0);
}

TEST(ScreenField, DirectionsFollowTheExactPerspectiveProjection) {
    Scene s = tiltedPlane(96);
    int checked = 0;
    double worst = 0;
    for (int y = 0; y < 96; y += 3)
        for (int x = 0; x < 96; x += 3) {
            if (!s.screen.isValid(x, y)) continue;
            const size_t i = size_t(s.gbuffer.index(x, y));
            const Vec3 p = s.gbuffer.position(i);
            const float a0 = s.screen.angle(0, i), a1 = s.screen.angle(1, i);
            ASSERT_GE(a0, 0.f);
            ASSERT_LT(a0, float(M_PI));
            // d0 along world x, d1 along n × x = world y (which recedes to a vanishing point).
            worst = std::max(worst, lineAngleDeg(Vec2(std::cos(a0), std::sin(a0)), projectedDirection(s.camera, p, Vec3::UnitX())));
            worst = std::max(worst, lineAngleDeg(Vec2(std::cos(a1), std::sin(a1)), projectedDirection(s.camera, p, Vec3::UnitY())));
            ++checked;
        }
    EXPECT_GT(checked, 300);
    EXPECT_LT(worst, 0.05);
    // The receding family really converges: dropping z would have made it vertical everywhere.
    const size_t left = size_t(s.gbuffer.index(20, 48)), right = size_t(s.gbuffer.index(76, 48));
    EXPECT_GT(std::abs(s.screen.angle(1, left) - s.screen.angle(1, right)) / test::kDeg, 5.0);
}

// valid() and lineNear() tell a valid pixel by its directions: a pixel that sees the
// plane (whose field is nowhere zero and which is nowhere edge-on) holds two unit
// directions, a background pixel zeros; the angle is the direction's, in [0, π).
TEST(ScreenField, CoveredPixelsAndOnlyTheyHoldUnitDirections) {
    Scene s = tiltedPlane(64);
    int covered = 0, background = 0;
    for (size_t i = 0; i < s.screen.nPixels(); ++i) {
        const bool sees = s.gbuffer.faceId[i] >= 0;
        ASSERT_EQ(s.screen.valid(i), sees) << "pixel " << i;
        for (int f = 0; f < 2; ++f) {
            const Eigen::Vector2f &d = s.screen.dir(f, i);
            if (sees) {
                ASSERT_NEAR(d.norm(), 1.0f, 1e-5f) << "pixel " << i;
                const float a = s.screen.angle(f, i);
                ASSERT_GE(a, 0.f);
                ASSERT_LT(a, float(M_PI));
                // The same line: (cos a, sin a) is ±d.
                ASSERT_NEAR(std::abs(std::cos(a) * d.x() + std::sin(a) * d.y()), 1.0f, 1e-5f) << "pixel " << i;
            } else {
                ASSERT_EQ(d.x(), 0.0f);
                ASSERT_EQ(d.y(), 0.0f);
                ASSERT_EQ(s.screen.angle(f, i), 0.0f);
            }
        }
        ++(sees ? covered : background);
    }
    // The plane does not fill the picture: both kinds occur.
    EXPECT_GT(covered, 500);
    EXPECT_GT(background, 100);
}

TEST(Hatching, PlaneAt45DegreesHasStyleSpacing) {
    Scene s = tiltedPlane(192);
    styles::HatchStyle st;
    const float density = 0.2f; // one family, d_sep = w / ρ
    const double dSep = st.strokeWidthPx / density;
    HatchReport report;
    StrokeList list = traceHatches(s.screen, s.uniformDensity(density), s.gbuffer, st, 7, &report);
    ASSERT_GT(report.strokes, 5);
    EXPECT_EQ(report.strokesFamily1, 0);
    EXPECT_EQ(report.minSpacingViolations, 0);
    // Crossings of the vertical centre line, middle half of the image.
    std::vector<double> ys;
    const double xc = 96.0;
    for (const Stroke &st2 : list.strokes)
        for (size_t k = 0; k + 1 < st2.points.size(); ++k) {
            const Vec2 &a = st2.points[k], &b = st2.points[k + 1];
            if ((a.x() - xc) * (b.x() - xc) > 0 || a.x() == b.x()) continue;
            const double y = a.y() + (xc - a.x()) / (b.x() - a.x()) * (b.y() - a.y());
            if (y > 48 && y < 144) ys.push_back(y);
        }
    std::sort(ys.begin(), ys.end());
    ASSERT_GE(ys.size(), 10u);
    double sum = 0;
    for (size_t k = 1; k < ys.size(); ++k) {
        const double gap = ys[k] - ys[k - 1];
        EXPECT_GT(gap, 0.5 * dSep) << "lines closer than d_test at y = " << ys[k];
        sum += gap;
    }
    EXPECT_NEAR(sum / double(ys.size() - 1) / dSep, 1.0, 0.05);
}

TEST(Hatching, NoSpacingViolationsAcrossAToneStep) {
    // A step from one family (light) to cross-hatching (dark) makes d_test jump
    // between neighbouring pixels; the measurement then takes the smaller d_test,
    // the tracer must keep away by the larger one.
    Scene s = tiltedPlane(192);
    styles::HatchStyle st;
    std::vector<float> density(s.gbuffer.nPixels(), 0.0f);
    for (int y = 0; y < s.gbuffer.height; ++y)
        for (int x = 0; x < s.gbuffer.width; ++x)
            density[size_t(s.gbuffer.index(x, y))] = x < 96 ? 0.15f : 0.7f;
    ASSERT_EQ(hatchFamilies(0.15, st), 1);
    ASSERT_EQ(hatchFamilies(0.7, st), 2);
    HatchReport report;
    traceHatches(s.screen, density, s.gbuffer, st, 3, &report);
    ASSERT_GT(report.strokesFamily0, 5);
    ASSERT_GT(report.strokesFamily1, 2);
    EXPECT_EQ(report.minSpacingViolations, 0);
    EXPECT_EQ(report.strokesNearSingularities, 0);
}

TEST(Hatching, CylinderHatchesFollowRulingsAndCircles) {
    Scene s = cylinder(160);
    styles::HatchStyle st;
    HatchReport report;
    StrokeList list = traceHatches(s.screen, s.uniformDensity(0.6f), s.gbuffer, st, 3, &report);
    ASSERT_GT(report.strokesFamily0, 5);
    ASSERT_GT(report.strokesFamily1, 5);
    int checked = 0, within = 0;
    double sumErr = 0;
    for (const Stroke &stroke : list.strokes)
        for (size_t k = 0; k + 1 < stroke.points.size(); ++k) {
            const Vec2 m = 0.5 * (stroke.points[k] + stroke.points[k + 1]);
            // The exact cylinder x² + y² = 1 along the ray through the segment midpoint.
            const Ray ray = s.camera.generateRay(m.x(), m.y());
            const double a = ray.dir.x() * ray.dir.x() + ray.dir.y() * ray.dir.y();
            const double b = 2 * (ray.origin.x() * ray.dir.x() + ray.origin.y() * ray.dir.y());
            const double c = ray.origin.x() * ray.origin.x() + ray.origin.y() * ray.origin.y() - 1;
            const double disc = b * b - 4 * a * c;
            if (disc <= 0) continue;
            const Vec3 p = ray.origin + (-b - std::sqrt(disc)) / (2 * a) * ray.dir;
            const Vec3 n(p.x(), p.y(), 0);
            // Away from the open ends and from grazing views, where the mesh and the
            // curvature estimate differ from the ideal cylinder.
            if (std::abs(p.z()) > 1.1 || -n.dot(ray.dir) < 0.4) continue;
            const Vec2 seg = stroke.points[k + 1] - stroke.points[k];
            if (seg.norm() < 0.3) continue;
            const double eRuling = lineAngleDeg(seg, projectedDirection(s.camera, p, Vec3::UnitZ()));
            const double eCircle = lineAngleDeg(seg, projectedDirection(s.camera, p, Vec3(-p.y(), p.x(), 0)));
            const double e = std::min(eRuling, eCircle);
            sumErr += e;
            within += e <= 1.0;
            ++checked;
        }
    ASSERT_GT(checked, 500);
    EXPECT_EQ(within, checked) << "mean error " << sumErr / checked << " deg";
}

TEST(Hatching, InkNeverDecreasesAlongAToneRamp) {
    Camera cam = Camera::orthographic(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 1.8, 256, 256);
    Scene s(field::makeGrid(4), cam);
    s.field = constantField(*s.frames, 2);
    s.render();
    // Eight horizontal bands of 32 rows, density 0.05 (paper) to 0.75 (cross-hatched).
    std::vector<float> density(s.gbuffer.nPixels());
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) density[size_t(y * 256 + x)] = 0.05f + 0.1f * float(y / 32);
    styles::HatchStyle st;
    // Spacing not clamped in the darkest bands, so every band asks for more ink than
    // the one above; no taper, which thins the ends of strokes at the image border
    // independently of tone.
    // The pen is kept well below the closest spacing (1.4 px lines at 2 px), so the
    // darkest band is still open hatching the tracer can fill, not lines touching.
    st.minSpacingPx = 2.0;
    st.strokeWidthPx = 1.4;
    st.taper = 0.0;
    StrokeList list = traceHatches(s.screen, density, s.gbuffer, st, 11, nullptr);
    // Ink per covered pixel of each band, over the band's inner 24 rows: the first
    // and last four rows meet the neighbouring band (where strokes of either tone may
    // end) or the image border (the guard band keeps strokes off it), and the
    // darkest band, the last one, would otherwise lose a line to the border.
    auto inner = [](double y) { const double t = std::fmod(y, 32.0); return t >= 4.0 && t < 28.0; };
    std::vector<double> ink(8, 0.0), area(8, 0.0);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            if (inner(y + 0.5)) area[size_t(y / 32)] += s.gbuffer.covered(x, y) ? 1.0 : 0.0;
    for (const Stroke &stroke : list.strokes)
        for (size_t k = 0; k + 1 < stroke.points.size(); ++k) {
            const Vec2 m = 0.5 * (stroke.points[k] + stroke.points[k + 1]);
            if (!inner(m.y())) continue;
            const int band = std::clamp(int(m.y() / 32), 0, 7);
            ink[size_t(band)] += (stroke.points[k + 1] - stroke.points[k]).norm() * 0.5 *
                                 (stroke.widths[k] + stroke.widths[k + 1]);
        }
    EXPECT_EQ(ink[0], 0.0); // below highlightDensity
    for (int b = 0; b < 8; ++b) {
        ASSERT_GT(area[size_t(b)], 1000.0);
        ink[size_t(b)] /= area[size_t(b)];
    }
    for (int b = 1; b < 8; ++b) EXPECT_GT(ink[size_t(b)], ink[size_t(b - 1)]) << "band " << b;
}

/// A disk (makeDisk(rings)) seen from above at res², its 4-RoSy field designed from one
/// singular element of `order` at `at`, rendered.
Scene diskWithElement(int rings, int res, const field::Vec3 &at, int order) {
    const Camera cam = Camera::perspective(Vec3(0, -1.6, 2.6), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, res, res);
    Scene s(field::makeDisk(rings), cam);
    field::DesignElement e;
    e.position = at;
    e.order = order;
    s.field = field::designField(*s.frames, 4, {e});
    s.render();
    return s;
}

TEST(Hatching, StrokesStayOnTheSurfaceAndAwayFromSingularities) {
    Scene s = diskWithElement(24, 192, field::Vec3(0.05, 0.02, 0), 1);
    styles::HatchStyle st;
    const float density = 0.1f;
    const double dSep = st.strokeWidthPx / density; // one family
    HatchReport report;
    StrokeList list = traceHatches(s.screen, s.uniformDensity(density), s.gbuffer, st, 5, &report);
    ASSERT_GT(report.strokes, 5);
    EXPECT_EQ(report.strokesNearSingularities, 0);
    EXPECT_EQ(report.minSpacingViolations, 0);

    // Singularities straight from the field, projected by the camera.
    const field::SingularityReport sing = field::findSingularities(*s.frames, s.field);
    ASSERT_FALSE(sing.singularities.empty());
    for (const Stroke &stroke : list.strokes)
        for (const Vec2 &p : stroke.points)
            ASSERT_TRUE(s.gbuffer.covered(int(std::floor(p.x())), int(std::floor(p.y()))))
                << "stroke " << stroke.id << " leaves the surface at " << p.transpose();
    const double nearest = nearestStrokeToSingularities(list, sing, s.camera);
    EXPECT_GE(nearest, 0.98 * dSep);
    // Not vacuous: hatches do come up to the disc.
    EXPECT_LT(nearest, 2.0 * dSep);
}

// A line that stops at a singularity's keep-away disc ends there at full width: a
// taper would thin its last three widths and widen the light hole around the disc.
// Its other end, stopped by anything else, is tapered, and the mean width is still
// the style's.
TEST(Hatching, StrokesEndingAtADiscKeepTheirWidth) {
    Camera cam = Camera::perspective(Vec3(0, -1.6, 2.6), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 192, 192);
    Scene s(field::makeDisk(24), cam);
    field::DesignElement e;
    e.position = field::Vec3(0.05, 0.02, 0);
    e.order = 1;
    s.field = field::designField(*s.frames, 4, {e});
    s.render();
    styles::HatchStyle st;
    st.pressureVariation = 0.0;
    st.jitterPx = 0.0;
    const float density = 0.2f;
    const double dSep = st.strokeWidthPx / density; // one family: the disc's radius, 9 px
    const StrokeList list = traceHatches(s.screen, s.uniformDensity(density), s.gbuffer, st, 5);
    const field::SingularityReport sing = field::findSingularities(*s.frames, s.field);
    ASSERT_FALSE(sing.singularities.empty());
    auto nearestSingularity = [&](const Vec2 &p) {
        double d = 1e9;
        for (const field::Singularity &sg : sing.singularities) d = std::min(d, (p - cam.project(sg.position)).norm());
        return d;
    };
    int atDisc = 0, elsewhere = 0;
    for (const Stroke &stroke : list.strokes) {
        const size_t n = stroke.points.size();
        ASSERT_GE(n, 2u);
        const float widest = *std::max_element(stroke.widths.begin(), stroke.widths.end());
        double length = 0.0, ink = 0.0;
        for (size_t k = 0; k + 1 < n; ++k) {
            const double l = (stroke.points[k + 1] - stroke.points[k]).norm();
            length += l;
            ink += l * 0.5 * (stroke.widths[k] + stroke.widths[k + 1]);
        }
        EXPECT_NEAR(ink / length, st.strokeWidthPx, 0.03 * st.strokeWidthPx) << "stroke " << stroke.id;
        for (size_t k : {size_t(0), n - 1}) {
            const double d = nearestSingularity(stroke.points[k]);
            if (d < dSep + 2.0) { // the last step (1.8 px) before the disc
                ++atDisc;
                EXPECT_FLOAT_EQ(stroke.widths[k], widest) << "stroke " << stroke.id << " at " << d << " px";
            } else if (d > 2.0 * dSep) {
                ++elsewhere;
                EXPECT_LT(stroke.widths[k], 0.5f * widest) << "stroke " << stroke.id;
            }
        }
    }
    EXPECT_GE(atDisc, 4); // lines do come up to the disc
    EXPECT_GE(elsewhere, 4);
}

// A +1 and a −1 design element a few pixels apart on screen give a pair of
// singularities whose indices cancel. In cross-hatched tone the pair is below the
// drawing's scale: hatching runs up to it (a separate keep-away disc for each would
// leave a light hole). Where a single family hatches, each keeps its own disc.
TEST(Hatching, CancellingPairIsClearedOnlyInLightTone) {
    Camera cam = Camera::perspective(Vec3(0, -1.6, 2.6), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 256, 256);
    Scene s(field::makeDisk(40), cam);
    field::DesignElement plus, minus;
    plus.position = field::Vec3(-0.015, 0.0, 0);
    plus.order = 1;
    minus.position = field::Vec3(0.015, 0.0, 0);
    minus.order = -1;
    s.field = field::designField(*s.frames, 4, {plus, minus});
    s.render();
    const field::SingularityReport sing = field::findSingularities(*s.frames, s.field);
    ASSERT_GE(sing.singularities.size(), 2u);
    styles::HatchStyle st;
    auto nearestStroke = [&](const StrokeList &list) { return nearestStrokeToSingularities(list, sing, cam); };
    // Dark: two families; d_sep of the first family from the spacing formula,
    // 1.8 / (1 − (1 − 0.8) / (1 − b)) with b = 1 − sqrt(0.2), about 3.26 px.
    HatchReport dark;
    const StrokeList darkList = traceHatches(s.screen, s.uniformDensity(0.8f), s.gbuffer, st, 5, &dark);
    ASSERT_GT(dark.strokesFamily1, 5);
    const double b = 1.0 - std::sqrt(0.2);
    const double dSepDark = st.strokeWidthPx / (1.0 - 0.2 / (1.0 - b));
    EXPECT_LT(nearestStroke(darkList), 0.5 * dSepDark);
    EXPECT_EQ(dark.minSpacingViolations, 0);
    // Light: one family, d_sep = 1.8 / 0.2 = 9 px; every singularity keeps its disc.
    HatchReport light;
    const StrokeList lightList = traceHatches(s.screen, s.uniformDensity(0.2f), s.gbuffer, st, 5, &light);
    ASSERT_GT(light.strokes, 5);
    EXPECT_EQ(light.strokesNearSingularities, 0);
    EXPECT_GE(nearestStroke(lightList), 0.98 * st.strokeWidthPx / 0.2);
}

// HatchReport::singularityHoles sees the white speck a lone singularity's keep-away
// disc leaves in cross-hatched tone (elk, dragknob: docs/hatching.md), and nothing in
// single tone or where a line passes; the tracer inks such a speck (lines that stopped
// at the disc run on straight through it), and leaves a single-tone disc empty.
TEST(Hatching, SingularityHoleIsCountedInCrossToneOnly) {
    Scene s = diskWithElement(40, 256, field::Vec3(0.0, 0.0, 0), 1);
    int visible = 0;
    Vec2 at = Vec2::Zero();
    for (const ScreenSingularity &sg : s.screen.singularities)
        if (sg.visible) ++visible, at = sg.pRaster;
    ASSERT_EQ(visible, 1);
    styles::HatchStyle st;
    const std::vector<float> dark = s.uniformDensity(0.8f), light = s.uniformDensity(0.2f);
    HatchReport r;
    const StrokeList traced = traceHatches(s.screen, dark, s.gbuffer, st, 5, &r);
    ASSERT_GT(r.strokesFamily1, 5);
    // The tracer inked the speck: no hole, and lines run through the disc.
    EXPECT_EQ(r.singularityHoles, 0);
    const double b = 1.0 - std::sqrt(0.2);
    const double dSep = st.strokeWidthPx / (1.0 - 0.2 / (1.0 - b)); // family 0's d_sep at 0.8
    auto pointsWithin = [&](const StrokeList &l, double radius) {
        int n = 0;
        for (const Stroke &k : l.strokes)
            for (const Vec2 &p : k.points) n += (p - at).norm() < radius;
        return n;
    };
    EXPECT_GT(pointsWithin(traced, 0.5 * dSep), 0);
    // The lines as they were before they ran on into the disc (every point within d_sep
    // of the singularity cut out, strokes split there): the measure sees the speck.
    StrokeList list = traced;
    list.strokes.clear();
    for (const Stroke &k : traced.strokes) {
        Stroke piece = k;
        piece.points.clear();
        piece.widths.clear();
        for (size_t i = 0; i <= k.points.size(); ++i) {
            if (i < k.points.size() && (k.points[i] - at).norm() >= dSep) {
                piece.points.push_back(k.points[i]);
                piece.widths.push_back(k.widths[i]);
            } else if (!piece.points.empty()) {
                if (piece.points.size() >= 2) list.strokes.push_back(piece);
                piece.points.clear();
                piece.widths.clear();
            }
        }
    }
    EXPECT_EQ(pointsWithin(list, dSep), 0);
    EXPECT_EQ(countHatches(list, s.screen, dark, st).singularityHoles, 1); // empty of both families
    // Single tone: a disc there is the rule, not a hole; the tracer keeps it empty.
    EXPECT_EQ(countHatches(list, s.screen, light, st).singularityHoles, 0);
    HatchReport single;
    traceHatches(s.screen, light, s.gbuffer, st, 5, &single);
    EXPECT_EQ(single.strokesNearSingularities, 0);
    EXPECT_EQ(single.singularityHoles, 0);
    // A line through it fills it.
    Stroke through;
    through.points = {at - Vec2(6, 0), at + Vec2(6, 0)};
    through.widths = {1.0f, 1.0f};
    through.family = 0;
    list.strokes.push_back(through);
    EXPECT_EQ(countHatches(list, s.screen, dark, st).singularityHoles, 0);
}

TEST(Hatching, SameStrokesForOneAndTwoThreads) {
    Scene s = cylinder(128);
    styles::HatchStyle st;
    st.jitterPx = 0.3;
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        ScreenField sf = computeScreenField(s.gbuffer, *s.frames, s.field, field::findSingularities(*s.frames, s.field), s.camera);
        return traceHatches(sf, s.uniformDensity(0.5f), s.gbuffer, st, 9, nullptr);
    };
    const StrokeList a = run(1), b = run(2);
    ASSERT_EQ(a.strokes.size(), b.strokes.size());
    ASSERT_GT(a.strokes.size(), 3u);
    for (size_t k = 0; k < a.strokes.size(); ++k) {
        EXPECT_EQ(a.strokes[k].id, uint32_t(k));
        EXPECT_EQ(a.strokes[k].id, b.strokes[k].id);
        EXPECT_EQ(a.strokes[k].family, b.strokes[k].family);
        ASSERT_EQ(a.strokes[k].points.size(), b.strokes[k].points.size());
        for (size_t i = 0; i < a.strokes[k].points.size(); ++i) {
            EXPECT_EQ(a.strokes[k].points[i], b.strokes[k].points[i]);
            EXPECT_EQ(a.strokes[k].widths[i], b.strokes[k].widths[i]);
        }
    }
}

// The hook the render uses to start its contours beside the sequential tracer: called
// exactly once, with or without pixels, and the strokes do not depend on it.
TEST(Hatching, WhileTracingIsCalledOnceOnEveryPath) {
    Scene s = cylinder(96);
    styles::HatchStyle st;
    ScreenField sf = computeScreenField(s.gbuffer, *s.frames, s.field, field::findSingularities(*s.frames, s.field), s.camera);
    int calls = 0;
    const StrokeList with = traceHatches(sf, s.uniformDensity(0.7f), s.gbuffer, st, 3, nullptr, [&] { ++calls; });
    EXPECT_EQ(calls, 1);
    const StrokeList without = traceHatches(sf, s.uniformDensity(0.7f), s.gbuffer, st, 3);
    ASSERT_GT(with.strokes.size(), 3u);
    ASSERT_EQ(with.strokes.size(), without.strokes.size());
    for (size_t k = 0; k < with.strokes.size(); ++k) EXPECT_EQ(with.strokes[k].points, without.strokes[k].points);

    calls = 0;
    const StrokeList none = traceHatches(ScreenField{}, {}, GBuffer{}, st, 3, nullptr, [&] { ++calls; });
    EXPECT_TRUE(none.strokes.empty());
    EXPECT_EQ(calls, 1);
}

TEST(Hatching, StubsAreStrokesShorterThanFourSpacings) {
    Camera cam = Camera::orthographic(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 1.8, 128, 128);
    Scene s(field::makeGrid(4), cam);
    s.field = constantField(*s.frames, 2);
    s.render();
    styles::HatchStyle st;
    const float density = 0.3f; // one family: d_sep = 1.8 / 0.3 = 6 px, a stub is < 24 px
    ASSERT_NEAR(familySpacingPx(density, 0, st), 6.0, 1e-6); // 0.3f is not 0.3
    StrokeList list;
    list.width = list.height = 128;
    auto add = [&](double length, double y) {
        Stroke stroke;
        stroke.kind = StrokeKind::Hatch;
        stroke.id = uint32_t(list.strokes.size());
        for (double x = 20; x <= 20 + length + 1e-9; x += length / 8) stroke.points.push_back(Vec2(x, y));
        stroke.widths.assign(stroke.points.size(), 1.8f);
        list.strokes.push_back(stroke);
    };
    add(100.0, 30.0); // long
    add(25.0, 50.0);  // just over four spacings
    add(23.0, 70.0);  // a stub
    add(8.0, 90.0);   // a dash
    const HatchReport r = measureHatches(list, s.screen, s.uniformDensity(density), st);
    EXPECT_EQ(r.strokes, 4);
    EXPECT_EQ(r.stubs, 2);
    EXPECT_DOUBLE_EQ(r.stubFraction, 0.5);
    // countHatches(), compare's per-panel figures, gives the same counts.
    const HatchReport c = countHatches(list, s.screen, s.uniformDensity(density), st);
    EXPECT_EQ(c.strokes, 4);
    EXPECT_EQ(c.stubs, 2);
    EXPECT_DOUBLE_EQ(c.stubFraction, 0.5);
}

// countHatches() is measureHatches() without the pairwise measures: on a traced cross-
// hatched cylinder with a singularity in view, the same counts, ink and strokes near
// singularities, and the pairwise figures left at 0.
TEST(Hatching, CountsAreMeasureHatchesWithoutThePairwiseMeasures) {
    Scene s = cylinder(128);
    styles::HatchStyle st;
    const ScreenField sf =
        computeScreenField(s.gbuffer, *s.frames, s.field, field::findSingularities(*s.frames, s.field), s.camera);
    const std::vector<float> density = s.uniformDensity(0.8f);
    const StrokeList list = traceHatches(sf, density, s.gbuffer, st, 5);
    const HatchReport all = measureHatches(list, sf, density, st), counts = countHatches(list, sf, density, st);
    ASSERT_GT(all.strokesFamily1, 0); // cross-hatched
    EXPECT_EQ(counts.strokes, all.strokes);
    EXPECT_EQ(counts.strokesFamily0, all.strokesFamily0);
    EXPECT_EQ(counts.strokesFamily1, all.strokesFamily1);
    EXPECT_EQ(counts.inkLengthPx, all.inkLengthPx);
    EXPECT_EQ(counts.stubs, all.stubs);
    EXPECT_EQ(counts.stubFraction, all.stubFraction);
    EXPECT_EQ(counts.strokesNearSingularities, all.strokesNearSingularities);
    EXPECT_EQ(counts.minSpacingViolations, 0);
    EXPECT_EQ(counts.squeezedFraction, 0.0);
    EXPECT_EQ(counts.incoherentFraction, 0.0);
    EXPECT_EQ(counts.crossOverdenseFraction, 0.0);
}

TEST(Hatching, SqueezedRunsAreInterleavedFronts) {
    // Regular hatching at d_sep = 6 px is not squeezed; three lines run through it at
    // half the spacing over 40 px (two fronts interleaved): those three and the two
    // regular lines between them are squeezed over that stretch, the outer two are not
    // (one neighbour each). A short intrusion (under one d_sep) does not count.
    Camera cam = Camera::orthographic(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 1.8, 128, 128);
    Scene s(field::makeGrid(4), cam);
    s.field = constantField(*s.frames, 2);
    s.render();
    styles::HatchStyle st;
    const float density = 0.3f;
    ASSERT_NEAR(familySpacingPx(density, 0, st), 6.0, 1e-6);
    StrokeList list;
    list.width = list.height = 128;
    auto add = [&](double x0, double x1, double y) {
        Stroke stroke;
        stroke.kind = StrokeKind::Hatch;
        stroke.id = uint32_t(list.strokes.size());
        for (double x = x0; x <= x1 + 1e-9; x += 1.0) stroke.points.push_back(Vec2(x, y));
        stroke.widths.assign(stroke.points.size(), 1.8f);
        list.strokes.push_back(stroke);
    };
    for (double y : {30.0, 36.0, 42.0, 48.0}) add(20, 120, y);
    EXPECT_EQ(measureHatches(list, s.screen, s.uniformDensity(density), st).squeezedFraction, 0.0);
    add(60, 64, 39.0); // 4 px < d_sep
    EXPECT_EQ(measureHatches(list, s.screen, s.uniformDensity(density), st).squeezedFraction, 0.0);
    list.strokes.pop_back();
    for (double y : {33.0, 39.0, 45.0}) add(20, 60, y);
    const HatchReport r = measureHatches(list, s.screen, s.uniformDensity(density), st);
    // 3 × 40 px intruding plus 2 × 40–42 px of the regular lines (their squeeze lasts
    // while an intruder's end is within 0.7 d_sep = 4.2 px), of 4 × 100 + 3 × 40 px.
    EXPECT_GE(r.squeezedFraction, 200.0 / 520.0 - 1e-9);
    EXPECT_LE(r.squeezedFraction, 206.0 / 520.0 + 1e-9);
}

TEST(Hatching, IncoherentDirectionsAreLinesOfOneLayerAtAnAngle) {
    // Regular hatching at d_sep = 6 px scores 0, and so do a line of the other layer
    // crossing it at 90°, a slow fan (5° between neighbours) and a line of the same
    // layer crossing at 60° (two fronts, outside the 20°–50° band). A short line of
    // the same layer at 30° (a fold of the field seeding across the hatching) counts
    // over its whole length (every point of it is within 3 px of a horizontal line)
    // and the horizontal lines count where they pass within d_sep of it.
    Camera cam = Camera::orthographic(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 1.8, 128, 128);
    Scene s(field::makeGrid(4), cam);
    s.field = constantField(*s.frames, 2);
    s.render();
    styles::HatchStyle st;
    const float density = 0.3f;
    ASSERT_NEAR(familySpacingPx(density, 0, st), 6.0, 1e-6);
    StrokeList list;
    list.width = list.height = 128;
    auto add = [&](Vec2 from, double angleDeg, double length, int family) {
        Stroke stroke;
        stroke.kind = StrokeKind::Hatch;
        stroke.family = family;
        stroke.id = uint32_t(list.strokes.size());
        const Vec2 d(std::cos(angleDeg * M_PI / 180.0), std::sin(angleDeg * M_PI / 180.0));
        for (double t = 0; t <= length + 1e-9; t += 1.0) stroke.points.push_back(from + t * d);
        stroke.widths.assign(stroke.points.size(), 1.8f);
        list.strokes.push_back(stroke);
    };
    auto incoherent = [&] { return measureHatches(list, s.screen, s.uniformDensity(density), st).incoherentFraction; };
    for (double y : {30.0, 36.0, 42.0, 48.0}) add(Vec2(20, y), 0.0, 100.0, 0);
    EXPECT_EQ(incoherent(), 0.0);
    add(Vec2(70, 20), 90.0, 40.0, 1);
    EXPECT_EQ(incoherent(), 0.0);
    list.strokes.pop_back();
    add(Vec2(40, 90), 0.0, 60.0, 0);
    add(Vec2(40, 96), 5.0, 60.0, 0);
    EXPECT_EQ(incoherent(), 0.0);
    list.strokes.resize(4);
    add(Vec2(60, 20), 60.0, 34.0, 0);
    EXPECT_EQ(incoherent(), 0.0);
    list.strokes.pop_back();
    add(Vec2(60, 33), 30.0, 12.0, 0);
    const double r = incoherent();
    // 12 px of 412 at least; at most those 12 plus the parts of the lines at y = 30,
    // 36, 42 within 6 px of the 12 px segment (its 10.4 px run along x and 6 px past
    // each end: 22.4 px each).
    EXPECT_GE(r, 12.0 / 412.0 - 1e-9);
    EXPECT_LE(r, (12.0 + 3 * 22.4) / 412.0);
}

TEST(Hatching, TracedStrokesAreNoStubs) {
    // The tracer drops what the measure would call a stub: on a plane with a tone
    // ramp (so spacing changes along the way) no stroke is shorter than 4 d_sep.
    Camera cam = Camera::orthographic(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 1.8, 256, 256);
    Scene s(field::makeGrid(4), cam);
    s.field = constantField(*s.frames, 4);
    s.render();
    std::vector<float> density(s.gbuffer.nPixels());
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) density[size_t(y * 256 + x)] = 0.12f + 0.6f * float(x) / 255.0f;
    styles::HatchStyle st;
    HatchReport report;
    traceHatches(s.screen, density, s.gbuffer, st, 3, &report);
    ASSERT_GT(report.strokes, 50);
    EXPECT_EQ(report.stubs, 0);
    EXPECT_EQ(report.minSpacingViolations, 0);
}

TEST(Hatching, SmallDarkPartIsFilledEvenWhenTheStyleAsksForLongLines) {
    // A dark patch 24 px wide on paper, in a style whose minLengthPx (40, as the
    // engraving preset) is longer than the patch: no line of the two tracing passes
    // fits, and left empty the patch reads as a white crack inside dark tone (an eye
    // socket, a fold of the mouth). The hole-filling pass holds the style's length
    // only up to the stub length (4 d_sep, about 16 px here), so the patch is hatched.
    Camera cam = Camera::orthographic(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 1.8, 128, 128);
    Scene s(field::makeGrid(4), cam);
    s.field = constantField(*s.frames, 4);
    s.render();
    std::vector<float> density(s.gbuffer.nPixels(), 0.0f);
    for (int y = 52; y < 76; ++y)
        for (int x = 52; x < 76; ++x) density[size_t(s.gbuffer.index(x, y))] = 0.7f;
    styles::HatchStyle st;
    st.minLengthPx = 40.0;
    ASSERT_EQ(hatchFamilies(0.7, st), 2);
    HatchReport report;
    const StrokeList list = traceHatches(s.screen, density, s.gbuffer, st, 5, &report);
    // Lines across the patch, spaced about d_sep (4 px): at least three.
    EXPECT_GE(report.strokes, 3);
    EXPECT_EQ(report.stubs, 0);
    EXPECT_EQ(report.minSpacingViolations, 0);
    for (const Stroke &stroke : list.strokes)
        for (const Vec2 &p : stroke.points) {
            EXPECT_GE(p.x(), 51.0);
            EXPECT_LE(p.x(), 77.0);
            EXPECT_GE(p.y(), 51.0);
            EXPECT_LE(p.y(), 77.0);
        }
}

TEST(Hatching, FamilyCoverageSplitsTheToneAndFadesTheCrossFamilyIn) {
    styles::HatchStyle st;
    for (double rho = 0.0; rho <= 0.9; rho += 0.01) {
        const auto [a, b] = familyCoverage(rho, st);
        if (rho < st.highlightDensity) {
            EXPECT_EQ(a + b, 0.0) << rho;
            continue;
        }
        EXPECT_NEAR(1.0 - (1.0 - a) * (1.0 - b), rho, 1e-12) << rho; // the two together give the tone
        EXPECT_GE(a, b - 1e-12) << rho;
        if (rho < st.crossDensity) {
            EXPECT_EQ(b, 0.0) << rho;
        }
    }
    // Continuous where the second family starts, an even split at the top of the band.
    const auto below = familyCoverage(st.crossDensity - 1e-9, st), above = familyCoverage(st.crossDensity + 1e-9, st);
    EXPECT_NEAR(below[0], above[0], 1e-6);
    EXPECT_NEAR(above[1], 0.0, 1e-6);
    const double top = st.crossDensity + kCrossFeatherBand;
    const auto even = familyCoverage(top, st);
    EXPECT_NEAR(even[0], even[1], 1e-12);
    EXPECT_NEAR(even[1], 1.0 - std::sqrt(1.0 - top), 1e-12);
    // Where the screen directions have folded together the first family takes it all.
    const auto folded = familyCoverage(0.7, st, 0.0);
    EXPECT_DOUBLE_EQ(folded[0], 0.7);
    EXPECT_EQ(folded[1], 0.0);
}

// Print mode (HatchStyle::pixelScale != 1, styles::printStyle()): the guard band
// that keeps stroke centres off the background is one style pixel at any pitch,
// a fraction of a traced pixel included. Before, it was whole traced pixels
// (ceil(pixelScale)): the nearest stroke point 1.51 style px from the background
// at pixelScale 0.68, 1.19 at 2.72 (now 1.000 and 0.996).
TEST(Hatching, PrintGuardBandKeepsItsWidthAtAnyPitch) {
    double nearest[2];
    const double scales[2] = {0.68, 2.72};
    for (int k = 0; k < 2; ++k) {
        const double ps = scales[k];
        const int size = int(std::lround(150 * ps));
        const Scene s = tiltedPlane(size);
        styles::HatchStyle st;
        st.strokeWidthPx *= ps;
        st.minSpacingPx *= ps;
        st.maxSpacingPx *= ps;
        st.minLengthPx *= ps;
        st.pixelScale = ps;
        const StrokeList list = traceHatches(s.screen, s.uniformDensity(0.3f), s.gbuffer, st, 3);
        ASSERT_GT(list.strokes.size(), 5u);
        // Distance from each stroke point to the nearest background pixel's square
        // (looked for within 6 px: farther than the 1.3 style px checked below).
        double best = 1e9;
        for (const Stroke &stroke : list.strokes)
            for (const Vec2 &p : stroke.points)
                for (int y = int(p.y()) - 6; y <= int(p.y()) + 6; ++y)
                    for (int x = int(p.x()) - 6; x <= int(p.x()) + 6; ++x) {
                        if (x >= 0 && y >= 0 && x < size && y < size && s.gbuffer.covered(x, y)) continue;
                        const double dx = std::max({x - p.x(), 0.0, p.x() - (x + 1)});
                        const double dy = std::max({y - p.y(), 0.0, p.y() - (y + 1)});
                        best = std::min(best, std::hypot(dx, dy));
                    }
        nearest[k] = best / ps; // in style px
        std::printf("pixelScale %.2f (%d px): nearest stroke point %.3f style px from the background\n", ps, size,
                    nearest[k]);
    }
    for (double d : nearest) {
        EXPECT_GT(d, 0.8); // the band holds
        EXPECT_LT(d, 1.3); // and is not whole pixels wide
    }
    EXPECT_NEAR(nearest[0], nearest[1], 0.25);
}

TEST(Hatching, ToneInkIsOneLinePerSpacingOnEveryValidPixel) {
    // Print mode's ink calibration (renderer/illustration.h) compares the drawn ink
    // with toneInkPx(): per valid pixel, 1 / d_sep of each family that hatches.
    const Scene s = tiltedPlane(96);
    size_t valid = 0;
    for (size_t i = 0; i < s.screen.nPixels(); ++i) valid += s.screen.valid(i) ? 1 : 0;
    ASSERT_GT(valid, 1000u);
    styles::HatchStyle st; // 1.8 px lines, spacings clamped to [3.2, 24] px
    // One family at density 0.2: lines 1.8 / 0.2 = 9 px apart.
    EXPECT_NEAR(toneInkPx(s.screen, s.uniformDensity(0.2f), st), double(valid) / 9.0, 1e-6 * double(valid));
    // The gain scales the spacing before the clamp: 1.25 × 9 px; at density 0.1,
    // 1.5 × 18 px = 27 px is clamped to maxSpacingPx.
    st.spacingGain = 1.25;
    EXPECT_NEAR(toneInkPx(s.screen, s.uniformDensity(0.2f), st), double(valid) / 11.25, 1e-6 * double(valid));
    st.spacingGain = 1.5;
    EXPECT_NEAR(toneInkPx(s.screen, s.uniformDensity(0.1f), st), double(valid) / 24.0, 1e-6 * double(valid));
    // Below highlightDensity nothing is asked for.
    EXPECT_EQ(toneInkPx(s.screen, s.uniformDensity(0.05f), st), 0.0);
    // The part asked at the densest spacing: none at 9 px; at density 0.6 of one
    // family, 1.8 / 0.6 = 3 px is held at 3.2 px, so all of it (1 / 3.2 per pixel).
    st.spacingGain = 1.0;
    st.crossDensity = 2.0; // one family only
    double atMin = -1;
    EXPECT_NEAR(toneInkPx(s.screen, s.uniformDensity(0.2f), st, &atMin), double(valid) / 9.0, 1e-6 * double(valid));
    EXPECT_EQ(atMin, 0.0);
    const double dense = toneInkPx(s.screen, s.uniformDensity(0.6f), st, &atMin);
    EXPECT_NEAR(dense, double(valid) / 3.2, 1e-6 * double(valid));
    EXPECT_EQ(atMin, dense);
    // hatchInkPx() sums the hatch polylines only.
    StrokeList list;
    Stroke hatch, contour;
    hatch.kind = StrokeKind::Hatch;
    hatch.points = {Vec2(0, 0), Vec2(3, 4), Vec2(3, 10)};
    contour.kind = StrokeKind::Contour;
    contour.points = {Vec2(0, 0), Vec2(100, 0)};
    list.strokes = {hatch, contour};
    EXPECT_DOUBLE_EQ(hatchInkPx(list), 11.0);
}
