// SVG output of a real render: the page from the scene's style, the SVG
// rasterised by an independent renderer (rsvg-convert, Debian librsvg2-bin)
// against the PNG of the same render, byte-identical SVG for 1, 2 and 8 threads,
// and the plotter pass's pen-down / pen-up figures on real strokes.

#include "core/diagnostics.h"
#include "core/error.h"
#include "renderer/illustration.h"
#include "renderer/output/image.h"
#include "renderer/output/plotter.h"
#include "renderer/output/svg.h"
#include "scenes/pipeline.h"
#include "scenes/print_units.h"
#include "scenes/scene.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace rosy;
using namespace rosy::renderer;

namespace {

const char *kSceneText = R"(
mesh: {primitive: torus}
camera:
  auto: true
  direction: [0.2, 1.0, 0.9]
  fov: 30
  resolution: [320, 256]
lights:
  - {type: directional, direction: [-0.6, 1.0, 0.7], intensity: 0.9}
style:
  page: {size: 120x100, margin_mm: 0}
)";

std::string scenePath() { return std::string(ROSY_SOURCE_DIR) + "/scenes/svg_render_test.yaml"; }

Illustration render(const scenes::SceneDesc &desc, std::optional<int> threads = std::nullopt) {
    scenes::PipelineOptions options;
    options.threads = threads;
    return std::move(*scenes::renderScene(desc, options).illustration);
}

/// The one-thread render, shared by the tests below.
const Illustration &sharedRender() {
    static const std::unique_ptr<Illustration> il = [] {
        return std::make_unique<Illustration>(render(scenes::parseScene(kSceneText, scenePath()), 1));
    }();
    return *il;
}

/// Reads an 8-bit image's channels as floats in [0, 1].
bool readImage(const std::string &path, int &w, int &h, int &channels, std::vector<float> &pixels) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return false;
    const OIIO::ImageSpec &spec = in->spec();
    w = spec.width;
    h = spec.height;
    channels = spec.nchannels;
    pixels.resize(size_t(w) * h * channels);
    const bool ok = in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data());
    in->close();
    return ok;
}

double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

/// Separable Gaussian blur (sigma in px, clamped borders).
std::vector<double> blur(const std::vector<double> &img, int w, int h, double sigma) {
    const int r = int(std::ceil(3 * sigma));
    std::vector<double> k(size_t(2 * r + 1));
    double sum = 0;
    for (int i = -r; i <= r; ++i) sum += k[size_t(i + r)] = std::exp(-0.5 * i * i / (sigma * sigma));
    for (double &v : k) v /= sum;
    std::vector<double> tmp(img.size()), out(img.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double acc = 0;
            for (int i = -r; i <= r; ++i) acc += k[size_t(i + r)] * img[size_t(y) * w + std::clamp(x + i, 0, w - 1)];
            tmp[size_t(y) * w + x] = acc;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double acc = 0;
            for (int i = -r; i <= r; ++i) acc += k[size_t(i + r)] * tmp[size_t(std::clamp(y + i, 0, h - 1)) * w + x];
            out[size_t(y) * w + x] = acc;
        }
    return out;
}

struct Mismatch {
    double relativeL1 = 0; ///< sum |a − b| / sum a over the blurred coverages
    double maxAbs = 0;     ///< largest blurred difference
};

Mismatch compare(const std::vector<double> &a, const std::vector<double> &b, int w, int h, double sigma) {
    const auto ba = blur(a, w, h, sigma), bb = blur(b, w, h, sigma);
    Mismatch m;
    double diff = 0, total = 0;
    for (size_t i = 0; i < ba.size(); ++i) {
        diff += std::abs(ba[i] - bb[i]);
        total += ba[i];
        m.maxAbs = std::max(m.maxAbs, std::abs(ba[i] - bb[i]));
    }
    m.relativeL1 = total > 0 ? diff / total : 0;
    return m;
}

bool haveRsvg() { return std::system("command -v rsvg-convert > /dev/null 2>&1") == 0; }

