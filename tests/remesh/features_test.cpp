/// \file features_test.cpp
/// Sharp features and boundaries (RemeshOptions::featureAngleDeg with the field
/// aligned to the same curves, FieldSpec::featureAngleDeg): judged by the
/// independent quality checks and by what is known of each surface (a cube's
/// edges and corners, a cylinder's two rims), not by the remesher's own numbers.

#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "remesh/input_refinement.h"
#include "remesh/quality.h"
#include "remesh/remesh.h"
#include "remesh_helpers.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <set>

namespace rosy::remesh {
namespace {

using field::Mesh;

using helpers::expectValid;
using helpers::Remeshed;

/// Field and remesher both with feature angle `angleDeg` (0: off), L = relativeEdge × diagonal,
/// the field ignoring creases shorter than 2 L as the remesher does (what `rosyhatch remesh` sets).
Remeshed remeshWithFeatures(const Mesh &mesh, double relativeEdge, double angleDeg,
                            double dislocationReach = kDislocationReachMove) {
    field::FieldSpec spec;
    spec.featureAngleDeg = angleDeg;
    spec.featureMinLength = 2 * relativeEdge;
    RemeshOptions opt;
    opt.featureAngleDeg = angleDeg;
    opt.dislocationReach = dislocationReach;
    return helpers::remeshAndMeasure(mesh, spec, opt, relativeEdge);
}

// A CGAL sample mesh from data/meshes (tools/setup.sh) remeshed at L = 1 %.
Remeshed runSample(const std::string &file) {
    return remeshWithFeatures(field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/" + file), 0.01, 50);
}

// Closed, valid with Euler characteristic `chi`, and within the 0.5 % of the
// diagonal of its input both ways.
void expectClosedAndNear(const Remeshed &r, int chi) {
    EXPECT_TRUE(r.quality.closed);
    expectValid(r.quality, chi);
    EXPECT_LE(r.quality.distanceOutToInPct, 0.5);
    EXPECT_LE(r.quality.distanceInToOutPct, 0.5);
}

// `mesh` remeshed at L = 1 % as `rosyhatch remesh` makes it: a coarse input refined
// first (refineCoarseInput); `refined` says whether it was.
Remeshed remeshAsTheCommandDoes(const Mesh &mesh, bool *refined = nullptr) {
    field::Vec3 lo, hi;
    mesh.bounds(lo, hi);
    InputRefinement refinement;
    const Mesh input = refineCoarseInput(mesh, 0.01 * (hi - lo).norm(), 20'000'000, &refinement);
    if (refined) *refined = refinement.applied;
    return remeshWithFeatures(input, 0.01, 50);
}

double segmentDistance(const Vec3 &x, const Vec3 &a, const Vec3 &b) {
    const Vec3 d = b - a;
    const double t = std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (a + t * d - x).norm();
}

// The cube [-1, 1]³: its 8 corners must be output vertices, its 12 edges must be
// covered by output edges lying on them, and no input point may be farther than
// 0.5 % of the diagonal from the output. Without features the curvature (here the
// smoothest) field does not run along the edges and the same checks fail.
TEST(RemeshFeatures, CubeKeepsItsEdgesAndCorners) {
    const Mesh cube = field::makeCube(8);
    const Remeshed r = remeshWithFeatures(cube, 0.07, 50);
    const QualityReport &q = r.quality;
    EXPECT_TRUE(q.closed) << q.boundaryEdges;
    expectValid(q, 2);
    EXPECT_LE(q.distanceInToOutPct, 0.5);
    EXPECT_LE(q.distanceOutToInPct, 0.5);
    EXPECT_GE(q.regularFaceFraction, 0.95);
    const std::vector<Vec3> &P = r.result.positions;
    for (int c = 0; c < 8; ++c) {
        const Vec3 corner(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
        double nearest = 1e9;
        for (const Vec3 &p : P) nearest = std::min(nearest, (p - corner).norm());
        EXPECT_LT(nearest, 1e-9) << "corner " << corner.transpose();
    }
    // Output edges on a cube edge: both ends with two coordinates at ±1.
    auto onCubeEdge = [](const Vec3 &p) {
        int at = 0;
        for (int k = 0; k < 3; ++k) at += std::abs(std::abs(p[k]) - 1) < 1e-9;
        return at >= 2;
    };
    std::vector<std::pair<Vec3, Vec3>> edgeSegments;
    for (const auto &poly : r.result.polygons)
        for (size_t k = 0; k < poly.size(); ++k) {
            const Vec3 &a = P[size_t(poly[k])], &b = P[size_t(poly[(k + 1) % poly.size()])];
            if (onCubeEdge(a) && onCubeEdge(b)) edgeSegments.emplace_back(a, b);
        }
    int uncovered = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (int s = 0; s < 4; ++s)
            for (int k = 0; k <= 40; ++k) {
                Vec3 x;
                x[axis] = -1 + 2.0 * k / 40;
                x[(axis + 1) % 3] = s & 1 ? 1 : -1;
                x[(axis + 2) % 3] = s & 2 ? 1 : -1;
                double d = 1e9;
                for (const auto &[a, b] : edgeSegments) d = std::min(d, segmentDistance(x, a, b));
                uncovered += d > 1e-6;
            }
    EXPECT_EQ(uncovered, 0) << "of 12 x 41 samples along the cube's edges";

    // The same cube without features misses its edges (the test can fail).
    const Remeshed off = remeshWithFeatures(cube, 0.07, 0);
    EXPECT_GT(off.quality.distanceInToOutPct, 1.0);
}

// fandisk (CGAL), a CAD part with sharp creases and corners, at L = 1 %: both
// one-sided distances within 0.5 % of the diagonal (issue 20's target; 0.78 %
// input -> output without features), and still closed with the input's χ.
TEST(RemeshFeatures, FandiskWithinHalfAPercentBothWays) {
    const Mesh mesh = field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/fandisk.off");
#ifdef ROSY_SANITIZED
    // Under ASan + UBSan (about ten times slower) at L = 2 %, the bound scaled with
    // L (measured 0.88 % / 0.46 %); the 0.5 % at 1 % is the Release suite's.
    const double edge = 0.02, bound = 1.0;
#else
    const double edge = 0.01, bound = 0.5;
#endif
    const Remeshed r = remeshWithFeatures(mesh, edge, 50);
    EXPECT_TRUE(r.quality.closed);
    expectValid(r.quality, 2);
    EXPECT_LE(r.quality.distanceInToOutPct, bound);
    EXPECT_LE(r.quality.distanceOutToInPct, bound);
    EXPECT_GE(r.quality.regularFaceFraction, 0.95);
}

// CGAL's man at L = 1 %, as `rosyhatch remesh` makes it: closed, manifold,
// oriented, χ 2 and, since the hole fans cut into ears and the flipped patches
// refilled (docs/remeshing.md, "When the topology is not kept", steps 7 and 8), no
// flipped or degenerate face: 24 flipped faces before, on parts 0.02–0.2 L thick,
// across gaps narrower than 0.1 L, and around hole fans turned over.
TEST(RemeshFeatures, ManHasNoFlippedOrDegenerateFace) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "about ten times slower under the sanitizers; the Release suite runs it";
#endif
    expectClosedAndNear(runSample("man.off"), 2);
}

// bunny00 at L = 0.98 %: a quad folded over the ear's top (a rim about 1.8 L thick,
// not thin by the thin-part rule) left its middle 0.53 % of the diagonal inside the
// ear, and no fan from the point under it faced the input. The quad is cut along
// the ridge now (cutFarQuad); this fails on the code before.
TEST(RemeshFeatures, BunnyEarFoldedQuadIsCutAndTheDistanceHolds) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "several times slower under the sanitizers; the Release suite runs it";
#endif
    // The fold is the position field's at this length (dislocations kept); with them
    // moved (the default) the lattice there differs and the distance must hold too.
    const Mesh bunny = field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
    const Remeshed r = remeshWithFeatures(bunny, 0.0098, 50, 0);
    const Remeshed moved = remeshWithFeatures(bunny, 0.0098, 50);
    for (const Remeshed *x : {&r, &moved}) {
        SCOPED_TRACE(x == &r ? "dislocations kept" : "dislocations moved");
        expectClosedAndNear(*x, 2);
    }
    EXPECT_GE(r.result.repairs.at("far_quads_cut"), 1);
}

// A pyramid (CGAL's pyramid.off: a square base at x = −1, the apex at (1, 0, 0)), as
// `rosyhatch remesh` makes it at L = 1 % (refined first): the lattice reached the apex
// from two of its four creases only, and the vertex there, with two neighbours, was
// dissolved like any other — the tip cut off, the apex 1.26 % of the diagonal from the
// output. A feature corner inside the surface stays now and its two faces are cut by
// diagonals from it; this fails on the code before.
TEST(RemeshFeatures, PyramidKeepsItsApex) {
    const Mesh pyramid = Mesh::fromTriangles({{-1, -0.5, -0.5}, {-1, -0.5, 0.5}, {-1, 0.5, 0.5}, {-1, 0.5, -0.5}, {1, 0, 0}},
                                             {{1, 0, 4}, {2, 1, 4}, {3, 2, 4}, {0, 3, 4}, {0, 1, 2}, {0, 2, 3}},
                                             "pyramid");
    const Remeshed r = remeshAsTheCommandDoes(pyramid);
    expectClosedAndNear(r, 2);
    EXPECT_EQ(r.quality.valence2Vertices, 0);
    for (int c = 0; c < 5; ++c) { // every corner of the input is a vertex of the output
        double nearest = 1e9;
        for (const Vec3 &p : r.result.positions) nearest = std::min(nearest, (p - pyramid.position(c)).norm());
        EXPECT_LT(nearest, 1e-9) << "corner " << pyramid.position(c).transpose();
    }
}

// CGAL's camel at L = 1 %: 0.65 % / 0.60 % of the diagonal from its input before —
// a far point along an edge but away from its midpoint (the repair looked at
// midpoints only), and patches the flip repairs refilled after the distance was held.
// Edges are sampled along their length now and the distance is held again after
// those repairs; this fails on the code before.
TEST(RemeshFeatures, CamelDistanceHeldAfterTheFlipRepairs) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "several times slower under the sanitizers; the Release suite runs it";
#endif
    bool refined = false;
    const Remeshed r =
        remeshAsTheCommandDoes(field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/camel.off"), &refined);
    ASSERT_TRUE(refined);
    expectClosedAndNear(r, 2);
    EXPECT_GE(r.result.repairs.at("flipped_patches_refilled"), 1); // the second hold has work to do
}

// CGAL's helmet at L = 1 % (a CAD-like shell with sharp creases): its farthest output
// points (0.52 % of the diagonal) lay beside two creases, in a polygon whose fans turned
// over, across a side between two feature vertices. Such a side was taken for a piece
// of a crease and never joined across; it is one only if its middle lies within L/4 of
// a feature curve, else it is a chord between two creases and the polygons on both
// sides are fanned together (fanAcrossSide). This fails on the code before.
TEST(RemeshFeatures, HelmetDistanceHeldBetweenItsCreases) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "several times slower under the sanitizers; the Release suite runs it";
#endif
    expectClosedAndNear(remeshAsTheCommandDoes(field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/helmet.off")), -4);
}

// The femur (CGAL data, genus 2): its tunnels are narrower than L at 1 %, and what
// the lattice kept of their walls were three closed specks of 5 to 10 faces beside
// the bone. They go (RemoveStrayPieces); the lost genus is still reported.
TEST(RemeshFeatures, FemurLeavesNoStraySpecks) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "several times slower under the sanitizers; the Release suite runs it";
#endif
    const Remeshed r = runSample("femur.off");
    EXPECT_EQ(r.quality.components, 1);
    EXPECT_EQ(r.quality.inputComponents, 1);
    EXPECT_EQ(r.quality.inputGenus, 2);
    EXPECT_TRUE(r.quality.closed);
    EXPECT_EQ(r.quality.flippedFaces, 0);
    EXPECT_TRUE(r.quality.topologyLost()); // genus 0 against 2: not hidden
}

// CGAL's hand (a fist cut flat at the wrist): on the flat cut, near a singularity,
// the position field tangled and two unit edges crossed; the faces traced over each
// other left 2 flipped faces and a handle (χ 0). The crossing edge goes now
// (RemoveCrossingEdges); this fails on the code before.
TEST(RemeshFeatures, HandKeepsItsTopologyWhereTheLatticeTangles) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "several times slower under the sanitizers; the Release suite runs it";
#endif
    const Remeshed r = runSample("hand.off");
    EXPECT_TRUE(r.quality.closed);
    expectValid(r.quality, 2);
    EXPECT_EQ(r.quality.components, 1);
    EXPECT_EQ(r.quality.genus, 0);
    EXPECT_FALSE(r.quality.topologyLost());
}

// An open cylinder (radius 1, height 2): the output is open like the input, with
// its χ (0), and its boundary follows the two rims: every output vertex on an
// edge with one face lies on a rim (z = ±1 and on the input's 48-gon), and each
// rim gets about 2π / L boundary edges. Without features the openings are capped.
TEST(RemeshFeatures, CylinderBoundaryIsFollowed) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "the cylinder's boundary is remeshed under the sanitizers by RemeshCli.FeatureAngleKeepsAnOpenSurfaceOpen; the Release suite runs this one";
#endif
    const Mesh tube = field::makeCylinder(1.0, 2.0, 48, 24);
    const Remeshed r = remeshWithFeatures(tube, 0.04, 50);
    const QualityReport &q = r.quality;
    EXPECT_FALSE(q.closed);
    expectValid(q, 0);
    EXPECT_LE(q.distanceInToOutPct, 0.5);
    EXPECT_LE(q.distanceOutToInPct, 0.5);
    std::set<std::pair<int, int>> directed;
    for (const auto &poly : r.result.polygons)
        for (size_t k = 0; k < poly.size(); ++k) directed.insert({poly[k], poly[(k + 1) % poly.size()]});
    int rimEdges[2] = {0, 0}, offRim = 0;
    const std::vector<Vec3> &P = r.result.positions;
    const double inscribed = std::cos(M_PI / 48);
    for (const auto &[a, b] : directed) {
        if (directed.count({b, a})) continue;
        for (int v : {a, b}) {
            const Vec3 &p = P[size_t(v)];
            const double rad = std::hypot(p.x(), p.y());
            if (std::abs(std::abs(p.z()) - 1) > 1e-9 || rad > 1 + 1e-9 || rad < inscribed - 1e-9) ++offRim;
        }
        ++rimEdges[P[size_t(a)].z() > 0 ? 1 : 0];
    }
    EXPECT_EQ(offRim, 0);
    const double expected = 2 * M_PI / r.edgeLength;
    for (int side : {0, 1}) {
        EXPECT_GT(rimEdges[side], 0.8 * expected) << side;
        EXPECT_LT(rimEdges[side], 1.25 * expected) << side;
    }
    const Remeshed off = remeshWithFeatures(tube, 0.04, 0);
    EXPECT_TRUE(off.quality.closed); // the behaviour features change
}

