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

#include "field/frames.h"
#include "field/rosy.h"
#include "field/separatrices.h"
#include "field/singularities.h"
#include "renderer/view/camera.h"
#include "renderer/output/image.h"
#include "renderer/view/shading.h"

#include <array>
#include <vector>

namespace rosy::renderer {

/// Linear-light RGB colour.
using Rgb = std::array<float, 3>;

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
    Rgb streamlineColor{0.08f, 0.08f, 0.08f};
    Rgb positiveColor{0.9f, 0.03f, 0.02f};
    Rgb negativeColor{0.02f, 0.12f, 0.95f};
    Rgb outgoingColor{0.0f, 0.42f, 0.04f};
    Rgb incomingColor{1.0f, 0.38f, 0.0f};
};

/// Renders the field picture: an RGB image (channels R, G, B, linear light) of
/// camera.width() x camera.height() pixels; the background (no surface) is white.
/// \param mesh          the surface; frames.mesh() must be this mesh
/// \param frames        tangent frames of mesh
/// \param field         #V representation vectors (field.nSym ≥ 1)
/// \param report        singularities of `field` (findSingularities); dots are drawn
///                      at their world positions where the surface there is visible
/// \param separatrices  traced separatrices (traceSeparatrices); may be empty
/// \param camera        the view; the raster size is the image size
/// Streamlines stop at singular faces and boundaries; parts hidden behind the surface
/// (G-buffer depth test with a small tolerance) are not drawn. An empty mesh gives a
/// white image. Deterministic: identical for any thread count (tracing runs in
/// parallel per seed, drawing is a max of coverages, independent of order).
Image renderFieldPicture(const field::Mesh &mesh, const field::TangentFrames &frames,
                         const field::RosyField &field, const field::SingularityReport &report,
                         const std::vector<field::Separatrix> &separatrices, const Camera &camera,
                         const FieldPictureOptions &options = {});

} // namespace rosy::renderer
