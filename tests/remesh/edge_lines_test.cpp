// remesh::edgeLines(): the lines of a quad mesh, their parity and their families.
// Expected values come from the meshes' construction (a grid, a torus grid), not
// from the code: rows and columns, which neighbours alternate, and which circles of
// a torus turn the normal faster (the tube's, 1/r against at most 1/(R − r)·(r/R)).

#include "remesh/edge_lines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace rosy;
using remesh::EdgeLine;

namespace {

/// A flat nx × ny grid of unit quads in the xy plane (z = 0), counter-clockwise
/// seen from +z.
field::PolyMesh grid(int nx, int ny) {
    std::vector<field::Vec3> p;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) p.emplace_back(i, j, 0);
    std::vector<std::vector<int>> quads;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const int a = j * (nx + 1) + i;
            quads.push_back({a, a + 1, a + nx + 2, a + nx + 1});
        }
    return field::polyMeshFromPolygons(p, quads, "grid");
}

/// A torus of nu × nv quads: tube radius r around a circle of radius R in the xy
/// plane; u goes round the axis (parallels), v round the tube (meridians).
field::PolyMesh torus(int nu, int nv, double R, double r) {
    std::vector<field::Vec3> p;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            p.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
        }
    auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
    std::vector<std::vector<int>> quads;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    return field::polyMeshFromPolygons(p, quads, "torus");
}

size_t segments(const EdgeLine &l) { return l.closed ? l.points.size() : l.points.size() - 1; }

} // namespace

TEST(EdgeLines, GridRowsAndColumnsAlternateInParity) {
    const int nx = 4, ny = 3;
    const std::vector<EdgeLine> lines = remesh::edgeLines(grid(nx, ny));
    // ny + 1 rows of nx edges and nx + 1 columns of ny edges: every edge once.
    ASSERT_EQ(lines.size(), size_t((ny + 1) + (nx + 1)));
    size_t edges = 0;
    std::map<int, int> rowParity, columnParity;
    for (const EdgeLine &l : lines) {
        EXPECT_FALSE(l.closed);
        ASSERT_EQ(l.normals.size(), l.points.size());
        ASSERT_EQ(l.families.size(), segments(l));
        edges += segments(l);
        for (const field::Vec3 &n : l.normals) EXPECT_NEAR(n.z(), 1.0, 1e-12); // counter-clockwise from +z
        const bool row = l.points.front().y() == l.points.back().y();
        if (row) {
            EXPECT_EQ(l.points.size(), size_t(nx + 1));
            for (const field::Vec3 &q : l.points) EXPECT_EQ(q.y(), l.points.front().y());
            rowParity[int(l.points.front().y())] = l.parity;
        } else {
            EXPECT_EQ(l.points.size(), size_t(ny + 1));
            for (const field::Vec3 &q : l.points) EXPECT_EQ(q.x(), l.points.front().x());
            columnParity[int(l.points.front().x())] = l.parity;
        }
    }
    EXPECT_EQ(edges, size_t(nx * (ny + 1) + ny * (nx + 1)));
    ASSERT_EQ(rowParity.size(), size_t(ny + 1));
    ASSERT_EQ(columnParity.size(), size_t(nx + 1));
    for (int y = 0; y < ny; ++y) EXPECT_NE(rowParity[y], rowParity[y + 1]) << "rows " << y << ", " << y + 1;
    for (int x = 0; x < nx; ++x) EXPECT_NE(columnParity[x], columnParity[x + 1]) << "columns " << x << ", " << x + 1;
}

TEST(EdgeLines, TorusLinesAreClosedAndTheTubesCirclesAreFamilyZero) {
    const int nu = 24, nv = 12;
    const double R = 3.0, r = 1.0;
    const std::vector<EdgeLine> lines = remesh::edgeLines(torus(nu, nv, R, r));
    ASSERT_EQ(lines.size(), size_t(nu + nv)); // nu meridians, nv parallels
    int meridians = 0, parallels = 0;
    for (const EdgeLine &l : lines) {
        EXPECT_TRUE(l.closed);
        ASSERT_EQ(l.families.size(), segments(l));
        // A meridian stays at one angle u round the axis: its points keep y / x.
        const double u0 = std::atan2(l.points[0].y(), l.points[0].x());
        bool meridian = true;
        for (const field::Vec3 &q : l.points)
            if (std::abs(std::remainder(std::atan2(q.y(), q.x()) - u0, 2 * M_PI)) > 1e-9) meridian = false;
        if (meridian) {
            ++meridians;
            EXPECT_EQ(l.points.size(), size_t(nv));
            for (int f : l.families) EXPECT_EQ(f, 0) << "the tube's circles turn the normal fastest";
        } else {
            ++parallels;
            EXPECT_EQ(l.points.size(), size_t(nu));
            for (int f : l.families) EXPECT_EQ(f, 1);
        }
    }
    EXPECT_EQ(meridians, nu);
    EXPECT_EQ(parallels, nv);
    // Neighbouring parallels alternate in parity (nv even: no odd cycle).
    std::map<int, int> parityAtHeight;
    for (const EdgeLine &l : lines)
        if (l.points.size() == size_t(nu)) {
            const double v = std::atan2(l.points[0].z(), std::hypot(l.points[0].x(), l.points[0].y()) - R);
            parityAtHeight[int(std::lround(v / (2 * M_PI) * nv + nv)) % nv] = l.parity;
        }
    ASSERT_EQ(parityAtHeight.size(), size_t(nv));
    for (int j = 0; j < nv; ++j) EXPECT_NE(parityAtHeight[j], parityAtHeight[(j + 1) % nv]) << j;
}

TEST(EdgeLines, LinesEndAtIrregularVerticesWhereEveryWayOnTurns) {
    // A cube: every vertex has valence 3 and every way on turns by 90°, so lines
    // end at each corner and each of its 12 edges is a line of its own.
    std::vector<field::Vec3> p;
    for (int k = 0; k < 8; ++k) p.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const std::vector<std::vector<int>> quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                 {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const std::vector<EdgeLine> lines = remesh::edgeLines(field::polyMeshFromPolygons(p, quads, "cube"));
    ASSERT_EQ(lines.size(), 12u);
    for (const EdgeLine &l : lines) {
        EXPECT_EQ(l.points.size(), 2u);
        EXPECT_FALSE(l.closed);
    }
}
