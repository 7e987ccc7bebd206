#pragma once
/// \file input_refinement.h
/// What `rosyhatch remesh` does to a coarse input before its field is built
/// (docs/remeshing.md, "Coarse meshes refined").
///
/// The field lives on the input's vertices. A CAD part of a few large triangles
/// (the CGAL data's cube: twelve) gives it a handful of values, interpolated across
/// faces tens of lattice cells wide, and the remesh follows a field that swirls
/// over flat faces: on the cube, p90 corner deviation 24.5° and 8.9 % irregular
/// vertices at L = 1 %, against 0.6° and the eight corners once the cube has
/// vertices every 2 L. Fine meshes are left as they are: where a few long edges
/// sit among short ones (bunny00: 1.6 % of its area), bisecting them moves the
/// field only as any perturbation does.

#include "field/mesh/mesh.h"
#include "field/mesh/refine.h"

namespace rosy::remesh {

/// The input's edges are made at most this many L long.
constexpr double kRefineEdgeRatio = 2.0;
/// ... when the faces with a longer edge cover at least this share of its area.
constexpr double kRefineAreaFraction = 0.05;

struct InputRefinement {
    double maxEdge = 0;                  ///< kRefineEdgeRatio L
    double longEdgeAreaFraction = 0;     ///< share of the area in faces with an edge longer than maxEdge
    bool applied = false;                ///< longEdgeAreaFraction >= kRefineAreaFraction
    int verticesBefore = 0, verticesAfter = 0;
    field::Refinement refinement;        ///< when applied
    int delaunayFlips = 0;               ///< field::flipCoplanarToDelaunay() after the bisection
};

/// `mesh` refined by field::refineLongEdges() to edges of at most kRefineEdgeRatio
/// × edgeLength, then its flat parts made Delaunay (field::flipCoplanarToDelaunay():
/// the bisection's needles in long thin CAD faces become well-shaped triangles),
/// when faces with longer edges cover at least kRefineAreaFraction of its area;
/// else `mesh` itself. The surface is the input's either way.
/// \throws InputError (field::refineLongEdges()) past maxVertices vertices;
///   CheckFailure if edgeLength is not positive and finite (a caller bug).
field::Mesh refineCoarseInput(const field::Mesh &mesh, double edgeLength, long long maxVertices,
                              InputRefinement *report = nullptr);

} // namespace rosy::remesh
