// The G-buffer and Lambert tone on hand-built spheres with known images.

#include "renderer/view/camera.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"
#include "renderer/view/shading.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

using namespace rosy::renderer;

namespace {

struct Rendered {
    rosy::field::Mesh mesh;
    Camera camera;
    GBuffer gbuffer;
};

Rendered renderSphere(int size, const FramingOptions &opt) {
    rosy::field::Mesh mesh = rosy::test::makeSphere(4);
    Camera cam = frameMesh(mesh, size, size, opt);
    RayScene scene(mesh);
    GBuffer g = renderGBuffer(scene, mesh, cam);
    Rendered r{std::move(mesh), cam, std::move(g)};
    r.gbuffer.mesh = &r.mesh; // the G-buffer reads the mesh it was rendered from
    return r;
}

double coveredFraction(const GBuffer &g) {
    int n = 0;
    for (int id : g.faceId) n += id >= 0;
    return double(n) / double(g.nPixels());
}

} // namespace

TEST(RayScene, HitsSphereAtAnalyticDistance) {
    rosy::field::Mesh mesh = rosy::test::makeSphere(4);
    RayScene scene(mesh);
    Ray ray;
    ray.origin = Vec3(0, 0, 5);
    ray.dir = Vec3(0, 0, -1);
    Hit hit = scene.intersect(ray);
    ASSERT_TRUE(hit.valid());
    // The vertex (0, 0, 1) lies on the axis, so the hit is exactly there (float precision).
    EXPECT_NEAR(hit.t, 4.0, 1e-5);
    EXPECT_TRUE(scene.occluded(ray));
    ray.origin = Vec3(2, 0, 5);
    EXPECT_FALSE(scene.intersect(ray).valid());
    EXPECT_FALSE(scene.occluded(ray));
}

TEST(RayScene, PacketAndStreamQueriesAnswerAsSingleRays) {
    // Shading traces its shadow rays eight at a time and ambient occlusion in streams;
    // both must say what occluded() says of each ray, also for rays that graze the
    // sphere, pass through its vertices and edges, or stop just short of it.
    rosy::field::Mesh mesh = rosy::test::makeSphere(3);
    RayScene scene(mesh);
    std::vector<Ray> rays;
    for (int a = 0; a < 37; ++a)
        for (int b = 0; b < 23; ++b) {
            Ray r;
            r.origin = Vec3(-1.2 + 2.4 * a / 36.0, -1.2 + 2.4 * b / 22.0, 3.0);
            r.dir = Vec3(0.05 * std::sin(a + b), 0.05 * std::cos(a * b), -1.0).normalized();
            r.tMin = 0.0;
            r.tMax = (a + b) % 5 == 0 ? 1.9 + 0.01 * b : std::numeric_limits<double>::infinity();
            rays.push_back(r);
        }
    for (const Vec3 &p : {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0.5, 0.5, std::sqrt(0.5))}) {
        Ray r; // toward a vertex of the octahedron-based sphere, and a point beside
        r.origin = 3.0 * p + Vec3(0.3, -0.2, 0.1);
        r.dir = (p - r.origin).normalized();
        rays.push_back(r);
    }
    std::vector<bool> single(rays.size());
    int hits = 0;
    for (size_t k = 0; k < rays.size(); ++k) hits += (single[k] = scene.occluded(rays[k])) ? 1 : 0;
    ASSERT_GT(hits, 100);
    ASSERT_LT(hits, int(rays.size()) - 100);
    for (size_t k0 = 0; k0 < rays.size(); k0 += 8) {
        const int m = int(std::min<size_t>(8, rays.size() - k0));
        bool out[8];
        scene.occluded8(rays.data() + k0, m, out);
        for (int q = 0; q < m; ++q) EXPECT_EQ(out[q], single[k0 + size_t(q)]) << "ray " << k0 + size_t(q);
    }
    std::unique_ptr<bool[]> many(new bool[rays.size()]);
    scene.occludedMany(rays.data(), int(rays.size()), many.get());
    for (size_t k = 0; k < rays.size(); ++k) EXPECT_EQ(many[k], single[k]) << "ray " << k;
}

TEST(RayScene, EmptyMeshMissesEverything) {
    rosy::field::Mesh empty;
    RayScene scene(empty);
    Ray ray;
    EXPECT_FALSE(scene.intersect(ray).valid());
    EXPECT_FALSE(scene.occluded(ray));
}

