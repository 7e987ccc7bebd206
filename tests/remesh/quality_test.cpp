/// \file quality_test.cpp
/// The quality checks (remesh/quality.h) and the closest-point tree on inputs
/// whose answers are known by construction.

#include "field/field_builder.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "remesh/aabb_tree.h"
#include "remesh/quality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rosy::remesh {
namespace {

using field::Mesh;

TEST(AabbTree, ClosestPointMatchesDenseSampling) {
    const Mesh mesh = field::makeIcosphere(2);
    const AabbTree tree(mesh);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.6, 1.6);
    for (int trial = 0; trial < 40; ++trial) {
        const Vec3 p(u(rng), u(rng), u(rng));
        const ClosestPoint c = tree.closest(p);
        // Brute force over a dense barycentric grid of every triangle: an upper bound
        // on the true distance, at most the grid spacing above it.
        double best = 1e300;
        const int k = 24;
        for (int f = 0; f < mesh.nFaces(); ++f) {
            const auto &t = mesh.face(f);
            const Vec3 &a = mesh.position(t[0]), &b = mesh.position(t[1]), &cc = mesh.position(t[2]);
            for (int i = 0; i <= k; ++i)
                for (int j = 0; i + j <= k; ++j)
                    best = std::min(best, (a + (b - a) * (double(i) / k) + (cc - a) * (double(j) / k) - p).norm());
        }
        const double d = std::sqrt(c.distance2);
        EXPECT_LE(d, best + 1e-12);
        EXPECT_GE(d, best - 0.35 / k); // edges are about 0.3 long
        EXPECT_NEAR((c.point - p).norm(), d, 1e-12);
        // A hint only tightens the search: the same distance from any starting
        // triangle, near (the answer), far (the opposite side) or arbitrary.
        for (int hint : {c.triangle, 0, mesh.nFaces() - 1, (trial * 37) % mesh.nFaces()})
            EXPECT_EQ(tree.closest(p, hint).distance2, c.distance2) << "hint " << hint;
    }
}

// Rays through the cube [-1, 1]^3 (makeCube, triangulated): from its centre along d
// the first face is at 1 / max |d_i|; from outside, the near face, or past tMin the
// far one; nothing within tMax, or a ray that misses, gives tMax.
TEST(AabbTree, FirstHitAlongARayMatchesTheCubesFaces) {
    const Mesh cube = field::makeCube(4);
    const AabbTree tree(cube);
    std::mt19937 rng(11);
    std::normal_distribution<double> g;
    for (int trial = 0; trial < 50; ++trial) {
        const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
        EXPECT_NEAR(tree.firstHit(Vec3::Zero(), d, 0.0, 10.0), 1.0 / d.cwiseAbs().maxCoeff(), 1e-12) << d.transpose();
    }
    const Vec3 below(0.3, -0.2, -3.0), up(0, 0, 1);
    EXPECT_NEAR(tree.firstHit(below, up, 1e-9, 10.0), 2.0, 1e-12);
    EXPECT_NEAR(tree.firstHit(below, up, 2.5, 10.0), 4.0, 1e-12);
    EXPECT_EQ(tree.firstHit(below, up, 1e-9, 1.5), 1.5);
    EXPECT_EQ(tree.firstHit(Vec3(3, 3, 3), Vec3(1, 0, 0), 1e-9, 10.0), 10.0);
    EXPECT_EQ(tree.firstHit(below, -up, 1e-9, 10.0), 10.0);
}

struct Fixture {
    Mesh mesh = field::makeCube(4);
    field::TangentFrames frames{mesh};
    field::RosyField field;
    field::SingularityReport sing;
    Fixture() {
        field.nSym = 4;
        field.u = Eigen::VectorXcd::Constant(mesh.nVertices(), field::Complex(1, 0));
    }
};