/// Ink coverage of an SVG as rsvg-convert draws it at w×h px: the alpha of black
/// ink on a transparent background. Empty on failure.
std::vector<double> svgCoverage(const std::string &svg, int w, int h, const std::string &stem) {
    const auto dir = std::filesystem::path(ROSY_BINARY_DIR);
    const std::string svgPath = (dir / (stem + ".svg")).string(), pngPath = (dir / (stem + "_rsvg.png")).string();
    {
        std::FILE *f = std::fopen(svgPath.c_str(), "wb");
        if (!f) return {};
        std::fwrite(svg.data(), 1, svg.size(), f);
        std::fclose(f);
    }
    const std::string cmd = "rsvg-convert -w " + std::to_string(w) + " -h " + std::to_string(h) + " -o '" + pngPath +
                            "' '" + svgPath + "'";
    if (std::system(cmd.c_str()) != 0) return {};
    int rw = 0, rh = 0, ch = 0;
    std::vector<float> px;
    if (!readImage(pngPath, rw, rh, ch, px) || rw != w || rh != h || ch != 4) return {};
    std::vector<double> cov(size_t(w) * h);
    for (size_t i = 0; i < cov.size(); ++i) cov[i] = px[i * 4 + 3];
    std::filesystem::remove(svgPath);
    std::filesystem::remove(pngPath);
    return cov;
}

} // namespace

TEST(SvgScene, PageBlockOfTheStyleIsParsedAndChecked) {
    auto desc = scenes::parseScene(
        "mesh: {primitive: torus}\nstyle:\n  page: {size: A3, margin_mm: 15, orientation: landscape, "
        "pen_width_mm: 0.35}\n",
        scenePath());
    const styles::PageStyle &page = desc.style.style.page;
    EXPECT_EQ(page.widthMm, 297.0);
    EXPECT_EQ(page.heightMm, 420.0);
    EXPECT_EQ(page.marginMm, 15.0);
    EXPECT_EQ(page.orientation, styles::PageStyle::Orientation::Landscape);
    EXPECT_EQ(page.penWidthMm, 0.35);
    const SvgOptions opt = svgOptionsFor(page);
    EXPECT_EQ(opt.pageWidthMm, 297.0);
    EXPECT_EQ(opt.penWidthMm, 0.35);

    // Defaults: A4, 10 mm, auto, the style's own widths.
    desc = scenes::parseScene("mesh: {primitive: torus}\n", scenePath());
    EXPECT_EQ(desc.style.style.page.widthMm, 210.0);
    EXPECT_EQ(desc.style.style.page.heightMm, 297.0);
    EXPECT_EQ(desc.style.style.page.marginMm, 10.0);
    EXPECT_EQ(desc.style.style.page.orientation, styles::PageStyle::Orientation::Auto);
    EXPECT_EQ(desc.style.style.page.penWidthMm, 0.0);

    const auto failsAtLine3 = [&](const std::string &pageLine) {
        try {
            scenes::parseScene("mesh: {primitive: torus}\nstyle:\n" + pageLine + "\n", scenePath());
        } catch (const InputError &e) {
            EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
            return true;
        }
        return false;
    };
    EXPECT_TRUE(failsAtLine3("  page: {size: b7}"));
    EXPECT_TRUE(failsAtLine3("  page: {size: 0x100}"));
    EXPECT_TRUE(failsAtLine3("  page: {orientation: sideways}"));
    EXPECT_TRUE(failsAtLine3("  page: {margin_mm: 105}")); // A4's shorter side is 210
    EXPECT_TRUE(failsAtLine3("  page: {colour: red}"));
}

