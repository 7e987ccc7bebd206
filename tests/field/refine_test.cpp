/// \file refine_test.cpp
/// refineLongEdges(): a coarse mesh gets vertices at a chosen spacing on the same
/// surface (field/mesh/refine.h), checked against the input's own geometry.

#include "field/mesh/mesh_stats.h"
#include "field/mesh/refine.h"
#include "field/primitives.h"

#include "core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace rosy::field;

namespace {

double area(const Mesh &m) {
    double a = 0;
    for (int f = 0; f < m.nFaces(); ++f) a += m.faceArea(f);
    return a;
}

double longestEdge(const Mesh &m) {
    double l = 0;
    for (int e = 0; e < m.nEdges(); ++e) l = std::max(l, m.vector(m.edgeHalfedge(e)).norm());
    return l;
}

double smallestAngle(const Mesh &m) {
    double a = M_PI;
    for (int h = 0; h < m.nHalfedges(); ++h) a = std::min(a, m.cornerAngle(h));
    return a;
}

int boundaryEdges(const Mesh &m) {
    int n = 0;
    for (int h = 0; h < m.nHalfedges(); ++h) n += m.isBoundaryHalfedge(h);
    return n;
}

/// Distance from p to segment [a, b].
double toSegment(const Vec3 &p, const Vec3 &a, const Vec3 &b) {
    const Vec3 d = b - a;
    const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (a + t * d - p).norm();
}

} // namespace

// The cube of twelve triangles (the CGAL data's cube.off), refined to edges of 0.3:
// the same closed surface of area 24 with its eight corners where they were, every
// new vertex on the cube and every face in one of its faces (its normal one of the six
// axes), its edges bisected into pieces of at most 0.3, no angle below half the
// input's smallest, the same on every run.
TEST(RefineLongEdges, ACoarseCubeKeepsItsSurfaceAndGetsShortEdges) {
    const Mesh cube = makeCube(1);
    ASSERT_EQ(cube.nFaces(), 12);
    Refinement report;
    const Mesh fine = refineLongEdges(cube, 0.3, 1'000'000, &report);
    EXPECT_LE(longestEdge(fine), 0.3);
    EXPECT_GT(fine.nVertices(), 100);
    EXPECT_EQ(report.bisections, fine.nVertices() - cube.nVertices());
    EXPECT_NEAR(report.maxEdgeBefore, std::sqrt(8.0), 1e-12);
    EXPECT_NEAR(area(fine), area(cube), 1e-9);
    const MeshStats before = computeStats(cube), after = computeStats(fine);
    EXPECT_EQ(after.eulerCharacteristic, before.eulerCharacteristic);
    EXPECT_EQ(boundaryEdges(fine), 0);
    for (int v = 0; v < cube.nVertices(); ++v) EXPECT_EQ(fine.position(v), cube.position(v)) << v;
    for (int v = cube.nVertices(); v < fine.nVertices(); ++v)
        EXPECT_NEAR(fine.position(v).cwiseAbs().maxCoeff(), 1.0, 1e-12) << "vertex " << v << " is off the cube";
    // The input's edges are still there, bisected: every point along each holds a vertex
    // at most 0.3 away, and the points of each edge's vertices are on the edge.
    for (int e = 0; e < cube.nEdges(); ++e) {
        const int h = cube.edgeHalfedge(e);
        const Vec3 a = cube.position(cube.tail(h)), b = cube.position(cube.head(h));
        int onIt = 0;
        for (int v = 0; v < fine.nVertices(); ++v) onIt += toSegment(fine.position(v), a, b) < 1e-12;
        EXPECT_GE(onIt, int(std::ceil((b - a).norm() / 0.3)) + 1) << "edge " << e;
    }
    for (int f = 0; f < fine.nFaces(); ++f) {
        const Vec3 n = fine.faceNormal(f);
        EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-9) << "face " << f << " leaves the cube's faces";
    }
    EXPECT_GE(smallestAngle(fine), 0.5 * smallestAngle(cube) - 1e-12);
    const Mesh again = refineLongEdges(cube, 0.3, 1'000'000);
    ASSERT_EQ(again.nFaces(), fine.nFaces());
    EXPECT_EQ(again.faces(), fine.faces());
    EXPECT_EQ(again.positions(), fine.positions());
}

