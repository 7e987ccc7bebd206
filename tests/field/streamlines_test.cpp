#include "field/design.h"
#include "field/field_builder.h"
#include "field/frames.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "field/streamlines.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rosy::field;

namespace {

/// Field whose member at every vertex is the world direction dir(p) (projected), strength s(p).
template <typename Dir, typename Strength>
RosyField fieldFrom(const TangentFrames &frames, int nSym, Dir dir, Strength strength) {
    const Mesh &m = frames.mesh();
    RosyField f{nSym, Eigen::VectorXcd(m.nVertices())};
    for (int v = 0; v < m.nVertices(); ++v)
        f.u[v] = representation(frames.angleOfTangent(v, dir(m.position(v))), nSym, strength(m.position(v)));
    return f;
}

/// First face whose triangle holds p (planar meshes in z = 0), with its barycentrics.
int locate(const Mesh &m, const Vec3 &p, Vec3 &b) {
    for (int f = 0; f < m.nFaces(); ++f) {
        b = barycentricOf(m, f, p);
        if (b.minCoeff() >= -1e-12) return f;
    }
    return -1;
}

bool allFinite(const Streamline &s) {
    for (const Vec3 &p : s.points)
        if (!p.allFinite()) return false;
    return std::isfinite(s.length);
}

} // namespace

TEST(Streamline, ConstantFieldGivesStraightLine) {
    Mesh m = makeGrid(12);
    TangentFrames fr(m);
    const Vec3 dir = Vec3(std::cos(0.3), std::sin(0.3), 0);
    for (int n : {1, 2, 4}) {
        RosyField f = fieldFrom(fr, n, [&](const Vec3 &) { return dir; }, [](const Vec3 &) { return 1.0; });
        Vec3 seed(-0.37, -0.21, 0), b;
        int face = locate(m, seed, b);
        ASSERT_GE(face, 0);
        Streamline s = traceStreamline(fr, f, face, b, dir, {});
        EXPECT_EQ(s.stop, StreamlineStop::Boundary);
        ASSERT_GE(s.points.size(), 3u);
        double maxDist = 0;
        for (const Vec3 &p : s.points) maxDist = std::max(maxDist, (p - seed).cross(dir).norm());
        EXPECT_LT(maxDist, 1e-9 * 2.0) << "N = " << n;
        // The line x(t) = seed + t dir leaves [−1, 1]² at x = 1 (t = 1.37 / cos 0.3).
        const Vec3 &last = s.points.back();
        EXPECT_NEAR(last.x(), 1.0, 1e-9);
        EXPECT_NEAR(s.length, 1.37 / std::cos(0.3), 1e-9);
    }
}

TEST(Streamline, RotationalFieldGivesClosedCircles) {
    Mesh m = makeDisk(16);
    TangentFrames fr(m);
    for (int n : {1, 4}) {
        // u = |p| e^{i N φ(p)}, φ the angle of (−y, x): linear in each face for N = 1.
        RosyField f = fieldFrom(
            fr, n, [](const Vec3 &p) { return Vec3(-p.y(), p.x(), 0); },
            [](const Vec3 &p) { return std::hypot(p.x(), p.y()); });
        for (double r : {0.3, 0.6}) {
            Vec3 seed(r, 0.01, 0), b;
            int face = locate(m, seed, b);
            ASSERT_GE(face, 0);
            Streamline s = traceStreamline(fr, f, face, b, Vec3::UnitY(), {});
            EXPECT_EQ(s.stop, StreamlineStop::Closed) << "N = " << n << " r = " << r;
            const double r0 = seed.norm();
            double worst = 0;
            for (const Vec3 &p : s.points) worst = std::max(worst, std::abs(p.norm() - r0) / r0);
            EXPECT_LT(worst, 0.03) << "N = " << n << " r = " << r;
            EXPECT_NEAR(s.length, 2 * M_PI * r0, 0.03 * 2 * M_PI * r0);
        }
    }
}