TEST(SvgRender, RasterisedSvgMatchesThePngOfTheSameRender) {
    if (!haveRsvg()) GTEST_SKIP() << "rsvg-convert not found: install librsvg2-bin (tools/setup.sh does)";
    const Illustration &il = sharedRender();
    const int w = il.composite.width, h = il.composite.height;
    ASSERT_EQ(w, 320);
    ASSERT_EQ(h, 256);

    // The PNG as the CLI writes it, read back: coverage = 1 − linear value (black ink on white paper).
    const std::string png = (std::filesystem::path(ROSY_BINARY_DIR) / "svg_render_test.png").string();
    writeImage(il.composite, png);
    int pw = 0, ph = 0, pc = 0;
    std::vector<float> px;
    ASSERT_TRUE(readImage(png, pw, ph, pc, px));
    ASSERT_EQ(pw, w);
    ASSERT_EQ(ph, h);
    std::filesystem::remove(png);
    std::vector<double> pngCov(size_t(w) * h);
    for (size_t i = 0; i < pngCov.size(); ++i) pngCov[i] = 1.0 - srgbToLinear(px[i * size_t(pc)]);

    // The scene's page (120×100 mm, no margin) holds the 320×256 picture at
    // min(120/320, 100/256) = 0.375 mm/px. For a pixel-exact comparison the test
    // then writes a page of exactly the picture's size at that scale.
    const scenes::SceneDesc desc = scenes::parseScene(kSceneText, scenePath());
    SvgOptions opt = svgOptionsFor(desc.style.style.page);
    SvgReport report;
    (void)svgDocument(il.strokes, opt, &report);
    EXPECT_NEAR(report.mmPerPx, 0.375, 1e-12);
    EXPECT_EQ(report.pageWidthMm, 120.0);
    opt.pageWidthMm = w * 0.375;
    opt.pageHeightMm = h * 0.375;
    const std::string svg = svgDocument(il.strokes, opt, &report);
    EXPECT_NEAR(report.mmPerPx, 0.375, 1e-12);
    const std::vector<double> svgCov = svgCoverage(svg, w, h, "svg_render_test");
    ASSERT_EQ(svgCov.size(), pngCov.size()) << "rsvg-convert failed";

    // Blur at the nominal hatch spacing: individual hatch lines (and the SVG's
    // constant width per path against the raster's taper and pressure) average
    // out into tone, while anything misplaced by more than about a spacing does not.
    const double sigma = nominalHatchSpacingPx(desc.style.style.hatch);
    const Mismatch same = compare(pngCov, svgCov, w, h, sigma);
    // Measured on this scene (librsvg 2.54): relative L1 0.100, max 0.139. Most of
    // it is the taper: an SVG path has one width (the stroke's length-weighted
    // mean), so its ends are heavier than the raster's tapered ones. The limits
    // 0.2 and 0.25 leave room for another rasteriser version, and stay at half or
    // less of what the broken SVGs below score (L1 0.41-1.48, max 0.45-0.64).
    constexpr double kMaxRelativeL1 = 0.2, kMaxAbs = 0.25;
    EXPECT_LT(same.relativeL1, kMaxRelativeL1);
    EXPECT_LT(same.maxAbs, kMaxAbs);

    // The test can fail: the same strokes flipped upside down, shifted by 12 px,
    // or drawn with a pen three times too wide must all be rejected.
    const auto broken = [&](auto &&edit, SvgOptions o) {
        StrokeList list = il.strokes;
        for (Stroke &s : list.strokes)
            for (auto &p : s.points) edit(p);
        return compare(pngCov, svgCoverage(svgDocument(list, o), w, h, "svg_render_test_broken"), w, h, sigma);
    };
    const Mismatch flipped = broken([&](Eigen::Vector2d &p) { p.y() = h - p.y(); }, opt);
    const Mismatch shifted = broken([](Eigen::Vector2d &p) { p.x() += 12; }, opt);
    SvgOptions wide = opt;
    wide.penWidthMm = 3 * 1.4 * 0.375;
    const Mismatch widePen = broken([](Eigen::Vector2d &) {}, wide);
    std::printf("blurred coverage (sigma %.2f px): relative L1 / max: same %.3f / %.3f, flipped %.3f / %.3f, "
                "shifted %.3f / %.3f, wide pen %.3f / %.3f\n",
                sigma, same.relativeL1, same.maxAbs, flipped.relativeL1, flipped.maxAbs, shifted.relativeL1,
                shifted.maxAbs, widePen.relativeL1, widePen.maxAbs);
    EXPECT_TRUE(flipped.relativeL1 >= kMaxRelativeL1 || flipped.maxAbs >= kMaxAbs);
    EXPECT_TRUE(shifted.relativeL1 >= kMaxRelativeL1 || shifted.maxAbs >= kMaxAbs);
    EXPECT_TRUE(widePen.relativeL1 >= kMaxRelativeL1 || widePen.maxAbs >= kMaxAbs);
}

TEST(SvgRender, ByteIdenticalSvgForOneTwoAndEightThreads) {
    const scenes::SceneDesc desc = scenes::parseScene(kSceneText, scenePath());
    const SvgOptions opt = svgOptionsFor(desc.style.style.page);
    std::string doc[3];
    const int threads[3] = {1, 2, 8};
    for (int k = 0; k < 3; ++k) {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, size_t(threads[k]));
        doc[k] = k == 0 ? svgDocument(sharedRender().strokes, opt) : svgDocument(render(desc).strokes, opt);
    }
    EXPECT_GT(doc[0].size(), 5000u); // a real drawing, not an empty page (an empty page is ~600 bytes)
    EXPECT_EQ(doc[0], doc[1]);
    EXPECT_EQ(doc[0], doc[2]);
}

