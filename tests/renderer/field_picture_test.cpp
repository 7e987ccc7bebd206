// Tests of the field picture: dots where the singularities are, in the colour of
// their sign, separatrices in their colour, thread-count independence, and the
// drawing as strokes (the SVG's pen layers, the rasterizer's max combine).

#include "renderer/field_picture.h"

#include "field/design.h"
#include "field/primitives.h"
#include "field/smoothing.h"
#include "renderer/output/raster.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <optional>
#include <vector>

using namespace rosy;
using namespace rosy::renderer;
using field::Vec3;

namespace {

// Colour classes in linear light, far apart from each other and from the grey
// background, the dark streamlines and the black dot rims.
bool isRed(const Image &im, int x, int y) {
    return im.at(x, y, 0) > 0.5f && im.at(x, y, 1) < 0.2f && im.at(x, y, 2) < 0.2f;
}
bool isBlue(const Image &im, int x, int y) {
    return im.at(x, y, 2) > 0.5f && im.at(x, y, 0) < 0.2f && im.at(x, y, 1) < 0.35f;
}
bool isGreen(const Image &im, int x, int y) {
    return im.at(x, y, 1) > 0.3f && im.at(x, y, 0) < 0.2f && im.at(x, y, 2) < 0.2f;
}

bool isOrange(const Image &im, int x, int y) {
    return im.at(x, y, 0) > 0.7f && im.at(x, y, 1) > 0.2f && im.at(x, y, 1) < 0.6f && im.at(x, y, 2) < 0.1f;
}

/// Connected components (4-neighbour) of the pixels where pred holds.
template <class Pred> int countBlobs(const Image &im, Pred pred) {
    std::vector<char> seen(size_t(im.width) * size_t(im.height), 0);
    int n = 0;
    for (int y0 = 0; y0 < im.height; ++y0)
        for (int x0 = 0; x0 < im.width; ++x0) {
            if (seen[size_t(y0 * im.width + x0)] || !pred(im, x0, y0)) continue;
            ++n;
            std::vector<std::pair<int, int>> stack{{x0, y0}};
            seen[size_t(y0 * im.width + x0)] = 1;
            while (!stack.empty()) {
                auto [x, y] = stack.back();
                stack.pop_back();
                const int nb[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
                for (const auto &q : nb) {
                    if (q[0] < 0 || q[1] < 0 || q[0] >= im.width || q[1] >= im.height) continue;
                    char &s = seen[size_t(q[1] * im.width + q[0])];
                    if (s || !pred(im, q[0], q[1])) continue;
                    s = 1;
                    stack.push_back({q[0], q[1]});
                }
            }
        }
    return n;
}

struct DiskScene {
    field::Mesh mesh = field::makeDisk(16);
    field::TangentFrames frames{mesh};
    field::RosyField field;
    field::SingularityReport report;
    std::vector<field::Separatrix> separatrices;
    explicit DiskScene(int nSym = 4) {
        field::DesignElement e;
        e.position = Vec3(0.21, -0.13, 0);
        e.order = -1;
        field = field::designField(frames, nSym, {e});
        report = field::findSingularities(frames, field);
        separatrices = field::traceSeparatrices(frames, field, report.singularities);
    }
};

// Camera above the unit disk in z = 0 looking down −z, image up = +y.
constexpr double kEyeZ = 3.0, kFovDeg = 50.0;
constexpr int kSize = 256;

FieldPictureOptions diskOptions() {
    FieldPictureOptions opt;
    opt.dotRadiusPx = 16; // 4 px at 256²
    opt.separatrixWidthPx = 8;
    opt.streamlineWidthPx = 4;
    return opt;
}

Camera diskCamera() {
    return Camera::perspective(Vec3(0, 0, kEyeZ), Vec3::Zero(), Vec3(0, 1, 0), kFovDeg, kSize, kSize);
}

Image renderDisk(const DiskScene &s) {
    return renderFieldPicture(s.mesh, s.frames, s.field, s.report, s.separatrices, diskCamera(), diskOptions());
}

} // namespace

TEST(FieldPicture, NegativeSingularityIsBlueDotAtItsProjection) {
    const DiskScene s;
    ASSERT_EQ(s.report.singularities.size(), 1u);
    ASSERT_EQ(s.report.singularities[0].indexNumerator, -1);
    ASSERT_FALSE(s.separatrices.empty());
    const Image im = renderDisk(s);
    ASSERT_EQ(im.width, kSize);
    ASSERT_EQ(im.height, kSize);
    ASSERT_EQ(im.nChannels, 3);

    // Pinhole projection by hand: x_raster = W/2 (1 + x / (d tan(fov/2))), y flipped.
    const Vec3 p = s.report.singularities[0].position;
    const double f = 0.5 * kSize / std::tan(0.5 * kFovDeg * M_PI / 180.0);
    const double px = 0.5 * kSize + f * p.x() / (kEyeZ - p.z());
    const double py = 0.5 * kSize - f * p.y() / (kEyeZ - p.z());

    int blueNear = 0, blueFar = 0, red = 0, green = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const double d = std::hypot(x + 0.5 - px, y + 0.5 - py);
            if (isBlue(im, x, y)) (d < 6 ? blueNear : blueFar)++;
            red += isRed(im, x, y);
            green += isGreen(im, x, y);
        }
    EXPECT_GE(blueNear, 20); // a disk of radius 4 px has ~50 pixels
    EXPECT_EQ(blueFar, 0);
    EXPECT_EQ(red, 0);
    EXPECT_GT(green, 50); // N + 1 = 5 outgoing separatrices, even N: all green
}