TEST(GBuffer, PerspectiveCoverageMatchesProjectedDiskArea) {
    FramingOptions opt;
    opt.direction = Vec3(0.3, 0.4, 1.0);
    opt.margin = 0.2;
    Rendered r = renderSphere(64, opt);
    ASSERT_EQ(r.gbuffer.width, 64);
    ASSERT_EQ(r.gbuffer.height, 64);
    // Independent of the framing code: a unit sphere at distance d has an image disk of
    // radius tan(asin(1/d)) / tan(fov/2) * H/2 pixels.
    double d = r.camera.position().norm();
    double rPx = std::tan(std::asin(1.0 / d)) / std::tan(0.5 * opt.fovYDeg * M_PI / 180.0) * 32.0;
    double expected = M_PI * rPx * rPx / (64.0 * 64.0);
    EXPECT_NEAR(coveredFraction(r.gbuffer) / expected, 1.0, 0.04);
}

TEST(GBuffer, OrthographicCoverageMatchesDiskArea) {
    FramingOptions opt;
    opt.projection = Projection::Orthographic;
    opt.margin = 0.1;
    Rendered r = renderSphere(64, opt);
    double rPx = 64.0 / r.camera.viewHeight(); // unit radius in pixels
    double expected = M_PI * rPx * rPx / (64.0 * 64.0);
    EXPECT_NEAR(coveredFraction(r.gbuffer) / expected, 1.0, 0.04);
}

TEST(GBuffer, StoresSurfaceGeometry) {
    Rendered r = renderSphere(32, {});
    const GBuffer &g = r.gbuffer;
    int checked = 0;
    for (size_t i = 0; i < g.nPixels(); ++i) {
        if (g.faceId[i] < 0) {
            EXPECT_EQ(g.depth[i], 0.0);
            continue;
        }
        ++checked;
        // On (a fine polyhedron inscribed in) the unit sphere the smooth normal is the
        // radial direction and the point lies at radius ~1, facing the camera.
        EXPECT_NEAR(g.position(i).norm(), 1.0, 0.01);
        EXPECT_GT(g.normal(i).dot(g.position(i).normalized()), 0.995);
        EXPECT_GT(g.normal(i).dot(r.camera.toViewer(g.position(i))), -0.05);
        // Stored in single precision: within a few float ulps of the exact depth.
        EXPECT_NEAR(g.depth[i], (g.position(i) - r.camera.position()).dot(r.camera.forward()), 1e-6 * std::abs(g.depth[i]));
    }
    EXPECT_GT(checked, 100);
}

TEST(GBuffer, IdenticalForAnyThreadCount) {
    rosy::field::Mesh mesh = rosy::test::makeSphere(3);
    Camera cam = frameMesh(mesh, 48, 40);
    RayScene scene(mesh);
    GBuffer one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = renderGBuffer(scene, mesh, cam);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = renderGBuffer(scene, mesh, cam);
    }
    EXPECT_EQ(one.faceId, two.faceId);
    EXPECT_EQ(one.depth, two.depth);
}

TEST(Shading, LitSideBrighterAndBackgroundIsPaper) {
    FramingOptions opt;
    opt.direction = Vec3(0, 0, 1); // raster +x is world +x
    Rendered r = renderSphere(64, opt);
    RayScene scene(r.mesh);
    Light light;
    light.direction = Vec3(1, 0, 0.3);
    ShadingOptions so;
    so.ambient = 0.1;
    std::vector<double> tone = shadeLambert(r.gbuffer, scene, r.mesh, r.camera, {light}, so);
    double left = 0, right = 0;
    int nLeft = 0, nRight = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            double t = tone[size_t(r.gbuffer.index(x, y))];
            ASSERT_GE(t, 0.0);
            ASSERT_LE(t, 1.0);
            if (!r.gbuffer.covered(x, y)) {
                EXPECT_EQ(t, 1.0);
                continue;
            }
            (x < 32 ? left : right) += t;
            (x < 32 ? nLeft : nRight) += 1;
        }
    ASSERT_GT(nLeft, 100);
    ASSERT_GT(nRight, 100);
    EXPECT_GT(right / nRight, left / nLeft + 0.3);

    rosy::styles::Style style;
    style.paper = {0.9, 0.8, 0.7};
    style.ink = {0.1, 0.0, 0.2};
    Image img = toneImage(tone, 64, 64, style);
    ASSERT_EQ(img.nChannels, 3);
    for (int k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(img.at(0, 0, k), float(style.paper[size_t(k)]));
    // The point of the sphere facing away from the light, seen edge-on from the front,
    // gets only the ambient tone: ink + 0.1 (paper - ink).
    Vec2 dark = r.camera.project(Vec3(-0.97, 0.0, 0.2));
    int dx = int(dark.x()), dy = int(dark.y());
    ASSERT_TRUE(r.gbuffer.covered(dx, dy));
    EXPECT_NEAR(img.at(dx, dy, 0), 0.1 + 0.1 * 0.8, 1e-6);
}

