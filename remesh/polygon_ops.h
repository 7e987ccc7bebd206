#pragma once
/// \file polygon_ops.h
/// Combinatorial clean-up steps of the remesher's polygon soup (faces as vertex
/// lists, counter-clockwise seen from outside), apart from remesh.cpp so that
/// each can be tested on hand-made meshes. Each keeps every directed edge in at
/// most one face and every undirected edge in at most two.

#include "field/mesh/mesh.h"
#include "remesh/aabb_tree.h"

#include <cstdint>
#include <functional>

#include <map>
#include <string>
#include <vector>

namespace rosy::remesh {

using field::Vec3;

/// One 64-bit key per directed edge a -> b (maps from an edge of the output to its face).
inline uint64_t directedEdgeKey(int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); }

/// Removes the polygons marked in `gone` (one flag per polygon), keeping the order of the rest.
void removeMarked(std::vector<std::vector<int>> &polygons, const std::vector<char> &gone);

/// A vertex left with two neighbours a, b (in exactly two faces that share both
/// its edges) is removed: a face of four or more sides loses it, a triangle
/// (a, v, b) goes (its third edge a–b is then shared by the faces on both sides
/// of it). Where a and b are already joined by an edge of a third face, removing
/// v from both faces would give a–b a second pair of sides (a non-manifold edge,
/// which OpenMesh refuses, leaving a hole): the two faces are then merged into
/// one along a–v–b instead (two quads make a quad), if that face has at most
/// `maxSides` sides and no repeated vertex; else v stays.
/// Counts: repairs["valence2_dissolved_in_faces"] (set), ["valence2_faces_merged"] (added).
void dissolveValence2(std::vector<std::vector<int>> &polygons, int nVertices, int maxSides,
                      std::map<std::string, int> &repairs);

/// A vertex whose corners form more than one fan (a face traced through a vertex
/// twice is split there into two loops, which pinches the surface at it: two
/// cones of faces meeting at one point, a non-manifold vertex OpenMesh would
/// refuse faces at) gets one copy per fan beyond the first. Every copy, the
/// original included, moves a quarter of the way toward the mean of its fan's
/// neighbours, at most `maxStep`, so no two coincide. Appends the copies to
/// `positions`; returns how many were made.
int splitPinchedVertices(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions, double maxStep);

/// Twice the vector area of a polygon (Newell): its normal times twice its area.
Vec3 vectorArea(const std::vector<int> &poly, const std::vector<Vec3> &positions);

/// The quality report's test of a flipped face, negated: true when the polygon's
/// vector area points along the normal of the input triangle nearest its centroid.
bool facesInput(const std::vector<int> &poly, const std::vector<Vec3> &positions, const field::Mesh &input,
                const AabbTree &inputTree);

/// Flipped faces (not facesInput) are untangled where moving one of their corners
/// mends them: a sliver whose middle corner lies on the line of the other two (its
/// orientation is rounding), a corner pulled across its neighbour by the repairs
/// before. Each corner of a flipped face in turn (not `fixed`) tries the mean of its
/// neighbours and the points 3/4, 1/2 and 1/4 of the way there from where it is,
/// each put back on the input; the first with which every face around the corner
/// faces the input with twice its area along the input's normal at least 0.01 L²
/// is kept. Faces in index order, up to three rounds; connectivity is not changed.
/// Returns how many corners moved.
int untangleFlipped(const std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                    const field::Mesh &input, const AabbTree &inputTree, double L,
                    const std::function<bool(size_t)> &fixed);

/// A triangle (a, m, b) still flipped after untangleFlipped — a sliver, or a
/// triangle of three feature vertices on one crease (zero area) — is absorbed into
/// the face across its side a–b: that face gains m between a and b (a → m → b
/// replaces a → b; the triangle's sides a → m and m → b had their reverses in the
/// faces beyond, so the mesh stays closed, manifold and oriented) and the triangle
/// goes. Tried across each side, longest first; only if the face across has fewer
/// than `maxSides` sides, does not hold m already and then faces the input
/// (facesInput). Faces in index order; returns how many triangles went.
int absorbFlippedTriangles(std::vector<std::vector<int>> &polygons, const std::vector<Vec3> &positions,
                           const field::Mesh &input, const AabbTree &inputTree, int maxSides);

/// A polygon of four or more sides still flipped after the two steps above, two of
/// whose corners that are not neighbours lie closer than `maxDiagonal` (a quad
/// folded along its short diagonal where the lattice crosses a thin part), loses
/// that diagonal: its two ends become one vertex, at the input point nearest their
/// midpoint (or where a `fixed` one is; both fixed: not done). The polygon splits
/// at that vertex into its two sides; a side of two corners (the vertex and the
/// corner between them) becomes one edge, whose two faces beyond now meet there, and
/// a side of three or more stays a face. Done only where it keeps the mesh manifold
/// (the two ends share no neighbour but the corners between them and no other
/// face) and every face at the merged vertex then faces the input (facesInput);
/// corners between them may be left with two neighbours (dissolveValence2 after).
/// Faces in index order; returns how many diagonals were collapsed.
int collapseFoldedDiagonals(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                            const field::Mesh &input, const AabbTree &inputTree, double maxDiagonal,
                            const std::function<bool(size_t)> &fixed);

} // namespace rosy::remesh
