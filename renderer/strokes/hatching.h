#pragma once
/// \file hatching.h
/// Field-aligned hatching: evenly spaced streamlines of the screen field
/// (Jobard & Lefer 1997) whose spacing follows a target ink density, with a
/// second, crossing family in dark regions (Hertzmann & Zorin 2000 tone levels).
///
/// Spacing. One family of lines of width w at spacing s covers w / s of the paper;
/// two crossing families cover 1 − (1 − w/s)². familyCoverage() splits a target
/// density between the families, familySpacingPx() turns each share into a spacing
/// clamped to the style's [minSpacingPx, maxSpacingPx]; this s is the local d_sep
/// and d_test = 0.5 d_sep, both evaluated at the query point, so spacing varies
/// smoothly with tone.
///
/// Families. Family 0 hatches wherever density >= highlightDensity; family 1, the
/// cross-hatching, fades in above crossDensity over kCrossFeatherBand (sparse lines
/// first, an even split at the top of the band) along the other screen direction,
/// and gives way to family 0 where foreshortening folds both directions together
/// (crossWeight()). Each stroke's end tone is staggered around its family's
/// threshold, so strokes do not all end on one iso-line. A cross field has no
/// global labels, so "same family" is decided by direction: a line keeps away from
/// samples whose tangent is within 55° of its own heading (a margin over the 45°
/// measureHatches() uses); where the tone asks for a single family it also keeps
/// away from every family-0 sample (mid-tones never cross). In cross tone lines of
/// other directions never stop it, so where two fronts of the first family meet at
/// a label jump both run on instead of leaving a crack; a first-family line that
/// mostly crosses earlier first-family lines is moved to family 1 afterwards, so
/// each layer keeps one direction. A last pass seeds holes in cross tone that
/// Jobard–Lefer's full-d_sep seeding leaves between diverging lines. The keep-away
/// distance is the larger d_test of the two points.

#include "renderer/view/gbuffer.h"
#include "renderer/strokes/screen_field.h"
#include "renderer/output/strokes.h"
#include "styles/style.h"

#include <array>
#include <cstdint>
#include <functional>
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
    /// Strokes that enter the disc of radius d_sep around a visible projected singularity
    /// outside cross tone, which the tracer keeps free (in cross tone, where both
    /// families stop at it, a disc that would be a hole is inked afterwards: lines that
    /// stopped there run on straight through it).
    int strokesNearSingularities = 0;
    /// Visible singularities in cross-hatched tone (two families drawn at their pixel)
    /// with no hatch line within kHoleRatio × the local spacing d_sep: a white speck
    /// in dark tone, where between two families' lines no point is farther than d_sep / 2
    /// from ink.
    int singularityHoles = 0;
    /// Stubs: hatch strokes shorter than kStubLengthRatio × their local spacing (the
    /// mean of familySpacingPx over the stroke's vertices), and their share of strokes.
    int stubs = 0;
    double stubFraction = 0.0;
    /// Share of the second family's ink length laid closer to another second-family
    /// line (within 45°) than that family's own d_test. Traced second-family lines
    /// keep that d_test, so this is the relabelled first-family lines (two fronts that
    /// ran through each other) drawing the cross direction at the first family's
    /// spacing: denser than the tone asks for inside the feather band.
    double crossOverdenseFraction = 0.0;
    /// Share of the hatch ink length lying in squeezed runs: stretches of at least one
    /// local d_sep along which a line of the same direction (within 45°) lies on each
    /// side closer than kSqueezeRatio d_sep. Two fronts of parallel lines that run
    /// through each other at half the spacing make such runs: a patch of double
    /// density with straight edges.
    double squeezedFraction = 0.0;
    /// Share of the hatch ink length along which a line of the same layer within one
    /// local d_sep runs at 20°–50° to it: strokes that disagree in direction with
    /// their neighbours of one family (a fold of the screen field seeding short lines
    /// at an angle across the regular hatching, kinks where lines of two directions
    /// meet end to end). Regular hatching scores 0.
    double incoherentFraction = 0.0;
};

