// The remesher's combinatorial clean-up steps on hand-made polygon meshes,
// checked by a walk written here (not the quality report's): every directed edge
// in one face and its reverse in another (closed, oriented), and the corners at
// every vertex one cycle (manifold).

#include "remesh/polygon_ops.h"

#include "remesh/aabb_tree.h"
#include "field/primitives.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

namespace rosy::remesh {
namespace {

using Polygons = std::vector<std::vector<int>>;

struct Shape {
    bool closedOriented = true; ///< each directed edge once, its reverse present
    bool manifold = true;       ///< one cycle of corners around every used vertex
    int usedVertices = 0, edges = 0, faces = 0;
    int chi() const { return usedVertices - edges + faces; }
};

Shape shapeOf(const Polygons &polygons) {
    Shape s;
    std::map<std::pair<int, int>, int> directed;
    std::map<int, std::map<int, int>> nextAfter; // vertex -> (prev -> next) of its corners
    std::map<int, int> cornerCount;
    for (const auto &P : polygons) {
        ++s.faces;
        for (size_t k = 0; k < P.size(); ++k) {
            const int a = P[k], b = P[(k + 1) % P.size()], p = P[(k + P.size() - 1) % P.size()];
            ++directed[{a, b}];
            if (!nextAfter[a].emplace(p, b).second) s.manifold = false;
            ++cornerCount[a];
        }
    }
    for (const auto &[e, n] : directed)
        if (n != 1 || !directed.count({e.second, e.first})) s.closedOriented = false;
    std::set<std::pair<int, int>> undirected;
    for (const auto &[e, n] : directed) undirected.insert({std::min(e.first, e.second), std::max(e.first, e.second)});
    s.edges = int(undirected.size());
    s.usedVertices = int(cornerCount.size());
    for (const auto &[v, after] : nextAfter) { // walk: a corner (p, n) is followed by the corner (n, ·)
        int steps = 0, x = after.begin()->first;
        do {
            auto it = after.find(x);
            if (it == after.end()) break;
            x = it->second;
            ++steps;
        } while (x != after.begin()->first && steps <= cornerCount[v]);
        if (steps != cornerCount[v]) s.manifold = false;
    }
    return s;
}

// Closed, oriented, manifold, with Euler characteristic chi.
void expectSound(const Polygons &polygons, int chi) {
    const Shape s = shapeOf(polygons);
    EXPECT_TRUE(s.closedOriented);
    EXPECT_TRUE(s.manifold);
    EXPECT_EQ(s.chi(), chi);
}

bool uses(const Polygons &polygons, int v) {
    for (const auto &f : polygons)
        if (std::find(f.begin(), f.end(), v) != f.end()) return true;
    return false;
}

// A cube, faces counter-clockwise from outside (bottom 0-3, top 4-7).
Polygons cube() {
    return {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
}

TEST(DissolveValence2, VertexOnACubeEdgeIsRemoved) {
    // Vertex 8 on the edge 0-1, in the bottom and the front face only.
    Polygons P = {{0, 3, 2, 1, 8}, {4, 5, 6, 7}, {0, 8, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    ASSERT_TRUE(shapeOf(P).closedOriented);
    std::map<std::string, int> repairs;
    dissolveValence2(P, 9, 6, repairs);
    EXPECT_EQ(P, cube());
    EXPECT_EQ(repairs["valence2_dissolved_in_faces"], 1);
    EXPECT_EQ(repairs["valence2_faces_merged"], 0);
}

TEST(DissolveValence2, NeighboursAlreadyJoinedMergeTheTwoFacesInsteadOfDoublingTheirEdge) {
    // A sphere of four faces: v = 2 between the quads (0 2 1 3) and (1 2 0 4), whose
    // other corners 0 and 1 are already joined by the triangles (0 3 1) and (0 1 4).
    // Removing 2 from both quads (the old step) would put 0 -> 1 and 1 -> 0 in two
    // faces each (found on CGAL's triceratops: OpenMesh refused the faces, leaving a hole).
    Polygons P = {{0, 2, 1, 3}, {1, 2, 0, 4}, {0, 3, 1}, {0, 1, 4}};
    const Shape before = shapeOf(P);
    ASSERT_TRUE(before.closedOriented && before.manifold);
    ASSERT_EQ(before.chi(), 2);
    std::map<std::string, int> repairs;
    dissolveValence2(P, 5, 6, repairs);
    // The union (1 3 0 4) leaves 3 and 4 with two neighbours each, which dissolve in
    // turn (a triangle goes each time): what is left must still be a closed,
    // oriented, manifold sphere without vertex 2.
    expectSound(P, 2);
    EXPECT_FALSE(uses(P, 2));
    EXPECT_EQ(repairs["valence2_faces_merged"], 1);
    // With at most three sides allowed the union (a quad) is refused: 2 stays, and
    // the mesh is still sound after 3 and 4 dissolve.
    Polygons Q = {{0, 2, 1, 3}, {1, 2, 0, 4}, {0, 3, 1}, {0, 1, 4}};
    std::map<std::string, int> none;
    dissolveValence2(Q, 5, 3, none);
    expectSound(Q, 2);
    EXPECT_TRUE(uses(Q, 2));
    EXPECT_EQ(none["valence2_faces_merged"], 0);
}

TEST(SplitPinchedVertices, TwoTetrahedraSharingAVertexGetOneEach) {
    Polygons P = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}};
    std::vector<Vec3> x = {{0, 0, 0},  {1, 0, 0},   {0, 1, 0},  {0.5, 0.5, 1},
                           {-1, 0, 0}, {0, -1, 0}, {-0.5, -0.5, -1}};
    ASSERT_FALSE(shapeOf(P).manifold);
    const int made = splitPinchedVertices(P, x, 0.1);
    EXPECT_EQ(made, 1);
    ASSERT_EQ(x.size(), 8u);
    expectSound(P, 4); // two spheres
    // The first tetrahedron keeps 0, the second gets 7; each moved toward its own
    // fan by at most 0.1, so they no longer coincide.
    EXPECT_EQ(P[0][0], 0);
    EXPECT_EQ(P[4][0], 7);
    EXPECT_LE(x[0].norm(), 0.1 + 1e-12);
    EXPECT_LE(x[7].norm(), 0.1 + 1e-12);
    EXPECT_GT((x[0] - x[7]).norm(), 0.1);
    EXPECT_GT(x[0].x() + x[0].y(), 0.0); // toward (1, 1)
    EXPECT_LT(x[7].x() + x[7].y(), 0.0);
}

TEST(SplitPinchedVertices, AManifoldMeshIsLeftAlone) {
    Polygons P = cube();
    std::vector<Vec3> x(8, Vec3::Zero());
    for (int i = 0; i < 8; ++i) x[size_t(i)] = Vec3(i & 1, (i >> 1) & 1, i >> 2);
    const std::vector<Vec3> before = x;
    EXPECT_EQ(splitPinchedVertices(P, x, 0.1), 0);
    EXPECT_EQ(P, cube());
    EXPECT_EQ(x, before);
}

// A fan of four triangles over a flat unit square (normal +z) whose centre has
// been pushed across the ring's right side: the triangle on that side is
// clockwise seen from +z, flipped. Moving the centre toward its neighbours' mean
// mends it; a fixed centre stays and so does the flip.
TEST(UntangleFlipped, ACentrePushedAcrossItsRingMovesBack) {
    const field::Mesh square = field::Mesh::fromTriangles({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                                                           {{0, 1, 2}, {0, 2, 3}}, "square");
    const AabbTree tree(square);
    const Polygons fan = {{4, 0, 1}, {4, 1, 2}, {4, 2, 3}, {4, 3, 0}};
    const std::vector<Vec3> start = {{0.1, 0.1, 0}, {0.9, 0.1, 0}, {0.9, 0.9, 0}, {0.1, 0.9, 0}, {0.95, 0.5, 0}};
    std::vector<Vec3> x = start;
    ASSERT_FALSE(facesInput(fan[1], x, square, tree));
    ASSERT_TRUE(facesInput(fan[0], x, square, tree));
    std::vector<Vec3> held = start;
    EXPECT_EQ(untangleFlipped(fan, held, square, tree, 0.5, [](size_t v) { return v == 4; }), 0);
    EXPECT_EQ(held, start);
    EXPECT_EQ(untangleFlipped(fan, x, square, tree, 0.5, [](size_t) { return false; }), 1);
    for (const auto &f : fan) EXPECT_TRUE(facesInput(f, x, square, tree));
    EXPECT_NEAR((x[4] - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-12); // the neighbours' mean, on the square
    for (int v = 0; v < 4; ++v) EXPECT_EQ(x[size_t(v)], start[size_t(v)]);
}

// A triangle of three points on one line (as three feature vertices on one crease
// come out): zero area, so it faces nowhere. It is absorbed into the quad across its
// longest side, which gains the middle point; with at most four sides allowed it stays.
TEST(AbsorbFlippedTriangles, AZeroAreaTriangleGoesIntoTheFaceAcrossItsLongestSide) {
    const field::Mesh strip = field::Mesh::fromTriangles({{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}},
                                                          {{0, 1, 2}, {0, 2, 3}}, "strip");
    const AabbTree tree(strip);
    const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    const Polygons start = {{0, 2, 3, 4}, {2, 0, 1}};
    ASSERT_TRUE(facesInput(start[0], x, strip, tree));
    ASSERT_FALSE(facesInput(start[1], x, strip, tree));
    Polygons P = start;
    EXPECT_EQ(absorbFlippedTriangles(P, x, strip, tree, 4), 0);
    EXPECT_EQ(P, start);
    EXPECT_EQ(absorbFlippedTriangles(P, x, strip, tree, 6), 1);
    EXPECT_EQ(P, (Polygons{{0, 1, 2, 3, 4}}));
    // A sound triangle is left alone.
    Polygons Q = {{0, 2, 3, 4}, {0, 1, 2}};
    const std::vector<Vec3> y = {{0, 0, 0}, {1, -0.5, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    EXPECT_EQ(absorbFlippedTriangles(Q, y, strip, tree, 6), 0);
}

// A 3 × 3 grid of unit quads on the plane z = 0 (vertex j · 4 + i at (i, j)) whose
// middle quad (5, 6, 10, 9) is folded: corner 5 pulled past corner 10, 0.14 away.
// Its diagonal 5–10 collapses: the quad goes, 5 and 10 become one vertex at their
// midpoint, the sides 5–6 / 6–10 and 5–9 / 9–10 become one edge each.
TEST(CollapseFoldedDiagonals, AQuadFoldedAlongItsShortDiagonalGoes) {
    const field::Mesh plane = field::Mesh::fromTriangles({{-1, -1, 0}, {4, -1, 0}, {4, 4, 0}, {-1, 4, 0}},
                                                          {{0, 1, 2}, {0, 2, 3}}, "plane");
    const AabbTree tree(plane);
    std::vector<Vec3> start;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) start.push_back(Vec3(i, j, 0));
    start[5] = Vec3(2.1, 2.1, 0);
    Polygons grid;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) grid.push_back({j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i});
    ASSERT_FALSE(facesInput(grid[4], start, plane, tree));
    for (size_t f = 0; f < grid.size(); ++f)
        if (f != 4) {
            ASSERT_TRUE(facesInput(grid[f], start, plane, tree)) << f;
        }
    auto none = [](size_t) { return false; };
    // Both ends fixed (corners of a crease): left alone; a diagonal longer than the limit too.
    {
        Polygons P = grid;
        std::vector<Vec3> x = start;
        EXPECT_EQ(collapseFoldedDiagonals(P, x, plane, tree, 0.5, [](size_t v) { return v == 5 || v == 10; }), 0);
        EXPECT_EQ(collapseFoldedDiagonals(P, x, plane, tree, 0.1, none), 0);
        EXPECT_EQ(P, grid);
        EXPECT_EQ(x, start);
    }
    Polygons P = grid;
    std::vector<Vec3> x = start;
    EXPECT_EQ(collapseFoldedDiagonals(P, x, plane, tree, 0.5, none), 1);
    ASSERT_EQ(P.size(), 8u);
    EXPECT_FALSE(uses(P, 10));
    EXPECT_NEAR((x[5] - Vec3(2.05, 2.05, 0)).norm(), 0.0, 1e-12);
    for (const auto &f : P) EXPECT_TRUE(facesInput(f, x, plane, tree));
    // An open patch: each directed edge in one face, the corners at the merged
    // vertex (interior) one cycle, χ still 1.
    const Shape s = shapeOf(P);
    std::map<int, int> nextAfter;
    for (const auto &f : P)
        for (size_t k = 0; k < f.size(); ++k)
            if (f[k] == 5) {
                EXPECT_TRUE(nextAfter.emplace(f[(k + f.size() - 1) % f.size()], f[(k + 1) % f.size()]).second);
            }
    ASSERT_EQ(nextAfter.size(), 6u); // the three other quads at 5 and the three at 10
    int steps = 0;
    for (int w = nextAfter.begin()->first; steps < 7; ++steps) {
        ASSERT_TRUE(nextAfter.count(w));
        w = nextAfter[w];
        if (w == nextAfter.begin()->first) break;
    }
    EXPECT_EQ(steps + 1, 6);
    EXPECT_EQ(s.usedVertices, 15);
    EXPECT_EQ(s.edges, 22);
    EXPECT_EQ(s.chi(), 1);
    std::set<std::pair<int, int>> directed;
    for (const auto &f : P)
        for (size_t k = 0; k < f.size(); ++k) EXPECT_TRUE(directed.insert({f[k], f[(k + 1) % f.size()]}).second);
    // The end that is fixed is the one kept, where it is.
    Polygons Q = grid;
    std::vector<Vec3> y = start;
    EXPECT_EQ(collapseFoldedDiagonals(Q, y, plane, tree, 0.5, [](size_t v) { return v == 10; }), 1);
    EXPECT_FALSE(uses(Q, 5));
    EXPECT_EQ(y[10], start[10]);
    for (const auto &f : Q) EXPECT_TRUE(facesInput(f, y, plane, tree));
}

// A folded quad whose two ends have another common neighbour (a triangle 5–10–x
// beside it would be doubled) is left alone: the mesh must stay manifold.
TEST(CollapseFoldedDiagonals, EndsWithAnotherCommonNeighbourStay) {
    const field::Mesh plane = field::Mesh::fromTriangles({{-1, -1, 0}, {4, -1, 0}, {4, 4, 0}, {-1, 4, 0}},
                                                          {{0, 1, 2}, {0, 2, 3}}, "plane");
    const AabbTree tree(plane);
    // Folded quad (0, 1, 2, 3) with 0 near 2, and triangles (0, 4, 2)... sharing 4.
    const std::vector<Vec3> x = {{1.1, 1.1, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 2, 0}};
    const Polygons start = {{0, 1, 2, 3}, {2, 4, 0}};
    ASSERT_FALSE(facesInput(start[0], x, plane, tree));
    Polygons P = start;
    std::vector<Vec3> y = x;
    EXPECT_EQ(collapseFoldedDiagonals(P, y, plane, tree, 0.5, [](size_t) { return false; }), 0);
    EXPECT_EQ(P, start);
}

// A hole shaped like a thin L (arms 4 long and 0.5 wide, eight corners) on the plane
// z = 0: its centroid lies in the notch, outside it, so the fan from there turns
// the triangles over the notch's sides over (it is what fillHole kept before, and
// what left flipped quads on CGAL's anchor, joint and rotor). It is cut into ears:
// no new vertex, every triangle facing +z, together covering the L once.
TEST(FillHole, AThinLIsCutIntoEarsNotFannedFromOutside) {
    const field::Mesh plane = field::Mesh::fromTriangles({{-1, -1, 0}, {5, -1, 0}, {5, 5, 0}, {-1, 5, 0}},
                                                          {{0, 1, 2}, {0, 2, 3}}, "plane");
    const AabbTree tree(plane);
    const std::vector<Vec3> start = {{0, 0, 0}, {2, 0, 0},   {4, 0, 0}, {4, 0.5, 0},
                                     {0.5, 0.5, 0}, {0.5, 4, 0}, {0, 4, 0}, {0, 2, 0}};
    const std::vector<int> hole = {0, 1, 2, 3, 4, 5, 6, 7};
    auto signedArea = [](const std::vector<int> &t, const std::vector<Vec3> &x) { return 0.5 * vectorArea(t, x).z(); };
    // The fan from the centroid turns over.
    std::vector<Vec3> withCentre = start;
    Vec3 c = Vec3::Zero();
    for (const Vec3 &p : start) c += p;
    withCentre.push_back(c / 8.0);
    ASSERT_LT(signedArea({8, 3, 4}, withCentre), 0);

    std::vector<Vec3> x = start;
    bool byEars = false;
    const Polygons tris = fillHole(hole, x, plane, tree, [](int, int) { return false; }, byEars);
    EXPECT_TRUE(byEars);
    EXPECT_EQ(x.size(), start.size()); // no centre
    ASSERT_EQ(tris.size(), 6u);
    double area = 0;
    for (const auto &t : tris) {
        EXPECT_GT(signedArea(t, x), 0);
        area += signedArea(t, x);
    }
    EXPECT_NEAR(area, signedArea(hole, x), 1e-12); // 3.75: each point of the L covered once

    // A convex hole keeps its fan, as before.
    std::vector<Vec3> y = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {0, 2, 0}, {0, 1, 0}};
    const Polygons fan = fillHole(hole, y, plane, tree, [](int, int) { return false; }, byEars);
    EXPECT_FALSE(byEars);
    EXPECT_EQ(fan.size(), 8u);
    EXPECT_EQ(y.size(), 9u);
}

// A closed cube (4 × 4 grid of squares per side, each cut in two) whose top-centre
// vertex is dragged 0.8 across its ring of radius 0.5: triangles of its fan turn over
// and moving the vertex back is not allowed (fixed). The patch of the turned faces and
// those beside them is cut out and filled again around the fixed vertex: nothing
// flipped, the cube closed, manifold, χ 2.
TEST(RefillFlippedPatches, ATriangleFanTurnedOverOnACubeIsRefilled) {
    const field::Mesh cube = field::makeCube(4);
    const AabbTree tree(cube);
    std::vector<Vec3> x = cube.positions();
    Polygons P;
    for (const field::Face &f : cube.faces()) P.push_back({f[0], f[1], f[2]});
    int top = -1;
    for (int v = 0; v < cube.nVertices(); ++v)
        if ((x[size_t(v)] - Vec3(0, 0, 1)).norm() < 1e-12) top = v;
    ASSERT_GE(top, 0);
    x[size_t(top)] = Vec3(0.8, 0.1, 1);
    int flipped = 0;
    for (const auto &f : P) flipped += !facesInput(f, x, cube, tree);
    ASSERT_GT(flipped, 0);
    const auto fixed = [&](size_t v) { return int(v) == top; };
    EXPECT_EQ(untangleFlipped(P, x, cube, tree, 0.5, fixed), 0); // the old step cannot
    EXPECT_GE(refillFlippedPatches(P, x, cube, tree, 0.5, fixed), 1);
    for (const auto &f : P) EXPECT_TRUE(facesInput(f, x, cube, tree));
    expectSound(P, 2);
    EXPECT_TRUE(uses(P, top)); // the fixed vertex is kept: the fan is from it
}

// A closed tetrahedron of edge about `size` centred at c, oriented outward.
void addTetrahedron(Polygons &P, std::vector<Vec3> &x, const Vec3 &c, double size) {
    const int b = int(x.size());
    const double h = 0.5 * size;
    x.push_back(c + Vec3(h, h, h));
    x.push_back(c + Vec3(h, -h, -h));
    x.push_back(c + Vec3(-h, h, -h));
    x.push_back(c + Vec3(-h, -h, h));
    for (const std::array<int, 3> &t : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}})
        P.push_back({b + t[0], b + t[1], b + t[2]});
}

TEST(RemoveStrayPieces, ASpeckOnACoveredComponentOrEnclosedGoesAPieceOfItsOwnComponentStays) {
    // Input: the cube [-1, 1]^3 and a small cube (half-side 0.1) at x = 5.
    const field::Mesh big = field::makeCube(4), small = field::makeCube(1);
    std::vector<Vec3> inPoints = big.positions();
    std::vector<field::Face> inFaces = big.faces();
    for (const Vec3 &p : small.positions()) inPoints.push_back(0.1 * p + Vec3(5, 0, 0));
    for (field::Face f : small.faces()) {
        for (int &v : f) v += big.nVertices();
        inFaces.push_back(f);
    }
    const field::Mesh input = field::Mesh::fromTriangles(inPoints, inFaces);
    const AabbTree tree(input);
    const double L = 0.05; // strays are below 16 L² = 0.04
    // Output: the input's faces, then three more pieces.
    std::vector<Vec3> x = input.positions();
    Polygons P;
    for (const field::Face &f : input.faces()) P.push_back({f[0], f[1], f[2]});
    const size_t nInput = P.size();
    const int speck = int(x.size());
    addTetrahedron(P, x, Vec3(0.2, 0.3, 0.98), 0.05); // a speck on the big cube's top (area 0.004)
    const int piece = int(x.size());
    addTetrahedron(P, x, Vec3(-0.5, 0.0, -0.8), 0.5); // a piece of area 0.43 on it: surface, stays
    const int apart = int(x.size());
    addTetrahedron(P, x, Vec3(0.0, 0.0, 1.3), 0.05); // as small, but 0.3 (6 L) off the rest: stays
    const int inside = int(x.size());
    addTetrahedron(P, x, Vec3(0.1, -0.2, 0.0), 0.05); // as small, 0.8 off the rest but inside the big cube: goes
    // The small cube's faces are the only piece on it and stay, though their area
    // (0.24) is below the second tetrahedron's.
    EXPECT_EQ(removeStrayPieces(P, x, input, tree, L), 2);
    ASSERT_EQ(P.size(), nInput + 8);
    for (size_t f = 0; f < nInput; ++f)
        EXPECT_EQ(P[f], (std::vector<int>{input.faces()[f][0], input.faces()[f][1], input.faces()[f][2]}));
    for (int v = speck; v < speck + 4; ++v) EXPECT_FALSE(uses(P, v)) << "the speck's corner " << v;
    for (int v = piece; v < piece + 4; ++v) EXPECT_TRUE(uses(P, v)) << "the larger piece's corner " << v;
    for (int v = apart; v < apart + 4; ++v) EXPECT_TRUE(uses(P, v)) << "the piece apart's corner " << v;
    for (int v = inside; v < inside + 4; ++v) EXPECT_FALSE(uses(P, v)) << "the enclosed speck's corner " << v;
    // Nothing more goes on a second call; a lone piece is never a stray.
    EXPECT_EQ(removeStrayPieces(P, x, input, tree, L), 0);
    Polygons alone{{speck, speck + 1, speck + 2}};
    EXPECT_EQ(removeStrayPieces(alone, x, input, tree, L), 0);
    // An open surface bounds no solid: with a face of the big cube missing, the speck
    // inside stays.
    Polygons open;
    for (size_t f = 2; f < size_t(big.nFaces()); ++f) open.push_back(P[f]);
    for (const std::array<int, 3> &t : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}})
        open.push_back({inside + t[0], inside + t[1], inside + t[2]});
    EXPECT_EQ(removeStrayPieces(open, x, input, tree, L), 0);
}

