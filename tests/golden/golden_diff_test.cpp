// Proof that the golden comparison can fail (USD found its idiff thresholds so
// lenient that different references passed): real changes of a drawing fail
// with the default thresholds, a one-pixel translation of the same drawing
// passes, and a plain per-pixel comparison would have failed that translation.

#include "golden_util.h"

#include "renderer/evaluation/image_diff.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <utility>

namespace {

using namespace golden;
namespace r = rosy::renderer;

r::Image loadGolden(const std::string &name) {
    const fs::path p = kGoldenDir / (name + ".png");
    if (!fs::exists(p)) return {};
    return r::readDiffInput(p.string()).image;
}

/// The picture moved by (dx, dy) pixels; uncovered pixels repeat the border.
r::Image translated(const r::Image &in, int dx, int dy) {
    r::Image out = in;
    for (int y = 0; y < in.height; ++y)
        for (int x = 0; x < in.width; ++x) {
            const int sx = std::clamp(x - dx, 0, in.width - 1), sy = std::clamp(y - dy, 0, in.height - 1);
            for (int c = 0; c < in.nChannels; ++c) out.at(x, y, c) = in.at(sx, sy, c);
        }
    return out;
}

const char *kAll[] = {"bunny", "bunny_2rosy", "fandisk", "torus", "genus2",
                      "bunny_fine_pen", "bunny_engraving", "bunny_sketch"};

TEST(GoldenDiff, OnePixelTranslationPassesEveryGolden) {
    for (const char *name : kAll) {
        const r::Image a = loadGolden(name);
        ASSERT_GT(a.width, 0) << name << " golden missing";
        for (auto [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{-1, 1}}) {
            const r::DiffResult d = r::compareImages(a, translated(a, dx, dy));
            EXPECT_NE(d.verdict, r::DiffVerdict::Fail)
                << name << " moved by (" << dx << ", " << dy << ")\n" << r::diffReportText(d, {});
        }
    }
}

TEST(GoldenDiff, PixelByPixelComparisonWouldFailTheTranslation) {
    // Why the blur and the shift tolerance exist: idiff's plain rule fails line art
    // moved by one pixel.
    const r::Image a = loadGolden("bunny");
    ASSERT_GT(a.width, 0);
    r::DiffOptions raw;
    raw.blurPx = 1e-9; // effectively none (0 means automatic)
    raw.shiftPx = 0;
    const r::DiffResult d = r::compareImages(a, translated(a, 1, 0), raw);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail) << r::diffReportText(d, raw);
}

void expectFails(const std::string &reference, const std::string &changed) {
    const r::Image a = loadGolden(reference), b = loadGolden(changed);
    ASSERT_GT(a.width, 0);
    ASSERT_GT(b.width, 0);
    const r::DiffResult d = r::compareImages(a, b);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail) << reference << " vs " << changed << "\n" << r::diffReportText(d, {});
    // Not by a hair: the coverage channel fails on far more pixels than allowed.
    EXPECT_GT(d.channels.at(0).failPercent, 10 * r::DiffOptions{}.failPercent) << r::diffReportText(d, {});
}

TEST(GoldenDiff, AnotherSymmetryFails) { expectFails("bunny", "bunny_2rosy"); }

TEST(GoldenDiff, AnotherStyleFails) {
    expectFails("bunny", "bunny_engraving");
    expectFails("bunny", "bunny_sketch");
    expectFails("bunny_engraving", "bunny_sketch");
}

TEST(GoldenDiff, ShiftedLightFails) {
    // The bunny's light [-1, 0.8, 0.35] turned by about 14 degrees.
    const fs::path dir = workDir("shifted-light");
    const std::string res = goldenResolution();
    const fs::path png = dir / "shifted.png";
    fs::remove(png);
    std::ostringstream args;
    args << "render "
         << sceneArgs(kScenesDir / "bunny.yaml",
                      {{"camera.resolution", res}, {"lights.0.direction", "[-0.8, 0.8, 0.6]"}}, dir)
         << " -o '" << png.string() << "' --quiet";
    const RunResult run = runRosy(args.str(), dir, "render");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const r::Image a = loadGolden("bunny");
    ASSERT_GT(a.width, 0);
    const r::DiffResult d = r::compareImages(a, r::readDiffInput(png.string()).image);
    EXPECT_EQ(d.verdict, r::DiffVerdict::Fail) << r::diffReportText(d, {});
    EXPECT_GT(d.channels.at(0).failPercent, 10 * r::DiffOptions{}.failPercent) << r::diffReportText(d, {});
}

} // namespace