/// A hatch stroke shorter than this many local spacings reads as a dash, not a line.
inline constexpr double kStubLengthRatio = 4.0;

/// HatchReport::singularityHoles: in cross-hatched tone no ink within this many local
/// spacings of a point is a hole (the farthest a point lies from ink there is half a
/// spacing; a little irregularity reaches about 0.6).
inline constexpr double kHoleRatio = 0.75;

/// Two same-direction neighbours, one on each side, both closer than this many d_sep
/// squeeze a line (HatchReport::squeezedFraction). Regular hatching has them at one
/// d_sep; Jobard–Lefer's d_test lets a line come to half of it where lines converge.
inline constexpr double kSqueezeRatio = 0.7;

/// Number of hatch families the style asks for at ink density `density` in [0, 1]:
/// 0 below highlightDensity, 2 at or above crossDensity, else 1. NaN counts as 0.
int hatchFamilies(double density, const styles::HatchStyle &style);

/// Spacing d_sep (px) of each family at `density` when `nFamilies` (1 or 2) families
/// share it (times spacingGain), clamped to [minSpacingPx, maxSpacingPx]. Density <= 0 gives maxSpacingPx.
double hatchSpacingPx(double density, int nFamilies, const styles::HatchStyle &style);

/// The darkest ink coverage the style can lay down: two crossing families at
/// minSpacingPx, 1 − (1 − min(1, w / minSpacingPx))². The tone curve maps the
/// darkest tone here (renderIllustration), so every target density is one the
/// hatching can actually reach instead of a darkness it can only fall short of.
double maxHatchDensity(const styles::HatchStyle &style);

/// Width (in target density) of the band above crossDensity over which the second
/// family fades in: its share of the ink grows from nothing at crossDensity to an
/// even split at crossDensity + kCrossFeatherBand (Hertzmann & Zorin 2000 add the
/// cross family gradually; a hard switch draws a visible edge where it starts).
inline constexpr double kCrossFeatherBand = 0.15;

/// Ink coverage of each family at `density`, {family 0, family 1}. Below
/// crossDensity family 0 alone covers the density; above it family 1's coverage is
/// smoothstep((ρ − c) / kCrossFeatherBand) · (1 − √(1 − ρ)) and family 0 covers the
/// rest, so that 1 − (1 − a)(1 − b) = ρ everywhere and both are continuous in ρ.
/// Zero where hatchFamilies() is 0.
/// `crossWeight` in [0, 1] scales family 1's share (crossWeight()); 0 gives all the
/// ink to family 0 at single-family spacing.
std::array<double, 2> familyCoverage(double density, const styles::HatchStyle &style, double crossWeight = 1.0);

/// Screen angle (degrees) between the two field directions below which they no
/// longer read as crossing lines (the same-direction test treats lines within 55° as
/// one family), and the band above it over which crossWeight() rises from 0 to 1.
/// Toward a silhouette foreshortening folds both members of a cross field onto the
/// silhouette's direction, so the second family cannot be drawn there; the first
/// then carries the whole tone at single-family spacing.
inline constexpr double kCrossCollapseDeg = 55.0;
inline constexpr double kCrossCollapseBandDeg = 20.0;

/// How far the second family can be drawn at `pixel` of `field`: smoothstep of the
/// cosine between dir0 and dir1 from cos kCrossCollapseDeg (0) to
/// cos(kCrossCollapseDeg + kCrossCollapseBandDeg) (1).
double crossWeight(const ScreenField &field, size_t pixel);

/// d_sep (px) of family `family` (0 or 1) at `density`: strokeWidthPx over its
/// familyCoverage() (times the style's spacingGain, 1 outside print mode's ink
/// calibration), clamped to [minSpacingPx, maxSpacingPx]. Both the tracer and
/// measureHatches() use it.
double familySpacingPx(double density, int family, const styles::HatchStyle &style, double crossWeight = 1.0);

/// d_sep of the first family at `density` (familySpacingPx of family 0), the
/// densest hatching there: the radius of the keep-away disc around singularities.
double localSpacingPx(double density, const styles::HatchStyle &style);

