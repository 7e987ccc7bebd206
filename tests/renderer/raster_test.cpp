#include "renderer/output/raster.h"

#include "core/error.h"

#include <OpenImageIO/imageio.h>
#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numeric>
#include <random>

using namespace rosy::renderer;
namespace fs = std::filesystem;

namespace {


Stroke line(Eigen::Vector2d a, Eigen::Vector2d b, float width, StrokeKind kind = StrokeKind::Hatch,
            int family = 0) {
    Stroke s;
    s.points = {a, b};
    s.widths = {width, width};
    s.kind = kind;
    s.family = kind == StrokeKind::Hatch ? family : -1;
    return s;
}

double sum(const std::vector<float> &v) { return std::accumulate(v.begin(), v.end(), 0.0); }

float at(const InkLayers &l, const std::vector<float> &v, int x, int y) {
    return v[size_t(y) * size_t(l.width) + size_t(x)];
}


/// Many random short strokes of every kind, including overlaps and strokes
/// leaving the image.
StrokeList randomStrokes(int width, int height, int count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(-10.0, width + 10.0), uy(-10.0, height + 10.0),
        ang(0.0, 2 * rosy::test::kPi), wid(0.3, 3.0);
    StrokeList list;
    list.width = width;
    list.height = height;
    for (int i = 0; i < count; ++i) {
        Stroke s;
        Eigen::Vector2d p(ux(rng), uy(rng));
        double a = ang(rng);
        for (int k = 0; k < 12; ++k) {
            s.points.push_back(p);
            s.widths.push_back(float(wid(rng)));
            a += 0.2;
            p += 3.0 * Eigen::Vector2d(std::cos(a), std::sin(a));
        }
        s.kind = StrokeKind(i % 3);
        s.family = s.kind == StrokeKind::Hatch ? (i / 3) % 2 : -1;
        s.id = uint32_t(i);
        list.strokes.push_back(std::move(s));
    }
    return list;
}

} // namespace

TEST(RasterizeStrokes, HorizontalStrokeCoversWidthTimesLength) {
    // Expected ink: a capsule of width w and length L has area w L + π w² / 4.
    for (float w : {0.6f, 1.0f, 2.0f, 3.3f}) {
        StrokeList list;
        list.width = 200;
        list.height = 60;
        const double L = 150.0;
        list.strokes.push_back(line({20.3, 30.7}, {20.3 + L, 30.7}, w));
        InkLayers layers = rasterizeStrokes(list);
        double expected = w * L + rosy::test::kPi * w * w / 4.0;
        EXPECT_NEAR(sum(layers.hatch0), expected, 0.02 * w * L) << "width " << w;
        EXPECT_EQ(sum(layers.hatch1), 0.0);
        EXPECT_EQ(sum(layers.contour), 0.0);
    }
}

TEST(RasterizeStrokes, DiagonalStrokeCoversWidthTimesLength) {
    StrokeList list;
    list.width = list.height = 128;
    const float w = 1.5f;
    list.strokes.push_back(line({10.2, 14.9}, {110.2, 100.9}, w));
    InkLayers layers = rasterizeStrokes(list);
    double L = std::hypot(100.0, 86.0);
    EXPECT_NEAR(sum(layers.hatch0), w * L + rosy::test::kPi * w * w / 4.0, 0.02 * w * L);
}

TEST(RasterizeStrokes, CoverageStaysInUnitInterval) {
    InkLayers layers = rasterizeStrokes(randomStrokes(96, 80, 3000, 7));
    for (const auto *v : {&layers.hatch0, &layers.hatch1, &layers.contour, &layers.hiddenContour}) {
        ASSERT_EQ(v->size(), size_t(96 * 80));
        for (float c : *v) {
            EXPECT_GE(c, 0.0f);
            EXPECT_LE(c, 1.0f);
        }
    }
    // Thousands of overlapping strokes saturate most pixels.
    EXPECT_GT(sum(layers.hatch0) / (96.0 * 80.0), 0.8);
}

