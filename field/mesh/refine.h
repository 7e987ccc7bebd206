#pragma once
/// \file refine.h
/// Refining a coarse mesh without changing its surface: longest-edge bisection.
///
/// A field lives on the vertices. A CAD mesh of a few large triangles (a cube's
/// twelve) gives a field only a handful of values, interpolated across faces many
/// lattice cells wide, so a remesh along it swirls (docs/remeshing.md, "Coarse
/// meshes refined"). refineLongEdges() gives such a mesh vertices at a chosen
/// spacing on the very same surface.

#include "field/mesh/mesh.h"

namespace rosy::field {

/// What refineLongEdges() did.
struct Refinement {
    int bisections = 0;     ///< edges bisected (= vertices added)
    double maxEdgeBefore = 0; ///< the longest edge of the input
};

/// `mesh` with no edge longer than maxEdge: the longest edge is bisected at its
/// midpoint, with the one or two faces beside it, until none is longer (ties by
/// vertex ids, so the result is one and the same on every run). Each bisected edge
/// is the longest of both its faces then (Rivara's longest-edge bisection), so no
/// angle falls below half of the smallest one of the input. Every new vertex is the
/// midpoint of an edge of the moment, so it lies on an input edge or inside an input
/// face, and every new face lies in an input face: the surface, its boundary and its
/// creases are the input's exactly. Vertices and faces of the input keep
/// their indices; new ones follow. A mesh with no longer edge comes back as a copy.
/// \throws InputError naming the mesh if the result would have more than
///   maxVertices vertices (maxEdge too short for the mesh's size);
///   CheckFailure if maxEdge is not positive and finite (a caller bug).
Mesh refineLongEdges(const Mesh &mesh, double maxEdge, long long maxVertices, Refinement *report = nullptr);

} // namespace rosy::field