TEST(FieldPicture, IdenticalForOneAndTwoThreads) {
    const DiskScene s;
    Image one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = renderDisk(s);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = renderDisk(s);
    }
    ASSERT_EQ(one.data.size(), two.data.size());
    EXPECT_TRUE(one.data == two.data);
    // Not a blank picture: streamlines darken many surface pixels below the shading's
    // floor (0.3 + 0.6 · ambient 0.2 = 0.42).
    int dark = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) dark += one.at(x, y, 0) < 0.35f && one.at(x, y, 1) < 0.35f && one.at(x, y, 2) < 0.35f;
    EXPECT_GT(dark, 200);
}

TEST(FieldPicture, RedBlobsMatchVisiblePositiveSingularitiesOnSphere) {
    const field::Mesh mesh = field::makeIcosphere(3);
    const field::TangentFrames frames(mesh);
    const field::RosyField rosy = field::smoothestField(frames, 4).field;
    const field::SingularityReport report = field::findSingularities(frames, rosy);
    // On a sphere around the origin a point is visible iff it faces the eye:
    // p · (eye − p) > 0. Views with a singularity near the silhouette, where that is
    // ambiguous at pixel scale, are skipped: the first clear view of a fixed list is used.
    std::optional<Camera> cam;
    int visiblePositive = 0, nPositive = 0;
    for (int k = 0; k < 40 && !cam; ++k) {
        // Fibonacci-sphere directions: a fixed, well spread list of views.
        const double z = 1.0 - (k + 0.5) / 20.0, r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = k * M_PI * (3.0 - std::sqrt(5.0));
        FramingOptions framing;
        framing.direction = Vec3(r * std::cos(phi), z, r * std::sin(phi));
        framing.up = std::abs(z) > 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        const Camera c = frameMesh(mesh, kSize, kSize, framing);
        bool clear = true;
        visiblePositive = nPositive = 0;
        for (const field::Singularity &sg : report.singularities) {
            if (sg.indexNumerator <= 0) continue;
            ++nPositive;
            const double cosine = sg.position.normalized().dot((c.position() - sg.position).normalized());
            clear = clear && std::abs(cosine) > 0.15;
            visiblePositive += cosine > 0;
        }
        if (clear) cam = c;
    }
    ASSERT_TRUE(cam.has_value()) << "no view without a singularity on the silhouette; " << report.singularities.size()
                                 << " singularities";
    ASSERT_GE(nPositive, 4); // Poincaré–Hopf: Σ k/4 = 2
    ASSERT_GT(visiblePositive, 0);

    FieldPictureOptions opt;
    opt.dotRadiusPx = 16;
    const Image im = renderFieldPicture(mesh, frames, rosy, report, {}, *cam, opt);
    EXPECT_EQ(countBlobs(im, isRed), visiblePositive);
}

TEST(FieldPicture, OddSymmetryDrawsIncomingSeparatricesOrange) {
    // N = 3, index −1/3: N + 1 = 4 outgoing and 4 incoming separatrices (Eq. 9–12).
    const DiskScene s(3);
    ASSERT_EQ(s.report.singularities.size(), 1u);
    int nIn = 0;
    for (const field::Separatrix &x : s.separatrices) nIn += x.incoming;
    ASSERT_GT(nIn, 0);
    const Image im = renderDisk(s);
    int orange = 0, green = 0, red = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            orange += isOrange(im, x, y);
            green += isGreen(im, x, y);
            red += isRed(im, x, y);
        }
    EXPECT_GT(orange, 50);
    EXPECT_GT(green, 50);
    EXPECT_EQ(red, 0); // orange is not mistaken for a positive dot
}

