// Tests of Mesh::fromTriangles (connectivity invariants) and mesh_stats.
#include "core/error.h"
#include "core/parallel.h"
#include "field/mesh.h"
#include "field/mesh/closest_point.h"
#include "field/mesh_stats.h"
#include "field/primitives.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

using namespace rosy;
using namespace rosy::field;

namespace {

// Two triangles forming the unit square, and a closed tetrahedron, both CCW outward.
std::vector<Vec3> tetraPositions() { return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }
std::vector<Face> tetraFaces() { return {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}; }

} // namespace

TEST(MeshFromTriangles, TwinIsAnInvolutionWithSwappedEnds) {
    Mesh m = makeGrid(4);
    for (int h = 0; h < m.nHalfedges(); ++h) {
        int t = m.twin(h);
        if (t < 0) continue;
        EXPECT_EQ(m.twin(t), h);
        EXPECT_EQ(m.tail(t), m.head(h));
        EXPECT_EQ(m.head(t), m.tail(h));
        EXPECT_EQ(m.edgeOf(t), m.edgeOf(h));
    }
}

namespace {

/// The message of the InputError fromTriangles() throws, or "" when it builds.
std::string buildError(std::vector<Vec3> positions, std::vector<Face> faces) {
    try {
        Mesh::fromTriangles(std::move(positions), std::move(faces), "m");
    } catch (const InputError &e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(MeshFromTriangles, NamesTheFirstBadVertexInOrderOnLargeMeshes) {
    // fromTriangles() checks vertices in parallel (in chunks of 1024); its message
    // must still name the first bad vertex, as a loop in vertex order would.
    const Mesh grid = makeGrid(80); // 6,561 vertices
    const int nV = grid.nVertices();
    ASSERT_GT(nV, 4 * 1024);
    // Unused vertices: copies inserted at 1500 and 5000 (faces re-indexed past them).
    auto withUnused = [&](std::vector<int> at) {
        std::vector<Vec3> positions;
        std::vector<int> newIndex(static_cast<size_t>(nV));
        for (int v = 0, k = 0; v < nV; ++v) {
            while (k < int(at.size()) && int(positions.size()) == at[size_t(k)]) {
                positions.push_back(grid.position(v));
                ++k;
            }
            newIndex[size_t(v)] = int(positions.size());
            positions.push_back(grid.position(v));
        }
        std::vector<Face> faces = grid.faces();
        for (Face &f : faces)
            for (int &v : f) v = newIndex[size_t(v)];
        return std::make_pair(positions, faces);
    };
    {
        auto [positions, faces] = withUnused({1500, 5000});
        EXPECT_NE(buildError(positions, faces).find("vertex 1500 is not used by any face"), std::string::npos)
            << buildError(positions, faces);
    }
    {
        auto [positions, faces] = withUnused({5000});
        EXPECT_NE(buildError(positions, faces).find("vertex 5000 is not used by any face"), std::string::npos);
    }
    // Faces that repeat a directed edge: two flipped faces; the first vertex with a
    // repeated outgoing edge is the smallest corner of the earlier one.
    {
        std::vector<Face> faces = grid.faces();
        const int early = 3000, late = int(faces.size()) - 500;
        for (int f : {late, early}) std::swap(faces[size_t(f)][1], faces[size_t(f)][2]);
        const int first = *std::min_element(faces[size_t(early)].begin(), faces[size_t(early)].end());
        ASSERT_LT(first, *std::min_element(faces[size_t(late)].begin(), faces[size_t(late)].end()));
        const std::string message = buildError(grid.positions(), faces);
        EXPECT_EQ(message.find("edge (" + std::to_string(first) + ", "), message.find("edge (")) << message;
        EXPECT_NE(message.find("is used in the same direction"), std::string::npos) << message;
    }
    EXPECT_EQ(buildError(grid.positions(), grid.faces()), "");
}

TEST(MeshFromTriangles, InteriorRingAnglesSumToTwoPiOnFlatGrid) {
    Mesh m = makeGrid(4);
    int interior = 0;
    for (int v = 0; v < m.nVertices(); ++v) {
        if (m.isBoundaryVertex(v)) continue;
        ++interior;
        double sum = 0;
        for (const int *h = m.outgoingBegin(v); h != m.outgoingEnd(v); ++h) {
            EXPECT_EQ(m.tail(*h), v);
            sum += m.cornerAngle(*h);
        }
        EXPECT_NEAR(sum, 2 * std::numbers::pi, 1e-12);
    }
    EXPECT_EQ(interior, 9); // (n-1)^2 for n = 4
}

// The kept corner angles and face normals: the per-element values, once, shared by
// copies, and the same when many threads ask at once.
TEST(MeshDerived, CornerAnglesAndFaceNormalsAreKeptOnceAndShared) {
    const Mesh m = makeGrid(40);
    const Mesh copy = m;
    std::vector<const std::vector<double> *> angles(16, nullptr);
    std::vector<const std::vector<Vec3> *> normals(16, nullptr);
    parallelFor(0, 16, [&](int64_t k) {
        angles[size_t(k)] = &(k % 2 ? copy : m).cornerAngles();
        normals[size_t(k)] = &(k % 2 ? copy : m).faceNormals();
    }, 1);
    for (int k = 1; k < 16; ++k) {
        EXPECT_EQ(angles[size_t(k)], angles[0]); // one vector, computed once
        EXPECT_EQ(normals[size_t(k)], normals[0]);
    }
    ASSERT_EQ(int(angles[0]->size()), m.nHalfedges());
    ASSERT_EQ(int(normals[0]->size()), m.nFaces());
    for (int h = 0; h < m.nHalfedges(); ++h) EXPECT_EQ((*angles[0])[size_t(h)], m.cornerAngle(h));
    for (int f = 0; f < m.nFaces(); ++f) EXPECT_EQ((*normals[0])[size_t(f)], m.faceNormal(f));
    // A flat grid: every interior vertex's corners sum to 2π, every normal is ±z.
    double sum = 0;
    for (const int *h = m.outgoingBegin(m.nVertices() / 2); h != m.outgoingEnd(m.nVertices() / 2); ++h)
        sum += (*angles[0])[size_t(*h)];
    EXPECT_NEAR(sum, 2 * std::numbers::pi, 1e-12);
    EXPECT_NEAR(std::abs((*normals[0])[0].z()), 1.0, 1e-12);
    const Mesh empty;
    EXPECT_TRUE(empty.cornerAngles().empty());
    EXPECT_TRUE(empty.faceNormals().empty());
}

TEST(MeshFromTriangles, RingsAreCounterClockwiseAndComplete) {
    Mesh m = makeGrid(3);
    std::vector<int> corners(m.nVertices(), 0);
    for (const Face &f : m.faces())
        for (int v : f) ++corners[v];
    for (int v = 0; v < m.nVertices(); ++v) {
        EXPECT_EQ(m.degree(v), corners[v]);
        // Consecutive outgoing edges turn left (+z) around v in the flat z = 0 plane.
        for (const int *h = m.outgoingBegin(v); h + 1 != m.outgoingEnd(v) && h != m.outgoingEnd(v); ++h)
            EXPECT_GT(m.vector(h[0]).cross(m.vector(h[1])).z(), 0);
    }
}

TEST(MeshFromTriangles, BoundaryVertexRingStartsWithBoundaryHalfedge) {
    Mesh m = makeGrid(3);
    int boundary = 0;
    for (int v = 0; v < m.nVertices(); ++v) {
        if (!m.isBoundaryVertex(v)) continue;
        ++boundary;
        EXPECT_TRUE(m.isBoundaryHalfedge(*m.outgoingBegin(v)));
        EXPECT_EQ(m.valence(v), m.degree(v) + 1);
    }
    EXPECT_EQ(boundary, 12); // 4n for n = 3
}

TEST(MeshFromTriangles, RejectsUncleanInput) {
    EXPECT_THROW(Mesh::fromTriangles(tetraPositions(), {{0, 0, 1}}), InputError);
    EXPECT_THROW(Mesh::fromTriangles(tetraPositions(), {{0, 1, 7}}), InputError);
    std::vector<Face> flipped = tetraFaces();
    std::swap(flipped[0][1], flipped[0][2]);
    EXPECT_THROW(Mesh::fromTriangles(tetraPositions(), flipped), InputError);
    // Isolated vertex 3.
    EXPECT_THROW(Mesh::fromTriangles(tetraPositions(), {{0, 1, 2}}), InputError);
    // Bow tie: vertex 0 has two fans.
    std::vector<Vec3> bow = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    EXPECT_THROW(Mesh::fromTriangles(bow, {{0, 1, 2}, {0, 3, 4}}), InputError);
    std::vector<Vec3> nan = tetraPositions();
    nan[2].y() = std::nan("");
    EXPECT_THROW(Mesh::fromTriangles(nan, tetraFaces()), InputError);
}

TEST(MeshStats, TetrahedronIsASphere) {
    Mesh m = Mesh::fromTriangles(tetraPositions(), tetraFaces());
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, 4);
    EXPECT_EQ(s.edges, 6);
    EXPECT_EQ(s.faces, 4);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.boundaryLoops, 0);
    EXPECT_EQ(s.genus, 0);
    EXPECT_EQ(s.boundsMin, Vec3(0, 0, 0));
    EXPECT_EQ(s.boundsMax, Vec3(1, 1, 1));
}

TEST(MeshStats, TwoDisjointPiecesAreTwoComponents) {
    // A tetrahedron (faces 0..3) and a lone triangle (face 4) far away.
    std::vector<Vec3> p = tetraPositions();
    p.push_back({5, 0, 0});
    p.push_back({6, 0, 0});
    p.push_back({5, 1, 0});
    std::vector<Face> f = tetraFaces();
    f.push_back({4, 5, 6});
    Mesh m = Mesh::fromTriangles(p, f);
    int n = 0;
    std::vector<int> comp = faceComponents(m, &n);
    EXPECT_EQ(n, 2);
    EXPECT_EQ(comp, (std::vector<int>{0, 0, 0, 0, 1}));
    EXPECT_EQ(componentEulerCharacteristics(m), (std::vector<int>{2, 1}));
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.eulerCharacteristic, 3);
    EXPECT_EQ(s.boundaryLoops, 1);
    EXPECT_EQ(s.genus, 0);
    std::vector<std::vector<int>> loops = boundaryLoops(m);
    ASSERT_EQ(loops.size(), 1u);
    EXPECT_EQ(loops[0], (std::vector<int>{12, 13, 14}));
}