TEST(SvgRender, PlotterPassKeepsPenDownAndCutsPenUp) {
    const Illustration &il = sharedRender();
    SvgReport report;
    const std::string svg = svgDocument(il.strokes, SvgOptions{}, &report);
    // Pen-down of the strokes as traced, measured here independently of the pass.
    double inputPx = 0;
    for (const Stroke &s : il.strokes.strokes)
        for (size_t i = 1; i < s.points.size(); ++i) inputPx += (s.points[i] - s.points[i - 1]).norm();
    ASSERT_GT(inputPx, 1000.0);
    EXPECT_NEAR(report.penDownMm, inputPx * report.mmPerPx, 0.01 * inputPx * report.mmPerPx);
    EXPECT_LT(report.penUpRatioVsUnsorted, 0.5);
    EXPECT_LE(report.paths, int(il.strokes.strokes.size()));
    std::printf("strokes %zu -> paths %d, pen-down %.1f mm (input %.1f mm), pen-up ratio %.3f, overlap %.2f mm\n",
                il.strokes.strokes.size(), report.paths, report.penDownMm, inputPx * report.mmPerPx,
                report.penUpRatioVsUnsorted, report.overlapRemovedMm);
}

// --- print mode (scenes/print_units.h) ---------------------------------------------

namespace {

/// Ink length in mm of the hatch layers ("1 hatch", "2 cross-hatch") read back
/// from the SVG text, and every stroke-width written there.
struct HatchInk {
    double lengthMm = 0;
    std::set<std::string> widths;
};

HatchInk hatchInk(const std::string &svg) {
    HatchInk ink;
    std::string layer;
    size_t at = 0;
    while ((at = svg.find('<', at)) != std::string::npos) {
        const size_t end = svg.find('>', at);
        const std::string tag = svg.substr(at, end - at);
        at = end;
        const auto attr = [&](const std::string &name) {
            const size_t k = tag.find(" " + name + "=\"");
            if (k == std::string::npos) return std::string();
            const size_t v = k + name.size() + 3;
            return tag.substr(v, tag.find('"', v) - v);
        };
        if (tag.rfind("<g", 0) == 0) layer = attr("inkscape:label");
        if (tag.rfind("<path", 0) != 0 || (layer != "1 hatch" && layer != "2 cross-hatch")) continue;
        ink.widths.insert(attr("stroke-width"));
        std::istringstream d(attr("d"));
        std::string token;
        std::vector<double> xy;
        while (d >> token)
            if (token != "M" && token != "L") xy.push_back(std::stod(token));
        for (size_t i = 2; i + 1 < xy.size(); i += 2) ink.lengthMm += std::hypot(xy[i] - xy[i - 2], xy[i + 1] - xy[i - 1]);
    }
    return ink;
}

/// The torus scene on a square page of side `pageMm` (5 mm margins, so the
/// picture is pageMm − 10 mm wide) at side² px, in print mode or not; returns
/// the hatch ink per mm² of the picture.
struct PrintRun {
    double inkPerMm2 = 0;
    HatchInk ink;
    scenes::PrintSetup setup;
};

PrintRun printRun(double pageMm, int side, bool print, bool keepResolution, const std::string &extraPage = "",
                  const std::string &direction = "0.2, 1.0, 0.9") {
    const std::string page = std::to_string(int(pageMm));
    const std::string text = "mesh: {primitive: torus}\ncamera:\n  auto: true\n  direction: [" + direction + "]\n"
                             "  fov: 30\n  resolution: [" + std::to_string(side) + ", " + std::to_string(side) +
                             "]\nlights:\n  - {type: directional, direction: [-0.6, 1.0, 0.7], intensity: 0.9}\n"
                             "style:\n  page: {size: " + page + "x" + page + ", margin_mm: 5" + extraPage + "}\n";
    scenes::SceneDesc desc = scenes::parseScene(text, scenePath());
    PrintRun run;
    SvgOptions opt = svgOptionsFor(desc.style.style.page);
    scenes::PipelineOptions options;
    options.raster = false;
    options.print = print;
    options.printKeepsResolution = keepResolution;
    scenes::RenderResult result = scenes::renderScene(desc, options);
    EXPECT_EQ(result.print.has_value(), print);
    if (print) {
        run.setup = *result.print;
        opt.penWidthMm = run.setup.lengths.penWidthMm;
        opt.plotter = run.setup.plotter;
    }
    const Illustration il = std::move(*result.illustration);
    run.ink = hatchInk(svgDocument(il.strokes, opt));
    const double pictureMm = pageMm - 10; // a square picture fills the square page inside the margins
    run.inkPerMm2 = run.ink.lengthMm / (pictureMm * pictureMm);
    return run;
}

} // namespace

