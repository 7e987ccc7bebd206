#pragma once
/// \file raster.h
/// From the stroke list to pixels: anti-aliased stroke coverage kept in separate
/// layers (hatch families, contours, hidden contours), their compositing over
/// paper in linear light, and the multi-channel EXR that `rosyhatch inspect`
/// measures.
///
/// Coverage model. Every polyline segment is a capsule whose width is
/// interpolated linearly between its end points' widths. A pixel's coverage by
/// one segment is the box-filtered band profile evaluated at the exact distance d
/// from the pixel centre to the segment:
///     c = clamp(min(w, w/2 + 0.5 - d), 0, 1),
/// which integrates to exactly w across a straight band for any sub-pixel offset
/// (thin lines get a plateau of height w instead of a brighter but narrower
/// peak). Caps and joins are round because every segment is a capsule. Within one
/// stroke the segments combine by max, so a polyline's joins are not inked twice;
/// across strokes coverage combines with "over": 1 − Π(1 − c_i).

#include "renderer/output/image.h"
#include "renderer/output/strokes.h"
#include "styles/style.h"

#include <cmath>
#include <string>
#include <vector>

namespace rosy::renderer {

/// Per-layer ink coverage in [0, 1], each width × height, row-major, rows top to
/// bottom (index y * width + x), pixel centres at (x + 0.5, y + 0.5) in the
/// stroke list's raster coordinates.
struct InkLayers {
    int width = 0, height = 0;
    std::vector<float> hatch0;        ///< Hatch strokes of family 0 (and any family other than 1)
    std::vector<float> hatch1;        ///< Hatch strokes of family 1 (the cross-hatching family)
    std::vector<float> contour;       ///< visible contours
    std::vector<float> hiddenContour; ///< hidden contours, already dashed (see RasterOptions)
};

struct RasterOptions {
    /// Side of the square tiles the image is split into; each tile is rasterized
    /// independently. Does not change any pixel.
    int tileSize = 32;
    /// Hidden contours are dashed along their arc length: `dashOnPx` inked, then
    /// `dashOffPx` of paper, starting inked at each stroke's first point. Dash
    /// ends are anti-aliased over one pixel. dashOffPx <= 0 draws them solid.
    double dashOnPx = 4.0;
    double dashOffPx = 3.0;
    /// How strokes of one layer combine. Over (the default): 1 − Π(1 − c_i), ink
    /// builds up where strokes cross, as pen on paper. Max: the largest c_i, a flat
    /// colour where strokes overlap, as one layer of a diagram (field pictures).
    enum class Combine { Over, Max } combine = Combine::Over;
};

/// Rasterizes `strokes` at the stroke list's own resolution
/// (strokes.width × strokes.height; an empty image if either is < 1).
/// Strokes with fewer than 2 points, and segments with a non-finite end point or
/// width, are skipped; negative widths count as 0. Parts outside the image are
/// clipped. Work is split into tiles that gather their segments in stroke order,
/// so the result is bit-identical for any thread count.
/// \pre every stroke has widths.size() == points.size() (checked: a producer bug).
InkLayers rasterizeStrokes(const StrokeList &strokes, const RasterOptions &options = {});

/// Zeroed layers of width × height (none if either is < 1): what rasterizeStrokes()
/// draws into. Made ahead of the strokes, they keep faulting in 16 MiB of fresh
/// memory out of the raster stage (renderer/illustration.cpp makes them beside the
/// hatching's sequential tracer).
InkLayers blankInkLayers(int width, int height);

/// rasterizeStrokes() into `blank`, which must be blankInkLayers(strokes.width,
/// strokes.height) (checked: a caller bug). The same layers, bit for bit.
InkLayers rasterizeStrokes(const StrokeList &strokes, InkLayers blank, const RasterOptions &options = {});

/// How the layers become one picture.
struct CompositeOptions {
    /// Opacity applied to the hidden-contour layer, so occluded lines read as
    /// fainter than visible ones.
    double hiddenOpacity = 0.4;
    /// Feature size of the paper grain in pixels (the lattice spacing of the
    /// value noise); only used when style.paperGrain > 0.
    double grainScalePx = 3.0;
};

/// Combined ink coverage per pixel: the "over" of all layers,
/// 1 − (1 − hatch0)(1 − hatch1)(1 − contour)(1 − hiddenOpacity · hiddenContour).
/// Empty layers count as 0. Size width × height.
std::vector<float> combinedCoverage(const InkLayers &layers, const CompositeOptions &options = {});

/// Paper colour per pixel in linear RGB, interleaved (3 floats per pixel):
/// style.paper × (1 − style.paperGrain · n(x, y)) with n in [0, 1] a smooth value
/// noise seeded from style.seed alone, so the same style gives the same paper at
/// any thread count. paperGrain is clamped to [0, 1].
std::vector<float> paperColors(int width, int height, const styles::Style &style,
                               const CompositeOptions &options = {});

/// Final picture: paper × (1 − c) + ink × c per channel in linear light, with c
/// the combined coverage. Channels R, G, B (linear) and A = 1; writeImage()
/// encodes it to 8- or 16-bit sRGB. Empty layers give plain paper.
Image compositeInk(const InkLayers &layers, const styles::Style &style,
                   const CompositeOptions &options = {});

/// The paper of compositeInk() without ink: R, G, B = paperColors(), A = 1. It needs
/// no strokes, so it can be made while they are traced (renderer/illustration.cpp).
Image paperImage(int width, int height, const styles::Style &style, const CompositeOptions &options = {});

/// compositeInk() over `paper`, which must be paperImage() of the layers' size with
/// the same style and options (size checked: a caller bug). The same picture, bit for bit.
Image compositeInk(const InkLayers &layers, const styles::Style &style, Image paper,
                   const CompositeOptions &options = {});

/// Paints one colour over an RGB or RGBA image (linear light) with per-pixel
/// coverage: each pixel's R, G, B become rgb × (1 − a) + colour × a with
/// a = opacity × coverage (coverage clamped to [0, 1], non-finite as 0); alpha is
/// kept. The compositing of compositeInk() for one ink over any background, e.g.
/// coloured layers drawn one after the other (field pictures, field_picture.h).
/// \pre coverage.size() == image width × height (checked: a caller bug).
void paintOver(Image &image, const std::vector<float> &coverage, const styles::Rgb &colour, double opacity = 1.0);

/// Per-pixel surface data the EXR carries beside the ink, each width × height
/// (row-major, top row first) or empty (written as zeros).
struct SurfaceChannels {
    std::vector<float> targetDensity; ///< target ink density in [0, 1] from the tone
    std::vector<float> depth;         ///< camera-space depth (Z), any unit; 0 off the object
    std::vector<float> normalX, normalY, normalZ; ///< unit shading normal (world frame)
    /// Screen angle in radians of each hatch family's line direction, measured in
    /// raster coordinates (x right, y down) as atan2(dy, dx); defined modulo π.
    std::vector<float> angle0, angle1;
    std::vector<float> mask; ///< 1 on the object, 0 elsewhere
};

/// Name of the EXR header attribute (float) holding the nominal hatch spacing in
/// pixels; `rosyhatch inspect` blurs and smooths at this scale.
inline constexpr const char *kHatchSpacingAttribute = "rosy:hatch_spacing_px";
/// Name of the EXR header attribute (float) holding the style's cross density
/// (hatch.cross_density): `rosyhatch inspect` measures seams where the target asks
/// for cross-hatching.
inline constexpr const char *kCrossDensityAttribute = "rosy:cross_density";

/// The channel names of inkExrImage(), in order: R G B A tone.target
/// ink.coverage ink.hatch0 ink.hatch1 ink.contour depth N.x N.y N.z
/// field.angle0 field.angle1 mask.
const std::vector<std::string> &inkExrChannelNames();

/// Builds the multi-channel EXR image: R G B A copied from `composite` (which
/// must be RGB or RGBA of the layers' size; A = 1 if absent), ink coverage
/// layers, and the surface channels. Non-finite values become 0; the field
/// angles are also 0 where mask == 0, so only `mask` says where they mean
/// something.
/// \throws CheckFailure if a non-empty input has the wrong size (a caller bug).
Image inkExrImage(const InkLayers &layers, const Image &composite, const SurfaceChannels &surface,
                  const CompositeOptions &options = {});

/// Write options for the EXR of inkExrImage(): 32-bit floats, the nominal
/// hatch spacing (pixels) in the header as kHatchSpacingAttribute and, when
/// finite, the style's cross density as kCrossDensityAttribute.
ImageWriteOptions inkExrWriteOptions(double hatchSpacingPx, double crossDensity = std::nan(""));

} // namespace rosy::renderer