TEST(Shading, LambertCosineAtSphereCentre) {
    FramingOptions opt;
    opt.direction = Vec3(0, 0, 1);
    Rendered r = renderSphere(33, opt); // odd size: pixel 16 sits on the axis
    RayScene scene(r.mesh);
    Light light;
    light.direction = Vec3(0, std::sin(M_PI / 3), std::cos(M_PI / 3)); // 60 deg from the view axis
    ShadingOptions so;
    so.ambient = 0.0;
    std::vector<double> tone = shadeLambert(r.gbuffer, scene, r.mesh, r.camera, {light}, so);
    // Normal at the centre pixel is +z: tone = cos 60 deg = 0.5.
    EXPECT_NEAR(tone[size_t(r.gbuffer.index(16, 16))], 0.5, 0.01);
}

TEST(Shading, SphereCastsShadowOnFloor) {
    rosy::field::Mesh mesh = rosy::test::makeSphereOverFloor(3, -1.5, 4.0);
    Camera cam = Camera::perspective(Vec3(0, -6, 4), Vec3(0, 0, -1.5), Vec3(0, 0, 1), 50.0, 64, 64);
    RayScene scene(mesh);
    GBuffer g = renderGBuffer(scene, mesh, cam);
    Light light;
    light.direction = Vec3(0, 0, 1); // straight down onto the floor
    // A floor point at distance 2.5 from the axis, in front of the sphere: lit. Directly
    // below the sphere (distance 0.5 from its axis): in shadow. Pick the spots in view.
    Vec2 lit = cam.project(Vec3(0, -2.5, -1.5));
    Vec2 shadowed = cam.project(Vec3(0.0, -0.9, -1.5));
    int il = g.index(int(lit.x()), int(lit.y())), is = g.index(int(shadowed.x()), int(shadowed.y()));
    ASSERT_GE(g.faceId[size_t(il)], 0);
    ASSERT_GE(g.faceId[size_t(is)], 0);
    ASSERT_NEAR(g.position(size_t(is)).z(), -1.5, 1e-6) << "the shadow probe must see the floor";
    ShadingOptions so;
    so.ambient = 0.2;
    so.shadows = true;
    std::vector<double> withShadows = shadeLambert(g, scene, mesh, cam, {light}, so);
    EXPECT_NEAR(withShadows[size_t(il)], 1.0, 1e-9);
    EXPECT_NEAR(withShadows[size_t(is)], 0.2, 1e-9);
    so.shadows = false;
    std::vector<double> without = shadeLambert(g, scene, mesh, cam, {light}, so);
    EXPECT_NEAR(without[size_t(is)], 1.0, 1e-9);
}

namespace {

/// A floor (z = 0, x in [0, 20], y in [-10, 10], normal +z) meeting a wall (x = 0,
/// same y range, z in [0, 20], normal +x) along the y axis: the inner corner of two
/// perpendicular planes. Without the wall (withWall false) an open plane.
rosy::field::Mesh makeCorner(bool withWall) {
    std::vector<Vec3> p = {Vec3(0, -10, 0), Vec3(20, -10, 0), Vec3(20, 10, 0), Vec3(0, 10, 0)};
    std::vector<rosy::field::Face> f = {{0, 1, 2}, {0, 2, 3}};
    if (withWall) {
        // Own vertices along the corner line: shared ones would average the two
        // planes' normals and tilt the shading normal of both.
        p.insert(p.end(), {Vec3(0, -10, 0), Vec3(0, 10, 0), Vec3(0, 10, 20), Vec3(0, -10, 20)});
        f.push_back({4, 5, 6});
        f.push_back({4, 6, 7});
    }
    return rosy::field::Mesh::fromTriangles(p, f, withWall ? "corner" : "plane");
}

/// Ambient occlusion at distance d from an infinite occluding half-plane meeting the
/// surface at a right angle, for rays of length R (worked out by hand): a
/// cosine-weighted direction is a uniform point (x, y) on the unit disk lifted to the
/// hemisphere, and the ray toward the wall reaches it within R exactly when
/// -x > d / R. The blocked part of the disk is the circular segment x < -a, a = d/R,
/// of area acos(a) - a sqrt(1 - a²); AO is one minus its share of the disk.
double cornerAo(double d, double R) {
    const double a = d / R;
    if (a >= 1.0) return 1.0;
    return 1.0 - (std::acos(a) - a * std::sqrt(1.0 - a * a)) / M_PI;
}

} // namespace