TEST(RasterizeStrokes, CapsAndJoinsAreRound) {
    // A wide stroke ending at the centre of pixel (50, 50): beyond the end the ink
    // is a disc of radius w/2, so pixel (52, 52) at distance 2√2 gets
    // w/2 + 0.5 − 2√2, (53, 52) at √13 > 3.5 gets none (a square cap would fill both).
    StrokeList list;
    list.width = list.height = 80;
    const float w = 6.0f;
    list.strokes.push_back(line({20.5, 50.5}, {50.5, 50.5}, w));
    InkLayers l = rasterizeStrokes(list);
    EXPECT_NEAR(at(l, l.hatch0, 52, 52), 3.5 - 2.0 * std::sqrt(2.0), 1e-5);
    EXPECT_NEAR(at(l, l.hatch0, 53, 50), 0.5, 1e-5);
    EXPECT_EQ(at(l, l.hatch0, 53, 52), 0.0f);
    EXPECT_EQ(at(l, l.hatch0, 54, 50), 0.0f);
    // Same distance sideways from the middle of the stroke as straight past its end.
    EXPECT_FLOAT_EQ(at(l, l.hatch0, 35, 53), at(l, l.hatch0, 53, 50));
}

TEST(RasterizeStrokes, SegmentsOfOneStrokeDoNotDoubleUp) {
    // Retracing a segment within one stroke (max) inks as much as drawing it once;
    // two separate strokes on top of each other combine with "over".
    StrokeList once, retraced, twice;
    for (StrokeList *l : {&once, &retraced, &twice}) l->width = l->height = 40;
    once.strokes.push_back(line({5, 20.2}, {35, 20.2}, 0.8f));
    Stroke back = once.strokes[0];
    back.points = {{5, 20.2}, {35, 20.2}, {5, 20.2}, {35, 20.2}};
    back.widths.assign(4, 0.8f);
    retraced.strokes.push_back(back);
    twice.strokes = {once.strokes[0], once.strokes[0]};
    InkLayers a = rasterizeStrokes(once), b = rasterizeStrokes(retraced), c = rasterizeStrokes(twice);
    EXPECT_EQ(a.hatch0, b.hatch0);
    for (size_t i = 0; i < a.hatch0.size(); ++i) {
        float ci = a.hatch0[i];
        EXPECT_NEAR(c.hatch0[i], 1.0f - (1.0f - ci) * (1.0f - ci), 1e-6);
    }
    EXPECT_GT(sum(c.hatch0), 1.2 * sum(a.hatch0));
}

TEST(RasterizeStrokes, WidthIsInterpolatedAlongTheStroke) {
    // Width tapering linearly from 3 to 0 over L: area of the trapezoid 1.5 L
    // plus the start cap's half disc (π 1.5² / 2).
    StrokeList list;
    list.width = 140;
    list.height = 40;
    Stroke s = line({10.0, 20.3}, {130.0, 20.3}, 3.0f);
    s.widths = {3.0f, 0.0f};
    list.strokes.push_back(s);
    InkLayers l = rasterizeStrokes(list);
    EXPECT_NEAR(sum(l.hatch0), 1.5 * 120.0 + rosy::test::kPi * 2.25 / 2.0, 0.03 * 180.0);
    // Column sums shrink along the stroke.
    auto column = [&](int x) {
        double c = 0;
        for (int y = 0; y < 40; ++y) c += at(l, l.hatch0, x, y);
        return c;
    };
    EXPECT_NEAR(column(40), 3.0 * (1.0 - (40.5 - 10.0) / 120.0), 0.05);
    EXPECT_NEAR(column(100), 3.0 * (1.0 - (100.5 - 10.0) / 120.0), 0.05);
}

