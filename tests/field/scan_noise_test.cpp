// field/scan_noise.h: a field on a noisy scan is judged noise by its singularities
// and computed on a copy smoothed along the normals, then carried back.
// Expected values come from the construction (an ellipsoid with 4 umbilics, made
// scan-like here) and from Poincaré–Hopf, not from the code under test.

#include "field/field_builder.h"
#include "field/frames.h"
#include "field/primitives.h"
#include "field/scan_noise.h"
#include "field/singularities.h"
#include "scan_like.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

using namespace rosy;
using namespace rosy::field;

namespace {

/// Root-mean-square of |x / (a, b, c)| − 1 over the vertices: how far they lie from
/// the ellipsoid (1, 0.7, 0.5) across its surface, relative to its size.
double ellipsoidError(const Mesh &mesh) {
    double sum = 0;
    for (const Vec3 &q : mesh.positions()) {
        const double e = q.cwiseQuotient(Vec3(1.0, 0.7, 0.5)).norm() - 1.0;
        sum += e * e;
    }
    return std::sqrt(sum / mesh.nVertices());
}

SingularityReport singularitiesOf(const TangentFrames &frames) {
    return findSingularities(frames, buildField(frames, FieldSpec{}).field);
}

} // namespace

TEST(ScanNoise, NoisyScanIsJudgedAndItsSmoothedCopyHasTheCleanSingularities) {
    // An ellipsoid with needles (its shape's field: a few singularities near the 4
    // umbilics), then with noise of half an edge along the normals (test::kScanEllipsoidNoise).
    const Mesh ellipsoid = makeEllipsoid(test::kScanEllipsoidLevel, 1.0, 0.7, 0.5);
    const Mesh needles = test::makeScanLike(ellipsoid, 0.0);
    const Mesh scan = test::makeScanLike(ellipsoid, test::kScanEllipsoidNoise);
    const TangentFrames cleanFrames(needles), scanFrames(scan);
    const size_t clean = singularitiesOf(cleanFrames).singularities.size();
    const size_t raw = singularitiesOf(scanFrames).singularities.size();
    EXPECT_LE(clean, 16u);
    EXPECT_GT(raw, 100 * clean);
    EXPECT_FALSE(fieldIsScanNoise(needles, clean));
    EXPECT_TRUE(fieldIsScanNoise(scan, raw));
    EXPECT_GT(singularityDensity(scan, raw), kScanNoiseDensity);
    ::testing::Test::RecordProperty("noisy_density", std::to_string(singularityDensity(scan, raw)));

    const SmoothedSurface copy = smoothAtScale(scan);
    ASSERT_EQ(copy.mesh->nVertices(), scan.nVertices());
    EXPECT_EQ(copy.mesh->faces(), scan.faces());
    // Closer to the ellipsoid than the scan is (the noise, not the shape, goes; measured
    // across the surface, as vertices may move along it).
    EXPECT_LT(ellipsoidError(*copy.mesh), 0.5 * ellipsoidError(scan));
    const FieldResult onCopy = buildField(*copy.frames, FieldSpec{});
    const SingularityReport copySings = findSingularities(*copy.frames, onCopy.field);
    EXPECT_LE(copySings.singularities.size(), 2 * clean + 4);
    ::testing::Test::RecordProperty("copy_singularities", int(copySings.singularities.size()));
    ::testing::Test::RecordProperty("clean_singularities", int(clean));
    EXPECT_FALSE(fieldIsScanNoise(scan, copySings.singularities.size()));
    EXPECT_EQ(copySings.indexNumeratorSum, 4 * 2); // N χ, a sphere

    // Carried back: on the scan's vertices, each member the copy's projected onto the
    // scan's tangent plane there, magnitudes kept.
    const RosyField back = carryField(*copy.frames, onCopy.field, scanFrames);
    ASSERT_EQ(back.u.size(), onCopy.field.u.size());
    int checked = 0, close = 0;
    for (int v = 0; v < scan.nVertices(); ++v) {
        const double a = std::abs(onCopy.field.u[v]);
        if (!(a > 1e-9)) continue;
        EXPECT_NEAR(std::abs(back.u[v]), a, 1e-9 * std::max(1.0, a)) << v;
        // The copy's first member, projected onto the scan's tangent plane, is the
        // carried field's member there (its angle in the scan's frame, times N).
        const Vec3 there = copy.frames->tangentOfAngle(v, std::arg(onCopy.field.u[v]) / 4);
        const Vec3 n = scanFrames.normal(v);
        const Vec3 projected = there - there.dot(n) * n;
        if (!(projected.norm() > 1e-3)) continue;
        const Complex expected = std::polar(a, 4 * scanFrames.angleOfTangent(v, projected));
        ++checked;
        close += std::abs(back.u[v] - expected) < 1e-9 * std::max(1.0, a);
    }
    EXPECT_GT(checked, scan.nVertices() / 2);
    EXPECT_EQ(close, checked);

    // Singularities placed on the scan: the copy's faces, positions on the scan's faces.
    const SingularityReport placed = placedOn(copySings, scan);
    ASSERT_EQ(placed.singularities.size(), copySings.singularities.size());
    for (const Singularity &s : placed.singularities) {
        const Face &t = scan.face(s.face);
        const Vec3 expected = s.barycentric[0] * scan.position(t[0]) + s.barycentric[1] * scan.position(t[1]) +
                              s.barycentric[2] * scan.position(t[2]);
        EXPECT_LT((s.position - expected).norm(), 1e-12);
    }
}

