#include "field/frames.h"
#include "field/mesh_stats.h"
#include "field/primitives.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rosy::field;

namespace {
// Independent corner angle: acos of normalized dot product.
double corner(const Mesh &m, int f, int c) {
    const Face &t = m.face(f);
    Vec3 a = m.position(t[(c + 1) % 3]) - m.position(t[c]);
    Vec3 b = m.position(t[(c + 2) % 3]) - m.position(t[c]);
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
}
// Rescaled holonomy of face f computed from scratch: interior vertices rescaled to 2π.
std::vector<double> holonomies(const Mesh &m) {
    std::vector<double> sum(m.nVertices(), 0.0);
    for (int f = 0; f < m.nFaces(); ++f)
        for (int c = 0; c < 3; ++c) sum[m.face(f)[c]] += corner(m, f, c);
    std::vector<double> k(m.nFaces(), -M_PI);
    for (int f = 0; f < m.nFaces(); ++f)
        for (int c = 0; c < 3; ++c) {
            int v = m.face(f)[c];
            double s = m.isBoundaryVertex(v) ? 1.0 : 2 * M_PI / sum[v];
            k[f] += s * corner(m, f, c);
        }
    return k;
}
} // namespace

TEST(Transport, TwinsAreInverse) {
    Mesh m = makeIcosphere(2);
    TangentFrames fr(m);
    for (int h = 0; h < m.nHalfedges(); ++h)
        EXPECT_NEAR(wrapAngle(fr.transportAngle(h) + fr.transportAngle(m.twin(h))), 0.0, 1e-12);
}

TEST(Transport, ConstantDirectionIsParallelOnAFlatGrid) {
    Mesh m = makeGrid(8);
    TangentFrames fr(m);
    // On a flat grid every vertex except the four corners has scale 1, so the
    // world x axis, written in each frame, must be carried exactly onto itself.
    for (int h = 0; h < m.nHalfedges(); ++h) {
        int i = m.tail(h), j = m.head(h);
        double ai = fr.angleOfTangent(i, Vec3::UnitX()), aj = fr.angleOfTangent(j, Vec3::UnitX());
        EXPECT_NEAR(wrapAngle(aj + fr.transportAngle(h) - ai), 0.0, 1e-9) << "halfedge " << h;
    }
}

TEST(Transport, LoopAroundVertexRotatesByEnclosedHolonomy) {
    // Discrete Gauss–Bonnet: carrying a vector around the link of a vertex rotates it
    // by the enclosed faces' angle defect.
    std::vector<Mesh> meshes;
    meshes.push_back(makeIcosphere(3));
    meshes.push_back(makeTorus(2.0, 0.6, 24, 12));
    meshes.push_back(makeGenus2(32));
    for (const Mesh &m : meshes) {
        TangentFrames fr(m);
        std::vector<double> k = holonomies(m);
        for (int v = 0; v < m.nVertices(); v += 7) {
            double rotation = 0, enclosed = 0;
            for (const int *it = m.outgoingBegin(v); it != m.outgoingEnd(v); ++it) {
                const int f = Mesh::faceOf(*it);
                enclosed += k[f];
                // Link edge of face f: from head(h) to tail(prev(h)), CCW around v.
                const int link = Mesh::next(*it);
                rotation -= fr.transportAngle(link); // transportAngle moves head -> tail
            }
            EXPECT_NEAR(wrapAngle(rotation - enclosed), 0.0, 1e-9) << "vertex " << v;
        }
    }
}

TEST(Transport, SmallLoopOnSphereRotatesByEnclosedArea) {
    Mesh m = makeIcosphere(4);
    TangentFrames fr(m);
    const int v = 5;
    double rotation = 0, area = 0;
    for (const int *it = m.outgoingBegin(v); it != m.outgoingEnd(v); ++it) {
        rotation -= fr.transportAngle(Mesh::next(*it));
        area += m.faceArea(Mesh::faceOf(*it));
    }
    // On the unit sphere the holonomy of a small loop equals the enclosed area (K = 1).
    EXPECT_NEAR(wrapAngle(rotation), area, 0.03 * area);
}

TEST(Transport, HolonomiesSumToTwoPiChi) {
    struct Case { Mesh mesh; int chi; };
    std::vector<Case> cases;
    cases.push_back({makeIcosphere(2), 2});
    cases.push_back({makeTorus(2.0, 0.5, 20, 10), 0});
    cases.push_back({makeGenus2(32), -2});
    cases.push_back({makeCube(3), 2});
    for (const auto &c : cases) {
        TangentFrames fr(c.mesh);
        double sum = 0;
        for (int f = 0; f < c.mesh.nFaces(); ++f) sum += fr.faceHolonomy(f);
        EXPECT_NEAR(sum, 2 * M_PI * c.chi, 1e-8);
    }
    // With boundary: Σ K_f + boundary turning = 2πχ (disk: χ = 1).
    Mesh disk = makeDisk(8);
    TangentFrames fr(disk);
    double sum = 0;
    for (int f = 0; f < disk.nFaces(); ++f) sum += fr.faceHolonomy(f);
    for (int v = 0; v < disk.nVertices(); ++v)
        if (disk.isBoundaryVertex(v)) sum += M_PI - fr.angleTotal(v);
    EXPECT_NEAR(sum, 2 * M_PI, 1e-9);
}

TEST(Frames, TangentAngleRoundTrip) {
    Mesh m = makeTorus(2.0, 0.7, 16, 8);
    TangentFrames fr(m);
    for (int v = 0; v < m.nVertices(); v += 5)
        for (double phi : {0.1, 1.0, 2.5, 4.0, 6.0}) {
            Vec3 d = fr.tangentOfAngle(v, phi);
            EXPECT_NEAR(std::abs(d.dot(fr.normal(v))), 0.0, 1e-12);
            EXPECT_NEAR(wrapAngle(fr.angleOfTangent(v, d) - phi), 0.0, 1e-9);
        }
}

TEST(Frames, EdgeDirectionsMapToHalfedgeAngles) {
    Mesh m = makeGrid(4);
    TangentFrames fr(m);
    for (int h = 0; h < m.nHalfedges(); ++h)
        EXPECT_NEAR(wrapAngle(fr.angleOfTangent(m.tail(h), m.vector(h)) - fr.halfedgeAngle(h)), 0.0, 1e-9);
}
