#pragma once
/// \file strokes.h
/// The stroke list: the one resolution-independent description of a drawing.
/// The rasterizer (raster.h) draws it into images; the SVG writer (svg.h, after
/// the plotter pass of plotter.h) writes the same list as paths. Coordinates are raster pixels of the
/// render resolution (x right, y down, pixel centres at +0.5); a consumer at
/// another resolution or in millimetres scales them uniformly.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace rosy::renderer {

enum class StrokeKind : uint8_t {
    Hatch,         ///< follows the field; `family` 0 or 1
    Contour,       ///< visible silhouette, crease or border
    HiddenContour, ///< occluded contour, drawn only on request
};

struct Stroke {
    std::vector<Eigen::Vector2d> points; ///< polyline, raster px, at least 2 points
    std::vector<float> widths;           ///< per point full width in px (same size as points)
    StrokeKind kind = StrokeKind::Hatch;
    int family = -1; ///< hatch family (0: along the field's first direction, 1: across); -1 otherwise
    /// Stable id, used to seed per-stroke randomness (jitter, pressure) so output
    /// does not depend on thread count or stroke order.
    uint32_t id = 0;
};

struct StrokeList {
    int width = 0, height = 0; ///< render resolution the coordinates refer to
    std::vector<Stroke> strokes;
};

} // namespace rosy::renderer
