// The comparison library on synthetic pictures whose differences are known by
// construction.

#include "renderer/output/image.h"
#include "renderer/evaluation/image_diff.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "tests/test_output.h"

namespace {

namespace r = rosy::renderer;
namespace fs = std::filesystem;

/// White paper, RGB linear.
r::Image paper(int w, int h, double level = 1.0) {
    r::Image im(w, h, {"R", "G", "B"});
    for (float &v : im.data) v = float(level);
    return im;
}

void fillRect(r::Image &im, int x0, int y0, int x1, int y1, double value) {
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < im.nChannels; ++c) im.at(x, y, c) = float(value);
}

/// Vertical black lines `width` px wide every `period` px from x = `start`,
/// as many as fit before 10 px from the right border when starting at x = 8,
/// so a copy started one pixel later has the same lines, moved.
r::Image lines(int w, int h, int period, int width, int start) {
    r::Image im = paper(w, h);
    for (int x0 = start; x0 - start + 8 + width < w - 10; x0 += period) fillRect(im, x0, 0, std::min(w, x0 + width), h, 0.0);
    return im;
}

TEST(GaussianBlur, KeepsConstantsAndTheMean) {
    const int w = 40, h = 30;
    std::vector<float> c(size_t(w * h), 0.3f);
    for (float v : r::gaussianBlur(c, w, h, 2.5)) EXPECT_NEAR(v, 0.3, 1e-6);
    // A period-6 stripe pattern of duty 1/3 blurred at sigma = half the period:
    // the fundamental's ripple is damped by exp(-2 pi^2 sigma^2 / p^2) = 7e-3.
    std::vector<float> s(size_t(w * h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) s[size_t(y * w + x)] = x % 6 < 2 ? 1.0f : 0.0f;
    const std::vector<float> b = r::gaussianBlur(s, w, h, 3.0);
    for (int x = 10; x < 30; ++x) EXPECT_NEAR(b[size_t(15 * w + x)], 1.0 / 3.0, 0.01) << x;
}

TEST(ImageDiff, IdenticalPicturesPassWithZeroError) {
    const r::Image a = lines(64, 48, 6, 2, 3);
    const r::DiffResult d = r::compareImages(a, a);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Pass);
    for (const r::ChannelDiff &c : d.channels) EXPECT_EQ(c.maxError, 0.0) << c.name;
}

TEST(ImageDiff, OnePixelShiftOfLinesPassesOnlyWithTheShiftTolerance) {
    const r::Image a = lines(64, 48, 6, 2, 9), b = lines(64, 48, 6, 2, 10);
    r::DiffOptions raw;
    raw.blurPx = 1e-9;
    raw.shiftPx = 0;
    const r::DiffResult plain = r::compareImages(a, b, raw);
    EXPECT_EQ(plain.verdict, r::DiffVerdict::Fail);
    EXPECT_NEAR(plain.channels[0].maxError, 1.0, 1e-6); // a pixel went from paper to full ink
    // An integer translation lies exactly within the one-pixel window: no error at all
    // (away from the border, where the pattern is cut differently).
    r::DiffOptions tolerant;
    tolerant.blurPx = 1e-9;
    const r::DiffResult shifted = r::compareImages(a, b, tolerant);
    EXPECT_EQ(shifted.channels[0].maxError, 0.0) << r::diffReportText(shifted, tolerant);
    const r::DiffResult blurred = r::compareImages(a, b);
    EXPECT_EQ(blurred.verdict, r::DiffVerdict::Pass) << r::diffReportText(blurred, {});
}

