#pragma once
/// \file print_units.h
/// Print mode: a scene drawn for paper. Its lengths are millimetres on the page
/// (styles::PrintLengths: the page keys in mm, or the style's *_px lengths times
/// page.px_mm), and the hatching is traced at a resolution that serves them, so
/// the same scene on A4 or A3, or at any camera resolution, has the same line
/// density on paper and every path the pen's width. `rosyhatch render` turns it
/// on for an SVG output or --paper (README, "SVG for print and pen plotters").

#include "renderer/output/plotter.h"
#include "scenes/scene.h"
#include "styles/style.h"

#include <array>
#include <string>
#include <vector>

namespace rosy::scenes {

/// Largest side, in px, print mode traces at when it chooses the resolution:
/// kMaxPrintSide, and at most kPrintBudget times the scene's own longer side.
inline constexpr int kMaxPrintSide = 8192;
inline constexpr int kPrintBudget = 4;

/// What applyPrintUnits() chose.
struct PrintSetup {
    styles::PrintLengths lengths;     ///< the lengths on paper asked for
    std::array<int, 2> resolution{};  ///< the traced resolution (camera.resolution after the call)
    bool resolutionChosen = false;    ///< chosen for page.px_mm (true) or the scene's kept (false)
    double mmPerPx = 0;               ///< of the traced picture on the page
    /// Plotter tolerances (merge, simplify, overlap) for this picture: the defaults
    /// are style pixels, page.px_mm on paper, so they keep their size in mm.
    renderer::PlotterOptions plotter;
    /// Things a plotter cannot draw as asked, and resolution limits, one sentence each.
    std::vector<std::string> warnings;
};

/// Rewrites `desc` for print: when `keepResolution` is false (no raster output)
/// camera.resolution becomes the one whose pixels are page.px_mm on the page
/// (aspect kept, at most kMaxPrintSide and kPrintBudget × its own longer side); then the style's hatch and contour
/// lengths become the printLengths() in px of that picture (styles::printStyle()).
/// renderScene() does not call it for a field picture (picture.kind: field). Deterministic.
/// \throws InputError when the page leaves no room for the picture.
PrintSetup applyPrintUnits(SceneDesc &desc, bool keepResolution);

} // namespace rosy::scenes
