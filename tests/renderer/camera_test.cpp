#include "renderer/view/camera.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rosy::renderer;

namespace {

std::vector<Camera> testCameras() {
    return {Camera::perspective(Vec3(3, 2, 5), Vec3(0.2, -0.1, 0.3), Vec3(0, 1, 0), 40.0, 80, 60),
            Camera::perspective(Vec3(-1, 4, 0.5), Vec3(0, 0, 0), Vec3(0, 0, 1), 70.0, 33, 97),
            Camera::orthographic(Vec3(3, 2, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 2.5, 64, 48)};
}

} // namespace

TEST(Camera, ProjectInvertsGenerateRay) {
    for (const Camera &cam : testCameras()) {
        for (double px : {0.0, 0.5, 17.25, double(cam.width())})
            for (double py : {0.0, 3.5, 22.75, double(cam.height())}) {
                Ray r = cam.generateRay(px, py);
                EXPECT_NEAR(r.dir.norm(), 1.0, 1e-12);
                for (double t : {0.5, 2.0, 9.0}) {
                    Vec2 q = cam.project(r.origin + t * r.dir);
                    EXPECT_NEAR(q.x(), px, 1e-9);
                    EXPECT_NEAR(q.y(), py, 1e-9);
                }
            }
    }
}

TEST(Camera, OpticalAxisProjectsToImageCentre) {
    for (const Camera &cam : testCameras()) {
        Vec2 q = cam.project(cam.position() + 4.0 * cam.forward());
        EXPECT_NEAR(q.x(), 0.5 * cam.width(), 1e-9);
        EXPECT_NEAR(q.y(), 0.5 * cam.height(), 1e-9);
    }
}

TEST(Camera, RasterYPointsDownAndXRight) {
    // Looking down -z with +y up: world +x is raster right, world +y is raster up (smaller y).
    Camera cam = Camera::perspective(Vec3(0, 0, 5), Vec3(0, 0, 0), Vec3(0, 1, 0), 45.0, 100, 100);
    EXPECT_GT(cam.project(Vec3(1, 0, 0)).x(), 50.0);
    EXPECT_LT(cam.project(Vec3(0, 1, 0)).y(), 50.0);
}

TEST(Camera, VerticalFovSpansImageHeight) {
    // A point at angle fov/2 above the axis lands on the top edge (y = 0).
    double fov = 50.0, half = 0.5 * fov * M_PI / 180.0;
    Camera cam = Camera::perspective(Vec3(0, 0, 0), Vec3(0, 0, -1), Vec3(0, 1, 0), fov, 40, 20);
    Vec2 q = cam.project(Vec3(0, std::tan(half) * 3.0, -3.0));
    EXPECT_NEAR(q.y(), 0.0, 1e-9);
    EXPECT_NEAR(q.x(), 20.0, 1e-9);
}

TEST(Camera, JacobianMatchesFiniteDifferences) {
    for (const Camera &cam : testCameras()) {
        for (Vec3 p : {Vec3(0.1, 0.2, -0.3), Vec3(-0.7, 0.4, 0.9), Vec3(0.5, -0.5, 0.5)}) {
            Eigen::Matrix<double, 2, 3> J = cam.projectJacobian(p);
            const double h = 1e-6;
            for (int k = 0; k < 3; ++k) {
                Vec3 e = Vec3::Zero();
                e[k] = h;
                Vec2 fd = (cam.project(p + e) - cam.project(p - e)) / (2 * h);
                EXPECT_NEAR(J(0, k), fd.x(), 1e-5 * (1 + std::abs(fd.x())));
                EXPECT_NEAR(J(1, k), fd.y(), 1e-5 * (1 + std::abs(fd.y())));
            }
        }
    }
}

TEST(Camera, JacobianKillsTheViewRayDirection) {
    // Moving a point along its own viewing ray does not move its image.
    Camera cam = testCameras()[0];
    Vec3 p(0.3, 0.1, -0.2);
    Vec3 along = (p - cam.position()).normalized();
    EXPECT_NEAR((cam.projectJacobian(p) * along).norm(), 0.0, 1e-9);
}

TEST(Camera, FrameSphereCentresSilhouetteWithMargin) {
    // The silhouette of a sphere of radius r seen from distance d subtends half-angle
    // asin(r/d); its image radius is tan(asin(r/d)) / tan(fov/2) * H/2 pixels.
    FramingOptions opt;
    opt.fovYDeg = 30.0;
    opt.margin = 0.25;
    opt.direction = Vec3(1, 2, 3);
    Vec3 c(1, -2, 0.5);
    Camera cam = frameSphere(c, 2.0, 120, 80, opt);
    double d = (cam.position() - c).norm();
    double rPx = std::tan(std::asin(2.0 / d)) / std::tan(15.0 * M_PI / 180.0) * 40.0;
    EXPECT_NEAR(rPx, 40.0 / 1.25, 1e-9); // tighter side is the height
    Vec2 q = cam.project(c);
    EXPECT_NEAR(q.x(), 60.0, 1e-9);
    EXPECT_NEAR(q.y(), 40.0, 1e-9);
    EXPECT_NEAR((cam.position() - c).normalized().dot(opt.direction.normalized()), 1.0, 1e-12);
}
