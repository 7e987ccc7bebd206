// Contour extraction checked against analytic images: the projected outline of a
// sphere (a circle of known radius), the projected edges of a cube and a square,
// and the chain count of a torus outline.

#include "renderer/strokes/contours.h"

#include "field/primitives.h"
#include "../field/scan_like.h"
#include "renderer/view/camera.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"

#include "test_support.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

using namespace rosy::renderer;
using rosy::field::Mesh;

namespace {


struct Contours {
    StrokeList strokes;
    ContourReport report;
};

Contours extract(const Mesh &mesh, const Camera &camera, const rosy::styles::ContourStyle &style) {
    RayScene scene(mesh);
    GBuffer g = renderGBuffer(scene, mesh, camera);
    Contours c;
    c.strokes = extractContours(mesh, camera, scene, g, style, &c.report);
    return c;
}

/// Distinct widths so a test can tell silhouettes (2.0) from creases and borders (1.0).
rosy::styles::ContourStyle testStyle(bool hidden = false) {
    rosy::styles::ContourStyle s;
    s.widthPx = 2.0;
    s.creaseWidthPx = 1.0;
    s.hidden = hidden;
    return s;
}

double distanceToSegment(const Vec2 &p, const Vec2 &a, const Vec2 &b) {
    Vec2 ab = b - a;
    double t = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    return (a + t * ab - p).norm();
}

double distanceToStrokes(const Vec2 &p, const StrokeList &list, StrokeKind kind) {
    double best = 1e30;
    for (const Stroke &s : list.strokes) {
        if (s.kind != kind) continue;
        for (size_t i = 1; i < s.points.size(); ++i)
            best = std::min(best, distanceToSegment(p, s.points[i - 1], s.points[i]));
    }
    return best;
}

double strokeLength(const Stroke &s) {
    double len = 0.0;
    for (size_t i = 1; i < s.points.size(); ++i) len += (s.points[i] - s.points[i - 1]).norm();
    return len;
}

using Edge3 = std::pair<Vec3, Vec3>;

/// Distance in pixels from raster point p to the nearest of `edges` as `camera` sees them.
double distanceToEdges(const Vec2 &p, const std::vector<Edge3> &edges, const Camera &camera) {
    double best = 1e30;
    for (const Edge3 &e : edges) best = std::min(best, distanceToSegment(p, camera.project(e.first), camera.project(e.second)));
    return best;
}

int countKind(const StrokeList &list, StrokeKind kind) {
    return int(std::count_if(list.strokes.begin(), list.strokes.end(),
                             [&](const Stroke &s) { return s.kind == kind; }));
}


/// The 12 edges of the cube [-1, 1]^3, split into those touching `hiddenCorner` and the rest.
void cubeEdges(const Vec3 &hiddenCorner, std::vector<Edge3> &visible, std::vector<Edge3> &hidden) {
    for (int axis = 0; axis < 3; ++axis) {
        for (int a = -1; a <= 1; a += 2) {
            for (int b = -1; b <= 1; b += 2) {
                Vec3 p, q;
                p[axis] = -1;
                q[axis] = 1;
                p[(axis + 1) % 3] = q[(axis + 1) % 3] = a;
                p[(axis + 2) % 3] = q[(axis + 2) % 3] = b;
                bool touches = p == hiddenCorner || q == hiddenCorner;
                (touches ? hidden : visible).push_back({p, q});
            }
        }
    }
}

} // namespace

