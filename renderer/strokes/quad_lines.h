#pragma once
/// \file quad_lines.h
/// Hatching along the edges of a quad mesh remeshed from the field (style key
/// `hatch.lines: quad_mesh`; issue 20): the lines are the mesh's edge lines
/// (remesh/edge_lines.h), so they are evenly spaced *on the surface* by
/// construction — the look of an engraving cut along a grid — where the field
/// tracer (hatching.h) spaces its streamlines evenly on screen.
///
/// Tone chooses which lines show. With w = hatch.stroke_width_px and L =
/// hatch.quad_edge_px (the edge length on screen at the mesh's centre), one family
/// of lines covers w / 2L with every other line drawn and w / L with all; the target
/// density picks the nearer of those below hatch.cross_density, and above it the
/// nearer of the two cross-hatched levels (the second family added every other line,
/// or all of it). Families are per edge (remesh/edge_lines.h: family 0 runs around
/// the form), so a line can change family along its length; "every other line" is
/// the line's parity.
/// Lines are drawn where they are seen: on the pixel's own surface (depth within a
/// few pixel footprints and a quarter of the edge) and facing the camera.

#include "renderer/output/strokes.h"
#include "renderer/strokes/screen_field.h"
#include "renderer/view/camera.h"
#include "renderer/view/gbuffer.h"
#include "styles/style.h"

#include <vector>

namespace rosy::renderer {

/// One edge line of the quad mesh (remesh::EdgeLine, without a dependency on it).
struct SurfaceLine {
    std::vector<Vec3> points;  ///< world positions along the line (≥ 2)
    std::vector<Vec3> normals; ///< unit surface normals at the points
    bool closed = false;       ///< the last point joins the first
    std::vector<int> families; ///< per segment (points − 1, or points if closed): 0 or 1 (remesh::EdgeLine::families)
    int parity = 0;            ///< 0 or 1, alternating between neighbouring parallel lines
};

/// Which lines a target density draws (see the file comment): 0 none; 1 family 0's
/// parity-0 lines; 2 all of family 0; 3 those and family 1's parity-0 lines; 4 all.
int quadLineLevel(double density, const styles::HatchStyle &style);

/// The hatch strokes (kind Hatch, family 0 or 1, raster px, finished with the
/// style's taper and pressure by finishStroke()) of the visible parts of `lines`
/// that the tone asks for; runs shorter than hatch.min_length_px are dropped.
/// Deterministic for any thread count (stroke ids: their index).
StrokeList quadLineHatches(const std::vector<SurfaceLine> &lines, const ScreenField &screen,
                           const std::vector<float> &targetDensity, const GBuffer &gbuffer, const Camera &camera,
                           const styles::HatchStyle &style, uint32_t seed);

} // namespace rosy::renderer
