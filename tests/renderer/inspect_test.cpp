// Quality measures on synthetic drawings built here from closed-form line
// profiles (not by the rasterizer), so the expected numbers are known exactly.

#include "renderer/evaluation/inspect.h"

#include "core/error.h"
#include "renderer/output/image.h"
#include "renderer/output/raster.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

using namespace rosy::renderer;
namespace fs = std::filesystem;

namespace {


/// Anti-aliased coverage of a straight band of width w at distance d from its axis.
float band(double d, double w) { return float(std::clamp(std::min(w, w / 2 + 0.5 - std::fabs(d)), 0.0, 1.0)); }

/// Parallel lines of direction `angleRad` (raster frame, y down) whose axes sit
/// at signed offsets `offsets` (px) along the normal from the image centre.
std::vector<float> lines(int size, double angleRad, const std::vector<double> &offsets, double width) {
    std::vector<float> v(size_t(size) * size_t(size), 0.0f);
    double nx = -std::sin(angleRad), ny = std::cos(angleRad), c = size / 2.0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            double t = (x + 0.5 - c) * nx + (y + 0.5 - c) * ny;
            float best = 0.0f;
            for (double o : offsets) best = std::max(best, band(t - o, width));
            v[size_t(y) * size_t(size) + size_t(x)] = best;
        }
    return v;
}

std::vector<double> evenOffsets(double spacing, int count) {
    std::vector<double> o;
    for (int k = -count; k <= count; ++k) o.push_back(k * spacing + 0.3);
    return o;
}

/// A drawing of `size`² with family-0 lines only, the object a centred disc.
InkMaps drawing(int size, const std::vector<float> &hatch0, double angle0Rad, double target) {
    InkMaps m;
    m.width = m.height = size;
    size_t n = size_t(size) * size_t(size);
    m.hatch0 = hatch0;
    m.hatch1.assign(n, 0.0f);
    m.coverage = hatch0;
    m.target.assign(n, float(target));
    m.angle0.assign(n, float(angle0Rad));
    m.angle1.assign(n, float(angle0Rad + rosy::test::kPi / 2));
    m.mask.assign(n, 0.0f);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            if (std::hypot(x + 0.5 - size / 2.0, y + 0.5 - size / 2.0) < 0.45 * size)
                m.mask[size_t(y) * size_t(size) + size_t(x)] = 1.0f;
    return m;
}

} // namespace

TEST(InspectInk, AlignedLinesHaveZeroAlignmentError) {
    const double angle = 30 * rosy::test::kDeg;
    InkMaps m = drawing(200, lines(200, angle, evenOffsets(8.0, 15), 1.5), angle, 0.2);
    m.hatchSpacingPx = 8.0;
    InspectResult r = inspectInk(m);
    EXPECT_GT(r.alignmentSamples, 1000);
    EXPECT_LT(r.alignmentMedianDeg, 0.5);
    EXPECT_LT(r.alignmentP90Deg, 1.5);
}

TEST(InspectInk, FieldRotatedByTwentyDegreesGivesTwenty) {
    const double angle = 30 * rosy::test::kDeg;
    InkMaps m = drawing(200, lines(200, angle, evenOffsets(8.0, 15), 1.5), angle + 20 * rosy::test::kDeg, 0.2);
    m.hatchSpacingPx = 8.0;
    InspectResult r = inspectInk(m);
    EXPECT_NEAR(r.alignmentMedianDeg, 20.0, 0.5);
    EXPECT_NEAR(r.alignmentP90Deg, 20.0, 1.5);
}

TEST(InspectInk, FamiliesMaySwapLabels) {
    // Family-0 ink drawn along the field's second direction still counts as aligned.
    const double angle = -50 * rosy::test::kDeg;
    InkMaps m = drawing(160, lines(160, angle, evenOffsets(7.0, 14), 1.2), angle + rosy::test::kPi / 2, 0.2);
    InspectResult r = inspectInk(m);
    EXPECT_LT(r.alignmentMedianDeg, 0.5);
}