TEST(RasterizeStrokes, LayersFollowKindAndFamily) {
    StrokeList list;
    list.width = list.height = 32;
    list.strokes = {line({2, 4.5}, {30, 4.5}, 1.0f, StrokeKind::Hatch, 0),
                    line({2, 10.5}, {30, 10.5}, 1.0f, StrokeKind::Hatch, 1),
                    line({2, 16.5}, {30, 16.5}, 1.0f, StrokeKind::Contour),
                    line({2, 22.5}, {30, 22.5}, 1.0f, StrokeKind::HiddenContour)};
    InkLayers l = rasterizeStrokes(list);
    EXPECT_EQ(at(l, l.hatch0, 16, 4), 1.0f);
    EXPECT_EQ(at(l, l.hatch1, 16, 10), 1.0f);
    EXPECT_EQ(at(l, l.contour, 16, 16), 1.0f);
    EXPECT_EQ(at(l, l.hatch0, 16, 10), 0.0f);
    EXPECT_EQ(at(l, l.hatch1, 16, 4), 0.0f);
    EXPECT_EQ(at(l, l.contour, 16, 22), 0.0f);
    EXPECT_GT(sum(l.hiddenContour), 0.0);
}

TEST(RasterizeStrokes, HiddenContoursAreDashed) {
    // 4 px on, 3 px off: along a long stroke 4/7 of the length is inked.
    StrokeList list;
    list.width = 300;
    list.height = 10;
    list.strokes.push_back(line({3.0, 5.5}, {283.0, 5.5}, 1.0f, StrokeKind::HiddenContour));
    InkLayers l = rasterizeStrokes(list);
    double row = 0;
    int gaps = 0;
    for (int x = 3; x < 283; ++x) {
        row += at(l, l.hiddenContour, x, 5);
        if (at(l, l.hiddenContour, x, 5) == 0.0f) ++gaps;
    }
    EXPECT_NEAR(row / 280.0, 4.0 / 7.0, 0.02);
    EXPECT_GT(gaps, 60); // 40 gaps of 2-3 fully clear pixels
    RasterOptions solid;
    solid.dashOffPx = 0.0;
    InkLayers s = rasterizeStrokes(list, solid);
    EXPECT_EQ(at(s, s.hiddenContour, 100, 5), 1.0f);
    EXPECT_EQ(at(s, s.hiddenContour, 101, 5), 1.0f);
}

TEST(RasterizeStrokes, BadGeometryIsSkippedNotDrawn) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    StrokeList list;
    list.width = list.height = 20;
    Stroke single;
    single.points = {{10, 10}};
    single.widths = {2.0f};
    list.strokes = {single, line({1, 1}, {nan, 5}, 1.0f), line({1, 1}, {15, 15}, -2.0f),
                    line({1e30, 1e30}, {-1e30, 1e30}, 1.0f)};
    InkLayers l = rasterizeStrokes(list);
    EXPECT_EQ(sum(l.hatch0), 0.0);
    StrokeList empty;
    InkLayers e = rasterizeStrokes(empty);
    EXPECT_EQ(e.width, 0);
    EXPECT_TRUE(e.hatch0.empty());
}

TEST(RasterizeStrokes, MismatchedWidthsAreABug) {
    StrokeList list;
    list.width = list.height = 8;
    Stroke s = line({1, 1}, {5, 5}, 1.0f);
    s.widths.pop_back();
    list.strokes.push_back(s);
    EXPECT_THROW(rasterizeStrokes(list), rosy::CheckFailure);
}

TEST(RasterizeStrokes, SameBytesForAnyThreadCountAndTileSize) {
    StrokeList list = randomStrokes(256, 192, 4000, 11);
    auto render = [&](int threads, int tile) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        RasterOptions o;
        o.tileSize = tile;
        return rasterizeStrokes(list, o);
    };
    InkLayers a = render(1, 32), b = render(2, 32), c = render(2, 7);
    for (auto member : {&InkLayers::hatch0, &InkLayers::hatch1, &InkLayers::contour, &InkLayers::hiddenContour}) {
        ASSERT_EQ((a.*member).size(), (b.*member).size());
        EXPECT_EQ(std::memcmp((a.*member).data(), (b.*member).data(), (a.*member).size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp((a.*member).data(), (c.*member).data(), (a.*member).size() * sizeof(float)), 0);
    }
}

