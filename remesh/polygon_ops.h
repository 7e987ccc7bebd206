#pragma once
/// \file polygon_ops.h
/// Combinatorial clean-up steps of the remesher's polygon soup (faces as vertex
/// lists, counter-clockwise seen from outside), apart from remesh.cpp so that
/// each can be tested on hand-made meshes. Each keeps every directed edge in at
/// most one face and every undirected edge in at most two.

#include "field/mesh/mesh.h"
#include "remesh/aabb_tree.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

namespace rosy::remesh {

using field::Vec3;

/// Points farther than this many L from the other surface are repaired (the
/// remesher's distance repair); a clean-up step leaves no face farther than this.
constexpr double kFarDistance = 0.4;

/// The re-cuts' cost of a vertex (cancelDislocationPairs, respokeVertices): 1 if it is
/// irregular, then how far its valence is from 4 (a valence 6 is worse than a 5).
inline double valenceCost(int valence) { return (valence != 4 ? 1.0 : 0.0) + 0.01 * (valence - 4) * (valence - 4); }

/// Smallest corner a re-cut quad may have (and 180° less it the largest); a triangle's bounds.
constexpr double kMinQuadCorner = 35.0 * std::numbers::pi / 180.0;
constexpr double kMinTriangleCorner = 25.0 * std::numbers::pi / 180.0;
constexpr double kMaxTriangleCorner = 130.0 * std::numbers::pi / 180.0;

/// The worst deviation (radians) of polygon P's corners from the angle its kind wants
/// (a triangle's 60°, else 90°), its corners at `at(v)`; negative when a corner turns
/// the wrong way about `normal` or lies outside its kind's bounds (kMinQuadCorner ..
/// 180° − kMinQuadCorner; triangles kMinTriangleCorner .. kMaxTriangleCorner).
template <typename At> double worstCornerDeviation(const std::vector<int> &P, const At &at, const Vec3 &normal) {
    const size_t m = P.size();
    const double lo = m == 3 ? kMinTriangleCorner : kMinQuadCorner;
    const double hi = m == 3 ? kMaxTriangleCorner : std::numbers::pi - kMinQuadCorner;
    const double want = (m == 3 ? 60.0 : 90.0) * std::numbers::pi / 180.0;
    double worst = 0;
    for (size_t k = 0; k < m; ++k) {
        const Vec3 &a = at(P[(k + m - 1) % m]), &b = at(P[k]), &c = at(P[(k + 1) % m]);
        const Vec3 e0 = a - b, e1 = c - b;
        const double l = e0.norm() * e1.norm();
        if (!(l > 0) || e1.cross(e0).dot(normal) <= 0) return -1.0;
        const double angle = std::acos(std::clamp(e0.dot(e1) / l, -1.0, 1.0));
        if (angle < lo || angle > hi) return -1.0;
        worst = std::max(worst, std::abs(angle - want));
    }
    return worst;
}

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

/// Calls visit(p) for the samples of triangle (a, b, c) the quality report takes: a
/// barycentric grid of k = ⌈longest side / (L/3)⌉ divisions (1 to 64), row by row.
template <typename Visit> void forEachSample(const Vec3 &a, const Vec3 &b, const Vec3 &c, double L, Visit &&visit) {
    const double steps = std::ceil(std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / (L / 3));
    const int k = steps >= 1 ? int(std::min(steps, 64.0)) : 1; // NaN: 1
    for (int i = 0; i <= k; ++i)
        for (int j = 0; i + j <= k; ++j) visit(a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k));
}

/// The farthest of a polygon's samples from the input (fanned from its first corner,
/// each triangle sampled as the report samples).
double farthestFromInput(const std::vector<int> &poly, const std::vector<Vec3> &positions, const AabbTree &inputTree,
                         double L);

