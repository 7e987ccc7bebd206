#pragma once
/// \file field_picture.h
/// Pictures of an N-RoSy field, in the spirit of Palacios & Zhang 2007, Figures 3–6:
/// the shaded mesh, dense streamlines of the field, singularities as coloured dots and
/// separatrices as coloured curves, all seen through a Camera with hidden parts removed.
///
/// Colour convention (documented for users, also in `rosyhatch field --help`):
///  - singularity dots: positive index red, negative index blue; higher order (|k| > 1)
///    darker and larger; every dot has a thin black rim so it reads on any background;
///  - separatrices: outgoing green, incoming orange (only odd N has incoming ones; the
///    lines of an even-N field have no orientation, so all of them are outgoing);
///  - streamlines: thin dark grey over a light grey Lambert shading from a headlight.
///
/// A picture is first a FieldDrawing: a shading fill and a list of inks (a colour and a
/// stroke list each). Pixels come from the one stroke rasterizer (raster.h), paths from
/// the SVG writer (svg.h), so `rosyhatch field --image` writes PNG, EXR, ... or SVG.

#include "field/frames.h"
#include "field/rosy.h"
#include "field/separatrices.h"
#include "field/singularities.h"
#include "renderer/output/image.h"
#include "renderer/output/strokes.h"
#include "renderer/view/camera.h"
#include "renderer/view/shading.h"
#include "styles/style.h"

#include <array>
#include <string>
#include <vector>

namespace rosy::renderer {

struct FieldPictureOptions {
    /// Draw the dense streamlines (off: only shading, separatrices and dots).
    bool streamlines = true;
    /// Spacing of streamline seeds, as a fraction of the bounding-box diagonal: one
    /// seed per cell of a 3D grid with this cell size (> 0).
    double seedSpacingRelative = 0.018;
    /// Length of each half of a streamline (forward and backward from its seed), as a
    /// fraction of the bounding-box diagonal (> 0).
    double streamlineLengthRelative = 0.018;
    /// Line widths and dot radius in pixels for a 1024-pixel image side; scaled with
    /// min(width, height) / 1024 so pictures look alike at any resolution.
    double streamlineWidthPx = 1.0;
    double separatrixWidthPx = 2.5;
    double dotRadiusPx = 4.5;
    /// Lights for the shading; empty: one headlight from slightly above-left of the camera.
    std::vector<Light> lights;
    /// Colours in linear RGB (the style's colour type).
    styles::Rgb streamlineColor{0.08, 0.08, 0.08};
    styles::Rgb positiveColor{0.9, 0.03, 0.02};
    styles::Rgb negativeColor{0.02, 0.12, 0.95};
    styles::Rgb outgoingColor{0.0, 0.42, 0.04};
    styles::Rgb incomingColor{1.0, 0.38, 0.0};
};

/// One colour of a field picture: strokes drawn in `colour` at `opacity`. Inks are
/// painted in list order, each over the ones before.
struct FieldInk {
    std::string name;         ///< "streamlines", "outgoing separatrices", "positive singularities", ...
    styles::Rgb colour{0, 0, 0};
    double opacity = 1.0;
    /// Part of the vector drawing (fieldPictureStrokes()); false for the black rims
    /// that only frame the coloured dots against the raster shading.
    bool vector = true;
    StrokeList strokes;       ///< raster px of the picture; a dot is a stroke of two equal points
    /// The raster picture draws thinner strokes this wide (px): below ~0.8 px a line
    /// fades into the shading at small resolutions. Paths keep their own width (on
    /// paper the picture's size, not its pixels, sets the scale).
    double minRasterWidthPx = 0.0;
};

/// A field picture before it becomes pixels or paths: the shading fill and the inks.
struct FieldDrawing {
    int width = 0, height = 0;
    /// RGB, linear: the light grey Lambert tone on the surface, white elsewhere. The
    /// raster picture's background; vector output leaves it out (paper instead).
    Image fill;
    std::vector<FieldInk> inks;
};

/// Traces and projects the field picture: streamlines (one grid of seeds over the
/// visible faces), separatrices and singularity dots, each cut to its visible parts
/// (G-buffer depth test with a small tolerance), as strokes in the camera's raster.
/// \param mesh          the surface; frames.mesh() must be this mesh
/// \param frames        tangent frames of mesh
/// \param field         #V representation vectors (field.nSym ≥ 1)
/// \param report        singularities of `field` (findSingularities); dots are drawn
///                      at their world positions where the surface there is visible
/// \param separatrices  traced separatrices (traceSeparatrices); may be empty
/// \param camera        the view; the raster size is the picture size
/// Streamlines stop at singular faces and boundaries. An empty mesh gives a white fill
/// and no strokes. Deterministic: identical for any thread count.
FieldDrawing drawFieldPicture(const field::Mesh &mesh, const field::TangentFrames &frames,
                              const field::RosyField &field, const field::SingularityReport &report,
                              const std::vector<field::Separatrix> &separatrices, const Camera &camera,
                              const FieldPictureOptions &options = {});

/// The drawing as pixels: its fill, then each ink's strokes through the stroke
/// rasterizer (rasterizeStrokes(), raster.h) painted over it in the ink's colour
/// (paintOver()). RGB, linear light, width × height.
Image rasterizeFieldDrawing(const FieldDrawing &drawing);

/// The drawing's vector inks as one stroke list for the SVG writer (svg.h), on its
/// pen layers: streamlines on layer 1, separatrices on layer 2, singularity dots on
/// layer 3. The SVG writer draws each layer with one pen, so colours (and the rims
/// and shading that serve them) are the raster picture's only.
StrokeList fieldPictureStrokes(const FieldDrawing &drawing);

/// The SVG layer labels of a field picture: "1 streamlines", "2 separatrices",
/// "3 singularities" (for SvgOptions::layerLabels).
inline constexpr std::array<const char *, 4> kFieldPictureLayerLabels{"1 streamlines", "2 separatrices",
                                                                      "3 singularities", "4 unused"};

/// rasterizeFieldDrawing(drawFieldPicture(...)): the field picture as an RGB image
/// (channels R, G, B, linear light) of camera.width() x camera.height() pixels; the
/// background (no surface) is white.
Image renderFieldPicture(const field::Mesh &mesh, const field::TangentFrames &frames,
                         const field::RosyField &field, const field::SingularityReport &report,
                         const std::vector<field::Separatrix> &separatrices, const Camera &camera,
                         const FieldPictureOptions &options = {});

} // namespace rosy::renderer
