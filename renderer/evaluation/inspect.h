#pragma once
/// \file inspect.h
/// Quality measures of a rendering, computed from the channels of its EXR alone
/// (see raster.h, inkExrImage()), so a picture can be judged without the scene:
///  - alignment: angle between the ink's local orientation (structure tensor of
///    each hatch layer) and the field's screen direction;
///  - tone: mean |target density − hatch coverage blurred at the hatch spacing|
///    (the Salisbury 1997 / Turk–Banks 1996 measure);
///  - spacing: coefficient of variation of the distance between neighbouring
///    hatch lines, measured across the lines in regions of even tone;
///  - ink outside the silhouette;
///  - seams: light cracks in cross-hatched regions (seam_fraction).

#include "renderer/output/image.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace rosy::renderer {

/// The channels inspect needs, each width × height, row-major, top row first.
/// Names in brackets are the EXR channels they come from.
struct InkMaps {
    int width = 0, height = 0;
    std::vector<float> hatch0, hatch1; ///< [ink.hatch0], [ink.hatch1] coverage in [0, 1]
    std::vector<float> coverage;       ///< [ink.coverage] all layers combined
    std::vector<float> target;         ///< [tone.target] target ink density
    /// [field.angle0], [field.angle1]: screen angle (radians, raster frame x right
    /// y down, atan2(dy, dx)) of each family's line direction, modulo π.
    std::vector<float> angle0, angle1;
    std::vector<float> mask; ///< [mask] 1 on the object
    /// Nominal hatch spacing in pixels from the header attribute
    /// "rosy:hatch_spacing_px"; 0 if the file has none (then it is estimated).
    double hatchSpacingPx = 0.0;
    /// The style's cross density from the header attribute "rosy:cross_density";
    /// NaN if the file has none (then seam_fraction uses InspectOptions::crossDensity).
    double crossDensity = std::numeric_limits<double>::quiet_NaN();
};

/// Reads the channels of InkMaps from a rosyhatch EXR.
/// \throws IoError if the file cannot be opened or read.
/// \throws InputError naming the path if it is not an image with every needed
///   channel (the message lists the missing ones).
InkMaps readInkMaps(const std::string &path);

struct InspectOptions {
    /// Coverage at or above which a pixel of a layer counts as ink.
    double inkThreshold = 0.5;
    /// Structure-tensor coherence ((λ1 − λ2)/(λ1 + λ2), in [0, 1]) a pixel needs
    /// before its orientation counts for alignment; crossings, line ends and
    /// isolated dots fall below it.
    double minCoherence = 0.6;
    /// Profiles for spacing_cv count only where the target density along them
    /// varies by at most this much ("even tone").
    double evenToneTolerance = 0.05;
    /// Spacing used when the file has no spacing attribute and none can be
    /// measured, in pixels.
    double fallbackSpacingPx = 8.0;
    /// Cross density used when the file does not store one (the default style's).
    double crossDensity = 0.45;
    /// seam_fraction: Gaussian σ (px) of the coverage blur, distance (px) a pixel
    /// keeps from the silhouette, share of the target below which blurred coverage
    /// counts as a gap, and the smallest 8-connected group of gap pixels counted.
    double seamBlurSigmaPx = 2.0;
    double seamEdgeDistancePx = 4.0;
    double seamCoverageRatio = 1.0 / 3.0;
    int seamMinGroupPx = 30;
    /// Keep the seam pixels (InspectResult::seamMask) for seamPicture().
    bool keepSeamMask = false;
};

/// The measures; NaN where nothing could be measured (e.g. no hatch ink).
struct InspectResult {
    /// Median and 90th percentile, in degrees in [0, 90], of the angle between the
    /// ink orientation at confident hatch ink pixels on the object and the closer
    /// of the two field angles (families may swap labels across the image).
    double alignmentMedianDeg = 0.0, alignmentP90Deg = 0.0;
    long long alignmentSamples = 0;
    /// Mean over object pixels (mask > 0.5) of |target − blurred hatch coverage|.
    /// Coverage is hatch0 over hatch1 (contours are outlines, not tone), blurred
    /// over the object only (normalized convolution) at about one hatch spacing.
    double toneMae = 0.0;
    long long tonePixels = 0;
    /// Pooled coefficient of variation of neighbouring-line distances: each
    /// distance divided by the mean of its own profile (so regions of different
    /// tone, hence spacing, do not count as spread), then RMS of (ratio − 1).
    double spacingCv = 0.0;
    long long spacingSamples = 0;
    /// Median measured distance between neighbouring lines of a family (pixels).
    double measuredSpacingPx = 0.0;
    /// Ink pixels (combined coverage >= inkThreshold) off the object that are
    /// more than one pixel away from it: pixels whose 3 × 3 neighbourhood holds a
    /// mask pixel are the anti-aliasing border of the silhouette and not counted.
    long long inkOutsideSilhouettePx = 0;
    /// Spacing the smoothing and blurring used (attribute, else measured, else fallback).
    double hatchSpacingPx = 0.0;
    /// Cracks in dark regions. Among the "cross pixels" (on the object, at least
    /// seamEdgeDistancePx from the silhouette, target >= cross density), the share
    /// whose combined ink coverage, blurred with a Gaussian of σ = seamBlurSigmaPx
    /// over the object only, is below seamCoverageRatio × target, counting only
    /// 8-connected groups of at least seamMinGroupPx such pixels. Even
    /// cross-hatching scores 0; NaN when there is no cross pixel.
    double seamFraction = 0.0;
    long long seamPixels = 0;  ///< gap pixels counted (in groups large enough)
    long long crossPixels = 0; ///< the denominator
    double crossDensity = 0.0; ///< the cross density used (file, else option)
    /// With InspectOptions::keepSeamMask: 1 at each counted seam pixel, row-major.
    std::vector<uint8_t> seamMask;
};

/// A picture for the eye: the combined ink in grey on white, the counted seam
/// pixels of `result` (inspected with keepSeamMask) in red. RGB, maps' size.
Image seamPicture(const InkMaps &maps, const InspectResult &result);

/// Computes every measure. Deterministic (no sampling); cost O(pixels).
/// \throws CheckFailure if a non-empty map has the wrong size (a caller bug);
///   empty maps count as zeros.
InspectResult inspectInk(const InkMaps &maps, const InspectOptions &options = {});

/// seam_fraction alone (seamFraction, seamPixels, crossPixels, crossDensity and,
/// with keepSeamMask, seamMask; the other measures NaN or 0): the same figures as
/// inspectInk() gives, reading only the coverage, target and mask channels. For
/// callers that need no more, such as compare's panels.
InspectResult inspectSeams(const InkMaps &maps, const InspectOptions &options = {});

/// The result as a JSON object with keys alignment_median_deg, alignment_p90_deg,
/// tone_mae, spacing_cv, ink_outside_silhouette_px, seam_fraction, then the sample counts and
/// spacings; unmeasurable values are null.
std::string inspectJson(const InspectResult &result);

} // namespace rosy::renderer