/// A quad cut along one of its diagonals into two triangles that both face the input
/// (facesInput), are no thinner than `minHeight` (smallest altitude) and have no
/// sample farther from the input than `limit`: of the two diagonals the one whose
/// farther triangle is nearer, the first on a tie. A quad folded over a ridge or rim
/// narrower than the lattice — its diagonal along the ridge, its other corners down
/// either side — has its middle inside the part, its two triangles on the two sides.
/// Empty when neither diagonal qualifies (or `quad` has not four corners).
std::vector<std::vector<int>> cutFarQuad(const std::vector<int> &quad, const std::vector<Vec3> &positions,
                                         const field::Mesh &input, const AabbTree &inputTree, double L,
                                         double minHeight, double limit);

/// A point `x` farther than kFarDistance L from the output (the remesher's distance
/// repair) taken by a corner of `poly` instead of a new vertex: its corners within
/// 0.75 L of x, nearest first, that are not `fixed` and whose faces `usable` allows,
/// each put at x and kept there if every face around it then faces the input
/// (facesInput), has no corner below 30°, has no sample farther from the input than
/// `limit` (farthestFromInput), and leaves the input point nearest the corner's old
/// place within kFarDistance L of them (a bump it covered stays covered). Returns the
/// corner moved and its faces in `around`, or −1 with `positions` unchanged. A fan
/// from x would add a vertex and turn the polygon into triangles, each corner of it
/// one edge more: at a cone's triangle, three irregular vertices where there was none.
int moveCornerOnto(const std::vector<int> &poly, const Vec3 &x, const std::vector<std::vector<int>> &polygons,
                   std::vector<Vec3> &positions, const field::Mesh &input, const AabbTree &inputTree, double L,
                   double limit, const std::function<bool(size_t)> &fixed, const std::function<bool(int)> &usable,
                   std::vector<int> &around);

/// The fan of triangles (apex, loop[k], loop[k + 1]) from positions[apex] over `loop`
/// (the distance repair's fan), if every one is no thinner than `minHeight` (its height
/// over its side of the loop), faces the input (facesInput) and has no sample farther
/// from the input than `limit` (farthestFromInput); else empty. `farthest`, if given,
/// gets the largest of its triangles' farthest samples.
std::vector<std::vector<int>> soundFan(const std::vector<int> &loop, int apex, const std::vector<Vec3> &positions,
                                       const field::Mesh &input, const AabbTree &inputTree, double L,
                                       double minHeight, double limit, double *farthest = nullptr);

/// A far point no fan of its polygon alone takes — one fan triangle would turn over
/// (the point lies beyond one of its sides) or stay as far as the polygon was (the far
/// region straddles a side) — fanned from the polygon joined with its neighbour across
/// one side. For each side k of polygons[f] (poly[k] → poly[k+1]) whose reverse
/// `across` finds in a polygon g ≠ f (−1: none, or a side that must stay) that `usable` allows, the two loops without their
/// shared side make one (it must pass no vertex twice), and each point of `targets` in
/// turn is tried as the apex of a fan over that loop: every triangle no thinner than
/// `minHeight`, facing the input (facesInput) and with no sample farther from the input
/// than the larger of `limit` and max(kFarDistance L, 0.9 × g's own farthest sample).
/// Of all sides and targets the fan whose farthest sample is nearest wins (the first on
/// a tie). On success the apex is appended to `positions` and the fan returned (its
/// first triangle for f, its second for g, the rest new), else `positions` is unchanged
/// and `neighbour` is −1. The fan covers the two polygons, so the mesh stays closed,
/// manifold and oriented.
struct JoinedFan {
    int neighbour = -1;
    std::vector<std::vector<int>> faces;
};
JoinedFan fanAcrossSide(int f, const std::vector<Vec3> &targets, const std::vector<std::vector<int>> &polygons,
                        std::vector<Vec3> &positions, const std::function<int(int, int)> &across,
                        const std::function<bool(int)> &usable, const field::Mesh &input,
                        const AabbTree &inputTree, double L, double minHeight, double limit);