TEST(Contours, SphereSilhouetteIsOneLoopOnTheAnalyticCircle) {
    Mesh mesh = rosy::field::makeIcosphere(4, 1.0);
    const int size = 256;
    const double distance = 4.0, fov = 40.0;
    Camera cam = Camera::perspective(Vec3(0, 0, distance), Vec3::Zero(), Vec3(0, 1, 0), fov, size, size);
    Contours c = extract(mesh, cam, testStyle());

    // The silhouette cone of a sphere has half-angle asin(r/d); on the unit image plane
    // its trace is a circle of radius tan(asin(r/d)) = r / sqrt(d^2 - r^2).
    double scale = 0.5 * size / std::tan(0.5 * fov * rosy::test::kPi / 180.0);
    double radiusPx = scale / std::sqrt(distance * distance - 1.0);
    Vec2 centre(0.5 * size, 0.5 * size);

    ASSERT_EQ(c.strokes.strokes.size(), 1u);
    const Stroke &s = c.strokes.strokes[0];
    EXPECT_EQ(s.kind, StrokeKind::Contour);
    EXPECT_LE((s.points.front() - s.points.back()).norm(), 2.0);
    for (const Vec2 &p : s.points) EXPECT_NEAR((p - centre).norm(), radiusPx, 1.0);
    EXPECT_NEAR(strokeLength(s), 2.0 * rosy::test::kPi * radiusPx, 0.02 * 2.0 * rosy::test::kPi * radiusPx);
    ASSERT_EQ(s.widths.size(), s.points.size());
    for (float w : s.widths) EXPECT_FLOAT_EQ(w, 2.0f); // a closed loop has no tapered ends
    EXPECT_EQ(c.report.nCreaseSegments, 0);
    EXPECT_EQ(c.report.nSilhouetteStrokes, 1);
    EXPECT_GE(s.id, kContourIdBase);
}

// A silhouette line wider than two pixels sits inside the outline so that it reaches at
// most 0.9 px past it (inspect allows one pixel of border); its inner edge still lies
// beyond the outline's inner side. The sphere's outline is the analytic circle.
TEST(Contours, WideSilhouetteLinesStayWithinAPixelOfTheOutline) {
    Mesh mesh = rosy::field::makeIcosphere(4, 1.0);
    const int size = 256;
    const double distance = 4.0, fov = 40.0;
    Camera cam = Camera::perspective(Vec3(0, 0, distance), Vec3::Zero(), Vec3(0, 1, 0), fov, size, size);
    const double scale = 0.5 * size / std::tan(0.5 * fov * rosy::test::kPi / 180.0);
    const double radiusPx = scale / std::sqrt(distance * distance - 1.0);
    const Vec2 centre(0.5 * size, 0.5 * size);
    for (double width : {1.6, 3.0, 5.0}) {
        rosy::styles::ContourStyle style = testStyle();
        style.widthPx = width;
        Contours c = extract(mesh, cam, style);
        ASSERT_EQ(c.strokes.strokes.size(), 1u);
        const Stroke &s = c.strokes.strokes[0];
        // Where the line's centre lies for each width: on the outline (within the 1 px
        // of polygonal tolerance of the test above) up to 1.8 px wide, then inset by
        // half the width less 0.9 px.
        const double inset = std::max(0.0, 0.5 * width - 0.9);
        for (size_t i = 0; i < s.points.size(); ++i) {
            const double r = (s.points[i] - centre).norm();
            EXPECT_NEAR(r, radiusPx - inset, 1.0) << "width " << width << " point " << i;
            // Outer edge at most a pixel past the outline (the polygonal sphere lies inside the circle).
            EXPECT_LE(r + 0.5 * s.widths[i], radiusPx + 1.0) << "width " << width;
        }
    }
}