TEST(ImageDiff, ToneChangeOverARegionIsMeasuredAndFails) {
    // Right half: paper 1.0 -> linear grey 0.85, i.e. ink coverage 0.15 (paper
    // stays the brightest thing, so it is still measured as 1.0).
    const r::Image a = paper(80, 40);
    r::Image b = a;
    fillRect(b, 40, 0, 80, 40, 0.85);
    const r::DiffResult d = r::compareImages(a, b);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail);
    EXPECT_NEAR(d.channels[0].maxError, 0.15, 1e-4);
    // Every pixel well inside the grey half fails, about half the picture.
    EXPECT_GT(d.channels[0].failPercent, 45.0);
    EXPECT_LT(d.channels[0].failPercent, 60.0);
}

TEST(ImageDiff, SmallToneChangeBelowTheThresholdPasses) {
    const r::Image a = paper(80, 40);
    r::Image b = a;
    fillRect(b, 40, 0, 80, 40, 0.99); // coverage 0.01 < fail 0.02
    const r::DiffResult d = r::compareImages(a, b);
    EXPECT_NE(d.verdict, r::DiffVerdict::Fail);
    EXPECT_NEAR(d.channels[0].maxError, 0.01, 1e-4);
    EXPECT_EQ(d.channels[0].nFail, 0);
}

TEST(ImageDiff, FailPercentAndHardFailFollowIdiff) {
    // One isolated dot of full ink, 3x3 px on 100x100: blurred away to a peak
    // of 9 / (2 pi sigma^2) (about 0.23 at sigma 2.5): over hardfail 0.1.
    const r::Image a = paper(100, 100);
    r::Image b = a;
    fillRect(b, 50, 50, 53, 53, 0.0);
    r::DiffOptions o;
    const r::DiffResult d = r::compareImages(a, b, o);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail);
    EXPECT_GT(d.channels[0].maxError, o.hardFail);
    // Without a hard limit, and allowing 5 % of pixels: the few failing pixels pass.
    o.hardFail = 1.0;
    o.failPercent = 5.0;
    o.warnPercent = 100.0;
    const r::DiffResult lenient = r::compareImages(a, b, o);
    EXPECT_EQ(lenient.verdict, r::DiffVerdict::Pass) << r::diffReportText(lenient, o);
    EXPECT_GT(lenient.channels[0].nFail, 0);
    // Warnings: allowed failures but too many pixels over warn -> WARNING (idiff exit 1).
    o.warnPercent = 0.0;
    EXPECT_EQ(r::compareImages(a, b, o).verdict, r::DiffVerdict::Warn);
}

TEST(ImageDiff, PaperColourChangeFailsThePaperChannel) {
    const r::Image a = lines(64, 48, 8, 2, 2);
    r::Image b = a;
    for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x)
            if (b.at(x, y, 0) > 0.5f) b.at(x, y, 2) = 0.8f; // yellowish paper, same lines
    const r::DiffResult d = r::compareImages(a, b);
    ASSERT_EQ(d.channels[1].name, "paper");
    EXPECT_NEAR(d.channels[1].maxError, 0.2, 1e-6);
    EXPECT_EQ(d.channels[1].verdict, r::DiffVerdict::Fail);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail);
}

TEST(ImageDiff, DifferentSizesFailWithoutComparing) {
    const r::DiffResult d = r::compareImages(paper(10, 10), paper(10, 11));
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail);
    EXPECT_NE(d.mismatch.find("10x10"), std::string::npos);
    EXPECT_TRUE(d.channels.empty());
}

TEST(ImageDiff, BadOptionsAreInputErrors) {
    r::DiffOptions o;
    o.fail = -1;
    EXPECT_THROW(r::compareImages(paper(4, 4), paper(4, 4), o), rosy::InputError);
    o = {};
    o.blurPx = std::nan("");
    EXPECT_THROW(r::compareImages(paper(4, 4), paper(4, 4), o), rosy::InputError);
}