/// A hole (a traced face with more sides than a face may have) filled with triangles.
/// The fan from its centroid put on the input (`inputTree.closest`, appended to
/// `positions`) is kept when every triangle of it faces the input (facesInput), as
/// before. A hole that is not star-shaped from that point (an L-shaped face on a
/// flat part of a CAD model: the fan triangles beyond the inner corner turn over)
/// is cut into triangles between its own corners instead: of all such cuts whose
/// new sides are no edges yet (`joined`), the one whose worst triangle faces the
/// input best (the cosine between its normal and the input's at the point nearest
/// its centroid), if every triangle of it faces the input; else the fan stays.
/// Returns the triangles (counter-clockwise like the hole); `byEars` says which way.
std::vector<std::vector<int>> fillHole(const std::vector<int> &hole, std::vector<Vec3> &positions,
                                       const field::Mesh &input, const AabbTree &inputTree,
                                       const std::function<bool(int, int)> &joined, bool &byEars);

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

/// What is still flipped (not facesInput) or degenerate (twice its area below
/// 10⁻⁵ L²) after the steps above — a face folded where the lattice crosses itself,
/// a fan over a hole turned over, a face on a part or across a gap thinner than its
/// own sag — is cut out with the faces around it and the hole filled again. The
/// patch is the face and the faces across its sides, else the faces at its corners,
/// else the faces at their corners, else the faces across the sides of the first
/// patch's faces; it must be a disk (one boundary loop through no
/// vertex twice, V − E + F = 1). Its boundary is filled with the cut between its
/// own corners facing the input best (fillHole's), with the fan from the input
/// point nearest the boundary's centroid, or with the fan from one of the vertices
/// inside it; a candidate counts if every triangle faces the input with twice its
/// area along the input's normal at least 10⁻⁴ L², no new side is an edge outside
/// the patch, and every vertex that goes lies within L/2 of the new triangles (the
/// issue's distance bound at 1 %: a corner of the input is not cut off); of those,
/// the one whose smallest angle is largest. `fixed` vertices inside a patch stay
/// (only the fan from one, if it is the only one) unless no patch can be refilled
/// that way. A disk replaced by a disk on the same boundary keeps the mesh closed,
/// manifold, oriented and its Euler characteristic; the vertices inside go (but
/// the fan's centre). Faces in index order, up to two rounds; returns how many
/// patches were refilled.
int refillFlippedPatches(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                         const field::Mesh &input, const AabbTree &inputTree, double L,
                         const std::function<bool(size_t)> &fixed);

/// A vertex whose star is irregular — it, one of its faces or one of their interior
/// corners: a valence other than 4, a face that is not a quad — gets its star cut again
/// around it. The star's boundary loop (the corners of its faces, each once) is kept;
/// the vertex's spokes go to another set of loop corners, the pieces between consecutive
/// spokes becoming quads (two loop steps), at most one triangle (one step) or two quads
/// (four steps, cut by a diagonal between loop corners). Of all such cuts whose faces
/// are convex with corners between 35° and 145° (triangles 25° and 130°) about the
/// loop's normal, whose diagonals are no edges yet and that leave no interior vertex
/// below valence 3, the one that lowers the count of irregular vertices and non-quad
/// faces the most (each irregular vertex counting 1 + 0.01 (valence − 4)², each face
/// that is not a quad 1), by more than 0.5, is taken; on a tie the one whose worst
/// corner is nearest its ideal angle. The vertex moves to the input point nearest its
/// loop's centroid. A cut is refused where a face would be farther from the input than
/// the old ones and kFarDistance L, or a sample of the old faces farther than L/10 from
/// the new ones (the surface stays where it was). What it mends, for one: a vertex
/// whose spokes go to the wrong corners of its ring (neighbours of valence 3 and 5 in
/// turn, RespokeVertices.ASpokeSetTurnedByOneStepIsTurnedBack). The indices inside
/// the loop add up as before, so a dislocation stays one and a cone a cone; the loop
/// is the same, so the mesh stays closed, manifold and oriented with its Euler
/// characteristic. `fixed` vertices (feature curves) are not re-cut. Vertices in index
/// order, up to three passes (N = 4 only); returns how many stars were re-cut.
int respokeVertices(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                    const AabbTree &inputTree, double L, const std::function<bool(size_t)> &fixed);