TEST(InspectInk, UniformCoverageEqualToTargetHasNoToneError) {
    const int size = 128;
    InkMaps m = drawing(size, std::vector<float>(size_t(size * size), 0.3f), 0.0, 0.3);
    InspectResult r = inspectInk(m);
    EXPECT_GT(r.tonePixels, 10000);
    EXPECT_LT(r.toneMae, 1e-4);
    // Against a target of 0.5 the error is 0.2 everywhere.
    m.target.assign(m.target.size(), 0.5f);
    EXPECT_NEAR(inspectInk(m).toneMae, 0.2, 1e-4);
}

TEST(InspectInk, HatchesBlurToTheirMeanCoverage) {
    // Lines of width 2 every 8 px cover 2/8 = 0.25 of the paper.
    const double angle = 20 * rosy::test::kDeg;
    InkMaps m = drawing(200, lines(200, angle, evenOffsets(8.0, 15), 2.0), angle, 0.25);
    m.hatchSpacingPx = 8.0;
    InspectResult r = inspectInk(m);
    EXPECT_LT(r.toneMae, 0.02);
    m.target.assign(m.target.size(), 0.55f);
    EXPECT_NEAR(inspectInk(m).toneMae, 0.30, 0.02);
}

TEST(InspectInk, InkOutsideTheSilhouetteIsCountedExactly) {
    const int w = 64, h = 40;
    InkMaps m;
    m.width = w;
    m.height = h;
    size_t n = size_t(w * h);
    m.mask.assign(n, 0.0f);
    m.coverage.assign(n, 0.0f);
    auto idx = [&](int x, int y) { return size_t(y) * size_t(w) + size_t(x); };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < 30; ++x) m.mask[idx(x, y)] = 1.0f;
    for (int y = 0; y < h; ++y) {
        m.coverage[idx(10, y)] = 1.0f; // inside: fine
        m.coverage[idx(30, y)] = 1.0f; // touches the object: anti-aliasing border
        m.coverage[idx(31, y)] = 0.8f; // two pixels out: counted (40)
        m.coverage[idx(35, y)] = 0.3f; // too faint to be ink
    }
    for (int y = 5; y < 10; ++y)
        for (int x = 50; x < 60; ++x) m.coverage[idx(x, y)] = 1.0f; // 50 more
    InspectResult r = inspectInk(m);
    EXPECT_EQ(r.inkOutsideSilhouettePx, 40 + 50);
}

TEST(InspectInk, EvenSpacingHasZeroSpreadJitteredSpacingHasSome) {
    const double angle = 65 * rosy::test::kDeg, s = 9.0;
    InkMaps even = drawing(220, lines(220, angle, evenOffsets(s, 14), 1.5), angle, 0.2);
    InspectResult re = inspectInk(even);
    EXPECT_GT(re.spacingSamples, 100);
    EXPECT_LT(re.spacingCv, 0.03);
    // Spacing measured from the image (no header value) matches the drawing.
    EXPECT_NEAR(re.measuredSpacingPx, s, 0.03 * s);
    EXPECT_NEAR(re.hatchSpacingPx, s, 0.03 * s);

    // Offsets jittered by a fixed pattern j_k (in units of s, period 10):
    // distances are s (1 + j_{k+1} − j_k), and the ten differences
    // −.5 .3 −.4 .55 −.25 −.15 .45 −.55 .3 .25 have RMS sqrt(1.545 / 10) = 0.393.
    const double jitter[] = {0.3, -0.2, 0.1, -0.3, 0.25, 0.0, -0.15, 0.3, -0.25, 0.05};
    std::vector<double> offsets;
    for (int k = -14; k <= 14; ++k) offsets.push_back((k + jitter[(k + 14) % 10]) * s);
    InkMaps jittered = drawing(220, lines(220, angle, offsets, 1.5), angle, 0.2);
    jittered.hatchSpacingPx = s;
    InspectResult rj = inspectInk(jittered);
    EXPECT_NEAR(rj.spacingCv, 0.393, 0.03);
}