// The unit square's sides and both diagonals, in the plane z = 0 (normals +z): the
// diagonals cross, one of them goes, the sides stay.
TEST(RemoveCrossingEdges, OneOfTwoCrossingDiagonalsGoesTheSidesStay) {
    const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    const std::vector<Vec3> n(4, Vec3(0, 0, 1));
    auto square = [] {
        std::vector<std::set<int>> g(4);
        for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 2}, {2, 1}, {1, 3}, {3, 0}, {0, 1}, {2, 3}}) {
            g[size_t(a)].insert(b);
            g[size_t(b)].insert(a);
        }
        return g;
    };
    std::vector<std::set<int>> g = square();
    EXPECT_EQ(removeCrossingEdges(g, findCrossingEdges(g, x, n), x, {}, 1.0), 1);
    EXPECT_NE(g[0].count(1), g[2].count(3)) << "exactly one diagonal is left";
    for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 2}, {2, 1}, {1, 3}, {3, 0}})
        EXPECT_TRUE(g[size_t(a)].count(b) && g[size_t(b)].count(a)) << a << "-" << b;
    // A feature vertex at 0 keeps the diagonal 0-1: 2-3 goes.
    g = square();
    EXPECT_EQ(removeCrossingEdges(g, findCrossingEdges(g, x, n), x, {1, 0, 0, 0}, 1.0), 1);
    EXPECT_TRUE(g[0].count(1));
    EXPECT_FALSE(g[2].count(3));
    // Feature vertices on both: neither goes.
    g = square();
    EXPECT_EQ(removeCrossingEdges(g, findCrossingEdges(g, x, n), x, {1, 0, 1, 0}, 1.0), 0);
    // The same drawing on two sheets (2 and 3 facing the other way, as across a thin
    // part): no crossing on the surface.
    g = square();
    const std::vector<Vec3> sheets = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0, 0, -1)};
    EXPECT_EQ(removeCrossingEdges(g, findCrossingEdges(g, x, sheets), x, {}, 1.0), 0);
}

} // namespace
} // namespace rosy::remesh