/// Two edges of the remesher's graph, (a, b) and (c, d) with a < b and c < d, that
/// cross on the surface as removeCrossingEdges() tests it.
struct EdgeCrossing {
    int a, b, c, d;
};

/// Every crossing pair of `graph` (output vertex v at `positions[v]`, unit `normals[v]`),
/// each once per edge (a, b) it is found from; the test is described at
/// removeCrossingEdges().
std::vector<EdgeCrossing> findCrossingEdges(const std::vector<std::set<int>> &graph,
                                           const std::vector<Vec3> &positions, const std::vector<Vec3> &normals);

/// Of each pair in `crossings` (findCrossingEdges()), one edge of the remesher's graph
/// (`graph[v]`, the neighbours of output vertex v at `positions[v]`) is removed;
/// returns how many edges went. Where the position field tangles (near a singularity
/// on a flat part: the bottom of CGAL's hand, where five output vertices fell
/// within L/2 of each other), two unit edges can cross; the rotation system then
/// traces faces lying over each other, some flipped, and a handle through them
/// (hand at 1 %: χ 0 against 2). A pair (a, b), (c, d) is tested where c is a
/// neighbour of a or b and d one of c's, in the plane through the middle of (a, b)
/// normal to its ends' mean normal, when all four lie near that plane (within a
/// quarter of |ab|, normals within 25° of its normal), so that the test is not made
/// across a thin part, a crease or a feature corner (where removing crossings cut
/// CGAL's corner.off's corner off: 0.53 → 1.19 %); of a crossing pair, the edge
/// whose length is further from L goes, but never an edge with a feature vertex at
/// one end (then the other one goes, and neither if both have one; `featureVertex`
/// may be empty; a vertex is one where it is not 0). With `only`, just the pairs
/// with a marked vertex: the remesher
/// marks the corners of the faces it traced that turn from the input and of its
/// holes, since crossings elsewhere (at a dislocation of a torus's lattice) trace
/// sound faces, and removing them costs distance (torus at L = 3 %: 0.36 → 0.50 %).
int removeCrossingEdges(std::vector<std::set<int>> &graph, const std::vector<EdgeCrossing> &crossings,
                        const std::vector<Vec3> &positions, const std::vector<char> &featureVertex, double L,
                        const std::vector<char> *only = nullptr);

/// Area below which a piece of the output is a stray, in L² (removeStrayPieces).
constexpr double kStrayPieceArea = 16.0;

/// Pieces of the output (connected by shared vertices) that are strays: smaller than
/// kStrayPieceArea L² and lying on an input component another, larger piece already
/// covers. Where a tunnel or a gap narrower than L closes, what the lattice keeps of
/// its wall can be a closed speck of a few faces inside the solid (femur at 1 %:
/// three pieces of 5 to 10 faces beside the bone), which no input component asks
/// for. A piece maps to the input component of the input triangle nearest most of
/// its vertices; the largest piece on each input component stays, and so does any
/// piece of at least kStrayPieceArea L² (a part cut off at a thin neck is surface the
/// input has) or with a corner farther than L from every piece that stays (a small
/// part of its own), unless the pieces that stay are closed and enclose every corner of
/// it (it is inside their solid: femur at 1 % after its coarse input is refined, a 9-face speck
/// 1.5 L from the bone's wall inside it). Most are two faces back to back, one of them flipped (cube_quad,
/// torus_quad, corner_with_sharp_edge at 1 %). Removes them from `polygons` (their
/// vertices are left unused); returns how many pieces went.
int removeStrayPieces(std::vector<std::vector<int>> &polygons, const std::vector<Vec3> &positions,
                      const field::Mesh &input, const AabbTree &inputTree, double L);

} // namespace rosy::remesh