TEST(CompositeInk, HalfCoverageOfBlackOnWhiteIsLinearGrey) {
    // 50 % ink reflects half the light: linear 0.5, sRGB code round(255 · 0.7354) = 188.
    InkLayers layers;
    layers.width = 4;
    layers.height = 2;
    layers.hatch0.assign(8, 0.5f);
    rosy::styles::Style style;
    Image img = compositeInk(layers, style);
    ASSERT_EQ(img.nChannels, 4);
    EXPECT_FLOAT_EQ(img.at(1, 1, 0), 0.5f);
    EXPECT_FLOAT_EQ(img.at(1, 1, 3), 1.0f);
    fs::path dir = rosy::test::freshDir("raster", "composite");
    writeImage(img, (dir / "half.png").string());
    ImageWriteOptions sixteen;
    sixteen.bitsPerChannel = 16;
    writeImage(img, (dir / "half16.png").string(), sixteen);

    auto in = OIIO::ImageInput::open((dir / "half.png").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
    std::vector<unsigned char> bytes(8 * 4);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, bytes.data()));
    EXPECT_EQ(int(bytes[0]), 188);
    EXPECT_EQ(int(bytes[3]), 255);

    auto in16 = OIIO::ImageInput::open((dir / "half16.png").string());
    ASSERT_TRUE(in16);
    EXPECT_EQ(in16->spec().format, OIIO::TypeDesc::UINT16);
    std::vector<uint16_t> words(8 * 4);
    ASSERT_TRUE(in16->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT16, words.data()));
    // round(65535 · 0.735356983) = 48192.
    EXPECT_EQ(int(words[0]), 48192);
    EXPECT_EQ(int(words[3]), 65535);
}

TEST(CompositeInk, LayersCombineWithOverAndInkColour) {
    InkLayers layers;
    layers.width = layers.height = 1;
    layers.hatch0 = {0.5f};
    layers.hatch1 = {0.5f};
    layers.contour = {0.0f};
    layers.hiddenContour = {1.0f};
    CompositeOptions o;
    o.hiddenOpacity = 0.4;
    // 1 − 0.5 · 0.5 · 1 · (1 − 0.4) = 0.85.
    EXPECT_NEAR(combinedCoverage(layers, o)[0], 0.85f, 1e-6);
    rosy::styles::Style style;
    style.paper = {1.0, 0.9, 0.8};
    style.ink = {0.2, 0.1, 0.0};
    Image img = compositeInk(layers, style, o);
    EXPECT_NEAR(img.at(0, 0, 0), 1.0 * 0.15 + 0.2 * 0.85, 1e-6);
    EXPECT_NEAR(img.at(0, 0, 1), 0.9 * 0.15 + 0.1 * 0.85, 1e-6);
    EXPECT_NEAR(img.at(0, 0, 2), 0.8 * 0.15, 1e-6);
}

TEST(CompositeInk, PaperGrainIsBoundedAndSeeded) {
    rosy::styles::Style style;
    style.paperGrain = 0.2;
    auto a = paperColors(64, 48, style), b = paperColors(64, 48, style);
    EXPECT_EQ(a, b);
    auto [lo, hi] = std::minmax_element(a.begin(), a.end());
    EXPECT_GE(*lo, 0.8f - 1e-6f);
    EXPECT_LE(*hi, 1.0f);
    EXPECT_GT(*hi - *lo, 0.05f); // visible texture, not flat
    style.seed = 2;
    EXPECT_NE(paperColors(64, 48, style), a);
    style.paperGrain = 0.0;
    for (float v : paperColors(8, 8, style)) EXPECT_EQ(v, 1.0f);
}

