#pragma once
/// \file svg.h
/// Layered SVG for print and pen plotters, written from the same stroke list
/// the raster image is drawn from. The picture (the render's raster rectangle)
/// is fitted into the page inside a margin and centred, aspect preserved.
/// The document is in millimetres: width/height in mm and a viewBox of the
/// same numbers, so one user unit is 1 mm and y points down, as in the raster.
/// Layers are Inkscape layers labelled with their number first, as vpype and
/// AxiDraw read them (kSvgLayerLabels): "1 hatch", "2 cross-hatch", "3 contours",
/// and "4 hidden contours" (dashed) when the list holds any.
/// Page size, margin, orientation and pen width come from the style's `page`
/// (styles::PageStyle, svgOptionsFor()); the CLI may override them.

#include "renderer/output/plotter.h"
#include "renderer/output/strokes.h"
#include "core/error.h"
#include "styles/style.h"

#include <array>
#include <optional>
#include <string>
#include <utility>

namespace rosy::renderer {

/// Inkscape labels of the layers, in document order: hatch family 0, family 1,
/// contours, hidden contours. Each label's only digits are its leading layer
/// number (ids layer1..layer4), so vpype (first digits of the label) and AxiDraw
/// (leading number) give each layer its own pen.
inline constexpr const char *kSvgLayerLabels[4] = {"1 hatch", "2 cross-hatch", "3 contours", "4 hidden contours"};

struct SvgOptions {
    double pageWidthMm = 210;  ///< A4 portrait by default
    double pageHeightMm = 297;
    double marginMm = 10;      ///< on every side; the picture is fitted inside
    /// Auto turns the page when that shows the picture larger; Portrait/Landscape force it.
    styles::PageStyle::Orientation orientation = styles::PageStyle::Orientation::Auto;
    double penWidthMm = 0;     ///< > 0: every path this wide; 0: the stroke's mean width scaled to the page
    bool plotterPass = true;   ///< merge, simplify and order strokes (plotter.h)
    PlotterOptions plotter;    ///< tolerances in raster px
    bool hiddenContours = true; ///< write the dashed layer when hidden contours exist
    /// The layers' Inkscape labels (kSvgLayerLabels by default). Diagnostic pictures
    /// name what their layers hold ("1 streamlines", "1 edges", ...); keep each
    /// label's layer number first and its only digits, for vpype and AxiDraw.
    std::array<const char *, 4> layerLabels{kSvgLayerLabels[0], kSvgLayerLabels[1], kSvgLayerLabels[2],
                                            kSvgLayerLabels[3]};
};

/// Measurements of the written document, in page millimetres.
struct SvgReport {
    /// Pen-up travel: from the page origin (0, 0 mm, the plotter's home) to each
    /// layer's first path and between its paths, summed over the layers; the
    /// return home is not counted. The one pen-up figure (--report, benchmarks).
    double penUpMm = 0;
    double penUpUnsortedMm = 0;  ///< the same for the input order
    double penDownMm = 0;        ///< drawn length
    double penUpRatioVsUnsorted = 1; ///< penUpMm / penUpUnsortedMm (1 when the input has no travel)
    int paths = 0;               ///< <path> elements written (after merging and splitting)
    double mmPerPx = 0;          ///< scale of the raster-to-page mapping
    double pageWidthMm = 0, pageHeightMm = 0; ///< the page written (after orientation)
    double overlapRemovedMm = 0; ///< collinear-overlapping ink the plotter pass dropped
};

/// Each side of a page must be in [kMinPaperSideMm, kMaxPaperSideMm] (1 mm to 100 m,
/// a long plotter roll): beyond that the numbers written to the SVG lose their
/// meaning (a 1e308 mm page once overflowed the number formatting).
inline constexpr double kMinPaperSideMm = 1.0;
inline constexpr double kMaxPaperSideMm = 100000.0;

/// Page size (width, height) in mm for "a4", "a3", "letter" (case-insensitive,
/// portrait), or "WxH" in mm such as "300x200". std::nullopt for anything else,
/// including sides outside [kMinPaperSideMm, kMaxPaperSideMm].
std::optional<std::pair<double, double>> parsePaperSize(const std::string &name);

/// parsePaperSize() for user input: \throws InputError at `where` ("--paper", a scene
/// value) saying whether the name is unknown or a side is out of range.
std::pair<double, double> paperSize(const std::string &name, const FileLoc &where);

/// SVG options for a style's page; plotter settings at their defaults.
SvgOptions svgOptionsFor(const styles::PageStyle &page);

/// The page (width, height) in mm that `orientation` gives for a picture of
/// pictureW×pictureH px: Portrait puts the shorter side across, Landscape the
/// longer; Auto keeps the size as written unless turning it fits the picture
/// (inside `marginMm`) strictly larger.
std::pair<double, double> orientedPage(double widthMm, double heightMm, styles::PageStyle::Orientation orientation,
                                       double marginMm, int pictureW, int pictureH);

/// Millimetres on the page per raster px when a w×h px picture is fitted into
/// the page of `options` (after orientation, inside the margin): the mapping
/// svgDocument() uses. \throws InputError like svgDocument() for a page without room.
double pictureMmPerPx(const SvgOptions &options, int w, int h);

/// The resolution (width, height) whose pixels are `pxMm` mm on the page for a
/// picture of aspect w:h fitted into the page of `options`; each side at least
/// 16 px and at most `maxSide` (the aspect kept; *capped set when it had to be).
std::pair<int, int> printResolution(const SvgOptions &options, int w, int h, double pxMm, int maxSide,
                                    bool *capped = nullptr);

/// The SVG document as text. Deterministic (fixed 3-decimal numbers, no
/// timestamps), identical for any thread count. Non-finite points are dropped;
/// an empty list gives a valid document with empty layers. Throws InputError if
/// the picture does not fit (margins leave no room) or the list has no size.
std::string svgDocument(const StrokeList &strokes, const SvgOptions &options, SvgReport *report = nullptr);

/// Writes svgDocument() to `path` atomically (core/atomic_file.h); IoError on failure.
void writeSvg(const StrokeList &strokes, const SvgOptions &options, const std::string &path,
              SvgReport *report = nullptr);

} // namespace rosy::renderer