TEST(InspectInk, SpacingIgnoresToneBoundaries) {
    // Two regions of different tone and spacing side by side: each is even, so the
    // pooled spread stays small.
    const int size = 200;
    auto fine = lines(size, 0.0, evenOffsets(6.0, 20), 1.2);
    auto coarse = lines(size, 0.0, evenOffsets(12.0, 10), 1.2);
    std::vector<float> ink(fine.size());
    InkMaps m = drawing(size, ink, 0.0, 0.0);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            size_t i = size_t(y) * size + size_t(x);
            bool left = x < size / 2;
            m.hatch0[i] = m.coverage[i] = left ? fine[i] : coarse[i];
            m.target[i] = left ? 0.2f : 0.1f;
        }
    m.hatchSpacingPx = 8.0;
    InspectResult r = inspectInk(m);
    EXPECT_GT(r.spacingSamples, 50);
    EXPECT_LT(r.spacingCv, 0.03);
}

TEST(InspectInk, EmptyDrawingGivesNoMeasures) {
    InkMaps m = drawing(32, std::vector<float>(32 * 32, 0.0f), 0.0, 0.0);
    InspectResult r = inspectInk(m);
    EXPECT_TRUE(std::isnan(r.alignmentMedianDeg));
    EXPECT_TRUE(std::isnan(r.spacingCv));
    EXPECT_EQ(r.inkOutsideSilhouettePx, 0);
    std::string json = inspectJson(r);
    EXPECT_NE(json.find("\"alignment_median_deg\": null"), std::string::npos) << json;
    EXPECT_NE(json.find("\"ink_outside_silhouette_px\": 0"), std::string::npos) << json;
}

TEST(ReadInkMaps, RoundTripThroughTheRenderExr) {
    const int size = 96;
    const double angle = 40 * rosy::test::kDeg;
    InkLayers layers;
    layers.width = layers.height = size;
    layers.hatch0 = lines(size, angle, evenOffsets(6.0, 12), 1.3);
    Image composite = compositeInk(layers, rosy::styles::Style{});
    SurfaceChannels surf;
    size_t n = size_t(size * size);
    surf.mask.assign(n, 1.0f);
    surf.angle0.assign(n, float(angle));
    surf.angle1.assign(n, float(angle + rosy::test::kPi / 2));
    surf.targetDensity.assign(n, 0.2f);
    const fs::path dir = rosy::test::testOutputDir("inspect");
    fs::path path = dir / "round_trip.exr";
    writeImage(inkExrImage(layers, composite, surf), path.string(), inkExrWriteOptions(6.0));

    InkMaps m = readInkMaps(path.string());
    EXPECT_EQ(m.width, size);
    EXPECT_DOUBLE_EQ(m.hatchSpacingPx, 6.0);
    EXPECT_EQ(m.hatch0, layers.hatch0);
    InspectResult r = inspectInk(m);
    EXPECT_LT(r.alignmentMedianDeg, 0.5);
    EXPECT_EQ(r.inkOutsideSilhouettePx, 0);
}

TEST(ReadInkMaps, MissingFileIsAnIoErrorAndPlainImageAnInputError) {
    EXPECT_THROW(readInkMaps("/nonexistent/render.exr"), rosy::IoError);
    const fs::path dir = rosy::test::testOutputDir("inspect");
    fs::path plain = dir / "plain.exr";
    writeImage(Image(4, 4, {"R", "G", "B"}), plain.string());
    try {
        readInkMaps(plain.string());
        FAIL() << "expected InputError";
    } catch (const rosy::InputError &e) {
        std::string what = e.what();
        EXPECT_NE(what.find("plain.exr"), std::string::npos) << what;
        EXPECT_NE(what.find("ink.hatch0"), std::string::npos) << what;
        EXPECT_NE(what.find("mask"), std::string::npos) << what;
    }
}