// The paper and the blank layers are made beside the hatching's tracer
// (renderer/illustration.cpp) and handed to the raster stage: what it draws over
// them must be paper × (1 − c) + ink × c of the paper's own colours, pixel by pixel.
TEST(CompositeInk, OverAPaperImageIsThePaperColoursMixedWithTheCoverage) {
    StrokeList list = randomStrokes(96, 80, 600, 5);
    InkLayers layers = rasterizeStrokes(list, blankInkLayers(list.width, list.height));
    rosy::styles::Style style;
    style.paper = {1.0, 0.93, 0.85};
    style.ink = {0.15, 0.1, 0.3};
    style.paperGrain = 0.3;
    style.seed = 9;
    const Image paper = paperImage(list.width, list.height, style);
    const std::vector<float> rgb = paperColors(list.width, list.height, style);
    const std::vector<float> c = combinedCoverage(layers);
    ASSERT_EQ(paper.nChannels, 4);
    Image img = compositeInk(layers, style, paper);
    size_t inked = 0;
    for (size_t k = 0; k < c.size(); ++k) {
        inked += c[k] > 0.0f;
        EXPECT_EQ(paper.data[4 * k + 3], 1.0f);
        EXPECT_EQ(img.data[4 * k + 3], 1.0f);
        for (size_t ch = 0; ch < 3; ++ch) {
            ASSERT_EQ(paper.data[4 * k + ch], rgb[3 * k + ch]) << "pixel " << k;
            ASSERT_EQ(img.data[4 * k + ch], float(rgb[3 * k + ch] * (1.0f - c[k]) + style.ink[ch] * c[k]))
                << "pixel " << k << " channel " << ch;
        }
    }
    EXPECT_GT(inked, c.size() / 10); // the strokes cover a fair share of the picture
    EXPECT_LT(inked, c.size());
    // And the same as compositeInk() making its own paper.
    const Image own = compositeInk(layers, style);
    EXPECT_EQ(own.data, img.data);
}

TEST(CompositeInk, LayersOrPaperOfAnotherSizeAreABug) {
    StrokeList list = randomStrokes(40, 30, 50, 3);
    EXPECT_THROW(rasterizeStrokes(list, blankInkLayers(30, 40)), rosy::CheckFailure);
    EXPECT_THROW(rasterizeStrokes(list, InkLayers{}), rosy::CheckFailure);
    const InkLayers layers = rasterizeStrokes(list, blankInkLayers(40, 30));
    rosy::styles::Style style;
    EXPECT_THROW(compositeInk(layers, style, paperImage(40, 29, style)), rosy::CheckFailure);
    EXPECT_NO_THROW(compositeInk(layers, style, paperImage(40, 30, style)));
    EXPECT_TRUE(blankInkLayers(0, 5).hatch0.empty());
}

TEST(InkExrImage, NamedChannelsAndSpacingAttributeReachTheFile) {
    const int w = 6, h = 4;
    const size_t n = size_t(w * h);
    InkLayers layers;
    layers.width = w;
    layers.height = h;
    layers.hatch0.assign(n, 0.25f);
    layers.contour.assign(n, 0.0f);
    Image composite = compositeInk(layers, rosy::styles::Style{});
    SurfaceChannels surf;
    surf.targetDensity.assign(n, 0.3f);
    surf.depth.assign(n, 2.5f);
    surf.normalZ.assign(n, 1.0f);
    surf.angle0.assign(n, 0.7f);
    surf.angle1.assign(n, std::numeric_limits<float>::quiet_NaN());
    surf.mask.assign(n, 1.0f);
    surf.mask[0] = 0.0f;
    Image exr = inkExrImage(layers, composite, surf);
    fs::path path = rosy::test::freshDir("raster", "exr") / "ink.exr";
    writeImage(exr, path.string(), inkExrWriteOptions(7.5));

    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec &spec = in->spec();
    const std::vector<std::string> expected = {"R",   "G",   "B",   "A",       "tone.target", "ink.coverage",
                                               "ink.hatch0", "ink.hatch1", "ink.contour", "depth",
                                               "N.x", "N.y", "N.z", "field.angle0", "field.angle1", "mask"};
    // OpenEXR sorts channels by name on disk; compare as sets.
    std::vector<std::string> got(spec.channelnames.begin(), spec.channelnames.end()), want = expected;
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    EXPECT_EQ(got, want);
    EXPECT_FLOAT_EQ(spec.get_float_attribute("rosy:hatch_spacing_px", 0.0f), 7.5f);
    std::vector<float> px(n * size_t(spec.nchannels));
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    auto channel = [&](const std::string &name, size_t i) {
        int c = int(std::find(spec.channelnames.begin(), spec.channelnames.end(), name) - spec.channelnames.begin());
        return px[i * size_t(spec.nchannels) + size_t(c)];
    };
    EXPECT_FLOAT_EQ(channel("ink.coverage", 5), 0.25f);
    EXPECT_FLOAT_EQ(channel("ink.hatch1", 5), 0.0f);
    EXPECT_FLOAT_EQ(channel("tone.target", 5), 0.3f);
    EXPECT_FLOAT_EQ(channel("depth", 5), 2.5f);
    EXPECT_FLOAT_EQ(channel("N.z", 5), 1.0f);
    EXPECT_FLOAT_EQ(channel("field.angle0", 5), 0.7f);
    EXPECT_FLOAT_EQ(channel("field.angle0", 0), 0.0f); // off the object
    EXPECT_FLOAT_EQ(channel("field.angle1", 5), 0.0f); // NaN replaced
    EXPECT_FLOAT_EQ(channel("A", 5), 1.0f);
    EXPECT_NEAR(channel("R", 5), 0.75f, 1e-6);
}