TEST(Contours, CubeShowsItsNineVisibleEdgesAndHidesTheOtherThree) {
    Mesh mesh = rosy::field::makeCube(1);
    const int size = 256;
    Camera cam = Camera::perspective(Vec3(3.2, 2.4, 4.0), Vec3::Zero(), Vec3(0, 1, 0), 40.0, size, size);
    std::vector<Edge3> visible, hidden;
    // The camera lies in the octant (+, +, +): every edge at the opposite corner is hidden.
    cubeEdges(Vec3(-1, -1, -1), visible, hidden);
    ASSERT_EQ(visible.size(), 9u);
    ASSERT_EQ(hidden.size(), 3u);

    Contours c = extract(mesh, cam, testStyle());
    EXPECT_EQ(countKind(c.strokes, StrokeKind::HiddenContour), 0);
    // Outline: the 6 edges between a front and a back face; the other 6 are creases.
    EXPECT_EQ(c.report.nSilhouetteSegments, 6);
    EXPECT_EQ(c.report.nCreaseSegments, 6);
    // One closed outline plus the three inner edges; two of those may chain through
    // the front corner when they look nearly straight on screen.
    EXPECT_EQ(c.report.nSilhouetteStrokes, 1);
    EXPECT_GE(c.report.nCreaseStrokes, 2);
    EXPECT_LE(c.report.nCreaseStrokes, 3);

    for (const Stroke &s : c.strokes.strokes) {
        for (const Vec2 &p : s.points)
            EXPECT_LT(distanceToEdges(p, visible, cam), 0.75) << "stroke point off every visible edge: " << p.transpose();
    }
    for (const Edge3 &e : visible) {
        for (int i = 1; i < 20; ++i) {
            Vec2 p = cam.project(e.first + (i / 20.0) * (e.second - e.first));
            EXPECT_LT(distanceToStrokes(p, c.strokes, StrokeKind::Contour), 1.0);
        }
    }
    for (const Edge3 &e : hidden) {
        Vec2 mid = cam.project(0.5 * (e.first + e.second));
        EXPECT_GT(distanceToStrokes(mid, c.strokes, StrokeKind::Contour), 3.0);
    }

    Contours withHidden = extract(mesh, cam, testStyle(true));
    EXPECT_EQ(countKind(withHidden.strokes, StrokeKind::Contour), countKind(c.strokes, StrokeKind::Contour));
    EXPECT_GE(countKind(withHidden.strokes, StrokeKind::HiddenContour), 3);
    for (const Edge3 &e : hidden) {
        for (int i = 3; i < 18; ++i) {
            Vec2 p = cam.project(e.first + (i / 20.0) * (e.second - e.first));
            EXPECT_LT(distanceToStrokes(p, withHidden.strokes, StrokeKind::HiddenContour), 1.0);
        }
    }
}

/// `mesh` as a scanner and its triangulation leave it: every fifth triangle split in
/// three at a point a twentieth of its height from one edge (a needle beside it), then
/// every vertex moved along its normal by noise of about `amount` times the mean edge
/// length (a sum of four hashed uniforms: the same on every platform).
Mesh scanLike(const Mesh &mesh, double amount) {
    const Mesh split = rosy::test::withNeedles(mesh, 5, 0.05);
    std::vector<Vec3> p = split.positions();
    std::vector<rosy::field::Face> faces = split.faces();
    double edge = 0.0;
    for (int e = 0; e < split.nEdges(); ++e) {
        int h = split.edgeHalfedge(e);
        edge += (split.position(split.head(h)) - split.position(split.tail(h))).norm();
    }
    edge /= split.nEdges();
    std::vector<Vec3> normal(p.size(), Vec3::Zero());
    for (int f = 0; f < split.nFaces(); ++f)
        for (int k = 0; k < 3; ++k) normal[size_t(split.face(f)[k])] += split.faceNormals()[size_t(f)];
    uint64_t state = 0x9e3779b97f4a7c15ull;
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53) - 0.5;
    };
    for (size_t v = 0; v < p.size(); ++v) {
        const double g = (uniform() + uniform() + uniform() + uniform()) * std::sqrt(3.0); // variance 1
        p[v] += amount * edge * g * normal[v].normalized();
    }
    return Mesh::fromTriangles(std::move(p), std::move(faces));
}