TEST(Streamline, CylinderCurvatureLinesAreRulingsAndCircles) {
    const double radius = 1, height = 3;
    Mesh m = makeCylinder(radius, height, 48, 24);
    TangentFrames fr(m);
    FieldSpec spec;
    spec.nSym = 4;
    RosyField f = buildField(fr, spec).field;
    // Seed on a face in the middle of the cylinder.
    int face = -1;
    Vec3 b(0.2, 0.3, 0.5);
    for (int g = 0; g < m.nFaces(); ++g) {
        Vec3 c = (m.position(m.face(g)[0]) + m.position(m.face(g)[1]) + m.position(m.face(g)[2])) / 3;
        if (std::abs(c.z()) < 0.1 && c.x() > 0.9) { face = g; break; }
    }
    ASSERT_GE(face, 0);
    const Face &t = m.face(face);
    const Vec3 seed = b[0] * m.position(t[0]) + b[1] * m.position(t[1]) + b[2] * m.position(t[2]);
    const double seedAngle = std::atan2(seed.y(), seed.x());

    Streamline ruling = traceStreamline(fr, f, face, b, Vec3::UnitZ(), {});
    EXPECT_EQ(ruling.stop, StreamlineStop::Boundary);
    for (const Vec3 &p : ruling.points)
        EXPECT_NEAR(wrapAngle(std::atan2(p.y(), p.x()) - seedAngle), 0.0, 0.02);
    EXPECT_NEAR(std::abs(ruling.points.back().z()), height / 2, 1e-9);

    Vec3 around = Vec3::UnitZ().cross(seed).normalized();
    Streamline circle = traceStreamline(fr, f, face, b, around, {});
    EXPECT_EQ(circle.stop, StreamlineStop::Closed);
    for (const Vec3 &p : circle.points) EXPECT_NEAR(p.z(), seed.z(), 0.02);
    // A closed loop around the axis: the chords of the 48-gon, 2π r up to the polygon.
    EXPECT_NEAR(circle.length, 2 * M_PI * radius, 0.03 * 2 * M_PI * radius);
}

TEST(Streamline, StopsAtDiskBoundary) {
    Mesh m = makeDisk(10);
    TangentFrames fr(m);
    RosyField f = fieldFrom(fr, 2, [](const Vec3 &) { return Vec3(1, 1, 0); }, [](const Vec3 &) { return 1.0; });
    Vec3 seed(0.1, -0.2, 0), b;
    int face = locate(m, seed, b);
    ASSERT_GE(face, 0);
    StreamlineOptions opt;
    opt.bothDirections = true;
    Streamline s = traceStreamline(fr, f, face, b, Vec3(1, 1, 0), opt);
    EXPECT_EQ(s.stop, StreamlineStop::Boundary);
    EXPECT_EQ(s.stopBackward, StreamlineStop::Boundary);
    // Both ends on the unit circle's inscribed polygon: cos(π / segments) ≤ |p| ≤ 1.
    for (const Vec3 *p : {&s.points.front(), &s.points.back()}) {
        EXPECT_LE(p->norm(), 1 + 1e-9);
        EXPECT_GE(p->norm(), 0.95);
    }
    EXPECT_EQ(s.points.size(), s.faces.size());
}

TEST(Streamline, StopsAtSingularFace) {
    Mesh m = makeDisk(16);
    TangentFrames fr(m);
    DesignElement e;
    e.position = Vec3::Zero();
    e.order = 1;
    RosyField f = designField(fr, 4, {e});
    std::vector<int> index = faceIndexNumerators(fr, f);
    int singular = -1;
    for (int g = 0; g < m.nFaces(); ++g)
        if (index[g] != 0) singular = g;
    ASSERT_GE(singular, 0);
    // The +1/4 source (θ0 = 0) has u = e^{iθ}: the member along −x at (0.5, 0) points at the centre.
    Vec3 seed(0.5, 0.003, 0), b;
    int face = locate(m, seed, b);
    Streamline s = traceStreamline(fr, f, face, b, -Vec3::UnitX(), {}, &index);
    EXPECT_EQ(s.stop, StreamlineStop::Singularity);
    EXPECT_EQ(s.faces.back(), singular);
    EXPECT_LT(s.points.back().norm(), 0.15);
}

TEST(Streamline, FiniteAndDeterministicOnSphere) {
    Mesh m = makeIcosphere(3);
    TangentFrames fr(m);
    FieldSpec spec;
    spec.source = FieldSource::Smoothest;
    RosyField f = buildField(fr, spec).field;
    std::vector<int> index = faceIndexNumerators(fr, f);
    StreamlineOptions opt;
    opt.maxLength = 3;
    opt.bothDirections = true;
    for (int face = 0; face < m.nFaces(); face += 97) {
        Vec3 dir = fr.faceAxisX(face) + 0.3 * fr.faceAxisY(face);
        Streamline a = traceStreamline(fr, f, face, Vec3(0.2, 0.5, 0.3), dir, opt, &index);
        Streamline c = traceStreamline(fr, f, face, Vec3(0.2, 0.5, 0.3), dir, opt, &index);
        EXPECT_TRUE(allFinite(a));
        EXPECT_LE(a.length, 2 * opt.maxLength + 1e-9);
        ASSERT_EQ(a.points.size(), c.points.size());
        for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i], c.points[i]);
        // Points stay on the unit sphere's inscribed polyhedron.
        for (const Vec3 &p : a.points) EXPECT_GT(p.norm(), 0.98);
    }
}
