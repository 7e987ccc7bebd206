// Curvature estimates checked against closed-form differential geometry. The test
// meshes are generated here, independently of field/primitives, so a bug there
// cannot hide one in the estimator.

#include "field/curvature.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>

namespace rosy::field {
namespace {

constexpr double kPi = std::numbers::pi;

double angleDeg(const Vec3 &a, const Vec3 &b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

/// Angle between two lines (directions up to sign), in degrees.
double lineAngleDeg(const Vec3 &a, const Vec3 &b) {
    const double d = angleDeg(a, b);
    return std::min(d, 180.0 - d);
}

/// The structural promises every estimate must keep: finite, unit, orthonormal,
/// right-handed frame, kMax >= kMin, non-negative area.
void expectWellFormed(const std::vector<VertexCurvature> &curv) {
    for (size_t v = 0; v < curv.size(); ++v) {
        const VertexCurvature &c = curv[v];
        ASSERT_TRUE(std::isfinite(c.kMax) && std::isfinite(c.kMin)) << "vertex " << v;
        ASSERT_TRUE(c.normal.allFinite() && c.dirMax.allFinite() && c.dirMin.allFinite())
            << "vertex " << v;
        ASSERT_TRUE(std::isfinite(c.area) && c.area >= 0) << "vertex " << v;
        EXPECT_GE(c.kMax, c.kMin) << "vertex " << v;
        EXPECT_NEAR(c.normal.norm(), 1.0, 1e-9) << "vertex " << v;
        EXPECT_NEAR(c.dirMax.norm(), 1.0, 1e-9) << "vertex " << v;
        EXPECT_NEAR(c.dirMax.dot(c.normal), 0.0, 1e-9) << "vertex " << v;
        EXPECT_LT((c.dirMin - c.normal.cross(c.dirMax)).norm(), 1e-9) << "vertex " << v;
    }
}

// --- independent test meshes ---------------------------------------------------

/// Open cylinder around z, radius r, z in [0, height], outward normals.
Mesh testCylinder(double r, double height, int nAround, int nAlong) {
    std::vector<Vec3> p;
    std::vector<Face> f;
    for (int j = 0; j <= nAlong; ++j)
        for (int i = 0; i < nAround; ++i) {
            const double t = 2 * kPi * i / nAround;
            p.emplace_back(r * std::cos(t), r * std::sin(t), height * j / nAlong);
        }
    auto id = [&](int i, int j) { return j * nAround + (i % nAround); };
    for (int j = 0; j < nAlong; ++j)
        for (int i = 0; i < nAround; ++i) {
            f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return Mesh::fromTriangles(std::move(p), std::move(f), "cylinder");
}

/// Octahedron (vertices on the axes) midpoint-subdivided `levels` times, with
/// vertices optionally pushed onto the unit sphere after each level.
std::pair<std::vector<Vec3>, std::vector<Face>> octahedron(int levels, bool project) {
    std::vector<Vec3> p = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    std::vector<Face> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                           {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            Vec3 m = 0.5 * (p[a] + p[b]);
            if (project) m.normalize();
            p.push_back(m);
            return mid[key] = int(p.size()) - 1;
        };
        std::vector<Face> g;
        for (const Face &t : f) {
            int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            g.push_back({t[0], a, c});
            g.push_back({a, t[1], b});
            g.push_back({c, b, t[2]});
            g.push_back({a, b, c});
        }
        f = std::move(g);
    }
    return {p, f};
}

Mesh testEllipsoid(int levels, double a, double b, double c) {
    auto [p, f] = octahedron(levels, true);
    for (Vec3 &x : p) x = Vec3(a * x.x(), b * x.y(), c * x.z());
    return Mesh::fromTriangles(std::move(p), std::move(f), "ellipsoid");
}

/// Torus around z: p(u, v) = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v).
/// Vertex (i, j) has index j * nU + i, u = 2π i / nU, v = 2π j / nV.
Mesh testTorus(double R, double r, int nU, int nV) {
    std::vector<Vec3> p;
    std::vector<Face> f;
    for (int j = 0; j < nV; ++j)
        for (int i = 0; i < nU; ++i) {
            const double u = 2 * kPi * i / nU, v = 2 * kPi * j / nV;
            p.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                           r * std::sin(v));
        }
    auto id = [&](int i, int j) { return (j % nV) * nU + (i % nU); };
    for (int j = 0; j < nV; ++j)
        for (int i = 0; i < nU; ++i) {
            f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return Mesh::fromTriangles(std::move(p), std::move(f), "torus");
}

/// n × n grid over [0, 1]² with heights z(x, y); vertex (i, j) has index j (n+1) + i.
template <typename Height>
std::pair<std::vector<Vec3>, std::vector<Face>> heightGrid(int n, Height z) {
    std::vector<Vec3> p;
    std::vector<Face> f;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = double(i) / n, y = double(j) / n;
            p.emplace_back(x, y, z(x, y));
        }
    auto id = [&](int i, int j) { return j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return {p, f};
}

/// Minimal OFF reader for the clean sample meshes (triangles only).
Mesh readOff(const std::string &path) {
    std::ifstream in(path);
    std::string magic;
    int nV = 0, nF = 0, nE = 0;
    in >> magic >> nV >> nF >> nE;
    std::vector<Vec3> p(nV);
    for (Vec3 &x : p) in >> x.x() >> x.y() >> x.z();
    std::vector<Face> f(nF);
    for (Face &t : f) {
        int k = 0;
        in >> k >> t[0] >> t[1] >> t[2];
    }
    if (!in) ADD_FAILURE() << "could not parse " << path;
    return Mesh::fromTriangles(std::move(p), std::move(f), path);
}

// --- analytic surfaces -----------------------------------------------------------

// Max's normals are exact on a sphere (Max 1999), and then so is the fit: every
// normal difference is the edge over r, so II = I / r up to rounding.
TEST(Curvature, SphereIsExactlyUmbilicWithMaxNormals) {
    const double r = 2.5;
    auto [p, f] = octahedron(4, true);
    for (Vec3 &x : p) x *= r;
    const Mesh mesh = Mesh::fromTriangles(std::move(p), std::move(f));
    const auto curv = computeCurvature(mesh, {.normals = NormalWeighting::Max});
    expectWellFormed(curv);
    for (int v = 0; v < mesh.nVertices(); ++v) {
        EXPECT_NEAR(curv[v].kMax, 1 / r, 1e-9) << "vertex " << v;
        EXPECT_NEAR(curv[v].kMin, 1 / r, 1e-9) << "vertex " << v;
        EXPECT_NEAR(meanCurvature(curv[v]), 1 / r, 1e-9);
        EXPECT_NEAR(gaussianCurvature(curv[v]), 1 / (r * r), 1e-9);
        EXPECT_LT(angleDeg(curv[v].normal, mesh.position(v)), 1e-6);
    }
}

// Angle-weighted normals tilt by O(h) at the irregular vertices of this mesh, which
// leaves a bias of a few percent (documented in NormalWeighting::Angle).
TEST(Curvature, SphereIsNearlyUmbilicWithAngleNormals) {
    const double r = 2.5;
    auto [p, f] = octahedron(4, true);
    for (Vec3 &x : p) x *= r;
    const Mesh mesh = Mesh::fromTriangles(std::move(p), std::move(f));
    const auto curv = computeCurvature(mesh);
    expectWellFormed(curv);
    double meanH = 0;
    for (int v = 0; v < mesh.nVertices(); ++v) {
        EXPECT_NEAR(curv[v].kMax, 1 / r, 0.08 / r) << "vertex " << v;
        EXPECT_NEAR(curv[v].kMin, 1 / r, 0.08 / r) << "vertex " << v;
        EXPECT_LT(angleDeg(curv[v].normal, mesh.position(v)), 1.0);
        meanH += meanCurvature(curv[v]) / mesh.nVertices();
    }
    EXPECT_NEAR(meanH, 1 / r, 0.03 / r);
}

TEST(Curvature, InwardOrientationFlipsTheSign) {
    auto [p, f] = octahedron(3, true);
    for (Face &t : f) std::swap(t[1], t[2]);
    const Mesh mesh = Mesh::fromTriangles(std::move(p), std::move(f));
    for (NormalWeighting w : {NormalWeighting::Angle, NormalWeighting::Max}) {
        const auto curv = computeCurvature(mesh, {.normals = w});
        expectWellFormed(curv);
        for (int v = 0; v < mesh.nVertices(); ++v) {
            EXPECT_NEAR(curv[v].kMax, -1.0, 0.08);
            EXPECT_NEAR(curv[v].kMin, -1.0, 0.08);
            EXPECT_GT(angleDeg(curv[v].normal, mesh.position(v)), 178.0);
        }
    }
}

TEST(Curvature, CylinderBendsAroundTheAxisAndIsStraightAlongIt) {
    const double r = 0.8;
    const int nAround = 64, nAlong = 40;
    const Mesh mesh = testCylinder(r, 4.0, nAround, nAlong);
    const auto curv = computeCurvature(mesh);
    expectWellFormed(curv);
    int checked = 0;
    for (int v = 0; v < mesh.nVertices(); ++v) {
        const int ring = v / nAround;
        if (ring < 2 || ring > nAlong - 2) continue; // one-sided estimate near the rims
        const Vec3 p = mesh.position(v);
        const Vec3 around(-p.y(), p.x(), 0);
        EXPECT_NEAR(curv[v].kMax, 1 / r, 0.03 / r) << "vertex " << v;
        EXPECT_NEAR(curv[v].kMin, 0.0, 0.03 / r) << "vertex " << v;
        EXPECT_LT(lineAngleDeg(curv[v].dirMax, around), 3.0) << "vertex " << v;
        EXPECT_LT(lineAngleDeg(curv[v].dirMin, Vec3::UnitZ()), 3.0) << "vertex " << v;
        ++checked;
    }
    EXPECT_EQ(checked, nAround * (nAlong - 3));
}

// At the tip (a, 0, 0) of an ellipsoid with semi-axes (a, b, c), the normal
// curvature along y is a / b² and along z is a / c² (the osculating ellipses of
// the two axis-aligned sections); similarly at the other tips.
TEST(Curvature, EllipsoidAxisTipsMatchTheOsculatingEllipses) {
    const double a = 1.6, b = 1.0, c = 0.7;
    const Mesh mesh = testEllipsoid(5, a, b, c);
    for (NormalWeighting w : {NormalWeighting::Angle, NormalWeighting::Max}) {
    SCOPED_TRACE(w == NormalWeighting::Max ? "Max normals" : "angle normals");
    const auto curv = computeCurvature(mesh, {.normals = w});
    expectWellFormed(curv);
    struct Tip {
        int vertex;
        double k1, k2; // along dir1, dir2
        Vec3 dir1, dir2;
    };
    // Octahedron vertices 0..5 are the tips ±x, ±y, ±z.
    const Tip tips[] = {
        {0, a / (b * b), a / (c * c), Vec3::UnitY(), Vec3::UnitZ()},
        {1, a / (b * b), a / (c * c), Vec3::UnitY(), Vec3::UnitZ()},
        {2, b / (a * a), b / (c * c), Vec3::UnitX(), Vec3::UnitZ()},
        {3, b / (a * a), b / (c * c), Vec3::UnitX(), Vec3::UnitZ()},
        {4, c / (a * a), c / (b * b), Vec3::UnitX(), Vec3::UnitY()},
        {5, c / (a * a), c / (b * b), Vec3::UnitX(), Vec3::UnitY()},
    };
    for (const Tip &t : tips) {
        const VertexCurvature &k = curv[t.vertex];
        const bool firstIsMax = t.k1 > t.k2;
        const double kMax = firstIsMax ? t.k1 : t.k2, kMin = firstIsMax ? t.k2 : t.k1;
        const Vec3 dMax = firstIsMax ? t.dir1 : t.dir2, dMin = firstIsMax ? t.dir2 : t.dir1;
        EXPECT_NEAR(k.kMax, kMax, 0.04 * kMax) << "tip " << t.vertex;
        EXPECT_NEAR(k.kMin, kMin, 0.04 * kMin) << "tip " << t.vertex;
        EXPECT_LT(lineAngleDeg(k.dirMax, dMax), 3.0) << "tip " << t.vertex;
        EXPECT_LT(lineAngleDeg(k.dirMin, dMin), 3.0) << "tip " << t.vertex;
    }
    }
}

// Outer equator: curvature 1/r across the tube (along z) and 1/(R + r) along
// the big circle. Inner equator: still 1/r across, but −1/(R − r) along the
// big circle (a saddle).
TEST(Curvature, TorusEquatorsMatchTheClosedForm) {
    const double R = 3.0, r = 1.0;
    const int nU = 120, nV = 48;
    const Mesh mesh = testTorus(R, r, nU, nV);
    for (NormalWeighting w : {NormalWeighting::Angle, NormalWeighting::Max}) {
    SCOPED_TRACE(w == NormalWeighting::Max ? "Max normals" : "angle normals");
    const auto curv = computeCurvature(mesh, {.normals = w});
    expectWellFormed(curv);
    for (int i = 0; i < nU; ++i) {
        const double u = 2 * kPi * i / nU;
        const Vec3 along(-std::sin(u), std::cos(u), 0);
        const VertexCurvature &outer = curv[i];
        EXPECT_NEAR(outer.kMax, 1 / r, 0.03 / r) << "u index " << i;
        EXPECT_NEAR(outer.kMin, 1 / (R + r), 0.03 / (R + r)) << "u index " << i;
        EXPECT_LT(lineAngleDeg(outer.dirMax, Vec3::UnitZ()), 3.0) << "u index " << i;
        EXPECT_LT(lineAngleDeg(outer.dirMin, along), 3.0) << "u index " << i;

        const VertexCurvature &inner = curv[(nV / 2) * nU + i];
        EXPECT_NEAR(inner.kMax, 1 / r, 0.03 / r) << "u index " << i;
        EXPECT_NEAR(inner.kMin, -1 / (R - r), 0.03 / (R - r)) << "u index " << i;
        EXPECT_LT(lineAngleDeg(inner.dirMax, Vec3::UnitZ()), 3.0) << "u index " << i;
        EXPECT_LT(lineAngleDeg(inner.dirMin, along), 3.0) << "u index " << i;
    }
    }
}

// z = (x² − y²) / 2 about the grid centre is a saddle. With the grid's +z normal the
// section along x, z = x² / 2, bends towards the normal: like the inside of a
// sphere, curvature −1. The section along y bends away from it: +1.
TEST(Curvature, SaddleCentreHasOppositePrincipalCurvatures) {
    const int n = 40;
    auto [p, f] = heightGrid(n, [](double x, double y) {
        const double dx = x - 0.5, dy = y - 0.5;
        return 0.5 * (dx * dx - dy * dy);
    });
    const Mesh mesh = Mesh::fromTriangles(std::move(p), std::move(f));
    const auto curv = computeCurvature(mesh);
    expectWellFormed(curv);
    const VertexCurvature &c = curv[(n / 2) * (n + 1) + n / 2];
    EXPECT_NEAR(c.kMax, 1.0, 0.03);
    EXPECT_NEAR(c.kMin, -1.0, 0.03);
    EXPECT_LT(lineAngleDeg(c.dirMax, Vec3::UnitY()), 2.0);
    EXPECT_LT(lineAngleDeg(c.dirMin, Vec3::UnitX()), 2.0);
    EXPECT_NEAR(gaussianCurvature(c), -1.0, 0.06);
    EXPECT_NEAR(meanCurvature(c), 0.0, 0.03);
}

// --- degenerate input ------------------------------------------------------------

TEST(Curvature, PlaneHasZeroCurvatureAndValidFrames) {
    auto [p, f] = heightGrid(8, [](double, double) { return 0.0; });
    const Mesh mesh = Mesh::fromTriangles(std::move(p), std::move(f));
    const auto curv = computeCurvature(mesh, {.smoothingRounds = 2});
    expectWellFormed(curv);
    for (const VertexCurvature &c : curv) {
        EXPECT_EQ(c.kMax, 0.0);
        EXPECT_EQ(c.kMin, 0.0);
        EXPECT_LT(angleDeg(c.normal, Vec3::UnitZ()), 1e-9);
    }
}

TEST(Curvature, EmptyMeshGivesEmptyResult) {
    EXPECT_TRUE(computeCurvature(Mesh()).empty());
}

TEST(Curvature, ZeroAreaFacesNeverProduceNaN) {
    const int n = 10;
    auto [p, f] = heightGrid(n, [](double x, double y) { return 0.3 * (x * x + 2 * y * y); });
    auto id = [&](int i, int j) { return j * (n + 1) + i; };
    // A collinear face: vertex (3, 3) moves onto the midpoint of the other edge
    // (2,2)-(3,2) of its face {(2,2), (3,2), (3,3)}.
    p[id(3, 3)] = 0.5 * (p[id(2, 2)] + p[id(3, 2)]);
    // A zero-length edge: vertex (6, 5) coincides with (7, 5).
    p[id(6, 5)] = p[id(7, 5)];
    // A whole degenerate fan: vertex (5, 8) and all its neighbours at one point.
    const Vec3 c = p[id(5, 8)];
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) p[id(5 + di, 8 + dj)] = c;
    const Mesh mesh = Mesh::fromTriangles(std::move(p), std::move(f));
    for (int rounds : {0, 3}) {
        const auto curv = computeCurvature(mesh, {.smoothingRounds = rounds});
        expectWellFormed(curv);
        // The fully collapsed vertex has no area and no usable face at all.
        EXPECT_EQ(curv[id(5, 8)].area, 0.0);
    }
}

TEST(Curvature, SharpCreasesStayFinite) {
    // The unprojected subdivided octahedron: flat faces, 90°-ish dihedral creases.
    auto [p, f] = octahedron(2, false);
    const Mesh octa = Mesh::fromTriangles(std::move(p), std::move(f));
    const auto curv = computeCurvature(octa, {.smoothingRounds = 1});
    expectWellFormed(curv);
    // Crease normals differ by at most 2 across an edge of length ≥ √2 / 4, so a
    // sane fit stays within a small multiple of 2 / (√2 / 4) ≈ 5.7.
    for (const VertexCurvature &c : curv) {
        EXPECT_LT(std::abs(c.kMax), 20.0);
        EXPECT_LT(std::abs(c.kMin), 20.0);
    }

    const Mesh fandisk = readOff(std::string(ROSY_DATA_DIR) + "/meshes/fandisk.off");
    expectWellFormed(computeCurvature(fandisk));
}

// --- weights, smoothing, determinism ------------------------------------------------

TEST(Curvature, MixedAreasOfAHandComputedObtuseTriangle) {
    // (0,0), (4,0), (2,1): obtuse at (2,1) (edge vectors (−2,−1)·(2,−1) = −3 < 0),
    // area 2, so Meyer's rule gives 1 to that corner and 1/2 to the others.
    const Mesh obtuse = Mesh::fromTriangles({{0, 0, 0}, {4, 0, 0}, {2, 1, 0}}, {Face{0, 1, 2}});
    const auto c = computeCurvature(obtuse);
    EXPECT_DOUBLE_EQ(c[0].area, 0.5);
    EXPECT_DOUBLE_EQ(c[1].area, 0.5);
    EXPECT_DOUBLE_EQ(c[2].area, 1.0);
    // Right isosceles (0,0), (2,0), (0,2), area 2: the Voronoi region of the right
    // corner is the square [0,1]², area 1; the other two get 1/2 each.
    const Mesh right = Mesh::fromTriangles({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, {Face{0, 1, 2}});
    const auto d = computeCurvature(right);
    EXPECT_NEAR(d[0].area, 1.0, 1e-12);
    EXPECT_NEAR(d[1].area, 0.5, 1e-12);
    EXPECT_NEAR(d[2].area, 0.5, 1e-12);
}

Mesh noisySphere(int levels, double noise, unsigned seed) {
    auto [p, f] = octahedron(levels, true);
    std::mt19937 rng(seed);
    for (Vec3 &x : p) x *= 1.0 + noise * (double(rng()) / double(rng.max()) - 0.5);
    return Mesh::fromTriangles(std::move(p), std::move(f));
}

TEST(Curvature, MixedAreasPartitionTheSurface) {
    const Mesh mesh = noisySphere(3, 0.2, 7); // rough enough to have obtuse triangles
    const auto curv = computeCurvature(mesh);
    double vertexSum = 0, faceSum = 0;
    for (const VertexCurvature &c : curv) vertexSum += c.area;
    for (int f = 0; f < mesh.nFaces(); ++f) faceSum += mesh.faceArea(f);
    EXPECT_NEAR(vertexSum, faceSum, 1e-12 * faceSum);
}

double meanCurvatureSpread(const std::vector<VertexCurvature> &curv) {
    double s = 0, s2 = 0;
    for (const VertexCurvature &c : curv) {
        s += meanCurvature(c);
        s2 += meanCurvature(c) * meanCurvature(c);
    }
    const double n = double(curv.size());
    return std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)));
}

