#pragma once
/// \file edge_lines.h
/// The lines of a quad-dominant polygon mesh (issue 20: hatching along the quad
/// mesh's edges): maximal chains of edges that go straight on through every regular
/// vertex. At an interior vertex of valence 4 a line arriving along one edge leaves
/// along the opposite one (two edges further round the vertex); at a boundary vertex
/// of valence 3 a boundary line goes on along the other boundary edge; at an
/// irregular interior vertex it goes on along the edge that turns least if that
/// turns less than 20°; anywhere else (corners, sharp turns) lines end. Every edge
/// lies on exactly one line (a line never takes an edge another line has), except
/// the spokes of vertices of valence 7 or more (the centres of the fans the remesher
/// fills large polygons with), which lie on none.
///
/// Each line also gets a parity such that the two lines through the opposite sides
/// of a quad (neighbouring parallel lines) differ wherever the mesh allows: a
/// breadth-first 2-colouring of the lines' neighbour graph. Around a singular vertex
/// of odd index the graph has odd cycles, so a few neighbours share a parity there.
/// A drawing that shows every other line in light tone uses it.
///
/// And each edge a family, 0 or 1, for a drawing that hatches one direction in
/// light tone: family 0 is the direction "around the form" (of the two directions
/// at a vertex, the one along which the surface normal turns faster), smoothed
/// over neighbouring edges; where the surface is flat, a 2-colouring of the
/// edges over the quads (opposite sides alike, neighbouring sides not) decides. A
/// quad mesh has no global labels around a singular vertex of odd index (going
/// round it turns one direction into the other), so families have seams, placed
/// by the geometry rather than by the order of the mesh's elements.
///
/// Deterministic: lines and parities depend only on the mesh's element order.

#include "field/mesh/mesh.h"
#include "field/mesh/poly_mesh.h"

#include <vector>

namespace rosy::remesh {

using field::Vec3;

struct EdgeLine {
    std::vector<Vec3> points; ///< vertex positions in order along the line (≥ 2)
    std::vector<Vec3> normals; ///< unit vertex normals (mean of the faces' around each), as points
    bool closed = false;      ///< the line comes back to its first vertex (not repeated in points)
    /// Per edge along the line (points.size() − 1 of them, points.size() if closed):
    /// 0 or 1, the edge's family (see the file comment).
    std::vector<int> families;
    int parity = 0;           ///< 0 or 1, alternating between neighbouring parallel lines
};

/// The lines of `mesh` in the order of their first edge's index (see the file comment).
std::vector<EdgeLine> edgeLines(const field::PolyMesh &mesh);

} // namespace rosy::remesh
