#pragma once
/// \file polygon_ops.h
/// Combinatorial clean-up steps of the remesher's polygon soup (faces as vertex
/// lists, counter-clockwise seen from outside), apart from remesh.cpp so that
/// each can be tested on hand-made meshes. Each keeps every directed edge in at
/// most one face and every undirected edge in at most two.

#include "field/mesh/mesh.h"

#include <map>
#include <string>
#include <vector>

namespace rosy::remesh {

using field::Vec3;

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

} // namespace rosy::remesh