/// The faces of `mesh` whose centroid passes `keep`, with the vertices they use
/// (renumbered in order): open patches cut from the procedural meshes.
template <typename Keep>
Mesh keepFaces(const Mesh &mesh, Keep &&keep) {
    std::vector<int> id(size_t(mesh.nVertices()), -1);
    std::vector<Vec3> positions;
    std::vector<field::Face> faces;
    for (const field::Face &f : mesh.faces()) {
        if (!keep(Vec3((mesh.position(f[0]) + mesh.position(f[1]) + mesh.position(f[2])) / 3))) continue;
        field::Face g;
        for (int k = 0; k < 3; ++k) {
            int &x = id[size_t(f[size_t(k)])];
            if (x < 0) x = int(positions.size()), positions.push_back(mesh.position(f[size_t(k)]));
            g[size_t(k)] = x;
        }
        faces.push_back(g);
    }
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "patch");
}

/// The output's boundary edges (sides of one polygon only) as point pairs.
std::vector<std::pair<Vec3, Vec3>> outputBoundary(const RemeshResult &r) {
    std::set<std::pair<int, int>> directed;
    for (const auto &poly : r.polygons)
        for (size_t k = 0; k < poly.size(); ++k) directed.insert({poly[k], poly[(k + 1) % poly.size()]});
    std::vector<std::pair<Vec3, Vec3>> out;
    for (const auto &[a, b] : directed)
        if (!directed.count({b, a})) out.emplace_back(r.positions[size_t(a)], r.positions[size_t(b)]);
    return out;
}

