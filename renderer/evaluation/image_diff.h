#pragma once
/// \file image_diff.h
/// Comparison of two renderings for regression tests (`rosyhatch diff`, the
/// golden suite in tests/golden/).
///
/// Line art defeats a plain per-pixel difference: a hatch moved by one pixel
/// fails every pixel it covers although nobody could tell the pictures apart.
/// So both pictures are first turned into what the eye reads from a drawing,
/// ink coverage (1 − luminance relative to the paper, in linear light), blurred
/// with a Gaussian at about half the hatch spacing, which turns a field of
/// hatches into its tone. The per-pixel error then tolerates a displacement of
/// `shiftPx`: a pixel of A is compared with the range of B's values in the
/// (2·shift + 1)² window around it, and the other way round, so an image moved
/// by up to one pixel compares as equal while a change of tone over a region
/// (a moved light, another style, another field symmetry) does not.
///
/// Verdicts follow OpenImageIO's idiff / ImageBufAlgo::compare: a pixel fails
/// when its error exceeds `fail`; a channel fails when more than `failPercent`
/// percent of its pixels fail or any one pixel exceeds `hardFail`; it warns when
/// more than `warnPercent` percent exceed `warn`.
///
/// Default thresholds (errors are coverage in [0, 1], after blur and shift):
///  - fail 0.02: two renders of the same drawing differ by a few strokes at most,
///    which blurred at the hatch spacing moves the local tone by well under 0.02;
///    the smallest changes that matter (light moved by 10°, another style, N = 2
///    instead of 4) move it by 0.05–0.3 over whole regions;
///  - failPercent 0.1: 65 pixels of a 256² image, room for a handful of strokes
///    that ended differently, never for a region;
///  - hardFail 0.1: no pixel may differ by a tenth of full ink, whatever the count.
/// (Measured figures are in tests/README.md, section "Image regression".)

#include "renderer/output/image.h"

#include <string>
#include <vector>

namespace rosy::renderer {

/// Outcome of a comparison, ordered by severity; the values are idiff's exit codes.
enum class DiffVerdict { Pass = 0, Warn = 1, Fail = 2 };

/// "PASS", "WARNING" or "FAILURE" (idiff's words).
const char *toString(DiffVerdict verdict);

struct DiffOptions {
    double fail = 0.02;       ///< per-pixel error above which a pixel fails
    double failPercent = 0.1; ///< percent of pixels allowed to fail
    double hardFail = 0.1;    ///< any single pixel above this fails the channel
    double warn = 0.01;       ///< per-pixel error above which a pixel warns
    double warnPercent = 0.1; ///< percent of pixels allowed to warn
    /// Gaussian σ of the blur in pixels; 0 = automatic: half the hatch spacing
    /// stored in A's EXR header (kHatchSpacingAttribute), else kDefaultBlurPx.
    double blurPx = 0.0;
    /// Displacement (pixels, rounded) tolerated between the two pictures; 0 compares
    /// pixel by pixel.
    double shiftPx = 1.0;
    /// With two multi-channel EXRs of rosyhatch, also compare the named channels
    /// (tone.target, ink.*, depth, normal, field angles, mask).
    bool exrChannels = true;
};

/// Blur σ (pixels) when neither the options nor the file give one: half the
/// mid-tone spacing of the fine-pen preset (about 5 px).
inline constexpr double kDefaultBlurPx = 2.5;

/// Statistics of one compared channel. Errors are in [0, 1] for every channel
/// (see compareImages for each channel's scale).
struct ChannelDiff {
    std::string name;
    double maxError = 0.0;
    int maxX = -1, maxY = -1; ///< where maxError is (raster, top row 0); -1 if nothing differs
    double meanError = 0.0;
    long long nFail = 0, nWarn = 0;
    double failPercent = 0.0; ///< 100 · nFail / pixels
    DiffVerdict verdict = DiffVerdict::Pass;
};

struct DiffResult {
    int width = 0, height = 0;
    double blurPx = 0.0, shiftPx = 0.0; ///< the values used
    std::vector<ChannelDiff> channels;  ///< "coverage" and "paper" first, then EXR channels
    DiffVerdict verdict = DiffVerdict::Pass; ///< the worst channel's
    /// Set when the images cannot be compared at all (different sizes): verdict Fail, no channels.
    std::string mismatch;
    /// Amplified difference of the coverage channel, RGB linear, width × height:
    /// A's drawing faint grey on white, red where B has more ink, blue where it has
    /// less, full colour at 2 × fail and above. Empty when sizes differ.
    Image diffImage;
};

/// An image read for comparison: linear-light floats with the file's channel
/// names, and the hatch spacing attribute of rosyhatch EXRs (0 if absent).
struct DiffInput {
    Image image;
    double hatchSpacingPx = 0.0;
};

/// Reads any image OpenImageIO can read. 8- and 16-bit files (sRGB unless their
/// header says linear) are decoded to linear light; alpha stays as stored. Float
/// files with premultiplied alpha (OpenEXR's convention, rosyhatch's ink matte)
/// get R, G, B over white paper: colour + (1 − alpha).
/// \throws IoError if the file does not exist or cannot be read.
/// \throws InputError naming the path if it is not an image or not 2D.
DiffInput readDiffInput(const std::string &path);

/// Compares B (the new picture) against A (the reference).
/// Channels:
///  - coverage: ink coverage 1 − L/L_paper from the linear luminance L of R, G, B
///    (or the single channel), L_paper the 99.5th percentile of L (the paper,
///    with its grain); clamped to [0, 1];
///  - paper: max over R, G, B of the difference of the paper colours (mean of the
///    pixels at or above the percentile); one value, fails as a whole;
///  - with options.exrChannels and both images carrying them: tone.target,
///    ink.coverage, ink.hatch0, ink.hatch1, ink.contour, ink.hidden (values as
///    stored), Z (or `depth` of older files; +inf read as 0, divided by the larger
///    maximum depth of the two), normal (|ΔN| / 2 over N.x N.y N.z),
///    field.cos/sin (|Δ(field.cos, field.sin)| / 2), field.angle0/1
///    (|Δ(cos 2θ, sin 2θ)| / 2 of the mask-weighted doubled angle, so lines are
///    compared modulo π), mask.
/// Every channel is blurred and shift-tolerated the same way.
/// \param hatchSpacingPx used for the automatic blur (0: kDefaultBlurPx).
/// \throws InputError for a non-finite or negative option, or an image without pixels.
DiffResult compareImages(const Image &a, const Image &b, const DiffOptions &options = {},
                         double hatchSpacingPx = 0.0);

/// readDiffInput on both paths, then compareImages with A's hatch spacing.
DiffResult compareImageFiles(const std::string &pathA, const std::string &pathB,
                             const DiffOptions &options = {});

/// idiff-style text report: one line per channel (max with its pixel, mean,
/// failing pixels and percent) and the verdict word on the last line.
std::string diffReportText(const DiffResult &result, const DiffOptions &options);

/// Gaussian blur (σ in pixels, kernel cut at 3σ, edges clamped) of a
/// width × height single-channel image, row-major. σ <= 0 returns the input.
std::vector<float> gaussianBlur(const std::vector<float> &values, int width, int height, double sigmaPx);

} // namespace rosy::renderer
