#include "core/error.h"
#include "field/design.h"
#include "field/field_builder.h"
#include "field/primitives.h"
#include "field/singularities.h"

#include <gtest/gtest.h>

using namespace rosy::field;

namespace {
int faceContaining(const Mesh &m, const Vec3 &p) {
    return snapToSurface(m, p).face;
}
} // namespace

// The paper's Eq. 13 elements on a planar disk: one element of order L gives
// exactly one singularity, of index L/N, in the element's face, for every N.
class DiskElement : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(DiskElement, GivesExactlyOneSingularityOfItsIndex) {
    const auto [nSym, order] = GetParam();
    Mesh disk = makeDisk(12);
    TangentFrames fr(disk);
    DesignElement el;
    el.position = Vec3(0.13, -0.07, 0.0);
    el.order = order;
    el.phaseRad = 0.3;
    RosyField f = designField(fr, nSym, {el});
    SingularityReport rep = findSingularities(fr, f);
    ASSERT_EQ(rep.singularities.size(), 1u) << "N=" << nSym << " L=" << order;
    EXPECT_EQ(rep.singularities[0].indexNumerator, order);
    EXPECT_EQ(rep.singularities[0].face, faceContaining(disk, el.position));
    EXPECT_NEAR(rep.singularities[0].index(), double(order) / nSym, 1e-15);
    // Poincaré–Hopf with the documented boundary term: χ(disk) = 1.
    EXPECT_NEAR(rep.totalIndex(nSym), 1.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(AllSymmetries, DiskElement,
                         ::testing::Combine(::testing::Values(1, 2, 3, 4, 6), ::testing::Values(-1, 1)));

TEST(Design, ConstantElementOnAPlaneStaysConstant) {
    // With the boundary held at the constant direction, relaxation on a flat grid
    // must reproduce it exactly (checks the transport sign convention of Eq. 15).
    Mesh grid = makeGrid(10);
    TangentFrames fr(grid);
    const int nSym = 4;
    const Vec3 dir = Vec3(1.0, 0.5, 0.0).normalized();
    std::vector<char> fixed(grid.nVertices(), 0);
    Eigen::VectorXcd values = Eigen::VectorXcd::Zero(grid.nVertices());
    for (int v = 0; v < grid.nVertices(); ++v)
        if (grid.isBoundaryVertex(v)) {
            fixed[v] = 1;
            values[v] = representation(fr.angleOfTangent(v, dir), nSym);
        }
    Eigen::VectorXcd u = solveRelaxation(fr, nSym, fixed, values, {});
    for (int v = 0; v < grid.nVertices(); ++v) {
        Complex expected = representation(fr.angleOfTangent(v, dir), nSym);
        EXPECT_NEAR(std::abs(u[v] - expected), 0.0, 1e-9) << "vertex " << v;
    }
}

TEST(Design, SingleDirectionElementGivesNoSingularity) {
    Mesh disk = makeDisk(10);
    TangentFrames fr(disk);
    DesignElement el;
    el.order = 0;
    el.direction = Vec3(0.0, 1.0, 0.0);
    RosyField f = designField(fr, 4, {el});
    SingularityReport rep = findSingularities(fr, f);
    EXPECT_TRUE(rep.singularities.empty());
    // Every member direction is y (mod 90°), up to the relaxation of a flat disk.
    for (int v = 0; v < disk.nVertices(); ++v) {
        double a = memberAngle(f.u[v], 4) - fr.angleOfTangent(v, Vec3::UnitY());
        EXPECT_NEAR(std::sin(4 * a), 0.0, 0.05);
    }
}

TEST(Design, PairOfOppositeElementsOnSphere) {
    Mesh sphere = makeIcosphere(3);
    TangentFrames fr(sphere);
    DesignElement a, b;
    a.position = Vec3(0, 0, 1);
    a.order = 1;
    b.position = Vec3(0, 0, -1);
    b.order = 1;
    RosyField f = designField(fr, 1, {a, b});
    SingularityReport rep = findSingularities(fr, f);
    EXPECT_EQ(rep.indexNumeratorSum, 2); // N χ with N = 1
    int atA = 0;
    for (const auto &s : rep.singularities)
        if (s.face == snapToSurface(sphere, a.position).face) atA = s.indexNumerator;
    EXPECT_EQ(atA, 1);
}

TEST(Design, RejectsBadElements) {
    Mesh disk = makeDisk(4);
    TangentFrames fr(disk);
    DesignElement off;
    off.position = Vec3(0, 0, 5);
    off.label = "scene.yaml:3:7";
    try {
        designField(fr, 4, {off});
        FAIL() << "expected InputError";
    } catch (const rosy::InputError &e) {
        EXPECT_EQ(std::string(e.what()).rfind("scene.yaml:3:7: error:", 0), 0u) << e.what();
    }
    DesignElement badOrder;
    badOrder.order = 2;
    EXPECT_THROW(designField(fr, 4, {badOrder}), rosy::InputError);
    DesignElement badStrength;
    badStrength.strength = std::nan("");
    EXPECT_THROW(designField(fr, 4, {badStrength}), rosy::InputError);
    DesignElement normalDir;
    normalDir.direction = Vec3::UnitZ();
    EXPECT_THROW(designField(fr, 4, {normalDir}), rosy::InputError);
    EXPECT_THROW(designField(fr, 4, {}), rosy::InputError);
}

TEST(Design, ElementsConstrainACurvatureField) {
    // A +1 / −1 pair on a torus over its (singularity-free) curvature cross field:
    // the elements' faces get their indices, the element vertices keep Eq. 13's values.
    Mesh torus = makeTorus(2.0, 0.8, 40, 20);
    TangentFrames fr(torus);
    FieldSpec spec;
    DesignElement pos, neg;
    pos.position = Vec3(2.8, 0.0, 0.0);
    pos.order = 1;
    neg.position = Vec3(-2.8, 0.0, 0.0);
    neg.order = -1;
    spec.elements = {pos, neg};
    FieldResult r = buildField(fr, spec);
    SingularityReport rep = findSingularities(fr, r.field);
    EXPECT_EQ(rep.indexNumeratorSum, 0);
    int atPos = 0, atNeg = 0;
    for (const auto &s : rep.singularities) {
        if (s.face == snapToSurface(torus, pos.position).face) atPos = s.indexNumerator;
        if (s.face == snapToSurface(torus, neg.position).face) atNeg = s.indexNumerator;
    }
    EXPECT_EQ(atPos, 1);
    EXPECT_EQ(atNeg, -1);
    std::vector<char> fixed;
    Eigen::VectorXcd values;
    elementConstraints(fr, 4, spec.elements, fixed, values);
    for (int v = 0; v < torus.nVertices(); ++v) {
        if (fixed[v]) {
            EXPECT_EQ(r.field.u[v], values[v]);
        }
    }
}

// A FieldCache kept across calls (the studio's session) must give every field bit
// for bit as a build without one: the same steps, only remembered. The sequence
// switches N, source, weights and elements back and forth, so an entry kept under
// the wrong key (a Laplacian of another N, a stale snap) changes some field.
TEST(FieldCache, GivesTheFieldOfAColdBuildBitForBit) {
    Mesh torus = makeTorus(2.0, 0.8, 40, 20);
    TangentFrames fr(torus);
    FieldCache cache(fr);
    DesignElement pos, neg, dir;
    pos.position = Vec3(2.8, 0.0, 0.0);
    pos.order = 1;
    neg.position = Vec3(-2.8, 0.0, 0.0);
    neg.order = -1;
    neg.phaseRad = 0.4;
    dir.position = Vec3(0.0, 2.75, 0.1);
    dir.direction = Vec3(0.3, 0.0, 1.0);
    std::vector<FieldSpec> specs;
    FieldSpec spec; // curvature, N = 4, no elements
    specs.push_back(spec);
    spec.elements = {pos};
    specs.push_back(spec);
    spec.elements = {pos, neg};
    specs.push_back(spec);
    spec.elements = {pos, neg, dir};
    specs.push_back(spec);
    spec.nSym = 2;
    specs.push_back(spec);
    spec.nSym = 4;
    spec.smoothingLength = 0; // the relaxation with the curvature guide
    specs.push_back(spec);
    spec.smoothingLength = 0.05;
    spec.globalSmoothingIterations = 3;
    specs.push_back(spec);
    spec.globalSmoothingIterations = 0;
    spec.source = FieldSource::Design;
    specs.push_back(spec);
    spec.weights = LaplaceWeights::Cotan;
    specs.push_back(spec);
    spec.source = FieldSource::Smoothest;
    specs.push_back(spec);
    spec.nSym = 3;
    specs.push_back(spec);
    spec = FieldSpec{};
    spec.elements = {neg, dir};
    spec.curvature.smoothingRounds = 1;
    specs.push_back(spec);
    specs.push_back(specs[2]); // again, everything it needs cached
    for (size_t k = 0; k < specs.size(); ++k) {
        const FieldResult cold = buildField(fr, specs[k]);
        const FieldResult warm = buildField(fr, specs[k], &cache);
        ASSERT_EQ(cold.field.nSym, warm.field.nSym);
        ASSERT_EQ(cold.field.u.size(), warm.field.u.size());
        int differ = 0;
        for (int v = 0; v < cold.field.u.size(); ++v) differ += !(cold.field.u[v] == warm.field.u[v]);
        EXPECT_EQ(differ, 0) << "spec " << k;
        ASSERT_EQ(bool(cold.curvature), bool(warm.curvature)) << "spec " << k;
        EXPECT_EQ(bool(cold.curvature), specs[k].source == FieldSource::Curvature) << "spec " << k;
        if (cold.curvature) {
            ASSERT_EQ(cold.curvature->size(), warm.curvature->size()) << "spec " << k;
            int curvatureDiffers = 0;
            for (size_t v = 0; v < cold.curvature->size(); ++v) {
                const VertexCurvature &a = (*cold.curvature)[v], &b = (*warm.curvature)[v];
                curvatureDiffers += !(a.kMin == b.kMin && a.kMax == b.kMax && a.dirMax == b.dirMax);
            }
            EXPECT_EQ(curvatureDiffers, 0) << "spec " << k;
        }
        EXPECT_EQ(cold.eigenSolve.has_value(), warm.eigenSolve.has_value()) << "spec " << k;
    }
    // And the cold build is the chain of the library's own steps, as before there was
    // a cache (curvature, its guide, the elements' constraints, the aligned solve).
    for (size_t k : {size_t(3), size_t(4)}) {
        const FieldSpec &s = specs[k];
        const RosyField guide = curvatureField(fr, computeCurvature(torus, s.curvature), s.nSym);
        std::vector<char> fixed;
        Eigen::VectorXcd values;
        elementConstraints(fr, s.nSym, s.elements, fixed, values);
        const RosyField direct = alignedField(fr, guide, s.smoothingLength, fixed, values);
        const RosyField built = buildField(fr, s, &cache).field;
        EXPECT_TRUE(direct.u == built.u) << "spec " << k;
    }
    // The specs do give different fields (the comparison above can fail).
    const FieldResult a = buildField(fr, specs[1], &cache), b = buildField(fr, specs[2], &cache);
    EXPECT_FALSE(a.field.u == b.field.u);
    // Builds through one cache share its curvature instead of copying it (a studio
    // edit must not copy #V tensors); a cold build computes its own.
    const FieldResult c1 = buildField(fr, specs[0], &cache), c2 = buildField(fr, specs[1], &cache);
    ASSERT_TRUE(c1.curvature && c2.curvature);
    EXPECT_EQ(c1.curvature.get(), c2.curvature.get());
    EXPECT_NE(buildField(fr, specs[0]).curvature.get(), c1.curvature.get());
    // A cache belongs to one mesh's frames.
    TangentFrames other(torus);
    EXPECT_ANY_THROW(buildField(other, specs[0], &cache));
}