// An open grid keeps its boundary: the boundary edges are the input's, bisected.
TEST(RefineLongEdges, AnOpenMeshKeepsItsBoundaryAndAShortMeshIsLeftAlone) {
    const Mesh grid = makeGrid(4);
    const MeshStats before = computeStats(grid);
    const double l = longestEdge(grid);
    const Mesh same = refineLongEdges(grid, 1.01 * l, 1'000'000);
    EXPECT_EQ(same.faces(), grid.faces());
    EXPECT_EQ(same.positions(), grid.positions());
    const Mesh fine = refineLongEdges(grid, 0.26 * l, 1'000'000);
    const MeshStats after = computeStats(fine);
    EXPECT_EQ(after.eulerCharacteristic, before.eulerCharacteristic);
    EXPECT_EQ(after.boundaryLoops, before.boundaryLoops);
    EXPECT_GT(boundaryEdges(fine), 2 * boundaryEdges(grid));
    EXPECT_NEAR(area(fine), area(grid), 1e-9);
}

TEST(RefineLongEdges, MoreVerticesThanAllowedIsAnInputError) {
    const Mesh cube = makeCube(1);
    try {
        refineLongEdges(cube, 0.01, 5000);
        ADD_FAILURE() << "no error";
    } catch (const rosy::InputError &e) {
        EXPECT_NE(std::string(e.what()).find("5000"), std::string::npos) << e.what();
    }
    EXPECT_THROW(refineLongEdges(cube, 0.0, 100), rosy::CheckFailure);
}

namespace {

/// Whether faces f and g lie in one plane (unit normals within 1e-6 rad).
bool coplanar(const Mesh &m, int f, int g) { return m.faceNormal(f).dot(m.faceNormal(g)) > std::cos(1e-6); }

/// The interior edges between coplanar faces whose two opposite angles sum to more
/// than π (plus a rounding slack): not locally Delaunay.
int nonDelaunayFlatEdges(const Mesh &m) {
    int n = 0;
    for (int h = 0; h < m.nHalfedges(); ++h) {
        const int t = m.twin(h);
        if (t < h) continue; // boundary (-1) or counted from the twin
        if (!coplanar(m, Mesh::faceOf(h), Mesh::faceOf(t))) continue;
        // The corner opposite halfedge h is the one at the third vertex of its face.
        const int oppH = 3 * Mesh::faceOf(h) + (h % 3 + 2) % 3, oppT = 3 * Mesh::faceOf(t) + (t % 3 + 2) % 3;
        n += m.cornerAngle(oppH) + m.cornerAngle(oppT) > M_PI + 1e-7;
    }
    return n;
}

} // namespace