/// The input's boundary edges as point pairs.
std::vector<std::pair<Vec3, Vec3>> inputBoundary(const Mesh &mesh) {
    std::vector<std::pair<Vec3, Vec3>> out;
    for (int h = 0; h < mesh.nHalfedges(); ++h)
        if (mesh.isBoundaryHalfedge(h)) out.emplace_back(mesh.position(mesh.tail(h)), mesh.position(mesh.head(h)));
    return out;
}

/// The largest distance from a point of `from` (each segment at 17 points) to the
/// nearest segment of `to`: a one-sided distance between two polylines.
double oneSidedDistance(const std::vector<std::pair<Vec3, Vec3>> &from, const std::vector<std::pair<Vec3, Vec3>> &to) {
    double worst = 0;
    for (const auto &[a, b] : from)
        for (int k = 0; k <= 16; ++k) {
            const Vec3 x = a + (b - a) * (k / 16.0);
            double d = std::numeric_limits<double>::infinity();
            for (const auto &[c, e] : to) d = std::min(d, segmentDistance(x, c, e));
            worst = std::max(worst, d);
        }
    return worst;
}

/// An open patch's boundary is followed: every corner in `corners` (the input's
/// boundary corners, known from its construction) is an output vertex, and the
/// output's boundary and the input's are within 1e-6 L of each other both ways (the
/// boundary vertices lie on the input's boundary edges, which are straight here).
void expectBoundaryFollowed(const Mesh &mesh, const Remeshed &r, const std::vector<Vec3> &corners) {
    for (const Vec3 &corner : corners) {
        double nearest = std::numeric_limits<double>::infinity();
        for (const Vec3 &p : r.result.positions) nearest = std::min(nearest, (p - corner).norm());
        EXPECT_LT(nearest, 1e-9) << "boundary corner " << corner.transpose();
    }
    const auto in = inputBoundary(mesh), out = outputBoundary(r.result);
    ASSERT_FALSE(out.empty());
    EXPECT_LT(oneSidedDistance(out, in), 1e-6 * r.edgeLength) << "output boundary -> input boundary";
    EXPECT_LT(oneSidedDistance(in, out), 1e-6 * r.edgeLength) << "input boundary -> output boundary";
}

