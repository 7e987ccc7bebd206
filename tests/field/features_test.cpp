/// \file features_test.cpp
/// Feature curves (field/features.h) on surfaces whose creases, corners and
/// boundaries are known, and the field constraint along them
/// (FieldSpec::featureAngleDeg): the field has a member along each curve.

#include "core/error.h"
#include "field/features.h"
#include "field/field_builder.h"
#include "field/primitives.h"
#include "field/rosy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace rosy::field {
namespace {

TEST(FeatureCurves, CubeHasTwelveEdgesMeetingAtEightCorners) {
    const Mesh cube = makeCube(4); // [-1, 1]^3, 4 x 4 quads per side, each split in two
    const FeatureCurves c = findFeatureCurves(cube, 40);
    EXPECT_EQ(c.edges.size(), 12u * 4u);
    EXPECT_EQ(c.boundaryEdges, 0);
    int corners = 0;
    for (int v = 0; v < cube.nVertices(); ++v) {
        const Vec3 &p = cube.position(v);
        int atSide = 0;
        for (int k = 0; k < 3; ++k) atSide += std::abs(std::abs(p[k]) - 1) < 1e-12;
        EXPECT_EQ(c.onCurve(v), atSide >= 2) << v;
        EXPECT_EQ(bool(c.corner[size_t(v)]), atSide == 3) << v;
        corners += c.corner[size_t(v)];
        if (atSide == 3) {
            EXPECT_EQ(c.degree[size_t(v)], 3);
        }
        if (atSide == 2) { // along the axis where p is not at ±1
            for (int k = 0; k < 3; ++k)
                if (std::abs(std::abs(p[k]) - 1) > 1e-12) {
                    EXPECT_NEAR(std::abs(c.tangent[size_t(v)][k]), 1, 1e-12);
                }
        }
    }
    EXPECT_EQ(corners, 8);
    // The diagonals of the flat sides (0°) and nothing else above 100°: a cube has only 90° creases.
    EXPECT_EQ(findFeatureCurves(cube, 100).edges.size(), 0u);
    // Each crease curve runs between two corners, length 2: kept at a minimum of
    // 1.9, dropped at 2.1 (and then no vertex is a corner any more).
    EXPECT_EQ(findFeatureCurves(cube, 40, 1.9).edges.size(), 12u * 4u);
    const FeatureCurves none = findFeatureCurves(cube, 40, 2.1);
    EXPECT_TRUE(none.empty());
    EXPECT_EQ(std::count(none.corner.begin(), none.corner.end(), 1), 0);
    EXPECT_THROW(findFeatureCurves(cube, 0), InputError);
    EXPECT_THROW(findFeatureCurves(cube, 180), InputError);
}

TEST(FeatureCurves, GridBoundaryHasFourCorners) {
    const Mesh grid = makeGrid(6); // [-1, 1]^2, flat: only its boundary
    const FeatureCurves c = findFeatureCurves(grid, 40);
    EXPECT_EQ(c.edges.size(), 24u);
    EXPECT_EQ(c.boundaryEdges, 24);
    int corners = 0;
    for (int v = 0; v < grid.nVertices(); ++v) corners += c.corner[size_t(v)];
    EXPECT_EQ(corners, 4); // the square's corners turn by 90° > kFeatureCornerTurnDeg
}

/// The angle (degrees) between tangent t at v and the nearest member of `field` there.
double memberDeviationDeg(const TangentFrames &frames, const RosyField &field, int v, const Vec3 &t) {
    const double period = 2 * std::numbers::pi / field.nSym;
    const double member = std::arg(field.u[v]) / field.nSym;
    double d = std::fmod(std::abs(frames.angleOfTangent(v, t) - member), period);
    d = std::min(d, period - d);
    return d * 180 / std::numbers::pi;
}

// The constrained field has a member along every curve vertex's tangent, on a
// cube's creases and on a disk's boundary circle, for N = 4 and 6 and through the
// curvature source (its smoothest fallback on the flat disk) and the smoothest
// source. The field without the constraint is farther from the curves somewhere
// (else this test could not fail; the cube's curvature 4-RoSy field happens to be
// within 0.2° of its edges already, so the cube's N = 4 case uses the smoothest source).
TEST(FeatureCurves, FieldHasAMemberAlongEveryCurve) {
    struct Case {
        Mesh mesh;
        int nSym;
        FieldSource source;
    };
    const Case cases[] = {{makeCube(6), 4, FieldSource::Smoothest},
                          {makeCube(6), 6, FieldSource::Curvature},
                          {makeDisk(12), 4, FieldSource::Curvature},
                          {makeDisk(12), 6, FieldSource::Smoothest}};
    for (const Case &k : cases) {
        SCOPED_TRACE(k.mesh.name() + " N = " + std::to_string(k.nSym) + " " + toString(k.source));
        const TangentFrames frames(k.mesh);
        const FeatureCurves c = findFeatureCurves(k.mesh, 40);
        ASSERT_FALSE(c.empty());
        FieldSpec spec;
        spec.nSym = k.nSym;
        spec.source = k.source;
        const RosyField free = buildField(frames, spec).field;
        spec.featureAngleDeg = 40;
        const RosyField aligned = buildField(frames, spec).field;
        double worstAligned = 0, worstFree = 0;
        int checked = 0;
        for (int v = 0; v < k.mesh.nVertices(); ++v) {
            if (!c.onCurve(v) || c.corner[size_t(v)]) continue;
            ++checked;
            worstAligned = std::max(worstAligned, memberDeviationDeg(frames, aligned, v, c.tangent[size_t(v)]));
            worstFree = std::max(worstFree, memberDeviationDeg(frames, free, v, c.tangent[size_t(v)]));
        }
        EXPECT_GT(checked, 20);
        EXPECT_LT(worstAligned, 0.01);
        EXPECT_GT(worstFree, 5.0);
    }
    EXPECT_EQ(FieldSpec{}.featureAngleDeg, 0); // off unless asked for: every render stays as it was
}

} // namespace
} // namespace rosy::field
