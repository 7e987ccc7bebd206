#pragma once
/// \file contours.h
/// Outline strokes: silhouettes, creases and mesh borders, split into visible and
/// hidden parts and chained into long polylines.
///
/// Silhouettes are the interpolated silhouette of Hertzmann & Zorin 2000
/// ("Illustrating smooth surfaces", §2): g = n·v is evaluated at the face corners
/// with smoothed normals and its zero set is traced linearly across each face. On a
/// smooth mesh this gives smooth curves instead of the zig-zag chains of mesh edges
/// between front and back faces. Corner normals are smoothed only within regions
/// bounded by creases ("auto-smooth"), so on flat-faced solids g is constant per face
/// and their outlines come out exactly along the crease edges that separate a front
/// from a back face (reported and drawn as silhouettes).

#include "field/mesh.h"
#include "renderer/view/camera.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"
#include "renderer/output/strokes.h"
#include "styles/style.h"

#include <cstdint>

namespace rosy::renderer {

/// What extractContours() found; lengths are raster pixels.
struct ContourReport {
    int nSilhouetteSegments = 0; ///< face segments of the interpolated silhouette + silhouette crease edges
    int nCreaseSegments = 0;     ///< crease edges (dihedral angle below the style's threshold)
    int nBorderSegments = 0;     ///< boundary edges (counted only when borders are drawn)
    int nChains = 0;             ///< chains built from the segments, before visibility splitting
    /// Edges whose two faces bend past the crease angle while the surface does not at
    /// the picture's scale (ContourStyle::featureScalePx): creases of a scan's noise.
    int nCreasesBelowScale = 0;
    /// Whether the outlines were judged at the picture's scale: such creases were more
    /// than 5 % of the mesh's edges and more than 3/4 of the edges bending past the
    /// crease angle (a scan), so they are not drawn, nor silhouette dots.
    bool judgedAtPictureScale = false;
    int nSmallLoopsDropped = 0;  ///< closed silhouette loops under half ContourStyle::featureScalePx across, not drawn
    int nSilhouetteStrokes = 0;  ///< visible silhouette strokes emitted
    int nCreaseStrokes = 0;      ///< visible crease or border strokes emitted
    int nHiddenStrokes = 0;      ///< HiddenContour strokes emitted (0 unless style.hidden)
    double visibleLengthPx = 0.0; ///< total length of the Contour strokes
    double hiddenLengthPx = 0.0;  ///< total length of the HiddenContour strokes
};

/// First id given to contour strokes: stroke i of the returned list has id
/// kContourIdBase + i, so contour ids do not collide with hatch ids counted from 0.
constexpr uint32_t kContourIdBase = 0x40000000u;

/// Extracts the outline strokes of `mesh` seen by `camera`.
///
/// \param mesh     the rendered mesh; face ids must match `scene` and `gbuffer`.
/// \param camera   the render camera; strokes are in its raster space (px, y down).
/// \param scene    ray queries over `mesh`; used for samples outside the image,
///                 where the G-buffer says nothing.
/// \param gbuffer  renderGBuffer(scene, mesh, camera); a sample is visible if a pixel
///                 of its 3×3 neighbourhood is background, shows the face the sample
///                 lies on, or lies behind the sample (within about two
///                 pixels' worth of depth) once its face plane is extended to the
///                 sample's exact position.
/// \param style    widths (silhouettes widthPx, creases and borders creaseWidthPx,
///                 both tapered over a few pixels at open chain ends), the crease
///                 threshold in degrees (an edge whose dihedral angle, 180° = flat, is
///                 below it is a crease; on a scan also at featureScalePx, see
///                 ContourStyle), and whether borders and hidden parts are drawn.
/// \param report   optional counts and lengths (may be null).
/// \return strokes of kind Contour (and HiddenContour when style.hidden), family −1,
///   ids kContourIdBase + index. Points are spaced about 1 px; a closed visible loop
///   repeats its first point at the end. Visible runs are merged across hidden gaps
///   shorter than ~2 px and visible runs shorter than 2 px are dropped, so noisy
///   occlusion flips do not break chains. Output is identical for any thread count.
///   An empty mesh gives an empty list; parts behind the camera plane are skipped.
/// `scanCopy`: `mesh` is a noisy scan's smoothed copy (field/scan_noise.h; same faces
///   as the mesh `scene` and `gbuffer` were made of, which visibility is tested
///   against): its outlines are judged at the picture's scale (style.featureScalePx)
///   whatever its counts of creases.
StrokeList extractContours(const field::Mesh &mesh, const Camera &camera, const RayScene &scene,
                           const GBuffer &gbuffer, const styles::ContourStyle &style,
                           ContourReport *report = nullptr, bool scanCopy = false);

} // namespace rosy::renderer
