// Tests of the polygon-mesh picture (renderer/mesh_picture.h): what a cube and a
// square pyramid must show from a corner view — every visible corner of the cube
// as a low-valence dot and the hidden one not, triangles tinted in a quad picture
// and quads not, singularity rings only where the surface is seen, and the SVG's
// pen layers. Expected values come from the solids' geometry, not from the code.

#include "renderer/mesh_picture.h"

#include "renderer/output/raster.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

using namespace rosy;
using namespace rosy::renderer;
using field::Vec3;

namespace {

constexpr int kPictureSize = 256;

// A corner view of the unit cube centred at the origin: the corner (1,1,1)/2 faces
// the eye, (-1,-1,-1)/2 is hidden behind the solid; the other six are on the outline.
Camera cornerCamera() {
    return Camera::perspective(Vec3(3.2, 2.6, 3.0), Vec3::Zero(), Vec3(0, 1, 0), 30.0, kPictureSize, kPictureSize);
}

std::vector<Vec3> cubeCorners() {
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back((i & 1) - 0.5, ((i >> 1) & 1) - 0.5, ((i >> 2) & 1) - 0.5);
    return p;
}

// Six quads, counter-clockwise seen from outside (vertex i = x + 2y + 4z).
std::vector<std::vector<int>> cubeQuads() {
    return {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
}

const FieldInk &inkNamed(const FieldDrawing &d, const std::string &name) {
    for (const FieldInk &in : d.inks)
        if (in.name == name) return in;
    throw std::runtime_error("no ink " + name);
}

} // namespace

TEST(MeshPicture, CubeShowsItsSevenVisibleCornersAsLowValenceDots) {
    const FieldDrawing d = drawMeshPicture(cubeCorners(), cubeQuads(), {}, cornerCamera());
    EXPECT_EQ(d.width, kPictureSize);
    // All eight corners have valence 3 < 4; the one behind the cube is hidden.
    EXPECT_EQ(inkNamed(d, "low-valence vertices").strokes.strokes.size(), 7u);
    EXPECT_TRUE(inkNamed(d, "high-valence vertices").strokes.strokes.empty());
    EXPECT_TRUE(inkNamed(d, "valence-2 vertices").strokes.strokes.empty());
    // Nine of the twelve edges are seen from a corner; each is one unbroken stroke
    // (an edge on the outline may split where it grazes, so at least nine).
    const auto &edges = inkNamed(d, "edges").strokes.strokes;
    EXPECT_GE(edges.size(), 9u);
    EXPECT_LE(edges.size(), 12u);
    // Quads only: no tint, the surface is grey (R = G = B) everywhere.
    for (size_t i = 0; i < size_t(kPictureSize) * kPictureSize; ++i)
        ASSERT_EQ(d.fill.data[3 * i], d.fill.data[3 * i + 2]) << "pixel " << i;
}

TEST(MeshPicture, TrianglesOfAQuadMeshAreTintedAndQuadsAreNot) {
    // A square pyramid: base quad (y = -0.5) and four triangles to the apex.
    const std::vector<Vec3> p{{-0.5, -0.5, -0.5}, {0.5, -0.5, -0.5}, {0.5, -0.5, 0.5}, {-0.5, -0.5, 0.5}, {0, 0.5, 0}};
    const std::vector<std::vector<int>> faces{{0, 1, 2, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 3}, {3, 4, 0}};
    // Seen from above: only triangles; from below: only the base quad.
    const Camera above = Camera::perspective(Vec3(0.4, 3.5, 0.6), Vec3::Zero(), Vec3(0, 0, -1), 30.0, kPictureSize, kPictureSize);
    const Camera below = Camera::perspective(Vec3(0.4, -3.5, 0.6), Vec3::Zero(), Vec3(0, 0, -1), 30.0, kPictureSize, kPictureSize);
    const FieldDrawing a = drawMeshPicture(p, faces, {}, above);
    const FieldDrawing b = drawMeshPicture(p, faces, {}, below);
    const int c = kPictureSize / 2;
    const size_t centre = size_t(c * kPictureSize + c) + 2 * kPictureSize; // off the apex, inside a triangle
    // Above: yellow (blue channel well under red), below: grey (equal channels).
    EXPECT_LT(a.fill.data[3 * centre + 2], 0.6f * a.fill.data[3 * centre]);
    EXPECT_EQ(b.fill.data[3 * centre + 2], b.fill.data[3 * centre]);
    EXPECT_LT(b.fill.data[3 * centre], 0.95f) << "the base is on the surface, not the white background";
    // As a triangle picture (regularSides 3) the roles swap.
    MeshPictureOptions tri;
    tri.regularSides = 3;
    const FieldDrawing bt = drawMeshPicture(p, faces, {}, below, tri);
    EXPECT_LT(bt.fill.data[3 * centre + 2], 0.6f * bt.fill.data[3 * centre]);
    // The apex has valence 4: regular in a quad picture, low (< 6) in a triangle picture.
    const FieldDrawing at = drawMeshPicture(p, faces, {}, above, tri);
    EXPECT_EQ(inkNamed(at, "low-valence vertices").strokes.strokes.size(), 5u); // apex 4, base corners 3
    EXPECT_EQ(inkNamed(a, "low-valence vertices").strokes.strokes.size(), 4u);  // base corners only
}

TEST(MeshPicture, RingsOnlyWhereTheSurfaceIsSeen) {
    const std::vector<Vec3> singular{{0.5, 0.5, 0.5}, {-0.5, -0.5, -0.5}, {0.5, 0.0, 0.0}};
    const FieldDrawing d = drawMeshPicture(cubeCorners(), cubeQuads(), singular, cornerCamera());
    const auto &rings = inkNamed(d, "field singularities").strokes.strokes;
    ASSERT_EQ(rings.size(), 2u); // the front corner and the centre of the +x face; not the hidden corner
    // A ring is a closed curve around the projected point.
    const Vec2 centre = cornerCamera().project(singular[0]);
    double minR = 1e9, maxR = 0;
    for (const Vec2 &q : rings[0].points) {
        minR = std::min(minR, (q - centre).norm());
        maxR = std::max(maxR, (q - centre).norm());
    }
    EXPECT_NEAR(minR, maxR, 1e-9);
    EXPECT_GT(minR, 0.5);
    EXPECT_NEAR((rings[0].points.front() - rings[0].points.back()).norm(), 0.0, 1e-9);
}

// A singularity flagged as not one irregular element gets a second ring inside its
// ring, about the same point; flags of the wrong count are refused.
TEST(MeshPicture, ASingularityNotEndingAsOneIrregularElementGetsASecondRing) {
    const std::vector<Vec3> singular{{0.5, 0.5, 0.5}, {0.5, 0.0, 0.0}};
    MeshPictureOptions options;
    options.singularityAsOne = {1, 0};
    const FieldDrawing d = drawMeshPicture(cubeCorners(), cubeQuads(), singular, cornerCamera(), options);
    const auto &rings = inkNamed(d, "field singularities").strokes.strokes;
    ASSERT_EQ(rings.size(), 3u);
    auto radius = [&](const Stroke &r, const Vec3 &p) { return (r.points.front() - cornerCamera().project(p)).norm(); };
    const double outer = radius(rings[1], singular[1]), inner = radius(rings[2], singular[1]);
    EXPECT_NEAR(radius(rings[0], singular[0]), outer, 1e-9);
    EXPECT_GT(inner, 0.3 * outer);
    EXPECT_LT(inner, 0.8 * outer);
    // Unflagged (empty) draws one ring each, as before.
    EXPECT_EQ(inkNamed(drawMeshPicture(cubeCorners(), cubeQuads(), singular, cornerCamera()), "field singularities")
                  .strokes.strokes.size(),
              2u);
    options.singularityAsOne = {1};
    EXPECT_THROW(drawMeshPicture(cubeCorners(), cubeQuads(), singular, cornerCamera(), options), std::invalid_argument);
}

TEST(MeshPicture, VectorInksAreThePenLayersAndRasterizeDarkerThanTheFill) {
    const FieldDrawing d = drawMeshPicture(cubeCorners(), cubeQuads(), {Vec3(0.5, 0.5, 0.5)}, cornerCamera());
    const StrokeList all = fieldPictureStrokes(d);
    size_t edges = 0, rings = 0, dots = 0;
    for (const Stroke &s : all.strokes) {
        if (s.kind == StrokeKind::Hatch && s.family == 0) ++edges;
        else if (s.kind == StrokeKind::Hatch && s.family == 1) ++rings;
        else if (s.kind == StrokeKind::Contour) ++dots;
    }
    EXPECT_EQ(edges, inkNamed(d, "edges").strokes.strokes.size());
    EXPECT_EQ(rings, 1u);
    EXPECT_EQ(dots, 7u);
    // Ink darkens the picture: less light in total than the fill alone.
    const Image im = rasterizeFieldDrawing(d);
    double sumFill = 0, sumImage = 0;
    for (size_t i = 0; i < im.data.size(); ++i) {
        sumFill += d.fill.data[i];
        sumImage += im.data[i];
    }
    EXPECT_LT(sumImage, sumFill - 100.0);
}

TEST(MeshPicture, RejectsBadPolygons) {
    EXPECT_THROW(drawMeshPicture(cubeCorners(), {{0, 1}}, {}, cornerCamera()), std::invalid_argument);
    EXPECT_THROW(drawMeshPicture(cubeCorners(), {{0, 1, 8}}, {}, cornerCamera()), std::invalid_argument);
    // An empty mesh is a white picture without strokes.
    const FieldDrawing e = drawMeshPicture({}, {}, {}, cornerCamera());
    for (float v : e.fill.data) ASSERT_EQ(v, 1.0f);
    for (const FieldInk &in : e.inks) EXPECT_TRUE(in.strokes.strokes.empty());
}

namespace {

// Total on-screen length of an ink's strokes, px.
double inkLength(const FieldInk &ink) {
    double sum = 0;
    for (const Stroke &s : ink.strokes.strokes)
        for (size_t i = 1; i < s.points.size(); ++i) sum += (s.points[i] - s.points[i - 1]).norm();
    return sum;
}

} // namespace

// A closed slab 0.001 thick (a thousandth of its width, well inside the depth tolerance
// of 0.4 % of the diagonal), seen from above: its top is a 4 x 4 grid, its bottom the
// same grid with the inner vertices shifted, so the bottom's lines would fall between
// the top's if they showed through. Seen from above it must look like its top alone
// (the same grid as an open sheet): the same length of edge ink, within the few
// pixels where the rim's side walls graze, and only the top's four corners as
// low-valence dots (the bottom's four lie under them). Before the visibility test
// looked at which way the surface faces, the bottom showed through: ink about twice
// the top's, and eight dots.
TEST(MeshPicture, AThinSlabSeenFromAboveShowsOnlyItsTop) {
    const double h = 0.001;
    std::vector<Vec3> p;
    for (int side = 0; side < 2; ++side)
        for (int j = 0; j <= 4; ++j)
            for (int i = 0; i <= 4; ++i) {
                const bool inner = i > 0 && i < 4 && j > 0 && j < 4;
                const double shift = side == 1 && inner ? 0.09 : 0.0;
                p.emplace_back(i * 0.25 - 0.5 + shift, j * 0.25 - 0.5 + 0.6 * shift, side == 0 ? h / 2 : -h / 2);
            }
    auto top = [](int i, int j) { return j * 5 + i; };
    auto bottom = [](int i, int j) { return 25 + j * 5 + i; };
    std::vector<std::vector<int>> topQuads, slab;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            topQuads.push_back({top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)});
            slab.push_back(topQuads.back());
            slab.push_back({bottom(i, j), bottom(i, j + 1), bottom(i + 1, j + 1), bottom(i + 1, j)});
        }
    // The rim, walked counter-clockwise seen from above: one side quad per step.
    std::vector<std::pair<int, int>> rim;
    for (int i = 0; i < 4; ++i) rim.emplace_back(i, 0);
    for (int j = 0; j < 4; ++j) rim.emplace_back(4, j);
    for (int i = 4; i > 0; --i) rim.emplace_back(i, 4);
    for (int j = 4; j > 0; --j) rim.emplace_back(0, j);
    for (size_t k = 0; k < rim.size(); ++k) {
        const auto [i0, j0] = rim[k];
        const auto [i1, j1] = rim[(k + 1) % rim.size()];
        slab.push_back({top(i0, j0), bottom(i0, j0), bottom(i1, j1), top(i1, j1)});
    }
    const Camera above = Camera::perspective(Vec3(0.3, 0.2, 3.0), Vec3::Zero(), Vec3(0, 1, 0), 30.0, kPictureSize,
                                             kPictureSize);
    const FieldDrawing sheet = drawMeshPicture(p, topQuads, {}, above);
    const FieldDrawing closed = drawMeshPicture(p, slab, {}, above);
    const double topInk = inkLength(inkNamed(sheet, "edges"));
    ASSERT_GT(topInk, 500.0); // ten lines across about 120 px of picture
    EXPECT_NEAR(inkLength(inkNamed(closed, "edges")), topInk, 0.03 * topInk);
    EXPECT_EQ(inkNamed(closed, "low-valence vertices").strokes.strokes.size(), 4u);
    EXPECT_TRUE(inkNamed(closed, "high-valence vertices").strokes.strokes.empty());
}