// A flat square patch [-1, 1]²: its four corners are output vertices (each a lattice
// point with two lattice neighbours, along the two sides), not cut off by a diagonal,
// and the output's boundary is the square's.
TEST(RemeshFeatures, SquarePatchKeepsItsCorners) {
    const Mesh grid = field::makeGrid(16);
    const Remeshed r = remeshWithFeatures(grid, 0.07, 50);
    EXPECT_FALSE(r.quality.closed);
    expectValid(r.quality, 1);
    expectBoundaryFollowed(grid, r, {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}});
}

// An L-shaped patch (the square without its quadrant x, y > 0): five convex corners
// and one reflex corner at the origin, all output vertices.
TEST(RemeshFeatures, LShapedPatchKeepsItsCorners) {
    const Mesh patch = keepFaces(field::makeGrid(16), [](const Vec3 &c) { return c.x() < 0 || c.y() < 0; });
    const Remeshed r = remeshWithFeatures(patch, 0.07, 50);
    EXPECT_FALSE(r.quality.closed);
    expectValid(r.quality, 1);
    expectBoundaryFollowed(patch, r,
                           {{-1, -1, 0}, {1, -1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}});
}

// An open box (the cube [-1, 1]³ without its top): the rim's four corners, where the
// boundary turns by 90° and a crease runs down, and the bottom's four corners are
// output vertices; the rim is followed; a disk, χ 1.
TEST(RemeshFeatures, OpenBoxKeepsItsRimCorners) {
    const Mesh box = keepFaces(field::makeCube(8), [](const Vec3 &c) { return c.z() < 1 - 1e-9; });
    const Remeshed r = remeshWithFeatures(box, 0.07, 50);
    EXPECT_FALSE(r.quality.closed);
    expectValid(r.quality, 1);
    std::vector<Vec3> corners;
    for (int c = 0; c < 8; ++c) corners.emplace_back(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1);
    expectBoundaryFollowed(box, r, corners);
    EXPECT_LE(r.quality.distanceInToOutPct, 0.5);
    EXPECT_LE(r.quality.distanceOutToInPct, 0.5);
}