TEST(ImageDiff, DiffImageIsRedWhereTheNewPictureHasMoreInk) {
    const r::Image a = paper(60, 40);
    r::Image b = a;
    fillRect(b, 10, 10, 20, 30, 0.0);
    const r::DiffResult more = r::compareImages(a, b), less = r::compareImages(b, a);
    ASSERT_EQ(more.diffImage.width, 60);
    EXPECT_GT(more.diffImage.at(15, 20, 0), 0.9f);
    EXPECT_LT(more.diffImage.at(15, 20, 2), 0.1f);
    EXPECT_LT(less.diffImage.at(15, 20, 0), 0.1f);
    EXPECT_GT(less.diffImage.at(15, 20, 2), 0.9f);
    EXPECT_GT(more.diffImage.at(50, 5, 1), 0.99f); // unchanged paper stays white
}

/// A rosyhatch-like EXR image: the channels image_diff compares.
r::Image exrLike(int w, int h, double angle) {
    r::Image im(w, h, {"R", "G", "B", "A", "tone.target", "ink.coverage", "depth", "N.x", "N.y", "N.z",
                       "field.angle0", "field.angle1", "mask"});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 4; ++c) im.at(x, y, c) = 1.0f;
            im.at(x, y, 6) = 5.0f;
            im.at(x, y, 9) = 1.0f;
            im.at(x, y, 10) = float(angle);
            im.at(x, y, 11) = float(angle + 1.5707963);
            im.at(x, y, 12) = 1.0f;
        }
    return im;
}

TEST(ImageDiff, FieldAnglesAreComparedModuloPi) {
    const double pi = 3.14159265358979;
    const r::DiffResult same = r::compareImages(exrLike(20, 20, 0.3), exrLike(20, 20, 0.3 + pi));
    EXPECT_EQ(same.verdict, r::DiffVerdict::Pass) << r::diffReportText(same, {});
    // A quarter turn of a line is the largest change: |2 (cos 2t, sin 2t)| / 2 = 1.
    const r::DiffResult turned = r::compareImages(exrLike(20, 20, 0.3), exrLike(20, 20, 0.3 + pi / 2));
    bool found = false;
    for (const r::ChannelDiff &c : turned.channels)
        if (c.name == "field.angle0") {
            found = true;
            EXPECT_NEAR(c.maxError, 1.0, 1e-5);
        }
    EXPECT_TRUE(found);
    EXPECT_EQ(turned.verdict, r::DiffVerdict::Fail);
    // Coverage only: the drawings (all paper) agree.
    r::DiffOptions o;
    o.exrChannels = false;
    EXPECT_EQ(r::compareImages(exrLike(20, 20, 0.3), exrLike(20, 20, 0.3 + pi / 2), o).verdict,
              r::DiffVerdict::Pass);
}

TEST(ImageDiff, DepthIsComparedRelativeToTheSceneDepth) {
    r::Image a = exrLike(20, 20, 0.0), b = a;
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x) b.at(x, y, 6) = 5.5f; // 10 % farther
    const r::DiffResult d = r::compareImages(a, b);
    for (const r::ChannelDiff &c : d.channels)
        if (c.name == "depth") {
            EXPECT_NEAR(c.maxError, 0.5 / 5.5, 1e-5);
        }
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail);
}

TEST(ReadDiffInput, DecodesSrgbFilesToLinearLight) {
    const fs::path dir = rosy::test::testOutputDir("image_diff");
    r::Image im = paper(4, 4, 0.2);
    r::writeImage(im, (dir / "grey.png").string());
    const r::DiffInput in = r::readDiffInput((dir / "grey.png").string());
    // 0.2 linear -> sRGB 124/255 -> back to linear within one 8-bit step.
    EXPECT_NEAR(in.image.at(1, 1, 0), 0.2, 0.004);
    EXPECT_EQ(in.hatchSpacingPx, 0.0);
    EXPECT_THROW(r::readDiffInput((dir / "missing.png").string()), rosy::IoError);
    std::ofstream(dir / "text.png") << "not a picture\n";
    EXPECT_THROW(r::readDiffInput((dir / "text.png").string()), rosy::InputError);
}

} // namespace