namespace rosy::remesh {
namespace {

// A 4 × 4 grid of unit quads on z = 0, counter-clockwise seen from +z: corner (i, j)
// is vertex gridId(i, j), the quads row by row.
int gridId(int i, int j) { return j * 5 + i; }
std::vector<Vec3> gridCorners() {
    std::vector<Vec3> x;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) x.push_back({double(i), double(j), 0});
    return x;
}
Polygons gridQuads() {
    Polygons grid;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            grid.push_back({gridId(i, j), gridId(i + 1, j), gridId(i + 1, j + 1), gridId(i, j + 1)});
    return grid;
}

// A roof: two planes at 45° meeting in a ridge along x (z = −|y|), faces outward.
field::Mesh roof() {
    return field::Mesh::fromTriangles({{-2, 0, 0}, {2, 0, 0}, {-2, 2, -2}, {2, 2, -2}, {-2, -2, -2}, {2, -2, -2}},
                                      {{0, 1, 3}, {0, 3, 2}, {1, 0, 4}, {1, 4, 5}}, "roof");
}

TEST(CutFarQuad, AQuadFoldedOverARidgeIsCutAlongTheRidge) {
    const field::Mesh input = roof();
    const AabbTree tree(input);
    // Corners 1 and 3 on the ridge, 0 and 2 down either side: the fan from corner 0
    // runs its diagonal 0–2 under the ridge, up to 0.8 / √2 = 0.57 from the roof (0.45
    // at the report's samples), farther than the repair's 0.4 L.
    const std::vector<Vec3> positions = {{0, 0.8, -0.8}, {-0.6, 0, 0}, {0, -0.8, -0.8}, {0.6, 0, 0}};
    const std::vector<int> quad = {0, 1, 2, 3};
    ASSERT_GT(farthestFromInput(quad, positions, tree, 1.0), 0.4);
    const std::vector<std::vector<int>> cut = cutFarQuad(quad, positions, input, tree, 1.0, 0.1, 0.4);
    ASSERT_EQ(cut.size(), 2u);
    EXPECT_EQ(cut[0], (std::vector<int>{1, 2, 3}));
    EXPECT_EQ(cut[1], (std::vector<int>{1, 3, 0}));
    for (const auto &t : cut) {
        EXPECT_LT(farthestFromInput(t, positions, tree, 1.0), 1e-9); // each on its side's plane
        EXPECT_TRUE(facesInput(t, positions, input, tree));
    }
}

TEST(CutFarQuad, AQuadAboveThePlaneOrThinIsNotCutAndATieTakesTheFirstDiagonal) {
    const field::Mesh plane = field::Mesh::fromTriangles({{-1, -1, 0}, {4, -1, 0}, {4, 4, 0}, {-1, 4, 0}},
                                                         {{0, 1, 2}, {0, 2, 3}}, "plane");
    const AabbTree tree(plane);
    // 0.6 above the plane: no diagonal brings a triangle within 0.4.
    const std::vector<Vec3> above = {{0, 0, 0.6}, {1, 0, 0.6}, {1, 1, 0.6}, {0, 1, 0.6}};
    EXPECT_TRUE(cutFarQuad({0, 1, 2, 3}, above, plane, tree, 1.0, 0.1, 0.4).empty());
    // On the plane both diagonals qualify equally: the first (from corner 0).
    const std::vector<Vec3> on = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    EXPECT_EQ(cutFarQuad({0, 1, 2, 3}, on, plane, tree, 1.0, 0.1, 0.4),
              (std::vector<std::vector<int>>{{0, 1, 2}, {0, 2, 3}}));
    // A sliver (altitudes at most 0.06 under a minimum of 0.1, whichever diagonal) and a
    // triangle are never cut.
    const std::vector<Vec3> sliver = {{0, 0, 0}, {1, 0, 0}, {2, 0.05, 0}, {1, 0.06, 0}};
    EXPECT_TRUE(cutFarQuad({0, 1, 2, 3}, sliver, plane, tree, 1.0, 0.1, 0.4).empty());
    EXPECT_TRUE(cutFarQuad({0, 1, 2}, on, plane, tree, 1.0, 0.1, 0.4).empty());
}

// A 5 × 5 grid of unit quads whose middle vertex c = (2, 2) has its spokes turned by
// 45°: to the four diagonal corners of its ring instead of the four beside it, so the
// ring alternates valence 3 (beside) and 5 (diagonal). Re-spoking puts the grid back:
// every interior valence 4, the four unit squares, c in the middle of its ring. Held
// (`fixed`), or with its ring already regular, nothing changes.
TEST(RespokeVertices, ASpokeSetTurnedByOneStepIsTurnedBack) {
    const field::Mesh plane = field::Mesh::fromTriangles({{-1, -1, 0}, {6, -1, 0}, {6, 6, 0}, {-1, 6, 0}},
                                                          {{0, 1, 2}, {0, 2, 3}}, "plane");
    const AabbTree tree(plane);
    auto id = [](int i, int j) { return j * 6 + i; };
    std::vector<Vec3> x;
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i) x.push_back({double(i), double(j), 0});
    const int c = id(2, 2);
    Polygons grid;
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i)
            if (!(i >= 1 && i <= 2 && j >= 1 && j <= 2)) grid.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    Polygons turned = grid;
    turned.push_back({c, id(3, 3), id(2, 3), id(1, 3)});
    turned.push_back({c, id(1, 3), id(1, 2), id(1, 1)});
    turned.push_back({c, id(1, 1), id(2, 1), id(3, 1)});
    turned.push_back({c, id(3, 1), id(3, 2), id(3, 3)});
    x[size_t(c)] = {2.3, 1.8, 0}; // off-centre, as the extraction leaves it

    Polygons held = turned;
    std::vector<Vec3> heldX = x;
    EXPECT_EQ(respokeVertices(held, heldX, tree, 1.0, [&](size_t v) { return int(v) == c; }), 0);
    EXPECT_EQ(held, turned);
    EXPECT_EQ(heldX, x);

    Polygons mended = turned;
    EXPECT_EQ(respokeVertices(mended, x, tree, 1.0, [](size_t) { return false; }), 1);
    EXPECT_EQ(mended.size(), turned.size());
    std::map<int, std::set<int>> nb;
    for (const auto &f : mended) {
        EXPECT_EQ(f.size(), 4u);
        for (size_t k = 0; k < f.size(); ++k) nb[f[k]].insert(f[(k + 1) % f.size()]), nb[f[(k + 1) % f.size()]].insert(f[k]);
    }
    for (int j = 1; j < 5; ++j)
        for (int i = 1; i < 5; ++i) EXPECT_EQ(nb[id(i, j)].size(), 4u) << i << "," << j;
    EXPECT_EQ(nb[c], (std::set<int>{id(1, 2), id(3, 2), id(2, 1), id(2, 3)}));
    EXPECT_NEAR((x[size_t(c)] - Vec3(2, 2, 0)).norm(), 0.0, 1e-12); // its ring's centroid, on the plane
    std::set<std::pair<int, int>> directed; // the grid is open: each directed edge in one face
    for (const auto &f : mended)
        for (size_t k = 0; k < f.size(); ++k) EXPECT_TRUE(directed.insert({f[k], f[(k + 1) % f.size()]}).second);
    EXPECT_EQ(shapeOf(mended).chi(), shapeOf(turned).chi());

    Polygons again = mended;
    EXPECT_EQ(respokeVertices(again, x, tree, 1.0, [](size_t) { return false; }), 0);
    EXPECT_EQ(again, mended);
}