// The feature steps keep the remesher's promise of the same bytes for any thread count.
TEST(RemeshFeatures, SameOutputForAnyThreadCount) {
    const Mesh cube = field::makeCube(8);
    std::vector<Remeshed> runs;
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        runs.push_back(remeshWithFeatures(cube, 0.05, 50));
    }
    ASSERT_EQ(runs[0].result.polygons, runs[1].result.polygons);
    ASSERT_EQ(runs[0].result.positions, runs[1].result.positions);
}


/// The triangle a, b, c cut into n² triangles (n along each side).
Mesh makeTrianglePatch(const Vec3 &a, const Vec3 &b, const Vec3 &c, int n) {
    std::vector<Vec3> positions;
    std::vector<field::Face> faces;
    auto id = [&](int i, int j) { return j * (n + 1) - j * (j - 1) / 2 + i; }; // row j holds n + 1 - j points
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i + j <= n; ++i) positions.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i + j < n; ++i) {
            faces.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
            if (i + j + 1 < n) faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "triangle");
}

// A right isosceles triangle: its two 45° corners are sharper than the square
// lattice, and at these two lengths the first lattice point along both sides of
// each is the same one (it was then removed as a dangling edge and the corner cut
// off, 2.6 L). All three corners are output vertices and the boundary is followed.
TEST(RemeshFeatures, RightTriangleKeepsItsAcuteCorners) {
    const Mesh tri = makeTrianglePatch({-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}, 24);
    for (double edge : {0.03, 0.08}) {
        SCOPED_TRACE("L " + std::to_string(edge) + " of the diagonal");
        const Remeshed r = remeshWithFeatures(tri, edge, 50);
        EXPECT_FALSE(r.quality.closed);
        expectValid(r.quality, 1);
        expectBoundaryFollowed(tri, r, {{-1, -1, 0}, {1, -1, 0}, {-1, 1, 0}});
    }
}

