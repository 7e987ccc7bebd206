#pragma once
/// \file style.h
/// The look of a rendering. For now only what the Lambert preview needs: the
/// colours of paper and ink and how dark the unlit side may get. The pen-and-ink
/// parameters (stroke widths, spacing, taper) join this struct later.

#include <array>
#include <cstdint>

namespace rosy::styles {

/// Linear-light RGB, each channel in [0, 1] (not sRGB-encoded).
using Rgb = std::array<double, 3>;

/// How hatches turn tone into ink. Densities are ink coverage in [0, 1]
/// (0 = white paper, 1 = solid ink); lengths are pixels of the render resolution.
struct HatchStyle {
    double strokeWidthPx = 1.4;     ///< nominal hatch line width
    double minSpacingPx = 2.5;      ///< densest spacing between parallel hatches (two families then cover 80%)
    double maxSpacingPx = 24.0;     ///< sparsest spacing (lightest hatched tone)
    double highlightDensity = 0.1;  ///< below this target density: no hatching (paper shows)
    double crossDensity = 0.45;     ///< above this: the second family (cross-hatching) is added
    double toneGamma = 1.6;         ///< target density = (1 − tone)^gamma; > 1 opens up the lit side
    double taper = 0.12;            ///< fraction of a stroke's length over which its ends thin out
    double pressureVariation = 0.2; ///< relative width variation along a stroke (smooth noise)
    double jitterPx = 0.0;          ///< positional wobble amplitude
    double angleOffsetDeg = 0.0;    ///< rotates hatch directions on screen
    double spacingJitter = 0.0;     ///< relative random variation of seed spacing
    double minLengthPx = 12.0;      ///< shorter strokes are dropped
};

/// Outline strokes.
struct ContourStyle {
    double widthPx = 1.8;          ///< silhouette width
    double creaseWidthPx = 1.2;    ///< crease and border width
    double creaseAngleDeg = 140.0; ///< edges whose dihedral angle is below this are creases (Blender Line Art's default)
    bool borders = true;           ///< draw mesh borders (open boundaries)
    bool hidden = false;           ///< also emit hidden contours (HiddenContour strokes)
};

struct Style {
    /// Colour of the background and of fully lit surfaces (linear RGB).
    Rgb paper = {1.0, 1.0, 1.0};
    /// Colour of the darkest tone (linear RGB). A pixel of tone t in [0, 1]
    /// gets ink + t (paper - ink).
    Rgb ink = {0.0, 0.0, 0.0};
    /// Tone floor of the Lambert preview in [0, 1]: surfaces no light reaches get
    /// this tone, so shadowed sides keep their shape instead of turning solid ink.
    double ambient = 0.15;
    HatchStyle hatch;
    ContourStyle contour;
    double paperGrain = 0.0; ///< amplitude of paper texture in [0, 1] (0 = flat paper)
    uint32_t seed = 1;       ///< base seed of every random choice (with stable ids)
};

/// Linear-light colour of tone t (0 = ink, 1 = paper); t is clamped to [0, 1].
Rgb toneToColor(const Style &style, double tone);

} // namespace rosy::styles
