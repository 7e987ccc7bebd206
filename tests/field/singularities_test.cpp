#include "field/frames.h"
#include "field/singularities.h"

#include <gtest/gtest.h>

using namespace rosy::field;

namespace {
// One flat equilateral-ish triangle; field values chosen by hand.
Mesh triangle() {
    return Mesh::fromTriangles({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.4, 0.9, 0)}, {Face{0, 1, 2}});
}
} // namespace

TEST(FaceIndex, HandBuiltSourceAndSaddle) {
    Mesh m = triangle();
    TangentFrames fr(m);
    const Vec3 c = (m.position(0) + m.position(1) + m.position(2)) / 3.0;
    for (int n : {1, 2, 4}) {
        for (int L : {1, -1}) {
            RosyField f{n, Eigen::VectorXcd(3)};
            for (int v = 0; v < 3; ++v) {
                Vec3 d = m.position(v) - c;
                double theta = std::atan2(d.y(), d.x());
                // Eq. 13 with θ0 = 0, written in the vertex frame (world angle + angle of x there).
                f.u[v] = std::polar(1.0, L * theta + n * fr.angleOfTangent(v, Vec3::UnitX()));
            }
            SingularityReport rep = findSingularities(fr, f);
            ASSERT_EQ(rep.singularities.size(), 1u);
            EXPECT_EQ(rep.singularities[0].indexNumerator, L);
            // The interpolated zero of a symmetric source lies near the centroid.
            EXPECT_LT((rep.singularities[0].position - c).norm(), 0.2);
            EXPECT_NEAR(rep.totalIndex(n), 1.0, 1e-9); // χ of a triangle
        }
    }
}

TEST(FaceIndex, ConstantFieldHasNoSingularity) {
    Mesh m = triangle();
    TangentFrames fr(m);
    RosyField f{4, Eigen::VectorXcd(3)};
    for (int v = 0; v < 3; ++v) f.u[v] = std::polar(1.0, 4 * fr.angleOfTangent(v, Vec3(1, 1, 0)));
    SingularityReport rep = findSingularities(fr, f);
    EXPECT_TRUE(rep.singularities.empty());
    EXPECT_NEAR(rep.boundaryIndex, 1.0, 1e-9);
}