/// An annulus around the z axis: inner radius r0, outer radius 1, nAround segments
/// and nRings rings, lifted to z = bend x² (0: flat).
Mesh makeAnnulus(double r0, int nAround, int nRings, double bend) {
    std::vector<Vec3> positions;
    std::vector<field::Face> faces;
    for (int j = 0; j <= nRings; ++j)
        for (int i = 0; i < nAround; ++i) {
            const double r = r0 + (1 - r0) * j / nRings, t = 2 * M_PI * i / nAround;
            positions.emplace_back(r * std::cos(t), r * std::sin(t), bend * std::pow(r * std::cos(t), 2));
        }
    auto id = [&](int i, int j) { return j * nAround + i % nAround; };
    for (int j = 0; j < nRings; ++j)
        for (int i = 0; i < nAround; ++i) {
            faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return Mesh::fromTriangles(std::move(positions), std::move(faces), "annulus");
}

// An opening as wide as L (an annulus whose inner circle has diameter L, flat and
// bent) stays open: χ 0 like the input, and output boundary vertices around the
// inner circle. Its traced mouth has few sides and a centroid near the rim, so it
// was filled before the sides' left-hand probe (χ 1).
TEST(RemeshFeatures, OpeningAsWideAsTheEdgeStaysOpen) {
    for (double bend : {0.0, 0.8})
        for (double edge : {0.03, 0.05}) {
            const double L = edge * 2 * std::sqrt(2.0); // L for the unit disk's bounding box
            const Mesh ring = makeAnnulus(0.5 * L, 96, 24, bend);
            field::Vec3 lo, hi;
            ring.bounds(lo, hi);
            const Remeshed r = remeshWithFeatures(ring, L / (hi - lo).norm(), 50);
            SCOPED_TRACE("bend " + std::to_string(bend) + ", L " + std::to_string(L));
            EXPECT_FALSE(r.quality.closed);
            expectValid(r.quality, 0);
            int inner = 0; // output boundary vertices within L of the axis
            for (const auto &[a, b] : outputBoundary(r.result)) inner += std::hypot(a.x(), a.y()) < L;
            EXPECT_GE(inner, 3);
        }
}
} // namespace
} // namespace rosy::remesh