// The cube [-1, 1]^3 as six quads, counter-clockwise seen from outside.
std::vector<Vec3> cubeCorners() {
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    return p;
}
std::vector<std::vector<int>> cubeQuads() {
    return {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
}

TEST(Quality, CubeOfSixQuadsIsClosedManifoldAndSquare) {
    Fixture fx;
    const QualityReport q = measureQuality(cubeCorners(), cubeQuads(), fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_TRUE(q.closed);
    EXPECT_TRUE(q.manifold);
    EXPECT_TRUE(q.oriented);
    EXPECT_EQ(q.eulerCharacteristic, 2);
    EXPECT_EQ(q.inputEulerCharacteristic, 2);
    EXPECT_EQ(q.vertices, 8);
    EXPECT_EQ(q.edges, 12);
    EXPECT_EQ(q.faces, 6);
    EXPECT_DOUBLE_EQ(q.regularFaceFraction, 1.0);
    EXPECT_EQ(q.valenceHistogram.at(3), 8);
    EXPECT_EQ(q.irregularVertices, 8);
    EXPECT_EQ(q.flippedFaces, 0);
    EXPECT_EQ(q.degenerateFaces, 0);
    EXPECT_NEAR(q.angleDevP90Deg, 0.0, 1e-9);
    EXPECT_NEAR(q.edgeLengthMean, 2.0, 1e-12);
    EXPECT_NEAR(q.edgeLengthCv, 0.0, 1e-12);
    EXPECT_NEAR(q.distanceOutToInPct, 0.0, 1e-9);
    EXPECT_NEAR(q.distanceInToOutPct, 0.0, 1e-9);
    // the constant field u = 1 is along x in some frames only: alignment is measured, not assumed
    EXPECT_GE(q.alignmentP90Deg, 0.0);
}

TEST(Quality, SingularRingsMeasureConesAgainstTheirOwnAngle) {
    // The measure near singularities: a singularity at a cube corner makes that
    // valence-3 corner its singular vertex, whose two rings of faces are all six; its
    // three corners (90°) are measured against 360° / 3, the other 21 against 90°.
    Fixture fx;
    field::Singularity corner;
    corner.position = Vec3(1, 1, 1); // vertex 7
    corner.indexNumerator = 1;
    fx.sing.singularities.push_back(corner);
    const QualityReport one = measureQuality(cubeCorners(), cubeQuads(), fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_EQ(one.cornersInSingularRings, 24);
    EXPECT_NEAR(one.angleDevSingularRingsMedianDeg, 0.0, 1e-9);
    // Nearest rank: the 22nd of 24 sorted deviations (21 of 0°, then 3 of 30°).
    EXPECT_NEAR(one.angleDevSingularRingsP90Deg, 30.0, 1e-9);
    // The measure against 90° throughout: every corner of the cube is square.
    EXPECT_NEAR(one.angleDevNearSingP90Deg, 0.0, 1e-9);
    // A second one at the opposite corner (vertex 0): its corners count as a cone too,
    // though its faces were taken by the first; each corner once.
    corner.position = Vec3(-1, -1, -1);
    fx.sing.singularities.push_back(corner);
    const QualityReport two = measureQuality(cubeCorners(), cubeQuads(), fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_EQ(two.cornersInSingularRings, 24);
    EXPECT_NEAR(two.angleDevSingularRingsMedianDeg, 0.0, 1e-9);
    EXPECT_NEAR(two.angleDevSingularRingsP90Deg, 30.0, 1e-9);
    // A minus-one singularity counts the same way (its index sets no target).
    fx.sing.singularities.resize(1);
    fx.sing.singularities[0].indexNumerator = -1;
    EXPECT_EQ(measureQuality(cubeCorners(), cubeQuads(), fx.frames, fx.field, fx.sing, 2.0).cornersInSingularRings, 24);
}

/// A 4 x 4 grid of unit quads in z = 0 (open: its boundary vertices have no valence to
/// judge), vertex (x, y) numbered 5 y + x, its corner quad [0,1]² cut into two triangles:
/// along (1,0)-(0,1), between two boundary vertices, so that every interior vertex keeps
/// valence 4, or with `throughInterior` along (0,0)-(1,1), which gives the interior vertex
/// (1,1) valence 5.
struct CutCornerGrid {
    std::vector<Vec3> pts;
    std::vector<std::vector<int>> polys;
    explicit CutCornerGrid(bool throughInterior) {
        for (int y = 0; y <= 4; ++y)
            for (int x = 0; x <= 4; ++x) pts.emplace_back(x, y, 0);
        const int c00 = 0, c10 = 1, c01 = 5, c11 = 6;
        if (throughInterior)
            polys = {{c00, c10, c11}, {c00, c11, c01}};
        else
            polys = {{c00, c10, c01}, {c10, c11, c01}};
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x)
                if (x + y > 0) polys.push_back({y * 5 + x, y * 5 + x + 1, (y + 1) * 5 + x + 1, (y + 1) * 5 + x});
    }
};

TEST(Quality, ASingularityIsMarkedByAnIrregularVertexOrAnIrregularFaceWithinTwoL) {
    const CutCornerGrid grid(false);
    Fixture fx;
    field::Singularity s;
    s.indexNumerator = 1;
    s.position = Vec3(0.5, 0.5, 0); // the triangles' corners within 2 L = 1
    fx.sing.singularities.push_back(s);
    s.indexNumerator = -1;
    s.position = Vec3(3.0, 3.0, 0); // only regular vertices and quads within 1
    fx.sing.singularities.push_back(s);
    const QualityReport q = measureQuality(grid.pts, grid.polys, fx.frames, fx.field, fx.sing, 0.5);
    EXPECT_EQ(q.irregularVertices, 0);
    EXPECT_EQ(q.singularities, 2);
    EXPECT_EQ(q.singularitiesWithIrregularVertex, 0);
    EXPECT_EQ(q.singularitiesMarked, 1);
    // With the diagonal the other way, (0,0)-(1,1), vertex (1,1) gets valence 5: an
    // irregular vertex within 2 L of the first singularity, which both counts see.
    const CutCornerGrid other(true);
    const QualityReport turned = measureQuality(other.pts, other.polys, fx.frames, fx.field, fx.sing, 0.5);
    EXPECT_EQ(turned.irregularVertices, 1);
    EXPECT_EQ(turned.singularitiesWithIrregularVertex, 1);
    EXPECT_EQ(turned.singularitiesMarked, 1);
}

TEST(Quality, TwoRingsAreCountedAlongEdgesFromTheNearestVertex) {
    // The corner cut through (1,1): the interior vertex (1,1) is the only irregular one.
    const CutCornerGrid grid(true);
    Fixture fx;
    field::Singularity s;
    s.indexNumerator = 1;
    auto measure = [&](const Vec3 &at) {
        fx.sing.singularities.assign(1, s);
        fx.sing.singularities[0].position = at;
        return measureQuality(grid.pts, grid.polys, fx.frames, fx.field, fx.sing, 1.1);
    };
    // Nearest vertex (2,2): two edges from (1,1), through (1,2) or (2,1).
    const QualityReport two = measure(Vec3(2.1, 2.1, 0));
    EXPECT_EQ(two.irregularVertices, 1);
    EXPECT_EQ(two.irregularWithinTwoRings, 1);
    // Nearest vertex (3,2): three edges from (1,1), though (1,1) is 2.13 from the point,
    // within 2 L = 2.2 in space.
    const QualityReport three = measure(Vec3(2.6, 2.4, 0));
    EXPECT_EQ(three.irregularNearSingularity, 1);
    EXPECT_EQ(three.irregularWithinTwoRings, 0);
    // On the irregular vertex itself.
    EXPECT_EQ(measure(Vec3(1.0, 1.05, 0)).irregularWithinTwoRings, 1);
}

/// k quads around a centre vertex 0 in the plane z = 0: spokes 1..k on the unit circle,
/// the quads' outer corners k+1..2k between them at radius 1.5. Only the centre is an
/// interior vertex (valence k); with `split`, the first quad is cut into two triangles
/// by its diagonal from the centre, which gives the centre one more edge.
struct Star {
    std::vector<Vec3> pts{Vec3::Zero()};
    std::vector<std::vector<int>> polys;
    explicit Star(int k, bool split = false) {
        for (int i = 0; i < k; ++i) pts.emplace_back(std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0);
        for (int i = 0; i < k; ++i)
            pts.emplace_back(1.5 * std::cos(2 * M_PI * (i + 0.5) / k), 1.5 * std::sin(2 * M_PI * (i + 0.5) / k), 0);
        for (int i = 0; i < k; ++i) {
            const int a = 1 + i, corner = 1 + k + i, b = 1 + (i + 1) % k;
            if (split && i == 0) {
                polys.push_back({0, a, corner});
                polys.push_back({0, corner, b});
            } else {
                polys.push_back({0, a, corner, b});
            }
        }
    }
};

// Item 2 at its word: a singularity ends up as one irregular vertex or face of its own
// sign, off by one. A valence-5 centre is a −1/4 cone and no +1/4 one; a valence-3 one
// the reverse; a valence-6 centre (two units) is marked but not one irregular; nor is
// a valence-6 centre beside a triangle pair (three irregular elements for one
// singularity), though each of them is within two rings.
TEST(Quality, ASingularityEndsUpAsOneIrregularVertexOfItsOwnSignOrNot) {
    Fixture fx;
    auto measure = [&](const Star &star, int k) {
        field::Singularity s;
        s.indexNumerator = k;
        s.position = Vec3(0.05, 0.02, 0);
        fx.sing.singularities.assign(1, s);
        return measureQuality(star.pts, star.polys, fx.frames, fx.field, fx.sing, 1.0);
    };
    const QualityReport five = measure(Star(5), -1);
    EXPECT_EQ(five.irregularVertices, 1);
    EXPECT_EQ(five.singularitiesMarked, 1);
    EXPECT_EQ(five.singularitiesAsOneIrregular, 1);
    EXPECT_EQ(five.singularityAsOneIrregular, std::vector<char>{1});
    EXPECT_EQ(measure(Star(5), +1).singularitiesAsOneIrregular, 0);
    EXPECT_EQ(measure(Star(3), +1).singularitiesAsOneIrregular, 1);
    EXPECT_EQ(measure(Star(3), -1).singularitiesAsOneIrregular, 0);
    const QualityReport six = measure(Star(6), -1);
    EXPECT_EQ(six.singularitiesMarked, 1);
    EXPECT_EQ(six.irregularWithinTwoRings, 1);
    EXPECT_EQ(six.singularitiesAsOneIrregular, 0);
    EXPECT_EQ(six.singularityAsOneIrregular, std::vector<char>{0});
    // Five quads with one cut: the centre has valence 6 and two triangles touch it.
    const QualityReport cut = measure(Star(5, true), -1);
    EXPECT_EQ(cut.irregularVertices, 1);
    EXPECT_EQ(cut.facesBySides.at(3), 2);
    EXPECT_EQ(cut.singularitiesAsOneIrregular, 0);
    // The regular grid with its corner cut (CutCornerGrid): no singularity is one
    // irregular element where it has none, however near it lies.
    const CutCornerGrid grid(false);
    field::Singularity s;
    s.indexNumerator = -1;
    s.position = Vec3(2.0, 2.0, 0);
    fx.sing.singularities.assign(1, s);
    EXPECT_EQ(measureQuality(grid.pts, grid.polys, fx.frames, fx.field, fx.sing, 1.0).singularitiesAsOneIrregular, 0);
}

TEST(Quality, FlippedFaceIsInconsistentAndFlipped) {
    Fixture fx;
    auto quads = cubeQuads();
    std::reverse(quads[2].begin(), quads[2].end());
    const QualityReport q = measureQuality(cubeCorners(), quads, fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_FALSE(q.oriented);
    EXPECT_EQ(q.inconsistentEdges, 4);
    EXPECT_EQ(q.flippedFaces, 1);
}

TEST(Quality, MissingFaceLeavesABoundary) {
    Fixture fx;
    auto quads = cubeQuads();
    quads.pop_back();
    const QualityReport q = measureQuality(cubeCorners(), quads, fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_FALSE(q.closed);
    EXPECT_TRUE(q.manifold);
    EXPECT_EQ(q.boundaryEdges, 4);
    EXPECT_EQ(q.eulerCharacteristic, 1);
    EXPECT_EQ(q.components, 1);
    EXPECT_EQ(q.genus, 0); // a disk: one boundary loop
    // the missing face's centre is 1 from the nearest output point (a side's centre... at most the half diagonal)
    EXPECT_GT(q.distanceInToOutPct, 10.0);
}

TEST(Quality, ThirdFaceOnAnEdgeIsNonManifold) {
    Fixture fx;
    auto pts = cubeCorners();
    pts.emplace_back(0, 0, 0);
    auto quads = cubeQuads();
    quads.push_back({0, 1, 8}); // a fin inside the cube on edge 0-1
    const QualityReport q = measureQuality(pts, quads, fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_FALSE(q.manifold);
    EXPECT_EQ(q.nonManifoldEdges, 1);
    EXPECT_EQ(q.facesBySides.at(3), 1);
    EXPECT_NEAR(q.regularFaceFraction, 6.0 / 7.0, 1e-12);
}

TEST(Quality, TwoCubesTouchingAtAVertexAreNonManifold) {
    Fixture fx;
    auto pts = cubeCorners();
    auto quads = cubeQuads();
    // a second cube sharing corner 7 = (1, 1, 1)
    for (int i = 1; i < 8; ++i) pts.push_back(pts[i] + Vec3(2, 2, 2));
    auto map = [](int i) { return i == 0 ? 7 : 7 + i; };
    for (const auto &f : cubeQuads()) quads.push_back({map(f[0]), map(f[1]), map(f[2]), map(f[3])});
    const QualityReport q = measureQuality(pts, quads, fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_EQ(q.nonManifoldEdges, 0);
    EXPECT_EQ(q.nonManifoldVertices, 1);
    EXPECT_FALSE(q.manifold);
}

TEST(Quality, PiecesAndGenusAreCountedWhereTheEulerCharacteristicCannotTell) {
    // A cube and, beside it, a torus of 4 x 3 quads: χ = 2 + 0, the input cube's, but
    // two pieces and genus 1 against one piece of genus 0.
    Fixture fx;
    auto pts = cubeCorners();
    auto quads = cubeQuads();
    const int base = int(pts.size()), nU = 4, nV = 3;
    for (int i = 0; i < nU; ++i)
        for (int j = 0; j < nV; ++j) {
            const double u = 2 * M_PI * i / nU, v = 2 * M_PI * j / nV, r = 3 + 0.5 * std::cos(v);
            pts.emplace_back(10 + r * std::cos(u), r * std::sin(u), 0.5 * std::sin(v));
        }
    auto id = [&](int i, int j) { return base + (i % nU) * nV + (j % nV); };
    for (int i = 0; i < nU; ++i)
        for (int j = 0; j < nV; ++j) quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
    const QualityReport q = measureQuality(pts, quads, fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_EQ(q.eulerCharacteristic, q.inputEulerCharacteristic);
    EXPECT_EQ(q.components, 2);
    EXPECT_EQ(q.inputComponents, 1);
    EXPECT_EQ(q.genus, 1);
    EXPECT_EQ(q.inputGenus, 0);
    EXPECT_TRUE(q.closed);
    EXPECT_TRUE(q.topologyLost());
    // The cube alone keeps all of it.
    const QualityReport cube = measureQuality(cubeCorners(), cubeQuads(), fx.frames, fx.field, fx.sing, 2.0);
    EXPECT_EQ(cube.components, 1);
    EXPECT_EQ(cube.genus, 0);
    EXPECT_FALSE(cube.topologyLost());
}

} // namespace
} // namespace rosy::remesh
