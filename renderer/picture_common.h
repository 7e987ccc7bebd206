#pragma once
/// \file picture_common.h
/// What the product's diagnostic pictures share (field pictures, field_picture.h;
/// pictures of polygon meshes, mesh_picture.h): a light grey shaded fill, a test
/// of whether a world point is seen, visible parts of world polylines as strokes,
/// and dots. Internal to rosy::renderer.

#include "renderer/field_picture.h"
#include "renderer/output/image.h"
#include "renderer/output/strokes.h"
#include "renderer/view/camera.h"
#include "renderer/view/gbuffer.h"
#include "renderer/view/shading.h"

#include <vector>

namespace rosy::renderer {

/// Decides whether world points are seen by the camera, against a G-buffer.
class Visibility {
public:
    /// \param diagonal the drawn mesh's bounding-box diagonal (sets the depth tolerance)
    Visibility(const GBuffer &gbuffer, const Camera &camera, double diagonal);

    /// True if p lies in front of the camera and on (not behind) the visible surface.
    /// The 3x3 pixel neighbourhood is searched because a point's own pixel centre
    /// may miss a silhouette or hit a steep neighbouring facet; the tolerance grows
    /// with the pixel footprint (times `slack`) so grazing surfaces keep their lines.
    bool visible(const Vec3 &p, double slack = 1.0) const;

    /// The same for a point of a surface facing along `normal` (any length, not
    /// zero), which must also face the same way as the visible surface there: the far
    /// side of a wall thinner than the depth tolerance faces away from its near side.
    bool visible(const Vec3 &p, const Vec3 &normal, double slack = 1.0) const;

private:
    const GBuffer &m_gbuffer;
    const Camera &m_camera;
    double m_diagonal;
    double m_footprintPerDepth = 0, m_footprintConst = 0;
};

/// Appends the visible parts of a world polyline to `out` as strokes of full width
/// `widthPx`: each segment is cut into pieces of at most ~1.5 px on screen and each
/// piece kept or dropped by the visibility of its midpoint; a run of kept pieces is
/// one stroke (ids: their index in `out`). `normals`, when given (one per point), is
/// the surface's normal at each point: a segment is then seen only where the visible
/// surface faces the way of its two ends' normals summed (Visibility::visible).
void addVisibleStrokes(std::vector<Stroke> &out, const std::vector<Vec3> &points, const Camera &camera,
                       const Visibility &vis, double widthPx, const std::vector<Vec3> *normals = nullptr);

/// A filled dot of radius r: a stroke of two equal points (a round cap), width 2r.
Stroke dot(const Vec2 &centre, double r, uint32_t id);

/// The G-buffer of `mesh` seen by `camera` and a drawing of the camera's size without
/// inks whose fill is the light grey picture: RGB (linear) 0.3 + 0.6 × Lambert tone
/// on the surface (ambient 0.2, no shadows), white elsewhere. Empty `lights`: one
/// headlight a little above and left of the eye.
struct ShadedFill {
    GBuffer gbuffer;
    FieldDrawing drawing;
    double diagonal = 1; ///< the mesh's bounding-box diagonal (at least 1e-12)
};
ShadedFill shadedFill(const field::Mesh &mesh, const Camera &camera, const std::vector<Light> &lights);

} // namespace rosy::renderer