/// The hatch ink length (px) the tone asks for: over the valid pixels, the sum of
/// 1 / familySpacingPx of each family that hatches there (lines per px across, per
/// px² of picture). Deterministic for any thread count. `atMinSpacingPx`, if given,
/// receives the part of it asked at or below minSpacingPx (held there by the clamp:
/// the pen's densest spacing, which no calibration goes below).
double toneInkPx(const ScreenField &field, const std::vector<float> &targetDensity, const styles::HatchStyle &style,
                 double *atMinSpacingPx = nullptr);

/// Total polyline length (px) of the Hatch strokes of `strokes`.
double hatchInkPx(const StrokeList &strokes);

/// Width profile (taper, pressure) and optional wobble of one hatch stroke, as
/// traceHatches() finishes its own; randomness from (seed, stroke.id) only. `blunt`
/// bit 0 / bit 1: the start / end stopped at a singularity's keep-away disc and
/// keeps its full width there (0: both ends taper).
void finishStroke(Stroke &stroke, const styles::HatchStyle &style, uint32_t seed, uint8_t blunt = 0);

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
/// \param whileTracing optional; called once the per-pixel maps are built (their loops
///   take every core) and before the sequential tracing starts, from the calling
///   thread: the place to start other work (a task) that should run beside the tracer.
/// Strokes also stop at the edge of their tone band, where the line turns by more
/// than 12° in one step, when they would come within d_test of a same-direction line,
/// and at the disc of radius d_sep (at the darkest tone within it) around each
/// visible singularity. Strokes shorter than minLengthPx or than kStubLengthRatio
/// times their mean d_sep are dropped; the hole pass (dark tone: cross tone, or tone
/// past crossDensity whose screen directions folded together) keeps strokes from 2
/// d_sep and holds minLengthPx only up to kStubLengthRatio d_sep. Tapers are at most
/// three line widths long; an end that stops at a singularity's disc keeps its full
/// width. Tracing is sequential (Jobard–Lefer is order dependent); the output is
/// identical for any thread count. Stroke ids follow
/// creation order: the first family's pass, the second's, then the hole pass.
/// Empty image or no valid pixel: an empty list.
StrokeList traceHatches(const ScreenField &field, const std::vector<float> &targetDensity,
                        const GBuffer &gbuffer, const styles::HatchStyle &style, uint32_t seed,
                        HatchReport *report = nullptr, const std::function<void()> &whileTracing = {});

/// Measures a hatch stroke list independently of the tracer's bookkeeping: total ink
/// length, same-family spacing violations (every stroke vertex against the segments
/// of other strokes of the same family within 45° of its direction, closer than
/// (1 − tolerance) d_test at that vertex; `tolerance` absorbs the chord error of
/// polylines sampled at 0.2 d_sep), strokes whose segments enter a disc of radius
/// (1 − tolerance) d_sep around a visible singularity of `field`, stubs, and the
/// second family's ink laid closer than its own d_test (crossOverdenseFraction),
/// squeezed runs (squeezedFraction) and incoherent directions (incoherentFraction). d_sep
/// here is the first family's (localSpacingPx with crossWeight), the densest
/// spacing the tone asks for, whichever layer a stroke ended up in.
/// Only strokes of kind Hatch are looked at.
HatchReport measureHatches(const StrokeList &strokes, const ScreenField &field,
                           const std::vector<float> &targetDensity,
                           const styles::HatchStyle &style, double tolerance = 0.05);

/// The per-stroke figures of measureHatches() alone, the same values: stroke counts by
/// family, ink length, stubs, strokes near singularities and singularity holes; the pairwise measures
/// (spacing violations, overdense, squeezed and incoherent fractions) stay 0. What
/// `compare` prints per panel, at a fraction of measureHatches()'s time.
HatchReport countHatches(const StrokeList &strokes, const ScreenField &field,
                         const std::vector<float> &targetDensity,
                         const styles::HatchStyle &style, double tolerance = 0.05);

} // namespace rosy::renderer
