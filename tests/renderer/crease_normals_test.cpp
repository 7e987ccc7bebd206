// Crease-aware shading normals against the geometry of meshes built by hand: a
// cube (every edge a 90° crease), a strip folded along one line by a known angle,
// a sphere (gently curved everywhere), and the screen field across such a fold.

#include "field/design.h"
#include "field/frames.h"
#include "field/singularities.h"
#include "renderer/strokes/screen_field.h"
#include "renderer/view/camera.h"
#include "renderer/view/crease_normals.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"
#include "test_meshes.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rosy;
using namespace rosy::renderer;

namespace {


/// Quad (a, b, c, d), counter-clockwise seen from outside, as two triangles.
void addQuad(std::vector<field::Face> &faces, int a, int b, int c, int d) {
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
}

/// The cube [-1, 1]³: vertex x + 2 y + 4 z for corner (x, y, z) in {0, 1}³.
field::Mesh makeCube() {
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    std::vector<field::Face> f;
    addQuad(f, 0, 2, 3, 1); // -z
    addQuad(f, 4, 5, 7, 6); // +z
    addQuad(f, 0, 1, 5, 4); // -y
    addQuad(f, 2, 6, 7, 3); // +y
    addQuad(f, 0, 4, 6, 2); // -x
    addQuad(f, 1, 3, 7, 5); // +x
    return field::Mesh::fromTriangles(p, f, "cube");
}

/// Two unit-wide rectangular flaps, x in [-1, 1], meeting along the x axis: the
/// first in the plane z = 0 (y in [-1, 0], normal +z), the second turned up about
/// the x axis by `fold` (normal (0, -sin fold, cos fold)). Vertices 0, 1 lie on the
/// fold line; every corner of both rectangles is a right angle, so the faces of
/// each flap have equal angle sums (90°) at the fold's vertices.
field::Mesh makeFoldedStrip(double fold) {
    const double c = std::cos(fold), s = std::sin(fold);
    std::vector<Vec3> p = {Vec3(-1, 0, 0), Vec3(1, 0, 0),  Vec3(-1, -1, 0),
                           Vec3(1, -1, 0), Vec3(-1, c, s), Vec3(1, c, s)};
    std::vector<field::Face> f;
    addQuad(f, 2, 3, 1, 0); // flat flap
    addQuad(f, 0, 1, 5, 4); // folded flap
    return field::Mesh::fromTriangles(p, f, "folded-strip");
}

double angleDeg(const Vec3 &a, const Vec3 &b) {
    return std::atan2(a.cross(b).norm(), a.dot(b)) / test::kDeg;
}

} // namespace

TEST(CreaseNormals, CubeCornersKeepTheirFaceNormals) {
    const field::Mesh cube = makeCube();
    const std::vector<Vec3> n = creaseAwareCornerNormals(cube, 45 * test::kDeg);
    ASSERT_EQ(int(n.size()), 3 * cube.nFaces());
    const Vec3 axes[6] = {-Vec3::UnitZ(), Vec3::UnitZ(), -Vec3::UnitY(), Vec3::UnitY(), -Vec3::UnitX(), Vec3::UnitX()};
    for (int f = 0; f < cube.nFaces(); ++f)
        for (int k = 0; k < 3; ++k)
            EXPECT_LT((n[size_t(3 * f + k)] - axes[f / 2]).norm(), 1e-12) << "face " << f << " corner " << k;
    // The vertex normal averages the three sides: the diagonal, 54.7° off each face.
    EXPECT_NEAR(angleDeg(cube.vertexNormal(7), Vec3::UnitX()), std::acos(1 / std::sqrt(3.0)) / test::kDeg, 1e-9);
}

TEST(CreaseNormals, FoldBelowTheCreaseAngleIsAveragedAndAboveItIsNot) {
    const double crease = 45 * test::kDeg;
    for (const double foldDeg : {0.0, 20.0, 40.0, 50.0, 90.0, 150.0}) {
        const field::Mesh strip = makeFoldedStrip(foldDeg * test::kDeg);
        const std::vector<Vec3> n = creaseAwareCornerNormals(strip, crease);
        const Vec3 flat = Vec3::UnitZ();
        const Vec3 folded(0, -std::sin(foldDeg * test::kDeg), std::cos(foldDeg * test::kDeg));
        // Equal angle sums on both sides: the average is the bisector of the two normals.
        const Vec3 bisector(0, -std::sin(0.5 * foldDeg * test::kDeg), std::cos(0.5 * foldDeg * test::kDeg));
        for (int f = 0; f < strip.nFaces(); ++f)
            for (int k = 0; k < 3; ++k) {
                const int v = strip.face(f)[size_t(k)];
                const Vec3 own = f < 2 ? flat : folded;
                const Vec3 expected = v <= 1 && foldDeg < 45 ? bisector : own;
                EXPECT_LT((n[size_t(3 * f + k)] - expected).norm(), 1e-12)
                    << "fold " << foldDeg << "°, face " << f << ", vertex " << v;
            }
    }
}

