#include "renderer/view/camera.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace rosy::renderer {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Points at or behind the eye have no image; clamping the depth keeps project() finite.
constexpr double kMinDepth = 1e-12;
} // namespace

void Camera::setFrame(const Vec3 &position, const Vec3 &lookAt, const Vec3 &up, int width,
                      int height) {
    ROSY_CHECK_GE(width, 1);
    ROSY_CHECK_GE(height, 1);
    Vec3 f = lookAt - position;
    ROSY_CHECK(f.norm() > 0.0);
    f.normalize();
    Vec3 r = f.cross(up);
    ROSY_CHECK(r.norm() > 1e-9 * up.norm());
    r.normalize();
    m_position = position;
    m_forward = f;
    m_right = r;
    m_up = r.cross(f);
    m_width = width;
    m_height = height;
}

Camera Camera::perspective(const Vec3 &position, const Vec3 &lookAt, const Vec3 &up,
                           double fovYDeg, int width, int height) {
    ROSY_CHECK(fovYDeg > 0.0 && fovYDeg < 180.0);
    Camera c;
    c.m_projection = Projection::Perspective;
    c.setFrame(position, lookAt, up, width, height);
    c.m_fovYDeg = fovYDeg;
    c.m_tanHalfFov = std::tan(0.5 * fovYDeg * kPi / 180.0);
    return c;
}

Camera Camera::orthographic(const Vec3 &position, const Vec3 &lookAt, const Vec3 &up,
                            double viewHeight, int width, int height) {
    ROSY_CHECK(viewHeight > 0.0);
    Camera c;
    c.m_projection = Projection::Orthographic;
    c.setFrame(position, lookAt, up, width, height);
    c.m_viewHeight = viewHeight;
    return c;
}

double Camera::scale() const {
    return m_projection == Projection::Perspective ? 0.5 * m_height / m_tanHalfFov
                                                   : m_height / m_viewHeight;
}

Ray Camera::generateRay(double px, double py) const {
    // Raster -> image plane at unit distance (perspective) or world units (ortho).
    double s = scale();
    double x = (px - 0.5 * m_width) / s;
    double y = (0.5 * m_height - py) / s;
    Ray ray;
    if (m_projection == Projection::Perspective) {
        ray.origin = m_position;
        ray.dir = (m_forward + x * m_right + y * m_up).normalized();
    } else {
        ray.origin = m_position + x * m_right + y * m_up;
        ray.dir = m_forward;
    }
    return ray;
}

Vec2 Camera::project(const Vec3 &pWorld) const {
    Vec3 d = pWorld - m_position;
    double s = scale();
    double x = d.dot(m_right), y = d.dot(m_up);
    if (m_projection == Projection::Perspective) {
        double z = std::max(d.dot(m_forward), kMinDepth);
        x /= z;
        y /= z;
    }
    return Vec2(0.5 * m_width + s * x, 0.5 * m_height - s * y);
}

Eigen::Matrix<double, 2, 3> Camera::projectJacobian(const Vec3 &pWorld) const {
    double s = scale();
    Eigen::Matrix<double, 2, 3> J;
    if (m_projection == Projection::Orthographic) {
        J.row(0) = s * m_right.transpose();
        J.row(1) = -s * m_up.transpose();
        return J;
    }
    // px = W/2 + s (d.r)/(d.f): quotient rule gives s (r - x f) / z with x = (d.r)/z.
    Vec3 d = pWorld - m_position;
    double z = std::max(d.dot(m_forward), kMinDepth);
    double x = d.dot(m_right) / z, y = d.dot(m_up) / z;
    J.row(0) = (s / z) * (m_right - x * m_forward).transpose();
    J.row(1) = (-s / z) * (m_up - y * m_forward).transpose();
    return J;
}

Vec3 Camera::toViewer(const Vec3 &pWorld) const {
    if (m_projection == Projection::Orthographic) return -m_forward;
    Vec3 v = m_position - pWorld;
    double n = v.norm();
    return n > 0.0 ? Vec3(v / n) : Vec3(-m_forward);
}

Eigen::Matrix4d Camera::worldToCamera() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = m_right.transpose();
    m.block<1, 3>(1, 0) = m_up.transpose();
    m.block<1, 3>(2, 0) = m_forward.transpose();
    m(0, 3) = -m_right.dot(m_position);
    m(1, 3) = -m_up.dot(m_position);
    m(2, 3) = -m_forward.dot(m_position);
    return m;
}

Eigen::Matrix4d Camera::worldToNdc() const {
    // project(): px = W/2 + s·xc (/ zc), py = H/2 − s·yc (/ zc); NDC divides by W, H.
    const double sx = scale() / m_width, sy = scale() / m_height;
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    if (m_projection == Projection::Perspective) {
        p(0, 0) = sx, p(0, 2) = 0.5; // (0.5·zc + sx·xc) / zc
        p(1, 1) = -sy, p(1, 2) = 0.5;
        p(2, 3) = 1.0;               // z = 1 / zc
        p(3, 2) = 1.0;               // w = zc
    } else {
        p(0, 0) = sx, p(0, 3) = 0.5;
        p(1, 1) = -sy, p(1, 3) = 0.5;
        p(2, 2) = 1.0; // z = zc
        p(3, 3) = 1.0;
    }
    return p * worldToCamera();
}

void boundingSphere(const field::Mesh &mesh, Vec3 &centre, double &radius) {
    if (mesh.nVertices() == 0) {
        centre = Vec3::Zero();
        radius = 1.0;
        return;
    }
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    centre = 0.5 * (lo + hi);
    double r2 = 0.0;
    for (const Vec3 &p : mesh.positions()) r2 = std::max(r2, (p - centre).squaredNorm());
    radius = std::sqrt(r2);
    // A single point still needs a visible neighbourhood.
    if (!(radius > 0.0)) radius = 1.0;
}

Camera frameSphere(const Vec3 &centre, double radius, int width, int height,
                   const FramingOptions &options) {
    ROSY_CHECK(radius > 0.0);
    ROSY_CHECK(options.direction.norm() > 0.0);
    Vec3 dir = options.direction.normalized();
    // Half-size of the tighter image side relative to the vertical half-size.
    double aspectMin = double(std::min(width, height)) / double(height);
    double fill = 1.0 / (1.0 + options.margin);
    if (options.projection == Projection::Perspective) {
        double tanHalf = std::tan(0.5 * options.fovYDeg * kPi / 180.0);
        // The silhouette of a sphere seen from distance d is a cone of half-angle
        // asin(r/d); its image on the unit plane is a disk of radius tan(asin(r/d)).
        double alpha = std::atan(fill * tanHalf * aspectMin);
        double distance = radius / std::sin(alpha);
        return Camera::perspective(centre + distance * dir, centre, options.up, options.fovYDeg,
                                   width, height);
    }
    double viewHeight = 2.0 * radius / (fill * aspectMin);
    return Camera::orthographic(centre + 3.0 * radius * dir, centre, options.up, viewHeight,
                                width, height);
}

Camera frameMesh(const field::Mesh &mesh, int width, int height, const FramingOptions &options) {
    Vec3 c;
    double r;
    boundingSphere(mesh, c, r);
    return frameSphere(c, r, width, height, options);
}

} // namespace rosy::renderer