TEST(PrintMode, SameLineDensityOnPaperForAnyResolutionAndPageSize) {
    // Pen 0.3 mm, hatches 0.8–6 mm apart: on a 60 mm page (50 mm picture) the
    // scene's 200² px put the densest spacing at 3.2 px, 400² at 6.4 px.
    const std::string pen = ", pen_width_mm: 0.3, min_spacing_mm: 0.8, max_spacing_mm: 2.4, min_length_mm: 1";
    const PrintRun r200 = printRun(60, 200, true, true, pen);
    const PrintRun r400 = printRun(60, 400, true, true, pen);
    // SVG only: traced at page.px_mm (0.17 mm) whatever the camera says; a 1.5x larger page.
    const PrintRun small = printRun(60, 128, true, false, pen);
    const PrintRun large = printRun(85, 128, true, false, pen);
    EXPECT_EQ(small.setup.resolution[0], 294); // 50 mm / 0.17 mm
    EXPECT_EQ(large.setup.resolution[0], 441); // 75 mm / 0.17 mm
    std::printf("hatch ink per mm² of picture: 200² %.4f, 400² %.4f; page 60 %.4f, page 85 %.4f (mm/mm²)\n",
                r200.inkPerMm2, r400.inkPerMm2, small.inkPerMm2, large.inkPerMm2);
    ASSERT_GT(r200.inkPerMm2, 0.05);
    // Issue 18 asks for 5 %. Measured (2026-12-02): page 85/60 1.002, SVG-only
    // (0.17 mm/px) / kept (0.25 mm/px) 1.015, 400²/200² 1.026. Before print mode
    // calibrated its ink to the tone (renderer/illustration.h, kInkCalibrationTraces)
    // they were 1.045, 1.000 and 1.063: on this 50 mm picture of ~40 strokes one stroke
    // is 2-5 % of the ink, and line ends and the 4 d_sep minimum length, fixed in mm,
    // took a larger share of the smaller picture; 400²/200² was held to 8 % then.
    EXPECT_NEAR(large.inkPerMm2 / small.inkPerMm2, 1.0, 0.05);
    EXPECT_NEAR(small.inkPerMm2 / r200.inkPerMm2, 1.0, 0.05);
    EXPECT_NEAR(r400.inkPerMm2 / r200.inkPerMm2, 1.0, 0.05);
    // Every hatch path has the pen's width.
    for (const PrintRun *r : {&r200, &r400, &small, &large}) EXPECT_EQ(r->ink.widths, (std::set<std::string>{"0.3"}));
    // The measure can fail: without print mode the lengths are pixels, so the
    // same page at 400² gets lines twice as dense on paper.
    const PrintRun px200 = printRun(60, 200, false, true), px400 = printRun(60, 400, false, true);
    std::printf("without print mode: 200² %.4f, 400² %.4f mm/mm², %zu distinct widths\n", px200.inkPerMm2,
                px400.inkPerMm2, px400.ink.widths.size());
    EXPECT_GT(px400.inkPerMm2 / px200.inkPerMm2, 1.5);
}

TEST(PrintMode, InkPerMm2DoesNotGrowWithResolution) {
    // The torus in four views on one 60 mm page (a 50 mm picture), a 0.15 mm pen,
    // hatches 0.4-1.2 mm apart, traced at 300² (0.167 mm/px) and 800² (0.0625 mm/px).
    // Before the guard band along silhouettes kept its size in mm, the coarser grid
    // drew less in every view (the band was whole traced pixels, 1.5 style px at
    // 300²): summed over the views 800²/300² was 1.095; then 0.994 with per view
    // 0.955-1.049 (the tracer's packing scatter); with the ink calibrated to the tone
    // 1.002, per view 0.980-1.024 (2026-12-02), so each view is held to 5 % too.
    const std::string pen = ", pen_width_mm: 0.15, min_spacing_mm: 0.4, max_spacing_mm: 1.2, min_length_mm: 0.5";
    double coarse = 0, fine = 0;
#ifdef ROSY_SANITIZED
    // Under ASan + UBSan two of the views (the code paths are the same; 24 s for four).
    const std::vector<const char *> views = {"0.2, 1.0, 0.9", "0, 1, 0.1"};
#else
    const std::vector<const char *> views = {"0.2, 1.0, 0.9", "1, 0.3, 0.2", "0, 1, 0.1", "0.5, 0.5, 1"};
#endif
    for (const char *view : views) {
        const PrintRun a = printRun(60, 300, true, true, pen, view), b = printRun(60, 800, true, true, pen, view);
        std::printf("view [%s]: 300² %.4f, 800² %.4f mm/mm² (%.3f)\n", view, a.inkPerMm2, b.inkPerMm2,
                    b.inkPerMm2 / a.inkPerMm2);
        ASSERT_GT(a.inkPerMm2, 0.1) << view;
        EXPECT_NEAR(b.inkPerMm2 / a.inkPerMm2, 1.0, 0.05) << view;
        coarse += a.inkPerMm2;
        fine += b.inkPerMm2;
    }
    std::printf("four views: 800²/300² %.3f\n", fine / coarse);
    EXPECT_NEAR(fine / coarse, 1.0, 0.05);
}

