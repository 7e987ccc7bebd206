#pragma once
/// \file hatching.h
/// Field-aligned hatching: evenly spaced streamlines of the screen field
/// (Jobard & Lefer 1997) whose spacing follows a target ink density, with a
/// second, crossing family in dark regions (Hertzmann & Zorin 2000 tone levels).
///
/// Spacing. One family of lines of width w at spacing s covers w / s of the paper;
/// two crossing families cover 1 − (1 − w/s)². hatchSpacingPx() solves these for s
/// and clamps to the style's [minSpacingPx, maxSpacingPx]; this s is the local
/// d_sep, and d_test = 0.5 d_sep. Both are evaluated at the query point, so spacing
/// varies smoothly with tone.
///
/// Families. Family 0 hatches wherever density >= highlightDensity, family 1 where
/// density >= crossDensity, along the other screen direction. Because a cross field
/// has no global labels, "same family" is decided by direction: a line keeps away
/// from samples whose tangent is within 55° of its own heading (a margin over the 45°
/// measureHatches() uses), from every sample of its own family (so each family's layer
/// never crosses itself), and where the tone asks for a single family from every
/// family-0 sample. The keep-away distance is the larger d_test of the two points.

#include "renderer/gbuffer.h"
#include "renderer/screen_field.h"
#include "renderer/strokes.h"
#include "styles/style.h"

#include <cstdint>
#include <vector>

namespace rosy::renderer {

/// What only the stroke list knows about a hatching (the render's --report).
struct HatchReport {
    int strokes = 0;                  ///< hatch strokes emitted
    int strokesFamily0 = 0;           ///< of which family 0
    int strokesFamily1 = 0;           ///< of which family 1 (cross-hatching)
    double inkLengthPx = 0;           ///< total polyline length, raster px
    /// Unordered pairs of strokes of the same family that come closer than the local
    /// d_test while running within 45° of each other (measured by measureHatches()).
    int minSpacingViolations = 0;
    /// Strokes that enter the disc of radius d_sep around a visible projected singularity.
    int strokesNearSingularities = 0;
};

/// Number of hatch families the style asks for at ink density `density` in [0, 1]:
/// 0 below highlightDensity, 2 at or above crossDensity, else 1. NaN counts as 0.
int hatchFamilies(double density, const styles::HatchStyle &style);

/// Spacing d_sep (px) of each family at `density` when `nFamilies` (1 or 2) families
/// share it, clamped to [minSpacingPx, maxSpacingPx]. Density <= 0 gives maxSpacingPx.
double hatchSpacingPx(double density, int nFamilies, const styles::HatchStyle &style);

/// The darkest ink coverage the style can lay down: two crossing families at
/// minSpacingPx, 1 − (1 − min(1, w / minSpacingPx))². The tone curve maps the
/// darkest tone here (renderIllustration), so every target density is one the
/// hatching can actually reach instead of a darkness it can only fall short of.
double maxHatchDensity(const styles::HatchStyle &style);

/// d_sep of the hatches at `density` (hatchSpacingPx with hatchFamilies, at least
/// one family): the radius of the keep-away disc around singularities.
double localSpacingPx(double density, const styles::HatchStyle &style);

/// Traces the hatches.
/// \param field screen field of the same resolution as `gbuffer`.
/// \param targetDensity #pixels, row-major, ink coverage in [0, 1] (values outside are
///   clamped, NaN is treated as 0); ignored on background pixels.
/// \param gbuffer supplies coverage and depth/normal discontinuities: strokes stop one
///   pixel before the background and at depth jumps (relative depth change > 3 % over a
///   pixel, or > 1 % where the normals also disagree by more than 60°).
/// \param seed base seed; per-stroke randomness (pressure, jitter) is seeded from
///   (seed, stroke id), so it does not depend on thread count.
/// \param report optional; filled with counts and measureHatches() results.
/// Strokes also stop at the edge of their tone band, where the line turns by more
/// than 12° in one step, when they would come within d_test of a same-direction line,
/// and at the disc of radius d_sep around each visible singularity. Strokes shorter
/// than minLengthPx are dropped. Tracing is sequential (Jobard–Lefer is order
/// dependent); the output is identical for any thread count. Stroke ids follow
/// creation order: all family-0 strokes, then family 1.
/// Empty image or no valid pixel: an empty list.
StrokeList traceHatches(const ScreenField &field, const std::vector<float> &targetDensity,
                        const GBuffer &gbuffer, const styles::HatchStyle &style, uint32_t seed,
                        HatchReport *report = nullptr);

/// Measures a hatch stroke list independently of the tracer's bookkeeping: total ink
/// length, same-family spacing violations (every stroke vertex against the segments
/// of other strokes of the same family within 45° of its direction, closer than
/// (1 − tolerance) d_test at that vertex; `tolerance` absorbs the chord error of
/// polylines sampled at 0.2 d_sep), and strokes whose segments enter a disc of radius
/// (1 − tolerance) d_sep around a visible singularity of `field`.
/// Only strokes of kind Hatch are looked at.
HatchReport measureHatches(const StrokeList &strokes, const ScreenField &field,
                           const std::vector<float> &targetDensity,
                           const styles::HatchStyle &style, double tolerance = 0.05);

} // namespace rosy::renderer
