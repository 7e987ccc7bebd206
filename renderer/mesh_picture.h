#pragma once
/// \file mesh_picture.h
/// Pictures of a polygon mesh, e.g. what `rosyhatch remesh` made (issue 20): the
/// surface in the field picture's light grey shading with every edge drawn, the
/// faces that are not of the mesh's own kind (not quads in a quad mesh, not
/// triangles in a triangle mesh) tinted, irregular interior vertices as dots, and
/// optionally the field's singularities as rings, so that a reader sees at once
/// whether each singularity got its irregular vertex (Palacios & Zhang 2007,
/// Figures 4 and 8, draw remeshed surfaces this way).
///
/// Colour convention: edges dark grey; valence below the regular one (3 in a quad
/// mesh) blue dots, above (5 and more) red dots, valence 2 or less black; faces with
/// another number of sides orange; field singularities black rings. The
/// result is a FieldDrawing (field_picture.h), so rasterizeFieldDrawing() makes
/// pixels and fieldPictureStrokes() the pen layers of an SVG (1 edges, 2 rings,
/// 3 dots).

#include "renderer/field_picture.h"

#include <vector>

namespace rosy::renderer {

/// The SVG layer labels of a mesh picture (for SvgOptions::layerLabels).
inline constexpr std::array<const char *, 4> kMeshPictureLayerLabels{"1 edges", "2 field singularities",
                                                                     "3 irregular vertices", "4 unused"};

struct MeshPictureOptions {
    /// Sides of a regular face (4: quads, 3: triangles); valence of a regular
    /// interior vertex is 4 or 6 accordingly.
    int regularSides = 4;
    /// Widths and radii in pixels for a 1024-pixel image side, scaled with
    /// min(width, height) / 1024 as in FieldPictureOptions.
    double edgeWidthPx = 0.9;
    double dotRadiusPx = 3.0;
    double ringRadiusPx = 7.0;
    double ringWidthPx = 1.6;
    /// Lights for the shading; empty: one headlight (picture_common.h).
    std::vector<Light> lights;
    styles::Rgb edgeColor{0.1, 0.1, 0.1};
    styles::Rgb lowValenceColor{0.02, 0.12, 0.95};
    styles::Rgb highValenceColor{0.9, 0.03, 0.02};
    styles::Rgb otherFaceTint{1.0, 0.72, 0.32};
    styles::Rgb ringColor{0.0, 0.0, 0.0};
    /// Per entry of singularityPositions (or empty): 0 for a singularity that did not
    /// end up as one irregular vertex or face of its own sign (the remesh report's
    /// `singularities_as_one_irregular`), drawn with a second ring inside its ring.
    std::vector<char> singularityAsOne;
};

/// Draws the polygon mesh (positions, counter-clockwise polygons of >= 3 valid,
/// distinct vertex indices, manifold as OpenMesh's PolyMesh accepts it) seen by
/// `camera`, with hidden parts removed against the mesh's own G-buffer. Each
/// polygon is drawn as a fan around its centroid, so any manifold polygon mesh
/// shades without new edges. `singularityPositions` (may be empty): world points
/// drawn as rings where the surface there is visible, doubled where
/// options.singularityAsOne says 0. Deterministic.
/// \throws std::invalid_argument for a polygon with fewer than 3 vertices or an
///   index out of range, or options.singularityAsOne neither empty nor of
///   singularityPositions' size.
FieldDrawing drawMeshPicture(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                             const std::vector<Vec3> &singularityPositions, const Camera &camera,
                             const MeshPictureOptions &options = {});

} // namespace rosy::renderer