// A 4 × 4 grid of unit quads on z = 0 over an input with a bump: a pyramid of height
// 0.2 whose apex x = (2.4, 2.2, 0.2) lies over the quad (2, 2)–(3, 3). The corner
// nearest x, (2, 2) (0.49 L), is moved onto it; held, the next nearest within 0.75 L,
// (3, 2) (0.66 L), is; with the quad not usable (it holds all four), or a limit no face
// can meet, nothing moves.
TEST(MoveCornerOnto, TheNearestFreeCornerTakesAFarPointTheGridKeepsItsFaces) {
    const Vec3 apex(2.4, 2.2, 0.2);
    const field::Mesh bump = field::Mesh::fromTriangles(
        {{-1, -1, 0}, {5, -1, 0}, {5, 5, 0}, {-1, 5, 0}, apex}, {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}, "bump");
    const AabbTree tree(bump);
    const auto id = gridId;
    const std::vector<Vec3> start = gridCorners();
    const Polygons grid = gridQuads();
    const std::vector<int> &quad = grid[size_t(2 * 4 + 2)];
    auto any = [](int) { return true; };
    std::vector<int> around;

    std::vector<Vec3> x = start;
    EXPECT_EQ(moveCornerOnto(quad, apex, grid, x, bump, tree, 1.0, 0.4, {}, any, around), id(2, 2));
    EXPECT_EQ(x[size_t(id(2, 2))], apex);
    EXPECT_EQ(around.size(), 4u);
    for (int v = 0; v < 25; ++v) {
        if (v != id(2, 2)) {
            EXPECT_EQ(x[size_t(v)], start[size_t(v)]);
        }
    }
    for (int f : around) EXPECT_TRUE(facesInput(grid[size_t(f)], x, bump, tree));

    x = start;
    EXPECT_EQ(moveCornerOnto(quad, apex, grid, x, bump, tree, 1.0, 0.4, [&](size_t v) { return int(v) == id(2, 2); },
                             any, around),
              id(3, 2));
    EXPECT_EQ(x[size_t(id(3, 2))], apex);

    x = start;
    EXPECT_EQ(moveCornerOnto(quad, apex, grid, x, bump, tree, 1.0, 0.4, {},
                             [&](int g) { return g != 2 * 4 + 2; }, around),
              -1);
    EXPECT_EQ(x, start);
    EXPECT_TRUE(around.empty());

    EXPECT_EQ(moveCornerOnto(quad, apex, grid, x, bump, tree, 1.0, 0.0, {}, any, around), -1); // no face that near
    EXPECT_EQ(x, start);
}