// The drawing's strokes on the SVG writer's pen layers: streamlines as hatch family
// 0, separatrices as family 1, the one singularity as a single dot (the black rim
// that frames it in the raster picture is not a vector stroke).
TEST(FieldPicture, StrokesGoToPenLayersAndTheDotIsOneRoundStroke) {
    const DiskScene s;
    ASSERT_EQ(s.report.singularities.size(), 1u);
    const FieldDrawing d = drawFieldPicture(s.mesh, s.frames, s.field, s.report, s.separatrices, diskCamera(),
                                            diskOptions());
    EXPECT_EQ(d.width, kSize);
    EXPECT_EQ(d.height, kSize);
    const StrokeList list = fieldPictureStrokes(d);
    EXPECT_EQ(list.width, kSize);
    int streamlines = 0, separatrices = 0, dots = 0;
    for (const Stroke &st : list.strokes) {
        ASSERT_GE(st.points.size(), 2u);
        ASSERT_EQ(st.widths.size(), st.points.size());
        for (const Eigen::Vector2d &p : st.points) {
            EXPECT_GE(p.x(), -1.0);
            EXPECT_LE(p.x(), kSize + 1.0);
        }
        if (st.kind == StrokeKind::Hatch && st.family == 0) ++streamlines;
        if (st.kind == StrokeKind::Hatch && st.family == 1) ++separatrices;
        if (st.kind == StrokeKind::Contour) {
            ++dots;
            // Radius 16 px at 1024 is 4 px at 256²: a 2-point stroke, 8 px wide, no length.
            ASSERT_EQ(st.points.size(), 2u);
            EXPECT_EQ(st.points[0], st.points[1]);
            EXPECT_FLOAT_EQ(st.widths[0], 8.0f);
        }
    }
    EXPECT_GT(streamlines, 20);
    EXPECT_GE(separatrices, 5); // N + 1 = 5 separatrices, each one stroke or more where cut
    EXPECT_EQ(dots, 1);
}

// Strokes of one ink are a flat colour where they overlap (Combine::Max), pen
// strokes build up ink (Combine::Over): two crossing 0.5 px lines give a centre
// coverage of 0.5 (the band profile's plateau at width 0.5) and 1 − 0.5² = 0.75.
TEST(FieldPicture, MaxCombineKeepsOverlapsFlat) {
    StrokeList list{9, 9, {}};
    Stroke h, v;
    h.points = {{0.0, 4.5}, {9.0, 4.5}};
    v.points = {{4.5, 0.0}, {4.5, 9.0}};
    h.widths = v.widths = {0.5f, 0.5f};
    v.id = 1;
    list.strokes = {h, v};
    const size_t centre = 4 * 9 + 4;
    EXPECT_NEAR(rasterizeStrokes(list).hatch0[centre], 0.75f, 1e-6);
    RasterOptions maxCombine;
    maxCombine.combine = RasterOptions::Combine::Max;
    const InkLayers flat = rasterizeStrokes(list, maxCombine);
    EXPECT_NEAR(flat.hatch0[centre], 0.5f, 1e-6);
    EXPECT_NEAR(flat.hatch0[4 * 9 + 1], 0.5f, 1e-6); // on one line only: the same as over
}

TEST(FieldPicture, PaintOverMixesInLinearLightAndKeepsAlpha) {
    Image im(2, 1, {"R", "G", "B", "A"});
    std::fill(im.data.begin(), im.data.end(), 1.0f);
    paintOver(im, {0.5f, 0.0f}, styles::Rgb{0.0, 0.5, 1.0}, 0.5);
    // a = 0.5 · 0.5 = 0.25: 1 · 0.75 + c · 0.25.
    EXPECT_FLOAT_EQ(im.at(0, 0, 0), 0.75f);
    EXPECT_FLOAT_EQ(im.at(0, 0, 1), 0.875f);
    EXPECT_FLOAT_EQ(im.at(0, 0, 2), 1.0f);
    EXPECT_FLOAT_EQ(im.at(0, 0, 3), 1.0f);
    EXPECT_FLOAT_EQ(im.at(1, 0, 0), 1.0f); // no coverage, untouched
}
