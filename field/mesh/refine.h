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

/// Two faces whose normals differ by less than this angle (radians) count as one
/// plane for flipCoplanarToDelaunay(): a flip between them moves the surface by at
/// most this angle times the edge's length, far below a file's own precision.
constexpr double kCoplanarAngle = 1e-6;

/// `mesh` with edges flipped until every interior edge between two coplanar faces
/// (normals within kCoplanarAngle) is locally Delaunay: the two angles opposite it
/// sum to at most π (Lawson's flips). Longest-edge bisection of a CAD part leaves
/// fans of needles where an input face was long and thin (edge midpoints only ever
/// split it along its length); within a plane the Delaunay triangulation of the same
/// vertices has the largest smallest angle, and the field interpolated over it
/// turns less between vertices. Only flat pairs flip, so creases, the boundary and
/// the surface stay where they are; vertices keep their indices. An edge is flipped
/// only when its new diagonal is not an edge already and both new faces keep the
/// pair's orientation. The order is fixed (edges by vertex pair, then those around
/// each flip), so the result is one and the same on every run. `flips` (if given)
/// receives the number of flips.
Mesh flipCoplanarToDelaunay(const Mesh &mesh, int *flips = nullptr);

} // namespace rosy::field
