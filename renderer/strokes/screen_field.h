#pragma once
/// \file screen_field.h
/// The surface's N-RoSy field as seen by the camera: per pixel, the two screen
/// directions hatches may follow. Hatching (hatching.h) traces streamlines in
/// this image instead of on the surface (Rössl & Kobbelt 2000, Hertzmann & Zorin 2000).
///
/// Member directions are projected with the exact Jacobian of the projection at
/// the pixel's surface point, so foreshortening bends and squeezes them the way
/// the surface does (dropping z would not).
///
/// Labels. d0 is the projection of the field's first member vector m0 and d1 that of
/// the on-surface perpendicular n × m0 (for N = 4 the second member; for N = 2 the
/// cross-hatch direction). Which member is "first" jumps across a cross field (a
/// 4-RoSy has no global labelling), so consumers must not rely on the labels being
/// continuous: lineNear() picks, per pixel, the direction closest to a heading.

#include "field/frames.h"
#include "field/rosy.h"
#include "field/singularities.h"
#include "renderer/view/camera.h"
#include "renderer/view/gbuffer.h"

#include <cstdint>
#include <vector>

namespace rosy::renderer {

/// A field singularity projected to the image.
struct ScreenSingularity {
    Vec2 pRaster = Vec2::Zero(); ///< raster px (pixel centres at +0.5)
    Vec3 pWorld = Vec3::Zero();  ///< world position on the surface
    double index = 0;            ///< k / N
    int face = -1;               ///< mesh face holding it
    /// True when it is in front of the camera, inside the image and not hidden by
    /// other geometry (its depth matches the G-buffer's at its pixel).
    bool visible = false;
};

/// Per-pixel screen-space line field. Arrays are row-major like GBuffer
/// (index = y * width + x, y down); invalid pixels hold zeros.
struct ScreenField {
    int width = 0;
    int height = 0;
    int nSym = 0; ///< N of the surface field it came from
    /// #pixels; unit screen line directions of the two field families: d0 (projected
    /// m0) and d1 (projected n × m0), folded into angles [0, π) in the raster frame (x
    /// right, y down, so a positive angle turns clockwise on screen). Both are zero
    /// exactly where the pixel is not valid(), which is how valid() tells them.
    /// Both in one 16-byte element per pixel, so the tracer's lookups (both
    /// directions of four neighbouring pixels per step) read one cache line, not two.
    struct Lines {
        Eigen::Vector2f d[2];
    };
    std::vector<Lines> lines;
    /// d0 (family 0) or d1 (family 1) at pixel i.
    const Eigen::Vector2f &dir(int family, size_t i) const { return lines[i].d[family]; }
    /// #pixels; field strength |u| interpolated in the face (0 at a zero of the field).
    std::vector<float> strength;
    /// True where pixel i sees the surface, the field is non-zero and both directions
    /// project to non-degenerate screen vectors: exactly where it holds directions
    /// (unit d0 and d1; zeros elsewhere), so no separate mask is stored or read.
    bool valid(size_t i) const {
        const Eigen::Vector2f &d0 = lines[i].d[0];
        return d0.x() != 0.0f || d0.y() != 0.0f;
    }
    /// Singularities of the field (all of them, with a visibility flag), in the order
    /// findSingularities() reports them (by face id).
    std::vector<ScreenSingularity> singularities;

    int index(int x, int y) const { return y * width + x; }
    size_t nPixels() const { return size_t(width) * size_t(height); }
    /// Screen angle of d0 (family 0) or d1 (family 1) at pixel i, radians in [0, π);
    /// 0 where the pixel is invalid. Taken from dir0 / dir1 when asked (only the
    /// EXR channels field.angle0/1 need it), so tracing pays no atan2 per pixel.
    float angle(int family, size_t i) const;
    bool isValid(int x, int y) const {
        return x >= 0 && y >= 0 && x < width && y < height && valid(size_t(index(x, y)));
    }

    /// The line direction at raster point p that is closest to `heading`, bilinear
    /// over the four surrounding pixel centres: at each valid pixel take whichever of
    /// d0, d1 is closer to the heading (mod π), then average in the doubled-angle
    /// representation (so θ and θ + π agree). Invalid pixels get no weight.
    /// \param heading any non-zero screen vector. \param dir unit result, oriented so
    ///   dir · heading >= 0. \return false if no neighbouring pixel is valid or the
    ///   directions cancel (dir untouched).
    bool lineNear(const Vec2 &p, const Vec2 &heading, Vec2 &dir) const;

    /// Direction of family `family` (0: d0, 1: d1) at p by its label, bilinear in the
    /// doubled-angle representation; meaningful only where labels are continuous
    /// (2-RoSy fields, or away from label jumps). \return false as for lineNear.
    bool lineOfFamily(const Vec2 &p, int family, Vec2 &dir) const;
};

/// Builds the screen field. Per covered pixel: the corner representation vectors of
/// its face (TangentFrames::faceValues) interpolated with the G-buffer barycentrics,
/// m0 = faceDirection(f, arg(u)/N), m⊥ = n_f × m0, both mapped by
/// camera.projectJacobian at the pixel's surface point. Rows run in parallel; the
/// result is identical for any thread count.
/// \param gbuffer rendered with `camera` from the mesh `frames` is built on.
/// \param field vertex-based field on that mesh (#V representation vectors).
/// \param singularities the field's singularities (field::findSingularities), found
///   once by the caller, which usually reports them too.
/// Empty G-buffer: an empty field. A zero field gives no valid pixel.
ScreenField computeScreenField(const GBuffer &gbuffer, const field::TangentFrames &frames,
                               const field::RosyField &field, const field::SingularityReport &singularities,
                               const Camera &camera);

} // namespace rosy::renderer