TEST(PrintMode, WarnsWhereThePenCannotLayTheToneInk) {
    // The torus from the side with a 0.3 mm pen held to 0.8 mm: most of the ink
    // the tone asks for is at that densest spacing, which print mode's calibration
    // never goes below, so the 50 mm picture cannot make up for its line ends and
    // draws less ink per mm² than the 75 mm one (0.44 against 0.49 mm/mm², 2026-12-03).
    // A promise of the same density on paper that cannot be kept must be said.
    const std::string pen = ", pen_width_mm: 0.3, min_spacing_mm: 0.8, max_spacing_mm: 2.4, min_length_mm: 1";
    const std::string side = "1, 0.3, 0.2";
    auto printWarnings = [](const WarningCapture &c) {
        std::vector<std::string> out;
        for (const Warning &w : c.warnings())
            if (w.kind == "print") out.push_back(w.message);
        return out;
    };
    PrintRun small, large;
    std::vector<std::string> smallWarnings, largeWarnings;
    {
        WarningCapture capture;
        small = printRun(60, 128, true, false, pen, side);
        smallWarnings = printWarnings(capture);
    }
    {
        WarningCapture capture;
        large = printRun(85, 128, true, false, pen, side);
        largeWarnings = printWarnings(capture);
    }
    std::printf("side view: page 60 %.4f, page 85 %.4f mm/mm² (%.3f)\n", small.inkPerMm2, large.inkPerMm2,
                large.inkPerMm2 / small.inkPerMm2);
    // Measured on the SVG text: the two pictures differ by more than 5 %...
    ASSERT_GT(large.inkPerMm2 / small.inkPerMm2, 1.05);
    // ...and the smaller one says so, naming the pen's limit; the larger one, whose
    // ink is the tone's, does not.
    ASSERT_EQ(smallWarnings.size(), 1u);
    EXPECT_NE(smallWarnings[0].find("page.min_spacing_mm"), std::string::npos) << smallWarnings[0];
    EXPECT_NE(smallWarnings[0].find("depends on the picture's size"), std::string::npos) << smallWarnings[0];
    EXPECT_TRUE(largeWarnings.empty()) << largeWarnings[0];
}

TEST(PrintMode, WarnsWhenAPenCannotDrawTheStyle) {
    styles::Style style;
    EXPECT_TRUE(styles::printProblems(styles::printLengths(style)).empty()); // 0.306 mm pen, 0.544 mm spacing
    style.page.penWidthMm = 0.05;
    auto problems = styles::printProblems(styles::printLengths(style));
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("0.05 mm"), std::string::npos) << problems[0];
    style.page.penWidthMm = 0.8; // wider than the 0.544 mm densest spacing
    problems = styles::printProblems(styles::printLengths(style));
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_NE(problems[0].find("closer than"), std::string::npos) << problems[0];
    // A resolution too coarse for the spacing (2 mm per px, hatches 0.544 mm
    // apart): the style's own pixels instead, and said so.
    bool coarsened = false;
    const styles::Style s = styles::printStyle(styles::Style{}, 2.0, &coarsened);
    EXPECT_TRUE(coarsened);
    EXPECT_NEAR(s.hatch.minSpacingPx, 3.2, 1e-12);
    EXPECT_NEAR(styles::printStyle(styles::Style{}, 0.085).hatch.minSpacingPx, 6.4, 1e-12); // half the 0.17 mm pitch
}