TEST(ScanNoise, SmoothingKeepsBoundaryVerticesAndTakesTheNoiseOutOfAPlane) {
    // A flat disk with noise along z (its normal): the copy flattens, the rim stays.
    const Mesh disk = makeDisk(16);
    std::vector<Vec3> p = disk.positions();
    for (int v = 0; v < disk.nVertices(); ++v) p[size_t(v)].z() = 0.01 * test::hashedUniform(uint64_t(v), 5);
    const Mesh bumpy = Mesh::fromTriangles(p, disk.faces(), "bumpy");
    const SmoothedSurface copy = smoothAtScale(bumpy, 2.0 * bumpy.meanEdgeLength());
    EXPECT_EQ(copy.mesh->faces(), bumpy.faces());
    double before = 0, after = 0;
    for (int v = 0; v < bumpy.nVertices(); ++v) {
        const Vec3 &a = bumpy.position(v), &b = copy.mesh->position(v);
        if (bumpy.isBoundaryVertex(v)) {
            EXPECT_EQ(a, b) << v;
            continue;
        }
        // In the plane, vertices move by less than an edge (the disk's rings are even).
        EXPECT_LT((a.head<2>() - b.head<2>()).norm(), bumpy.meanEdgeLength()) << v;
        before += a.z() * a.z();
        after += b.z() * b.z();
    }
    // A low-pass filter: the noise's long waves on so small a disk stay.
    EXPECT_LT(after, 0.25 * before);
    // Radius zero: the same positions.
    const SmoothedSurface none = smoothAtScale(bumpy, 0.0);
    EXPECT_EQ(none.mesh->positions(), bumpy.positions());
}

TEST(ScanNoise, SmoothingDoesNotShrinkTheShape) {
    // A sphere smoothed at a tenth of its radius keeps its radius (the displacement's
    // low-pass is taken back out), where one implicit step alone shrinks it.
    const Mesh sphere = makeIcosphere(4, 1.0);
    const SmoothedSurface copy = smoothAtScale(sphere, 0.1);
    double meanRadius = 0;
    for (const Vec3 &q : copy.mesh->positions()) meanRadius += q.norm();
    meanRadius /= copy.mesh->nVertices();
    EXPECT_NEAR(meanRadius, 1.0, 2e-3);
    // And it is the same for any thread count.
    const SmoothedSurface again = [&] {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        return smoothAtScale(sphere, 0.1);
    }();
    EXPECT_EQ(again.mesh->positions(), copy.mesh->positions());
}
