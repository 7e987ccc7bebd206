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
