/// \file input_refinement_test.cpp
/// remesh::refineCoarseInput(): which inputs are refined before their field.

#include "remesh/input_refinement.h"

#include "core/error.h"
#include "field/primitives.h"

#include <gtest/gtest.h>

using namespace rosy;

// A cube of twelve triangles against L = 0.1 (its faces 20 L wide) is refined to
// edges of at most 2 L; the same cube as a 16 × 16 grid per face (edges 0.125) is
// not at L = 0.1 and is at L = 0.05; a torus coarse around its tube is refined, one
// fine all over is not.
TEST(RefineCoarseInput, RefinesWhereLongEdgesCoverTheSurfaceOnly) {
    remesh::InputRefinement r;
    const field::Mesh coarse = field::makeCube(1);
    const field::Mesh a = remesh::refineCoarseInput(coarse, 0.1, 1'000'000, &r);
    EXPECT_TRUE(r.applied);
    EXPECT_EQ(r.longEdgeAreaFraction, 1.0);
    EXPECT_DOUBLE_EQ(r.maxEdge, 0.2);
    EXPECT_EQ(r.verticesBefore, 8);
    EXPECT_EQ(r.verticesAfter, a.nVertices());
    EXPECT_EQ(r.refinement.bisections, a.nVertices() - 8);
    for (int e = 0; e < a.nEdges(); ++e) EXPECT_LE(a.vector(a.edgeHalfedge(e)).norm(), 0.2);

    const field::Mesh grid = field::makeCube(16);
    const field::Mesh b = remesh::refineCoarseInput(grid, 0.1, 1'000'000, &r);
    EXPECT_FALSE(r.applied);
    EXPECT_EQ(r.longEdgeAreaFraction, 0.0);
    EXPECT_EQ(b.positions(), grid.positions());
    EXPECT_EQ(b.faces(), grid.faces());
    remesh::refineCoarseInput(grid, 0.05, 1'000'000, &r);
    EXPECT_TRUE(r.applied);

    // 200 × 6 quads around a torus of radii 1 and 0.3: the edges along the tube
    // (2π · 1.3 / 200 ≈ 0.041 outside, 0.022 inside) are short, those around it
    // (2π 0.3 / 6 ≈ 0.31) long: every face has a long edge, so it is refined at
    // L = 0.1; with 60 segments around the tube (0.031) no edge is long.
    remesh::refineCoarseInput(field::makeTorus(1.0, 0.3, 200, 6), 0.1, 1'000'000, &r);
    EXPECT_TRUE(r.applied);
    remesh::refineCoarseInput(field::makeTorus(1.0, 0.3, 200, 60), 0.1, 1'000'000, &r);
    EXPECT_FALSE(r.applied);
    EXPECT_LT(r.longEdgeAreaFraction, remesh::kRefineAreaFraction);

    EXPECT_THROW(remesh::refineCoarseInput(coarse, 0.0, 100), CheckFailure);
}
