// Procedural meshes: counts by closed-form formulas, χ by topology, volume and
// area against analytic values, outward orientation by signed volume.
#include "core/error.h"
#include "field/mesh_stats.h"
#include "field/primitives.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

using namespace rosy;
using namespace rosy::field;

namespace {


/// Divergence theorem: V = Σ p0 · (p1 × p2) / 6, positive for outward faces.
double signedVolume(const Mesh &m) {
    double v = 0;
    for (const Face &f : m.faces())
        v += m.position(f[0]).dot(m.position(f[1]).cross(m.position(f[2])));
    return v / 6;
}

double area(const Mesh &m) {
    double a = 0;
    for (int f = 0; f < m.nFaces(); ++f) a += m.faceArea(f);
    return a;
}

/// Number of distinct face normal directions (to 1e-9).
int distinctNormals(const Mesh &m) {
    std::set<std::array<long long, 3>> dirs;
    for (int f = 0; f < m.nFaces(); ++f) {
        Vec3 n = m.faceNormal(f);
        dirs.insert({std::llround(n.x() * 1e9), std::llround(n.y() * 1e9), std::llround(n.z() * 1e9)});
    }
    return int(dirs.size());
}

} // namespace

TEST(Icosphere, CountsFollowSubdivisionFormula) {
    for (int s = 0; s <= 3; ++s) {
        Mesh m = makeIcosphere(s, 2.0);
        const int p = 1 << (2 * s); // 4^s
        MeshStats st = computeStats(m);
        EXPECT_EQ(st.faces, 20 * p);
        EXPECT_EQ(st.edges, 30 * p);
        EXPECT_EQ(st.vertices, 10 * p + 2);
        EXPECT_EQ(st.eulerCharacteristic, 2);
        EXPECT_EQ(st.genus, 0);
        EXPECT_EQ(st.boundaryLoops, 0);
        EXPECT_GT(signedVolume(m), 0);
        for (const Vec3 &q : m.positions()) EXPECT_NEAR(q.norm(), 2.0, 1e-12);
    }
}

TEST(Icosphere, VolumeApproachesBall) {
    // An inscribed polyhedron: slightly below 4/3 π r³, within 2% at s = 3.
    const double v = signedVolume(makeIcosphere(3));
    EXPECT_LT(v, 4.0 / 3.0 * std::numbers::pi);
    EXPECT_GT(v, 0.98 * 4.0 / 3.0 * std::numbers::pi);
}

TEST(Ellipsoid, VolumeAndBoundsMatchSemiAxes) {
    Mesh m = makeEllipsoid(3, 3, 2, 1);
    EXPECT_NEAR(signedVolume(m), 4.0 / 3.0 * std::numbers::pi * 6, 0.02 * 4.0 / 3.0 * std::numbers::pi * 6);
    MeshStats s = computeStats(m);
    EXPECT_NEAR(s.boundsMax.x(), 3, 1e-12); // icosahedron vertices lie on the axes' planes
    EXPECT_EQ(s.eulerCharacteristic, 2);
}

TEST(Torus, CountsVolumeAndGenus) {
    const int nU = 32, nV = 16;
    Mesh m = makeTorus(2.0, 0.5, nU, nV);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, nU * nV);
    EXPECT_EQ(s.faces, 2 * nU * nV);
    EXPECT_EQ(s.edges, 3 * nU * nV);
    EXPECT_EQ(s.eulerCharacteristic, 0);
    EXPECT_EQ(s.genus, 1);
    // Pappus: V = 2π R · π r² for the smooth torus; the inscribed mesh loses
    // about 1 − (16/2π) sin(2π/16) ≈ 2.5% of the tube cross-section.
    const double exact = 2 * std::numbers::pi * 2.0 * std::numbers::pi * 0.25;
    EXPECT_LT(signedVolume(m), exact);
    EXPECT_GT(signedVolume(m), 0.95 * exact);
}

TEST(Genus2, IsAClosedOrientedDoubleTorus) {
    Mesh m = makeGenus2(16);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.eulerCharacteristic, -2);
    EXPECT_EQ(s.genus, 2);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.boundaryLoops, 0);
    EXPECT_GT(signedVolume(m), 0);
    for (int f = 0; f < m.nFaces(); ++f) EXPECT_GT(m.faceArea(f), 0);
    EXPECT_NEAR(s.boundsMax.x(), 1.0, 0.1);
    EXPECT_NEAR(s.boundsMin.x(), -1.0, 0.1);
}

TEST(Cube, CountsVolumeAndFlatFaces) {
    for (int n : {1, 3}) {
        Mesh m = makeCube(n);
        MeshStats s = computeStats(m);
        EXPECT_EQ(s.vertices, 6 * n * n + 2);
        EXPECT_EQ(s.faces, 12 * n * n);
        EXPECT_EQ(s.edges, 18 * n * n);
        EXPECT_EQ(s.eulerCharacteristic, 2);
        EXPECT_NEAR(signedVolume(m), 8.0, 1e-12);
        EXPECT_NEAR(area(m), 24.0, 1e-12);
        EXPECT_EQ(distinctNormals(m), 6);
    }
}