// A rectangle 20 × 1 cut as CAD exporters do, in a fan from one corner over its
// bottom side split in five, bisected to edges of at most 0.5: fans of needles that
// bisection keeps. Flipped, its flat edges are all Delaunay, its smallest angle is
// several times larger, and the vertices, the boundary and the area are the same.
TEST(FlipCoplanarToDelaunay, NeedlesOfABisectedFanBecomeDelaunayOnTheSameVertices) {
    std::vector<Vec3> corners = {Vec3(0, 1, 0)};
    std::vector<Face> fan;
    for (int i = 0; i <= 5; ++i) corners.push_back(Vec3(4.0 * i, 0, 0));
    corners.push_back(Vec3(20, 1, 0));
    for (int i = 1; i <= 6; ++i) fan.push_back(Face{0, i, i + 1});
    const Mesh strip = Mesh::fromTriangles(corners, fan, "fan");
    const Mesh needles = refineLongEdges(strip, 0.5, 1'000'000);
    ASSERT_GT(nonDelaunayFlatEdges(needles), 10) << "the case does not test anything";
    int flips = -1;
    const Mesh flipped = flipCoplanarToDelaunay(needles, &flips);
    EXPECT_GT(flips, 10);
    EXPECT_EQ(nonDelaunayFlatEdges(flipped), 0);
    EXPECT_EQ(flipped.positions(), needles.positions());
    EXPECT_EQ(flipped.nFaces(), needles.nFaces());
    EXPECT_NEAR(area(flipped), area(strip), 1e-9);
    EXPECT_EQ(boundaryEdges(flipped), boundaryEdges(needles));
    EXPECT_EQ(computeStats(flipped).eulerCharacteristic, computeStats(strip).eulerCharacteristic);
    EXPECT_GT(smallestAngle(flipped), 3.0 * smallestAngle(needles));
    for (int f = 0; f < flipped.nFaces(); ++f) EXPECT_GT(flipped.faceNormal(f).z(), 1.0 - 1e-12) << f;
    const Mesh again = flipCoplanarToDelaunay(needles);
    EXPECT_EQ(again.faces(), flipped.faces());
}

// Creases stay: a cube refined and flipped keeps every face in one of its six faces
// and all its edges' points; a folded strip (two planes 30° apart) flips within each
// plane only. A grid of squares cut by diagonals is cocircular everywhere: no flip
// (and no endless flipping back and forth).
TEST(FlipCoplanarToDelaunay, CreasesAndCocircularPointsAreLeftAlone) {
    const Mesh cube = refineLongEdges(makeCube(1), 0.3, 1'000'000);
    const Mesh flippedCube = flipCoplanarToDelaunay(cube);
    EXPECT_EQ(nonDelaunayFlatEdges(flippedCube), 0);
    for (int f = 0; f < flippedCube.nFaces(); ++f)
        EXPECT_NEAR(flippedCube.faceNormal(f).cwiseAbs().maxCoeff(), 1.0, 1e-9) << "face " << f << " crosses a crease";
    EXPECT_NEAR(area(flippedCube), 24.0, 1e-9);

    // The fan above and its mirror image below y = 0, sharing the split bottom side,
    // the lower one turned by 30° about that line: flips happen within each plane only.
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    std::vector<Vec3> points = {Vec3(0, 1, 0), Vec3(20, 1, 0), Vec3(0, -c, -s), Vec3(20, -c, -s)};
    for (int i = 0; i <= 5; ++i) points.push_back(Vec3(4.0 * i, 0, 0)); // shared: 4 + i
    std::vector<Face> faces;
    for (int i = 0; i < 5; ++i) faces.push_back(Face{0, 4 + i, 5 + i});
    faces.push_back(Face{0, 9, 1});
    for (int i = 0; i < 5; ++i) faces.push_back(Face{2, 5 + i, 4 + i});
    faces.push_back(Face{2, 3, 9});
    const Mesh bentNeedles = refineLongEdges(Mesh::fromTriangles(points, faces, "fold"), 0.5, 1'000'000);
    ASSERT_GT(nonDelaunayFlatEdges(bentNeedles), 10);
    const Mesh folded = flipCoplanarToDelaunay(bentNeedles);
    EXPECT_EQ(nonDelaunayFlatEdges(folded), 0);
    for (int f = 0; f < folded.nFaces(); ++f) {
        const Vec3 n = folded.faceNormal(f);
        EXPECT_TRUE(n.z() > 1 - 1e-9 || n.dot(Vec3(0, -s, c)) > 1 - 1e-9) << "face " << f << " crosses the fold";
    }
    EXPECT_NEAR(area(folded), 40.0, 1e-9);

    const Mesh grid = makeGrid(6);
    int flips = -1;
    const Mesh same = flipCoplanarToDelaunay(grid, &flips);
    EXPECT_EQ(flips, 0);
    EXPECT_EQ(same.faces(), grid.faces());
}