TEST(CreaseNormals, SmoothSurfaceCornersAreItsNormal) {
    // Level 4: 2,048 faces, neighbouring faces about 5° apart, all under the crease angle.
    const field::Mesh sphere = test::makeSphere(4);
    std::vector<Vec3> vertexNormals;
    const std::vector<Vec3> n = creaseAwareCornerNormals(sphere, kCreaseAngleDeg * test::kDeg, &vertexNormals);
    ASSERT_EQ(int(vertexNormals.size()), sphere.nVertices());
    for (int v = 0; v < sphere.nVertices(); ++v) EXPECT_EQ(vertexNormals[size_t(v)], sphere.vertexNormal(v)) << v;
    double worst = 0, spread = 0;
    for (int f = 0; f < sphere.nFaces(); ++f)
        for (int k = 0; k < 3; ++k) {
            const int v = sphere.face(f)[size_t(k)];
            worst = std::max(worst, angleDeg(n[size_t(3 * f + k)], sphere.position(v).normalized()));
            // Every face around a vertex sums the same whole fan.
            spread = std::max(spread, (n[size_t(3 * f + k)] - sphere.vertexNormal(v)).norm());
        }
    EXPECT_LT(worst, 1.0);
    EXPECT_LT(spread, 1e-12);
}

TEST(CreaseNormals, BoundaryAndCreaseStopTheWalkFromBothSides) {
    // A fan of four faces around vertex 0, open between the first and the last: faces
    // 0-1 lie in the plane z = 0 (normal +z), faces 2-3 in x = 0 (normal -x), the
    // two pairs meet at 90° along the y axis and have 135° each at vertex 0. The
    // corner at vertex 0 of each face averages its own pair only, whichever way round.
    std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(1, -1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1), Vec3(0, -1, -1)};
    std::vector<field::Face> f = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
    const field::Mesh fan = field::Mesh::fromTriangles(p, f, "fan");
    const std::vector<Vec3> n = creaseAwareCornerNormals(fan, 45 * test::kDeg);
    EXPECT_LT((n[0] - Vec3::UnitZ()).norm(), 1e-12);
    EXPECT_LT((n[3] - Vec3::UnitZ()).norm(), 1e-12);
    EXPECT_LT((n[6] + Vec3::UnitX()).norm(), 1e-12);
    EXPECT_LT((n[9] + Vec3::UnitX()).norm(), 1e-12);
    // Above the fold's 90° nothing is a crease: one normal for the whole fan, between the two.
    const std::vector<Vec3> all = creaseAwareCornerNormals(fan, 100 * test::kDeg);
    for (int h : {0, 3, 6, 9}) EXPECT_NEAR(angleDeg(all[size_t(h)], Vec3(-1, 0, 1)), 0.0, 1e-9);
}

TEST(ScreenField, DirectionsTurnSmoothlyAcrossAGentleFold) {
    // A 2-RoSy along the fold line on a strip folded by 30°: the member across the fold
    // is world y on the flat flap and (0, cos 30°, sin 30°) on the folded one. Both
    // flaps' shading normals meet in the bisector at the fold, so the screen direction
    // of that member is the same on both sides of it; taken from each face's own
    // plane it would jump there by the angle between the two projections.
    const double fold = 30 * test::kDeg;
    const field::Mesh strip = makeFoldedStrip(fold);
    const field::TangentFrames frames(strip);
    field::DesignElement e;
    e.position = Vec3(0, -0.5, 0);
    e.order = 0;
    e.direction = Vec3::UnitX();
    const field::RosyField rosy = field::designField(frames, 2, {e});
    const Camera cam = Camera::perspective(Vec3(2.5, -2.0, 1.2), Vec3(0, 0, 0), Vec3(0, 0, 1), 40.0, 128, 128);
    const RayScene scene(strip);
    const GBuffer g = renderGBuffer(scene, strip, cam);
    const ScreenField sf = computeScreenField(g, frames, rosy, field::findSingularities(frames, rosy), cam);

    auto lineDeg = [](double a, double b) {
        const double d = std::fmod(std::abs(a - b), M_PI);
        return std::min(d, M_PI - d) / test::kDeg;
    };
    auto screenDir = [&](const Vec3 &p, const Vec3 &t) {
        return (cam.project(p + 1e-5 * t) - cam.project(p - 1e-5 * t)).normalized();
    };
    int pairs = 0;
    double worst = 0, flatJump = 1e9;
    for (int y = 0; y + 1 < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const size_t a = size_t(g.index(x, y)), b = size_t(g.index(x, y + 1));
            if (g.faceId[a] < 0 || g.faceId[b] < 0 || !sf.valid(size_t(a)) || !sf.valid(size_t(b))) continue;
            if ((g.faceId[a] < 2) == (g.faceId[b] < 2)) continue; // not across the fold
            ++pairs;
            worst = std::max(worst, lineDeg(sf.angle(1, a), sf.angle(1, b)));
            const Vec2 d0 = screenDir(g.position(a), Vec3::UnitY());
            const Vec2 d1 = screenDir(g.position(a), Vec3(0, std::cos(fold), std::sin(fold)));
            flatJump = std::min(flatJump, lineDeg(std::atan2(d0.y(), d0.x()), std::atan2(d1.y(), d1.x())));
        }
    ASSERT_GT(pairs, 40);
    EXPECT_GT(flatJump, 15.0) << pairs << " pairs, worst " << worst; // the view makes the flat projection's jump plain
    EXPECT_LT(worst, 1.5) << "flat projection would jump by at least " << flatJump << "°";
}