namespace {

/// Even cross-hatching on the disc: two families of lines 1.8 px wide, 3.6 px apart
/// (each covers half the paper, together 75 %), a target of 0.6 (cross tone).
InkMaps crossHatched(int size) {
    InkMaps m = drawing(size, lines(size, 20 * rosy::test::kDeg, evenOffsets(3.6, 60), 1.8), 20 * rosy::test::kDeg, 0.6);
    m.hatch1 = lines(size, 110 * rosy::test::kDeg, evenOffsets(3.6, 60), 1.8);
    for (size_t i = 0; i < m.coverage.size(); ++i) {
        m.coverage[i] = 1.0f - (1.0f - m.hatch0[i]) * (1.0f - m.hatch1[i]);
        m.coverage[i] *= m.mask[i];
        m.hatch0[i] *= m.mask[i];
        m.hatch1[i] *= m.mask[i];
    }
    m.crossDensity = 0.45;
    return m;
}

/// Clears the ink in a band |t − offset| < halfWidth across the image, t along the
/// normal of direction angleRad: a crack through both families.
void crack(InkMaps &m, double angleRad, double offset, double halfWidth, double maxLength = 1e9) {
    const int size = m.width;
    const double nx = -std::sin(angleRad), ny = std::cos(angleRad), c = size / 2.0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double px = x + 0.5 - c, py = y + 0.5 - c;
            const double t = px * nx + py * ny, along = px * ny - py * nx;
            if (std::fabs(t - offset) < halfWidth && std::fabs(along) < maxLength) {
                const size_t i = size_t(y) * size_t(size) + size_t(x);
                m.coverage[i] = m.hatch0[i] = m.hatch1[i] = 0.0f;
            }
        }
}

} // namespace

TEST(InspectInk, EvenCrossHatchingHasNoSeam) {
    const InkMaps m = crossHatched(200);
    const InspectResult r = inspectInk(m);
    EXPECT_GT(r.crossPixels, 20000);
    EXPECT_EQ(r.seamPixels, 0);
    EXPECT_EQ(r.seamFraction, 0.0);
    EXPECT_DOUBLE_EQ(r.crossDensity, 0.45);
}

TEST(InspectInk, ACrackThroughBothFamiliesIsASeam) {
    InkMaps m = crossHatched(200);
    crack(m, 65 * rosy::test::kDeg, 10.0, 4.0); // an 8 px light curve, two spacings wide
    InspectOptions o;
    o.keepSeamMask = true;
    const InspectResult r = inspectInk(m, o);
    // The crack's blurred coverage falls below a third of the target along most of
    // its length inside the disc (about 8 px x 160 px, less its blurred margins).
    EXPECT_GT(r.seamPixels, 500);
    EXPECT_GT(r.seamFraction, 0.02);
    EXPECT_LT(r.seamFraction, 0.08);
    ASSERT_EQ(r.seamMask.size(), m.mask.size());
    const Image pic = seamPicture(m, r);
    EXPECT_EQ(pic.width, 200);
    size_t red = 0;
    for (size_t i = 0; i < r.seamMask.size(); ++i) red += pic.data[3 * i] == 1.0f && pic.data[3 * i + 1] == 0.0f;
    EXPECT_EQ(red, size_t(r.seamPixels));
}