TEST(Contours, ScanNoiseDrawsNoCreasesWhileFoldsStay) {
    // A sphere of about 110k faces, 2–4 px per edge at 512², with a scan's needles and
    // noise of a twentieth of an edge (a fifth of a pixel): a crease test on each edge's
    // two faces finds creases all over it, and dots; so many edges bend only below the
    // picture's scale that the outlines are judged at it (the default), and there are
    // neither.
    const Mesh sphere = scanLike(rosy::field::makeIcosphere(6, 1.0), 0.05);
    const Camera cam = Camera::perspective(Vec3(0, 0, 3.2), Vec3::Zero(), Vec3(0, 1, 0), 45.0, 512, 512);
    rosy::styles::ContourStyle faces = testStyle();
    faces.featureScalePx = 0.0;
    const Contours raw = extract(sphere, cam, faces);
    const Contours judged = extract(sphere, cam, testStyle());
    EXPECT_FALSE(raw.report.judgedAtPictureScale);
    EXPECT_TRUE(judged.report.judgedAtPictureScale);
    EXPECT_GT(judged.report.nCreasesBelowScale, sphere.nEdges() / 20);
    EXPECT_GT(raw.report.nCreaseSegments, 100);
    EXPECT_GT(raw.report.nCreaseStrokes, 20);
    EXPECT_LE(judged.report.nCreaseSegments, raw.report.nCreaseSegments / 50);
    EXPECT_LE(judged.report.nCreaseStrokes, 2);
    // The outlines of the noise's bumps seen edge-on, dots under 4 px, are gone
    // (silhouettes are the strokes of width 2 in testStyle(); the inset toward the
    // outline moves their points by a fraction of a pixel after their length is judged).
    auto dots = [](const StrokeList &list) {
        return int(std::count_if(list.strokes.begin(), list.strokes.end(), [](const Stroke &st) {
            return strokeLength(st) < 3.5 && *std::max_element(st.widths.begin(), st.widths.end()) > 1.5f;
        }));
    };
    EXPECT_GT(dots(raw.strokes), 20);
    EXPECT_EQ(dots(judged.strokes), 0);
    EXPECT_GT(judged.report.nSmallLoopsDropped, 20);
    // What is drawn is the outline: every point near the sphere's projected circle,
    // of radius f tan(asin(1 / 3.2)) for the focal length f in pixels.
    const double r = 256.0 / std::tan(0.5 * 45.0 * rosy::test::kPi / 180.0) / std::sqrt(3.2 * 3.2 - 1.0);
    for (const Stroke &st : judged.strokes.strokes)
        for (const Vec2 &q : st.points) EXPECT_NEAR((q - Vec2(256, 256)).norm(), r, 6.0);

    // A cube with its faces cut into 64 × 64 grids, made scan-like the same way: its
    // nine visible edges are still drawn, whole, and nothing else (not the noise beside
    // them, whose longer walks cross the real fold). Clean, it is not judged so at all.
    const Mesh cube = scanLike(rosy::field::makeCube(64), 0.05);
    const Camera cubeCam = Camera::perspective(Vec3(3.2, 2.4, 4.0), Vec3::Zero(), Vec3(0, 1, 0), 40.0, 512, 512);
    const Contours rawCube = extract(cube, cubeCam, faces);
    const Contours judgedCube = extract(cube, cubeCam, testStyle());
    EXPECT_TRUE(judgedCube.report.judgedAtPictureScale);
    const Contours cleanCube = extract(rosy::field::makeCube(64), cubeCam, testStyle());
    EXPECT_FALSE(cleanCube.report.judgedAtPictureScale);
    EXPECT_EQ(cleanCube.report.nCreasesBelowScale, 0);
    EXPECT_EQ(cleanCube.report.nCreaseSegments, 6 * 64);
    EXPECT_GT(rawCube.report.nCreaseSegments, judgedCube.report.nCreaseSegments + 100);
    std::vector<Edge3> visible, hidden;
    cubeEdges(Vec3(-1, -1, -1), visible, hidden);
    for (const Edge3 &e : visible) {
        for (int i = 1; i < 40; ++i) {
            Vec2 q = cubeCam.project(e.first + (i / 40.0) * (e.second - e.first));
            EXPECT_LT(distanceToStrokes(q, judgedCube.strokes, StrokeKind::Contour), 1.5) << "edge point " << q.transpose();
        }
    }
    for (const Stroke &st : judgedCube.strokes.strokes)
        for (const Vec2 &q : st.points)
            EXPECT_LT(distanceToEdges(q, visible, cubeCam), 2.0) << "stroke point off every visible edge: " << q.transpose();
}

