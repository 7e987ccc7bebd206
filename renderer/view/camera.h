#pragma once
/// \file camera.h
/// Pinhole and orthographic cameras, the map between world points and raster
/// pixels, and automatic framing of a mesh.
///
/// Raster space: x to the right in [0, width], y DOWN in [0, height]; the centre of
/// pixel (i, j) is (i + 0.5, j + 0.5). Camera space: right-handed basis
/// (right, up, -forward); the view axis is `forward`. Pixels are square.

#include "field/mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>

namespace rosy::renderer {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

/// A ray origin + t dir for t in [tMin, tMax]. dir is unit length for camera rays.
struct Ray {
    Vec3 origin = Vec3::Zero();
    Vec3 dir = Vec3(0, 0, -1);
    double tMin = 0.0;
    double tMax = std::numeric_limits<double>::infinity();
};

enum class Projection { Perspective, Orthographic };

class Camera {
public:
    /// Pinhole camera at `position` looking at `lookAt`; `up` need not be orthogonal
    /// to the view axis but must not be parallel to it. `fovYDeg` is the full vertical
    /// field of view in degrees, in (0, 180). `width`, `height` in pixels (>= 1).
    /// \throws CheckFailure for degenerate input (the scene parser validates user values).
    static Camera perspective(const Vec3 &position, const Vec3 &lookAt, const Vec3 &up,
                              double fovYDeg, int width, int height);
    /// Orthographic camera; `viewHeight` is the world-space height of the image (> 0).
    static Camera orthographic(const Vec3 &position, const Vec3 &lookAt, const Vec3 &up,
                               double viewHeight, int width, int height);

    Projection projection() const { return m_projection; }
    int width() const { return m_width; }
    int height() const { return m_height; }
    const Vec3 &position() const { return m_position; }
    /// Unit view axis, from the camera into the scene.
    const Vec3 &forward() const { return m_forward; }
    /// Unit raster +x direction in world space.
    const Vec3 &right() const { return m_right; }
    /// Unit world direction of raster -y (image up).
    const Vec3 &up() const { return m_up; }
    /// Vertical field of view in degrees (perspective only).
    double fovYDeg() const { return m_fovYDeg; }
    /// World-space image height (orthographic only).
    double viewHeight() const { return m_viewHeight; }

    /// The primary ray through raster point (px, py). Perspective rays start at the
    /// eye; orthographic rays start on the camera plane through `position`.
    Ray generateRay(double px, double py) const;
    /// Raster position of a world point. Meaningful only for points in front of the
    /// camera (depth() > 0); for others the depth is clamped to a tiny positive value
    /// so the result stays finite.
    Vec2 project(const Vec3 &pWorld) const;
    /// Exact derivative d(project)/d(pWorld), shape 2 x 3, in pixels per world unit:
    /// maps a world tangent vector at pWorld to its image in raster space.
    Eigen::Matrix<double, 2, 3> projectJacobian(const Vec3 &pWorld) const;
    /// Distance of pWorld along the view axis from the camera plane (world units).
    double depth(const Vec3 &pWorld) const { return (pWorld - m_position).dot(m_forward); }
    /// Unit direction from pWorld toward the viewer (the reversed primary ray direction).
    Vec3 toViewer(const Vec3 &pWorld) const;

    /// OpenEXR's camera space (the standard attribute `worldToCamera`, the same as
    /// RenderMan's): left-handed, origin at position(), x = right(), y = up() (image
    /// up), z = forward(), so a point in front of the camera has z = depth() > 0.
    /// Column-vector form: [xc yc zc 1]ᵀ = M · [x y z 1]ᵀ. (An OpenEXR file stores
    /// the transpose, Imath multiplying row vectors: p · Mᵀ.)
    Eigen::Matrix4d worldToCamera() const;
    /// OpenEXR's NDC (the standard attribute `worldToNDC`, RenderMan's): after the
    /// divide by w, x = px / width and y = py / height for the raster position
    /// (px, py) of project(): (0, 0) the top-left corner of the image, (1, 1) the
    /// bottom-right, y down; the centre of pixel (i, j) at ((i + 0.5) / width,
    /// (j + 0.5) / height). z after the divide is 1 / depth (perspective) or depth
    /// (orthographic); the standard says to discard it. Column-vector form as
    /// worldToCamera(), including the projective row (w = depth for perspective).
    Eigen::Matrix4d worldToNdc() const;

private:
    Camera() = default;
    void setFrame(const Vec3 &position, const Vec3 &lookAt, const Vec3 &up, int width, int height);
    /// Pixels per unit of the normalized image plane (perspective) or per world unit (ortho).
    double scale() const;

    Projection m_projection = Projection::Perspective;
    int m_width = 1, m_height = 1;
    Vec3 m_position = Vec3::Zero();
    Vec3 m_forward = Vec3(0, 0, -1), m_right = Vec3(1, 0, 0), m_up = Vec3(0, 1, 0);
    double m_fovYDeg = 35.0;
    double m_viewHeight = 2.0;
    double m_tanHalfFov = 0.0;
};

/// Settings for automatic framing.
struct FramingOptions {
    /// Direction from the object's centre toward the camera (any length > 0).
    Vec3 direction = Vec3(1.0, 0.55, 1.6);
    /// World up; must not be parallel to `direction`.
    Vec3 up = Vec3(0, 1, 0);
    double fovYDeg = 35.0;
    /// Fraction of the bounding sphere's radius kept free around it on the tighter
    /// image side (0.1 = 10 % margin).
    double margin = 0.1;
    Projection projection = Projection::Perspective;
};

/// A sphere enclosing all vertices of `mesh`: centred on the bounding box centre,
/// radius = farthest vertex distance. Empty mesh: centre 0, radius 1.
void boundingSphere(const field::Mesh &mesh, Vec3 &centre, double &radius);

/// A camera that sees the whole sphere (centre, radius > 0) from options.direction with
/// the margin on the tighter of the two image sides: the sphere's silhouette is a disk
/// of radius radius / (1 + margin) of the half-size of that side, centred in the image.
Camera frameSphere(const Vec3 &centre, double radius, int width, int height,
                   const FramingOptions &options = {});

/// frameSphere() around boundingSphere(mesh).
Camera frameMesh(const field::Mesh &mesh, int width, int height, const FramingOptions &options = {});

} // namespace rosy::renderer