TEST(AmbientOcclusion, InnerCornerOfTwoPlanesMatchesTheAnalyticValue) {
    rosy::field::Mesh mesh = makeCorner(true);
    // Looking down into the corner from the open side, both planes in view.
    Camera cam = Camera::perspective(Vec3(6, 0, 6), Vec3(0.5, 0, 0.5), Vec3(0, 0, 1), 50.0, 64, 64);
    RayScene scene(mesh);
    GBuffer g = renderGBuffer(scene, mesh, cam);
    ShadingOptions so;
    so.aoSamples = 256;
    so.aoRadius = 1.0;
    so.aoSeed = 7;
    const std::vector<float> ao = ambientOcclusion(g, scene, mesh, cam, so);
    double sumError = 0.0, maxError = 0.0;
    int n = 0, nearCorner = 0;
    for (size_t i = 0; i < g.nPixels(); ++i) {
        if (g.faceId[i] < 0) continue;
        const Vec3 p = g.position(i);
        // The distance to the other plane: x on the floor, z on the wall.
        const double d = g.faceId[i] < 2 ? p.x() : p.z();
        const double want = cornerAo(d, so.aoRadius);
        const double err = double(ao[i]) - want;
        sumError += err;
        maxError = std::max(maxError, std::abs(err));
        ++n;
        nearCorner += d < 0.2;
    }
    ASSERT_GT(n, 2000);
    ASSERT_GT(nearCorner, 10) << "the view must include points near the corner (AO -> 1/2 there)";
    // 256 stratified samples: each pixel within a few standard deviations (about 0.03),
    // and no bias on average.
    EXPECT_LT(maxError, 0.15);
    EXPECT_NEAR(sumError / n, 0.0, 0.01);
}

TEST(AmbientOcclusion, OpenPlaneIsUnoccludedAndToneTakesAoIntoTheAmbientTerm) {
    rosy::field::Mesh mesh = makeCorner(false);
    Camera cam = Camera::perspective(Vec3(6, 0, 6), Vec3(5, 0, 0), Vec3(0, 0, 1), 50.0, 48, 48);
    RayScene scene(mesh);
    GBuffer g = renderGBuffer(scene, mesh, cam);
    ShadingOptions so;
    so.aoSamples = 32;
    so.aoRadius = 100.0;
    int covered = 0;
    const std::vector<float> ao = ambientOcclusion(g, scene, mesh, cam, so);
    for (size_t i = 0; i < g.nPixels(); ++i) {
        if (g.faceId[i] < 0) continue;
        ++covered;
        EXPECT_EQ(ao[i], 1.0f) << "pixel " << i;
    }
    EXPECT_GT(covered, 500);

    // In the corner, with no light, the tone is ambient times AO and nothing else.
    rosy::field::Mesh corner = makeCorner(true);
    Camera cam2 = Camera::perspective(Vec3(6, 0, 6), Vec3(0.5, 0, 0.5), Vec3(0, 0, 1), 50.0, 32, 32);
    RayScene scene2(corner);
    GBuffer g2 = renderGBuffer(scene2, corner, cam2);
    so.ambient = 0.3;
    so.aoRadius = 1.0;
    const std::vector<float> ao2 = ambientOcclusion(g2, scene2, corner, cam2, so);
    const std::vector<double> tone = shadeLambert(g2, scene2, corner, cam2, {}, so);
    int darker = 0;
    for (size_t i = 0; i < g2.nPixels(); ++i) {
        if (g2.faceId[i] < 0) continue;
        EXPECT_DOUBLE_EQ(tone[i], 0.3 * double(ao2[i]));
        darker += ao2[i] < 0.9f;
    }
    EXPECT_GT(darker, 20) << "the corner must darken some pixels";
}

TEST(AmbientOcclusion, IdenticalForAnyThreadCountAndSeeded) {
    rosy::field::Mesh mesh = rosy::test::makeSphereOverFloor(3, -1.1, 4.0);
    Camera cam = Camera::perspective(Vec3(0, -6, 3), Vec3(0, 0, -0.5), Vec3(0, 0, 1), 45.0, 96, 96);
    RayScene scene(mesh);
    GBuffer g = renderGBuffer(scene, mesh, cam);
    ShadingOptions so;
    so.aoSamples = 8;
    so.aoRadius = 1.5;
    so.aoSeed = 3;
    std::vector<float> one, many = ambientOcclusion(g, scene, mesh, cam, so);
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = ambientOcclusion(g, scene, mesh, cam, so);
    }
    EXPECT_EQ(one, many);
    // The sphere occludes the floor under it (AO clearly below 1 there).
    const Vec2 under = cam.project(Vec3(0.0, -0.9, -1.1));
    const size_t iu = size_t(g.index(int(under.x()), int(under.y())));
    ASSERT_GE(g.faceId[iu], 0);
    EXPECT_LT(many[iu], 0.8f);
    // Another seed draws other directions: the noise changes, its mean does not.
    so.aoSeed = 4;
    const std::vector<float> other = ambientOcclusion(g, scene, mesh, cam, so);
    EXPECT_NE(other, many);
}