TEST(Contours, GridBorderIsItsFourSides) {
    const int n = 8;
    Mesh mesh = rosy::field::makeGrid(n);
    Camera cam = Camera::perspective(Vec3(0.8, -2.0, 2.5), Vec3::Zero(), Vec3(0, 0, 1), 50.0, 200, 200);
    std::vector<Edge3> sides = {{Vec3(-1, -1, 0), Vec3(1, -1, 0)},
                                {Vec3(1, -1, 0), Vec3(1, 1, 0)},
                                {Vec3(1, 1, 0), Vec3(-1, 1, 0)},
                                {Vec3(-1, 1, 0), Vec3(-1, -1, 0)}};
    Contours c = extract(mesh, cam, testStyle());
    EXPECT_EQ(c.report.nBorderSegments, 4 * n);
    EXPECT_EQ(c.report.nCreaseSegments, 0);
    EXPECT_EQ(c.report.nSilhouetteSegments, 0);
    ASSERT_FALSE(c.strokes.strokes.empty());
    for (const Stroke &s : c.strokes.strokes) {
        for (const Vec2 &p : s.points) {
            double best = 1e30;
            for (const Edge3 &e : sides)
                best = std::min(best, distanceToSegment(p, cam.project(e.first), cam.project(e.second)));
            EXPECT_LT(best, 0.5);
        }
    }
    for (const Edge3 &e : sides) {
        for (int i = 0; i <= 20; ++i) {
            Vec2 p = cam.project(e.first + (i / 20.0) * (e.second - e.first));
            EXPECT_LT(distanceToStrokes(p, c.strokes, StrokeKind::Contour), 1.0);
        }
    }

    rosy::styles::ContourStyle noBorders = testStyle();
    noBorders.borders = false;
    EXPECT_TRUE(extract(mesh, cam, noBorders).strokes.strokes.empty());
}

TEST(Contours, TorusOutlineChainsIntoFewLongStrokes) {
    Mesh mesh = rosy::field::makeTorus(1.0, 0.4, 96, 48);
    Camera cam = Camera::perspective(Vec3(0, -3.2, 2.4), Vec3::Zero(), Vec3(0, 0, 1), 45.0, 256, 256);
    Contours c = extract(mesh, cam, testStyle());
    // Outer outline, plus the visible parts of the hole's outline: a handful of chains.
    int n = int(c.strokes.strokes.size());
    EXPECT_GE(n, 2);
    EXPECT_LE(n, 6);
    double longest = 0.0, total = 0.0;
    for (const Stroke &s : c.strokes.strokes) {
        longest = std::max(longest, strokeLength(s));
        total += strokeLength(s);
    }
    EXPECT_GT(longest, 0.5 * total);
    EXPECT_NEAR(total, c.report.visibleLengthPx, 1e-6 * total);
}

TEST(Contours, EmptyMeshGivesNoStrokes) {
    Mesh mesh;
    Camera cam = Camera::perspective(Vec3(0, 0, 3), Vec3::Zero(), Vec3(0, 1, 0), 40.0, 32, 32);
    Contours c = extract(mesh, cam, testStyle(true));
    EXPECT_TRUE(c.strokes.strokes.empty());
    EXPECT_EQ(c.strokes.width, 32);
    EXPECT_EQ(c.report.nChains, 0);
}

TEST(Contours, IdenticalForOneAndTwoThreads) {
    Mesh mesh = rosy::field::makeTorus(1.0, 0.4, 96, 48);
    Camera cam = Camera::perspective(Vec3(0.5, -3.2, 2.4), Vec3::Zero(), Vec3(0, 0, 1), 45.0, 256, 256);
    auto run = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return extract(mesh, cam, testStyle(true)).strokes;
    };
    StrokeList a = run(1), b = run(2);
    ASSERT_EQ(a.strokes.size(), b.strokes.size());
    EXPECT_GT(a.strokes.size(), 1u);
    for (size_t i = 0; i < a.strokes.size(); ++i) {
        EXPECT_EQ(a.strokes[i].id, b.strokes[i].id);
        EXPECT_EQ(a.strokes[i].kind, b.strokes[i].kind);
        EXPECT_EQ(a.strokes[i].points, b.strokes[i].points);
        EXPECT_EQ(a.strokes[i].widths, b.strokes[i].widths);
    }
}
