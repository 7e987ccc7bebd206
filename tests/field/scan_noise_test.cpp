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

#include <cmath>
#include <vector>

using namespace rosy;
using namespace rosy::field;

namespace {

/// Root-mean-square distance of a's vertices from b's (the same vertices).
double rmsOffset(const Mesh &a, const Mesh &b) {
    double sum = 0;
    for (int v = 0; v < a.nVertices(); ++v) sum += (a.position(v) - b.position(v)).squaredNorm();
    return std::sqrt(sum / a.nVertices());
}

SingularityReport singularitiesOf(const TangentFrames &frames) {
    return findSingularities(frames, buildField(frames, FieldSpec{}).field);
}

} // namespace

TEST(ScanNoise, NoisyScanIsJudgedAndItsSmoothedCopyHasTheCleanSingularities) {
    // An ellipsoid with needles (its shape's field: a few singularities near the 4
    // umbilics), then with noise of half an edge along the normals.
    const Mesh needles = test::makeScanLike(makeEllipsoid(6, 1.0, 0.7, 0.5), 0.0);
    const Mesh scan = test::makeScanLike(makeEllipsoid(6, 1.0, 0.7, 0.5), 0.5);
    const TangentFrames cleanFrames(needles), scanFrames(scan);
    const size_t clean = singularitiesOf(cleanFrames).singularities.size();
    const size_t raw = singularitiesOf(scanFrames).singularities.size();
    EXPECT_LE(clean, 16u);
    EXPECT_GT(raw, 100 * clean);
    EXPECT_FALSE(fieldIsScanNoise(needles, clean));
    EXPECT_TRUE(fieldIsScanNoise(scan, raw));
    EXPECT_GT(singularityDensity(scan, raw), kScanNoiseDensity);

    const SmoothedSurface copy = smoothAlongNormals(scan);
    ASSERT_EQ(copy.mesh->nVertices(), scan.nVertices());
    EXPECT_EQ(copy.mesh->faces(), scan.faces());
    // Closer to the noise-free surface than the scan is (the noise, not the shape, goes).
    EXPECT_LT(rmsOffset(*copy.mesh, needles), 0.6 * rmsOffset(scan, needles));
    const FieldResult onCopy = buildField(*copy.frames, FieldSpec{});
    const SingularityReport copySings = findSingularities(*copy.frames, onCopy.field);
    EXPECT_LE(copySings.singularities.size(), 2 * clean + 4);
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
    const SmoothedSurface copy = smoothAlongNormals(bumpy);
    double before = 0, after = 0;
    for (int v = 0; v < bumpy.nVertices(); ++v) {
        const Vec3 &a = bumpy.position(v), &b = copy.mesh->position(v);
        if (bumpy.isBoundaryVertex(v)) {
            EXPECT_EQ(a, b) << v;
            continue;
        }
        // Along the normal only: x and y stay (the plane's normal is z up to the bumps).
        EXPECT_NEAR(a.x(), b.x(), 2e-3) << v;
        EXPECT_NEAR(a.y(), b.y(), 2e-3) << v;
        before += a.z() * a.z();
        after += b.z() * b.z();
    }
    // A low-pass filter: the noise's long waves on so small a disk stay (measured 0.15).
    EXPECT_LT(after, 0.25 * before);
    // Zero rounds: the same positions.
    const SmoothedSurface none = smoothAlongNormals(bumpy, 0);
    EXPECT_EQ(none.mesh->positions(), bumpy.positions());
}