TEST(RasterizeStrokes, FiftyThousandStrokesAt1024) {
    // Speed smoke test (the benchmark figure is taken with --gtest_repeat): 50 000
    // strokes of about 40 px, 20 segments each, at 1024².
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1024.0), ang(0.0, 2 * rosy::test::kPi), bend(-0.05, 0.05);
    StrokeList list;
    list.width = list.height = 1024;
    list.strokes.reserve(50000);
    for (int i = 0; i < 50000; ++i) {
        Stroke s;
        s.points.reserve(21);
        s.widths.reserve(21);
        Eigen::Vector2d p(u(rng), u(rng));
        double a = ang(rng);
        for (int k = 0; k <= 20; ++k) {
            s.points.push_back(p);
            s.widths.push_back(float(1.2 * std::sin(rosy::test::kPi * (k + 0.5) / 21.0)));
            a += bend(rng);
            p += 2.0 * Eigen::Vector2d(std::cos(a), std::sin(a));
        }
        s.family = i % 2;
        list.strokes.push_back(std::move(s));
    }
    auto start = std::chrono::steady_clock::now();
    InkLayers l = rasterizeStrokes(list);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    RecordProperty("rasterize_ms", std::to_string(ms));
    std::printf("rasterize 50k strokes at 1024^2: %.1f ms\n", ms);
    // Ink without overlaps would be Σ (mean width × length) per segment (caps are
    // negligible at these widths); "over" of random overlaps keeps the total between
    // about half of that (1 − e^−0.73 ≈ 0.52 of the paper per layer) and all of it.
    double linear = 0.0;
    for (const Stroke &s : list.strokes)
        for (size_t k = 0; k + 1 < s.points.size(); ++k)
            linear += 0.5 * (s.widths[k] + s.widths[k + 1]) * (s.points[k + 1] - s.points[k]).norm();
    double inked = sum(l.hatch0) + sum(l.hatch1);
    EXPECT_GT(inked, 0.5 * linear);
    EXPECT_LT(inked, linear);
}

TEST(WriteImage, SixteenBitsOnlyWhereTheFormatHoldsThem) {
    fs::path dir = rosy::test::freshDir("raster", "bits");
    Image img(2, 2, {"R", "G", "B"});
    ImageWriteOptions sixteen;
    sixteen.bitsPerChannel = 16;
    EXPECT_THROW(writeImage(img, (dir / "x.jpg").string(), sixteen), rosy::InputError);
    ImageWriteOptions twelve;
    twelve.bitsPerChannel = 12;
    EXPECT_THROW(writeImage(img, (dir / "x.png").string(), twelve), rosy::InputError);
    writeImage(img, (dir / "x.tif").string(), sixteen);
    auto in = OIIO::ImageInput::open((dir / "x.tif").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
    EXPECT_FALSE(fs::exists(dir / "x.jpg"));
}
