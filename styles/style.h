#pragma once
/// \file style.h
/// The look of a drawing, as plain values with defaults (the `fine-pen` preset):
/// paper and ink colours and the tone floor (Style), how tone becomes hatching
/// (HatchStyle: widths, spacing range, tone curve, taper, jitter), the contour
/// lines (ContourStyle) and the SVG page (PageStyle). scenes/ reads them from a
/// scene's `style:` block and the presets in styles/presets/; keys and ranges
/// are in scenes/README.md.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rosy::styles {

/// Linear-light RGB, each channel in [0, 1] (not sRGB-encoded).
using Rgb = std::array<double, 3>;

/// How hatches turn tone into ink. Densities are ink coverage in [0, 1]
/// (0 = white paper, 1 = solid ink); lengths are pixels of the render resolution.
struct HatchStyle {
    /// What the hatch lines follow: the field's streamlines, traced on screen with
    /// evenly spaced seeds (Jobard–Lefer; renderer/strokes/hatching.h), or the
    /// edges of a quad mesh remeshed along the field (remesh/, then
    /// renderer/strokes/quad_lines.h): evenly spaced on the surface by construction.
    enum class Lines : uint8_t { Field, QuadMesh };
    Lines lines = Lines::Field;
    /// Lines::QuadMesh: the quad mesh's edge length, in pixels at the depth of the
    /// mesh's bounding-box centre (turned into world units by the camera): the
    /// spacing of one family where every one of its lines is drawn.
    double quadEdgePx = 6.0;
    double strokeWidthPx = 1.8;     ///< mean hatch line width (tapered ends included)
    double minSpacingPx = 3.2;      ///< densest spacing between parallel hatches (two families then cover 81%);
                                    ///< closer than ~3 px, lines near the Nyquist rate lose their direction
    double maxSpacingPx = 24.0;     ///< sparsest spacing (lightest hatched tone)
    double highlightDensity = 0.1;  ///< below this target density: no hatching (paper shows)
    double crossDensity = 0.45;     ///< above this: the second family (cross-hatching) is added
    double toneGamma = 1.6;         ///< target density = min((1 − tone)^gamma, maxHatchDensity); > 1 opens up the lit side
    double taper = 0.12;            ///< fraction of a stroke's length over which its ends thin out
    double pressureVariation = 0.2; ///< relative width variation along a stroke (smooth noise)
    double jitterPx = 0.0;          ///< positional wobble amplitude
    double angleOffsetDeg = 0.0;    ///< rotates hatch directions on screen
    double spacingJitter = 0.0;     ///< relative random variation of seed spacing
    double minLengthPx = 12.0;      ///< shorter strokes are dropped
    /// Traced pixels per style pixel (not a scene key): 1, except in print mode, where
    /// printStyle() sets page.px_mm / (mm per traced px). The tracer's own pixel sizes
    /// (integration step bounds, wavelengths of pressure and wobble) scale with it, so
    /// a drawing traced at another pixel pitch keeps their size on paper.
    double pixelScale = 1.0;
    /// Every spacing the tone asks for (before the [minSpacingPx, maxSpacingPx] clamp)
    /// is multiplied by this (not a scene key): 1, except on print mode's second trace
    /// (calibrateInk).
    double spacingGain = 1.0;
    /// Print mode (not a scene key; printStyle() sets it): the hatching is traced twice,
    /// the second time with spacingGain = the first trace's ink length over the ink the
    /// tone asks for (renderer::toneInkPx), so the drawing lays down the tone's line
    /// density at any picture size on paper (renderer/illustration.h).
    bool calibrateInk = false;
};

/// Outline strokes.
struct ContourStyle {
    double widthPx = 1.8;          ///< silhouette width
    double creaseWidthPx = 1.2;    ///< crease and border width
    double creaseAngleDeg = 140.0; ///< edges whose dihedral angle is below this are creases (Blender Line Art's default)
    /// The picture's scale for a scan's outlines, in pixels. Where the edges whose faces
    /// bend past the crease angle while the surface does not over this much surface are
    /// more than 5 % of the mesh's edges and 3/4 of its bent ones (a scan's noise and
    /// needle triangles), a crease must also bend so at this scale (and a quarter of
    /// it), and silhouette loops and pieces under half of it are dropped; a modelled
    /// mesh keeps every crease. 0: never.
    double featureScalePx = 8.0;
    bool borders = true;           ///< draw mesh borders (open boundaries)
    bool hidden = false;           ///< also emit hidden contours (HiddenContour strokes)
};

/// The page of vector output (SVG): the picture is fitted inside the margin and
/// centred. Sizes in millimetres.
struct PageStyle {
    enum class Orientation : uint8_t {
        Auto,      ///< of the size as written and its turned copy, the one that shows the picture larger (ties: as written)
        Portrait,  ///< the shorter side across
        Landscape, ///< the longer side across
    };
    double widthMm = 210.0;  ///< A4 as written (portrait)
    double heightMm = 297.0;
    double marginMm = 10.0;  ///< on every side
    Orientation orientation = Orientation::Auto;
    double penWidthMm = 0.0; ///< print: the pen, every path this wide; 0: hatch.stroke_width_px × pxMm
    /// Print mode (SVG output or --paper): one pixel of the style's *_px lengths
    /// is this many mm on paper, and an SVG-only render is traced on a grid of
    /// this pitch (the camera resolution then sets only the aspect ratio).
    double pxMm = 0.17;
    double minSpacingMm = 0.0; ///< print: densest hatch spacing on paper; 0: hatch.min_spacing_px × pxMm
    double maxSpacingMm = 0.0; ///< print: sparsest hatch spacing on paper; 0: hatch.max_spacing_px × pxMm
    double minLengthMm = -1.0; ///< print: shorter hatches are dropped; < 0: hatch.min_length_px × pxMm
};

/// A style's lengths on paper in print mode (PageStyle), in mm.
struct PrintLengths {
    double penWidthMm = 0, minSpacingMm = 0, maxSpacingMm = 0, minLengthMm = 0;
};

/// Narrowest line a plotter pen draws reliably (fine liners start at 0.1 mm).
inline constexpr double kMinPenWidthMm = 0.1;

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
    PageStyle page;          ///< vector output page (SVG)
    double paperGrain = 0.0; ///< amplitude of paper texture in [0, 1] (0 = flat paper)
    uint32_t seed = 1;       ///< base seed of every random choice (with stable ids)
};

/// Linear-light colour of tone t (0 = ink, 1 = paper); t is clamped to [0, 1].
Rgb toneToColor(const Style &style, double tone);

/// The page keys given in mm, the others derived from the *_px lengths × page.pxMm.
PrintLengths printLengths(const Style &style);

/// The style for tracing a picture whose pixels are `mmPerPx` mm on paper: hatch
/// width, spacings and minimum length become printLengths() / mmPerPx, jitter is
/// scaled with pxMm / mmPerPx, and the contour widths become the pen's (every
/// path is drawn with it; a width of 0, no contours, stays 0). If the densest
/// spacing would fall under 1 px (a grid too coarse for the lengths asked) the
/// lengths are taken as style pixels instead (mm / pxMm) and *coarsened is set.
Style printStyle(const Style &style, double mmPerPx, bool *coarsened = nullptr);

/// What a pen plotter cannot draw as asked, one sentence each (empty: nothing):
/// a pen under kMinPenWidthMm, or a densest spacing below the pen's width.
std::vector<std::string> printProblems(const PrintLengths &lengths);

} // namespace rosy::styles