TEST(Curvature, SmoothingReducesNoiseAndKeepsTheMean) {
    const Mesh mesh = noisySphere(4, 0.01, 42);
    const auto raw = computeCurvature(mesh);
    const auto smooth = computeCurvature(mesh, {.smoothingRounds = 3});
    expectWellFormed(smooth);
    EXPECT_LT(meanCurvatureSpread(smooth), 0.5 * meanCurvatureSpread(raw));
    double sum = 0;
    for (const VertexCurvature &c : smooth) sum += meanCurvature(c);
    EXPECT_NEAR(sum / double(smooth.size()), 1.0, 0.03);
}

TEST(Curvature, SmoothingKeepsCylinderDirections) {
    const double r = 0.8;
    const int nAround = 48, nAlong = 30;
    const Mesh mesh = testCylinder(r, 3.0, nAround, nAlong);
    const auto curv = computeCurvature(mesh, {.smoothingRounds = 2});
    for (int v = 3 * nAround; v < (nAlong - 2) * nAround; ++v) {
        const Vec3 p = mesh.position(v);
        EXPECT_NEAR(curv[v].kMax, 1 / r, 0.03 / r);
        EXPECT_NEAR(curv[v].kMin, 0.0, 0.03 / r);
        EXPECT_LT(lineAngleDeg(curv[v].dirMax, Vec3(-p.y(), p.x(), 0)), 3.0);
    }
}

TEST(Curvature, ResultsAreIdenticalForAnyThreadCount) {
    const Mesh mesh = testTorus(3.0, 1.0, 200, 100); // 20k vertices: many parallel chunks
    const CurvatureOptions options{.smoothingRounds = 2};
    std::vector<VertexCurvature> one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = computeCurvature(mesh, options);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = computeCurvature(mesh, options);
    }
    ASSERT_EQ(one.size(), two.size());
    for (size_t v = 0; v < one.size(); ++v) {
        const double a[] = {one[v].kMax, one[v].kMin, one[v].area, one[v].dirMax.x(),
                            one[v].dirMax.y(), one[v].dirMax.z()};
        const double b[] = {two[v].kMax, two[v].kMin, two[v].area, two[v].dirMax.x(),
                            two[v].dirMax.y(), two[v].dirMax.z()};
        ASSERT_EQ(std::memcmp(a, b, sizeof a), 0) << "vertex " << v;
    }
}

} // namespace
} // namespace rosy::field
