#pragma once
/// \file plotter.h
/// The plotter pass: turns a layer of strokes into fewer, longer, simpler
/// paths drawn in an order that keeps the pen-up travel short. It runs on the
/// stroke list before vector output (svg.h), in raster px, one layer at a time
/// (a pen plotter draws a layer with one pen, so strokes are never reordered
/// across layers). Deterministic: the result depends only on the input strokes
/// and options, never on thread count.

#include "renderer/output/strokes.h"

#include <vector>

namespace rosy::renderer {

/// Tolerances and effort limits of the plotter pass. Lengths in raster px.
struct PlotterOptions {
    /// Where the pen starts each layer, in raster px: the page origin (svgDocument
    /// sets it), so the order and the pen-up figure both count the travel from home.
    Eigen::Vector2d homePx = Eigen::Vector2d::Zero();
    double mergeTolerancePx = 0.5;     ///< strokes whose ends are this close are joined (0 disables)
    double simplifyTolerancePx = 0.25; ///< Ramer–Douglas–Peucker tolerance (0 keeps every point)
    double overlapTolerancePx = 0.1;   ///< ink within this of earlier ink, near-parallel, is dropped (0 disables)
    double overlapMinGapPx = 1.0;      ///< an overlap inside a stroke shorter than this is kept (a pen lift costs more)
    bool sort = true;                  ///< greedy nearest-neighbour order, then 2-opt and Or-opt
    int neighbours = 8;                ///< candidate partners per endpoint for 2-opt / Or-opt (nearest endpoints)
    int twoOptMaxPasses = 50;          ///< looks per stroke, at most (0: greedy only); stops when no move is left
    bool orOpt = true;                 ///< also move single strokes (either way round) next to a nearer endpoint
    int exhaustiveTwoOptMax = 3000;    ///< layers of at most this many strokes also try exhaustive 2-opt (O(n²) per sweep)
    int largeLayer = 20000;            ///< above this many strokes: lighter search (lists only, single-stroke Or-opt, one round)
    int maxRun = 10000;                ///< a move shifts or reverses at most this many strokes of the order
    int movesPerStroke = 200;          ///< work bound: entries shifted by reversals and moves, per stroke (min 100k total)
};

/// What the pass measured, summed over the layers it was given. Lengths in raster px.
/// Every layer's travel starts at PlotterOptions::homePx, the plotter's home.
struct PlotterReport {
    double penUpPx = 0;         ///< travel between strokes in the optimised order
    double penUpUnsortedPx = 0; ///< travel of the input strokes in their given order and direction
    double penDownPx = 0;       ///< drawn length after the pass
    double penDownInputPx = 0;  ///< drawn length of the input
    double overlapRemovedPx = 0; ///< length dropped as collinear overlap (removeOverlaps)
    int paths = 0;              ///< strokes after merging
};

/// Drops consecutive duplicate points (closer than 1e-9 px) and non-finite
/// points. A stroke that collapses to one point keeps it twice (a dot).
/// Returns false if no finite point is left.
bool removeDuplicatePoints(Stroke &stroke);

/// Ramer–Douglas–Peucker simplification of one stroke: keeps both endpoints and
/// every point further than `tolerancePx` from the chord of its span. Kept
/// points keep their own widths (they are input points), so the width profile
/// is the input's sampled at the kept points.
void simplifyStroke(Stroke &stroke, double tolerancePx);

/// Drops duplicate and collinear-overlapping ink. Strokes are taken in order and
/// segment by segment; the part of a segment that lies within `tolerancePx` of ink
/// already kept (earlier strokes, or earlier segments of the same stroke: a
/// retrace) by a segment at most kMaxOverlapAngleDeg from parallel (either
/// direction) is removed. Crossings are never cut (the angle bound), and a stroke
/// continuing straight on never overlaps its own previous segment. Removing a
/// covered run inside a stroke splits it; runs shorter than `minGapPx` inside a
/// stroke are kept, so one stroke does not become two for a sliver. Pieces
/// shorter than `tolerancePx` are dropped; zero-length strokes (dots) pass
/// through. Widths at cut points are interpolated. Deterministic, single-threaded.
/// Adds the removed length to *removedPx when given.
std::vector<Stroke> removeOverlaps(std::vector<Stroke> strokes, double tolerancePx, double minGapPx = 1.0,
                                   double *removedPx = nullptr);

/// Largest angle between two segments whose overlap counts as collinear.
constexpr double kMaxOverlapAngleDeg = 10.0;

/// Joins strokes whose ends meet within `tolerancePx`, reversing strokes as
/// needed. Chains grow greedily from the lowest-index stroke, always taking the
/// nearest free end (lowest index on ties). A joined point present at both ends
/// is kept once. The merged stroke takes the kind, family and id of its first stroke.
std::vector<Stroke> mergeStrokes(std::vector<Stroke> strokes, double tolerancePx);

/// Orders (and reverses) strokes to shorten pen-up travel starting from
/// options.homePx: greedy nearest end through a uniform grid, then local search over
/// the nearest endpoints of each end: 2-opt, in which reversing a run of strokes
/// (any length) also reverses each stroke in it, and Or-opt, moving one stroke
/// either way round. Layers of at most exhaustiveTwoOptMax strokes also run
/// exhaustive first-improvement 2-opt from the greedy tour (then the same local
/// search) and keep the shorter tour. Each applied move shortens the travel;
/// work is bounded (twoOptMaxPasses, movesPerStroke). Deterministic.
std::vector<Stroke> sortStrokes(std::vector<Stroke> strokes, const PlotterOptions &options);

/// Pen-up travel of strokes drawn in the given order and direction, from
/// `homePx` (where the pen starts) to the first stroke and between strokes; the
/// return home is not counted.
double penUpLength(const std::vector<Stroke> &strokes, const Eigen::Vector2d &homePx = Eigen::Vector2d::Zero());

/// Sum of polyline lengths.
double penDownLength(const std::vector<Stroke> &strokes);

/// The whole pass on one layer: dedupe, drop overlaps, merge, simplify, sort. Adds the
/// layer's measurements to *report when it is not null. Empty input gives empty output.
std::vector<Stroke> optimizeForPlotter(std::vector<Stroke> strokes, const PlotterOptions &options,
                                       PlotterReport *report = nullptr);

} // namespace rosy::renderer