TEST(Platonic, EachSolidHasItsFaceCountAndSphereTopology) {
    struct Case {
        Platonic solid;
        int vertices, triangles, planes;
    };
    // Dodecahedron: 20 vertices + 12 pentagon centres, 12 × 5 triangles.
    const Case cases[] = {{Platonic::Tetrahedron, 4, 4, 4},
                          {Platonic::Cube, 8, 12, 6},
                          {Platonic::Octahedron, 6, 8, 8},
                          {Platonic::Dodecahedron, 32, 60, 12},
                          {Platonic::Icosahedron, 12, 20, 20}};
    for (const Case &c : cases) {
        for (int sub : {0, 1}) {
            Mesh m = makePlatonic(c.solid, sub);
            MeshStats s = computeStats(m);
            EXPECT_EQ(s.eulerCharacteristic, 2);
            EXPECT_EQ(s.faces, c.triangles * (sub ? 4 : 1));
            if (sub == 0) {
                EXPECT_EQ(s.vertices, c.vertices);
            }
            EXPECT_GT(signedVolume(m), 0);
            // Subdivision stays in the face planes.
            EXPECT_EQ(distinctNormals(m), c.planes);
        }
    }
    // Original corners lie on the unit sphere.
    const Mesh ico = makePlatonic(Platonic::Icosahedron);
    for (const Vec3 &p : ico.positions()) EXPECT_NEAR(p.norm(), 1, 1e-12);
}

TEST(Platonic, TetrahedronVolumeMatchesFormula) {
    // Regular tetrahedron inscribed in the unit sphere: edge a = sqrt(8/3), V = a³ / (6√2).
    const double a = std::sqrt(8.0 / 3.0);
    EXPECT_NEAR(signedVolume(makePlatonic(Platonic::Tetrahedron)), a * a * a / (6 * std::sqrt(2.0)), 1e-12);
}

TEST(Disk, IsAFlatTopologicalDisk) {
    const int rings = 6;
    Mesh m = makeDisk(rings);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.eulerCharacteristic, 1);
    EXPECT_EQ(s.boundaryLoops, 1);
    EXPECT_EQ(s.faces, 6 * rings * rings);
    EXPECT_EQ(s.vertices, 1 + 3 * rings * (rings + 1));
    for (int f = 0; f < m.nFaces(); ++f) EXPECT_NEAR(m.faceNormal(f).z(), 1.0, 1e-12);
    // Regular 36-gon inscribed in the unit circle: (n/2) sin(2π/n).
    EXPECT_NEAR(area(m), 18 * std::sin(2 * std::numbers::pi / 36), 1e-12);
    EXPECT_EQ(int(boundaryLoops(m)[0].size()), 6 * rings);
}

TEST(Grid, CountsAndArea) {
    Mesh m = makeGrid(7);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, 64);
    EXPECT_EQ(s.faces, 98);
    EXPECT_EQ(s.eulerCharacteristic, 1);
    EXPECT_EQ(s.boundaryLoops, 1);
    EXPECT_NEAR(area(m), 4.0, 1e-12);
}

TEST(Cylinder, IsAnAnnulusFacingOutward) {
    Mesh m = makeCylinder(0.5, 2.0, 24, 6);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.eulerCharacteristic, 0);
    EXPECT_EQ(s.boundaryLoops, 2);
    EXPECT_EQ(s.genus, 0);
    EXPECT_EQ(s.vertices, 24 * 7);
    for (int f = 0; f < m.nFaces(); ++f) {
        const Face &t = m.face(f);
        Vec3 c = (m.position(t[0]) + m.position(t[1]) + m.position(t[2])) / 3;
        EXPECT_GT(m.faceNormal(f).dot(Vec3(c.x(), c.y(), 0)), 0);
    }
    EXPECT_NEAR(s.boundsMax.z(), 1.0, 1e-12);
}

TEST(SubdivideMidpoint, QuadruplesFacesAndKeepsShape) {
    Mesh base = makeTorus(2, 0.5, 8, 6);
    Mesh m = subdivideMidpoint(base);
    MeshStats a = computeStats(base), b = computeStats(m);
    EXPECT_EQ(b.faces, 4 * a.faces);
    EXPECT_EQ(b.vertices, a.vertices + a.edges);
    EXPECT_EQ(b.edges, 2 * a.edges + 3 * a.faces);
    EXPECT_EQ(b.eulerCharacteristic, a.eulerCharacteristic);
    EXPECT_NEAR(signedVolume(m), signedVolume(base), 1e-9); // flat split: same solid
    for (int v = 0; v < base.nVertices(); ++v) EXPECT_EQ(m.position(v), base.position(v));
}

TEST(Primitives, RejectTooCoarseParameters) {
    EXPECT_THROW(makeTorus(1, 0.5, 2, 8), InputError);
    EXPECT_THROW(makeGenus2(8), InputError);
    EXPECT_THROW(makeGrid(0), InputError);
}