TEST(InspectInk, SeamsAloneReadOnlyCoverageTargetAndMask) {
    // compare's panels need seam_fraction only: inspectSeams() gives inspectInk()'s
    // seam figures with the hatch layers and angles absent.
    InkMaps m = crossHatched(200);
    crack(m, 65 * rosy::test::kDeg, 10.0, 4.0);
    InspectOptions o;
    o.keepSeamMask = true;
    const InspectResult full = inspectInk(m, o);
    InkMaps bare = m;
    bare.hatch0.clear();
    bare.hatch1.clear();
    bare.angle0.clear();
    bare.angle1.clear();
    const InspectResult seams = inspectSeams(bare, o);
    EXPECT_GT(seams.seamPixels, 500); // the crack, as in ACrackThroughBothFamiliesIsASeam
    EXPECT_EQ(seams.seamPixels, full.seamPixels);
    EXPECT_EQ(seams.crossPixels, full.crossPixels);
    EXPECT_EQ(seams.seamFraction, full.seamFraction);
    EXPECT_EQ(seams.seamMask, full.seamMask);
    EXPECT_TRUE(std::isnan(seams.toneMae));
    EXPECT_EQ(inspectSeams(crossHatched(200)).seamPixels, 0);
}

TEST(InspectInk, OneMissingLineOrASmallHoleIsNoSeam) {
    // A single missing line (a gap of 2 spacings in one family) keeps the other
    // family's ink: blurred coverage stays above a third of the target.
    InkMaps m = crossHatched(200);
    for (size_t i = 0; i < m.coverage.size(); ++i) {
        const int x = int(i % 200), y = int(i / 200);
        const double t = (x + 0.5 - 100) * -std::sin(20 * rosy::test::kDeg) + (y + 0.5 - 100) * std::cos(20 * rosy::test::kDeg);
        if (std::fabs(t - 0.3) < 1.5) m.hatch0[i] = 0.0f;
        m.coverage[i] = m.mask[i] * (1.0f - (1.0f - m.hatch0[i]) * (1.0f - m.hatch1[i]));
    }
    EXPECT_EQ(inspectInk(m).seamPixels, 0);
    // A blank spot about 5 px across leaves fewer than 30 gap pixels once blurred.
    InkMaps hole = crossHatched(200);
    crack(hole, 0.0, 0.0, 2.5, 2.5);
    EXPECT_EQ(inspectInk(hole).seamPixels, 0);
    // Light tone (below the cross density) is never measured.
    InkMaps light = crossHatched(200);
    crack(light, 65 * rosy::test::kDeg, 10.0, 4.0);
    light.target.assign(light.target.size(), 0.3f);
    const InspectResult r = inspectInk(light);
    EXPECT_EQ(r.crossPixels, 0);
    EXPECT_TRUE(std::isnan(r.seamFraction));
}

TEST(InspectInk, SeamsNearTheSilhouetteAreNotCounted) {
    // A crack tangent to the disc's rim, within 4 px of the silhouette, is the
    // silhouette's business (strokes keep a guard band from it), not a seam.
    InkMaps m = crossHatched(200);
    crack(m, 0.0, 0.45 * 200 - 2.0, 2.0);
    EXPECT_EQ(inspectInk(m).seamPixels, 0);
}

TEST(InspectInk, CrossDensityComesFromTheFileHeader) {
    const fs::path path = fs::path(testing::TempDir()) / "inspect_cross.exr";
    InkLayers layers;
    layers.width = layers.height = 8;
    for (std::vector<float> *v : {&layers.hatch0, &layers.hatch1, &layers.contour}) v->assign(64, 0.0f);
    Image composite(8, 8, {"R", "G", "B"});
    SurfaceChannels surf;
    surf.targetDensity.assign(64, 0.5f);
    surf.mask.assign(64, 1.0f);
    writeImage(inkExrImage(layers, composite, surf), path.string(), inkExrWriteOptions(6.0, 0.62));
    const InkMaps m = readInkMaps(path.string());
    fs::remove(path);
    EXPECT_FLOAT_EQ(float(m.crossDensity), 0.62f);
    EXPECT_DOUBLE_EQ(m.hatchSpacingPx, 6.0);
    // Without the attribute: NaN, and inspect falls back to the option's 0.45.
    InkMaps none = m;
    none.crossDensity = std::nan("");
    EXPECT_DOUBLE_EQ(inspectInk(none).crossDensity, 0.45);
}