TEST(MeshStats, GridBoundaryIsOneOrderedLoop) {
    const int n = 5;
    Mesh m = makeGrid(n);
    std::vector<std::vector<int>> loops = boundaryLoops(m);
    ASSERT_EQ(loops.size(), 1u);
    const std::vector<int> &loop = loops[0];
    ASSERT_EQ(int(loop.size()), 4 * n);
    EXPECT_EQ(loop[0], *std::min_element(loop.begin(), loop.end()));
    double length = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
        EXPECT_TRUE(m.isBoundaryHalfedge(loop[i]));
        EXPECT_EQ(m.head(loop[i]), m.tail(loop[(i + 1) % loop.size()]));
        length += m.vector(loop[i]).norm();
    }
    EXPECT_NEAR(length, 8.0, 1e-12); // perimeter of [-1, 1]^2
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.eulerCharacteristic, 1);
    EXPECT_EQ(s.genus, 0);
}

TEST(MeshStats, TorusHasGenusOne) {
    MeshStats s = computeStats(makeTorus(2, 0.5, 12, 8));
    EXPECT_EQ(s.eulerCharacteristic, 0);
    EXPECT_EQ(s.genus, 1);
    EXPECT_EQ(s.boundaryLoops, 0);
}

// closestPointOnTriangle against brute force: the minimum distance over a fine
// barycentric grid of the triangle is at least the function's (it is the minimum)
// and exceeds it by at most the grid's resolution.
TEST(ClosestPoint, MatchesABruteForceSearch) {
    uint32_t state = 12345u;
    auto uniform = [&]() { // xorshift32 in [-1, 1)
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return double(state) / 2147483648.0 - 1.0;
    };
    const int n = 200;
    for (int trial = 0; trial < 60; ++trial) {
        const Vec3 a(uniform(), uniform(), uniform()), b(uniform(), uniform(), uniform());
        // Every tenth triangle degenerate: c on the line through a and b.
        const Vec3 c = trial % 10 == 0 ? Vec3(a + 1.7 * (b - a)) : Vec3(uniform(), uniform(), uniform());
        const Vec3 p(2 * uniform(), 2 * uniform(), 2 * uniform());
        const Vec3 q = closestPointOnTriangle(p, a, b, c);
        ASSERT_TRUE(q.allFinite()) << trial;
        double brute = std::numeric_limits<double>::infinity();
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const Vec3 s = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
                brute = std::min(brute, (p - s).norm());
            }
        const double got = (p - q).norm();
        const double res = 2.0 * std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / n;
        EXPECT_LE(got, brute + 1e-12) << trial;
        EXPECT_GE(got, brute - res) << trial;
        // q lies on the triangle: inside its plane and its bounding box.
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(q[k], std::min({a[k], b[k], c[k]}) - 1e-12);
            EXPECT_LE(q[k], std::max({a[k], b[k], c[k]}) + 1e-12);
        }
    }
}