TEST(FanAcrossSide, APointBeyondASideIsFannedWithTheNeighbourThere) {
    // A 4 × 4 grid of unit quads on the plane z = 0 (the input). The point x lies in the
    // quad right of quad f, 0.2 from their shared side: f's own fan from x turns its
    // triangle on that side over, the fan of f and its right neighbour joined does not.
    const field::Mesh plane = field::Mesh::fromTriangles({{-1, -1, 0}, {5, -1, 0}, {5, 5, 0}, {-1, 5, 0}},
                                                         {{0, 1, 2}, {0, 2, 3}}, "plane");
    const AabbTree tree(plane);
    const auto id = gridId;
    const std::vector<Vec3> start = gridCorners();
    const Polygons grid = gridQuads();
    std::map<std::pair<int, int>, int> owner;
    for (size_t g = 0; g < grid.size(); ++g)
        for (size_t k = 0; k < 4; ++k) owner[{grid[g][k], grid[g][(k + 1) % 4]}] = int(g);
    auto across = [&](int a, int b) {
        const auto it = owner.find({a, b});
        return it == owner.end() ? -1 : it->second;
    };
    auto any = [](int) { return true; };
    const int f = 1 * 4 + 1, right = 1 * 4 + 2; // the quads (1..2, 1..2) and (2..3, 1..2)
    const Vec3 x(2.2, 1.5, 0);
    {
        std::vector<Vec3> p = start;
        p.push_back(x);
        const std::vector<int> beside = {int(p.size()) - 1, id(2, 1), id(2, 2)}; // f's fan triangle on the shared side
        EXPECT_FALSE(facesInput(beside, p, plane, tree));
    }

    std::vector<Vec3> p = start;
    const JoinedFan fan = fanAcrossSide(f, {x}, grid, p, across, any, plane, tree, 1.0, 0.1, 0.4);
    ASSERT_EQ(fan.neighbour, right);
    ASSERT_EQ(p.size(), start.size() + 1);
    EXPECT_EQ(p.back(), x);
    const int apex = int(start.size());
    // Six triangles round the apex over the 2 × 1 rectangle's six corners, each facing
    // the input, together its area, and the rectangle's boundary run counter-clockwise.
    ASSERT_EQ(fan.faces.size(), 6u);
    double area = 0;
    std::set<std::pair<int, int>> outer;
    for (const auto &t : fan.faces) {
        ASSERT_EQ(t.size(), 3u);
        EXPECT_EQ(t[0], apex);
        EXPECT_TRUE(facesInput(t, p, plane, tree));
        area += 0.5 * (p[size_t(t[1])] - p[size_t(t[0])]).cross(p[size_t(t[2])] - p[size_t(t[0])]).z();
        outer.insert({t[1], t[2]});
    }
    EXPECT_NEAR(area, 2.0, 1e-12);
    const std::set<std::pair<int, int>> rectangle = {{id(1, 1), id(2, 1)}, {id(2, 1), id(3, 1)}, {id(3, 1), id(3, 2)},
                                                     {id(3, 2), id(2, 2)}, {id(2, 2), id(1, 2)}, {id(1, 2), id(1, 1)}};
    EXPECT_EQ(outer, rectangle);

    // The right neighbour not to be replaced (or its side one that must stay): the
    // other sides' unions do not hold x, their fans turn over, nothing is made.
    p = start;
    EXPECT_EQ(fanAcrossSide(f, {x}, grid, p, across, [&](int g) { return g != right; }, plane, tree, 1.0, 0.1, 0.4)
                  .neighbour,
              -1);
    EXPECT_EQ(p, start);
    auto keepShared = [&](int a, int b) {
        return (a == id(2, 2) && b == id(2, 1)) ? -1 : across(a, b);
    };
    EXPECT_EQ(fanAcrossSide(f, {x}, grid, p, keepShared, any, plane, tree, 1.0, 0.1, 0.4).neighbour, -1);
    EXPECT_EQ(p, start);
    // Too thin a triangle (the apex 0.05 from the far side of the rectangle) is refused.
    EXPECT_EQ(fanAcrossSide(f, {Vec3(2.95, 1.5, 0)}, grid, p, across, any, plane, tree, 1.0, 0.1, 0.4).neighbour, -1);
    EXPECT_EQ(p, start);
}

} // namespace
} // namespace rosy::remesh
