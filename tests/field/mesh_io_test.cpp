// Loading every format, rejecting every kind of bad input, and each repair of
// repairAndBuild(). Expected counts come from the hand-built files themselves
// or, for the shipped bunny, from its header parsed here independently.
#include "core/diagnostics.h"
#include "core/error.h"
#include "field/mesh_io.h"
#include "field/mesh_stats.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <unistd.h>

using namespace rosy;
using namespace rosy::field;
namespace fs = std::filesystem;

namespace {

// Unit tetrahedron, faces CCW seen from outside.
const std::vector<Vec3> kTetraP = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<std::vector<int>> kTetraF = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

double signedVolume(const Mesh &m) {
    double v = 0;
    for (const Face &f : m.faces())
        v += m.position(f[0]).dot(m.position(f[1]).cross(m.position(f[2])));
    return v / 6;
}

class MeshIoTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto *info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() /
                ("rosy_mesh_io_" + std::to_string(::getpid()) + "_" + info->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    std::string write(const std::string &name, const std::string &content) {
        std::string path = (m_dir / name).string();
        std::ofstream(path, std::ios::binary) << content;
        return path;
    }
    std::string tetraOff(const std::string &extraVertex = "") {
        return "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1" + extraVertex +
               "\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    }
    /// Expects an InputError whose message names the file (and returns it).
    template <typename F> std::string expectInputError(const std::string &path, F &&f) {
        try {
            f();
        } catch (const InputError &e) {
            EXPECT_NE(std::string(e.what()).find(fs::path(path).filename().string()), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find(": error: "), std::string::npos) << e.what();
            return e.what();
        } catch (const std::exception &e) {
            ADD_FAILURE() << "expected InputError, got " << e.what();
            return {};
        }
        ADD_FAILURE() << "expected InputError for " << path;
        return {};
    }

    fs::path m_dir;
};

void expectTetra(const Mesh &m) {
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, 4);
    EXPECT_EQ(s.faces, 4);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    EXPECT_NEAR(signedVolume(m), 1.0 / 6.0, 1e-7);
}

void putFloat(std::string &s, float x) { s.append(reinterpret_cast<const char *>(&x), 4); }
void putU32(std::string &s, uint32_t x) { s.append(reinterpret_cast<const char *>(&x), 4); }

std::string binaryTetraStl(float poison = 0) {
    std::string s(80, ' ');
    putU32(s, 4);
    for (const auto &f : kTetraF) {
        for (int k = 0; k < 3; ++k) putFloat(s, 0);
        for (int v : f)
            for (int k = 0; k < 3; ++k) putFloat(s, float(kTetraP[v][k]) + (v == 3 && k == 2 ? poison : 0));
        s.append(2, '\0');
    }
    return s;
}

} // namespace

// --- formats ------------------------------------------------------------------

TEST_F(MeshIoTest, LoadsOffTetrahedron) {
    LoadReport rep;
    Mesh m = loadMesh(write("t.off", tetraOff()), {}, &rep);
    expectTetra(m);
    EXPECT_EQ(rep.facesReoriented, 0);
}

TEST_F(MeshIoTest, LoadsObjCubeWithQuads) {
    const std::string obj =
        "# unit cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    LoadReport rep;
    WarningCapture capture;
    Mesh m = loadMesh(write("cube.OBJ", obj), {}, &rep);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, 8);
    EXPECT_EQ(s.faces, 12);
    EXPECT_EQ(s.edges, 18);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    EXPECT_EQ(rep.polygonsTriangulated, 6);
    EXPECT_NEAR(signedVolume(m), 1.0, 1e-12);
    EXPECT_TRUE(capture.warnings().empty()); // quads are ordinary, no warning
}

TEST_F(MeshIoTest, LoadsAsciiAndBinaryPly) {
    std::string header = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    std::string ascii = header + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    expectTetra(loadMesh(write("a.ply", ascii)));

    std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 4\n"
                      "property list uchar int vertex_indices\nend_header\n";
    for (const Vec3 &p : kTetraP)
        for (int k = 0; k < 3; ++k) putFloat(bin, float(p[k]));
    for (const auto &f : kTetraF) {
        bin.push_back(char(3));
        for (int v : f) putU32(bin, uint32_t(v));
    }
    expectTetra(loadMesh(write("b.ply", bin)));
}

TEST_F(MeshIoTest, LoadsAsciiAndBinaryStl) {
    std::string ascii = "solid t\n";
    for (const auto &f : kTetraF) {
        ascii += " facet normal 0 0 0\n  outer loop\n";
        for (int v : f)
            ascii += "   vertex " + std::to_string(kTetraP[v].x()) + " " + std::to_string(kTetraP[v].y()) +
                     " " + std::to_string(kTetraP[v].z()) + "\n";
        ascii += "  endloop\n endfacet\n";
    }
    ascii += "endsolid t\n";
    expectTetra(loadMesh(write("a.stl", ascii)));
    expectTetra(loadMesh(write("b.stl", binaryTetraStl())));
}

TEST_F(MeshIoTest, LoadsShippedBunnyWithHeaderCounts) {
    const std::string path = std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off";
    std::ifstream in(path);
    std::string magic;
    long nV = 0, nF = 0;
    in >> magic >> nV >> nF;
    ASSERT_EQ(magic, "OFF");
    LoadReport rep;
    const auto t0 = std::chrono::steady_clock::now();
    Mesh m = loadMesh(path, {}, &rep);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    RecordProperty("load_seconds", std::to_string(seconds));
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, nV);
    EXPECT_EQ(s.faces, nF);
    EXPECT_EQ(s.components, 1);
    EXPECT_EQ(s.boundaryLoops, 0);
    // Closed, one component: χ = V − E + F with E = 3F/2.
    EXPECT_EQ(s.eulerCharacteristic, nV - 3 * nF / 2 + nF);
}

TEST_F(MeshIoTest, ElephantWithHolesHasBoundaryLoops) {
    Mesh m = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/elephant-with-holes.off");
    MeshStats s = computeStats(m);
    EXPECT_GT(s.boundaryLoops, 0);
    EXPECT_EQ(s.eulerCharacteristic, s.vertices - s.edges + s.faces);
}

// --- bad input ----------------------------------------------------------------

TEST_F(MeshIoTest, MissingFileAndFolderAreIoErrors) {
    const std::string missing = (m_dir / "nothing.off").string();
    try {
        loadMesh(missing);
        ADD_FAILURE();
    } catch (const IoError &e) {
        EXPECT_NE(std::string(e.what()).find("nothing.off"), std::string::npos);
    }
    fs::create_directories(m_dir / "folder.off");
    EXPECT_THROW(loadMesh((m_dir / "folder.off").string()), IoError);
}

TEST_F(MeshIoTest, RejectsUnknownExtensionEmptyAndGarbage) {
    std::string p = write("mesh.xyz", tetraOff());
    expectInputError(p, [&] { loadMesh(p); });
    p = write("empty.off", "");
    expectInputError(p, [&] { loadMesh(p); });
    p = write("garbage.off", "hello world\n\x01\x02\x03");
    expectInputError(p, [&] { loadMesh(p); });
    p = write("garbage.ply", "this is not a ply\n");
    expectInputError(p, [&] { loadMesh(p); });
    p = write("garbage.stl", "12345 not stl");
    expectInputError(p, [&] { loadMesh(p); });
    // A comment line is skipped (Geomview's OFF has them); the truncation is named at the counts.
    p = write("comment.off", "OFF\n# made by hand\n4 4 0\n0 0 0\n");
    std::string msg = expectInputError(p, [&] { loadMesh(p); });
    EXPECT_NE(msg.find("comment.off:3:1"), std::string::npos) << msg;
    EXPECT_NE(msg.find("header says 4 vertices"), std::string::npos) << msg;
    p = write("garbage.obj", "just some words\n");
    expectInputError(p, [&] { loadMesh(p); }); // no faces
}

TEST_F(MeshIoTest, RejectsNonFiniteCoordinates) {
    std::string p = write("nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    std::string msg = expectInputError(p, [&] { loadMesh(p); });
    EXPECT_NE(msg.find("nan.off:4:3"), std::string::npos) << msg;
    p = write("inf.obj", "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n");
    msg = expectInputError(p, [&] { loadMesh(p); });
    EXPECT_NE(msg.find("inf.obj:2:7"), std::string::npos) << msg;
    p = write("nan.stl", binaryTetraStl(std::numeric_limits<float>::quiet_NaN()));
    expectInputError(p, [&] { loadMesh(p); });
    // Soups from code are checked too.
    std::vector<Vec3> bad = kTetraP;
    bad[1].x() = std::numeric_limits<double>::infinity();
    EXPECT_THROW(repairAndBuild(bad, kTetraF, "soup"), InputError);
}

TEST_F(MeshIoTest, RejectsOutOfRangeIndex) {
    std::string p = write("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    std::string msg = expectInputError(p, [&] { loadMesh(p); });
    EXPECT_NE(msg.find("range.off:6:7"), std::string::npos) << msg;
    p = write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    expectInputError(p, [&] { loadMesh(p); });
    EXPECT_THROW(repairAndBuild(kTetraP, {{0, 1, 4}}, "soup"), InputError);
    EXPECT_THROW(repairAndBuild(kTetraP, {{0, -1, 2}}, "soup"), InputError);
}

TEST_F(MeshIoTest, RejectsAbsurdHeaderCountsBeforeAllocating) {
    std::string p = write("huge.off", "OFF\n1000000000 1000000000 0\n0 0 0\n");
    std::string msg = expectInputError(p, [&] { loadMesh(p); });
    EXPECT_NE(msg.find("huge.off:2:1"), std::string::npos) << msg;
    p = write("huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 3\n"
                          "property list uchar int vertex_indices\nend_header\n");
    expectInputError(p, [&] { loadMesh(p); });
    // Fewer faces than the header promises.
    p = write("short.off", "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
                           "                ");
    expectInputError(p, [&] { loadMesh(p); });
}

TEST_F(MeshIoTest, RejectsMoreFacesThanTheLimit) {
    LoadOptions opt;
    opt.maxFaces = 3;
    for (const std::string &name : {std::string("t.off"), std::string("t.stl")}) {
        std::string p = name == "t.off" ? write(name, tetraOff()) : write(name, binaryTetraStl());
        std::string msg = expectInputError(p, [&] { loadMesh(p, opt); });
        EXPECT_NE(msg.find("limit"), std::string::npos) << msg;
    }
    EXPECT_THROW(repairAndBuild(kTetraP, kTetraF, "soup", opt), InputError);
}

// --- repairs ------------------------------------------------------------------

namespace {
int countKind(const WarningCapture &c, const std::string &kind) {
    int n = 0;
    for (const Warning &w : c.warnings()) n += w.kind == kind;
    return n;
}
} // namespace

TEST(MeshRepair, BowTieVertexIsSplitIntoTwoComponents) {
    // Two triangles sharing only vertex 0.
    std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    WarningCapture capture;
    LoadReport rep;
    Mesh m = repairAndBuild(p, {{0, 1, 2}, {0, 3, 4}}, "bowtie", {}, &rep);
    EXPECT_EQ(rep.nonManifoldVerticesSplit, 1);
    EXPECT_EQ(rep.nonManifoldEdgesSplit, 0);
    EXPECT_EQ(countKind(capture, "nonmanifold-vertices"), 1);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, 6);
    EXPECT_EQ(s.components, 2);
    EXPECT_EQ(s.eulerCharacteristic, 2); // two disks
    LoadOptions strict;
    strict.repair = false;
    EXPECT_THROW(repairAndBuild(p, {{0, 1, 2}, {0, 3, 4}}, "bowtie", strict), InputError);
}

TEST(MeshRepair, TwoClosedFansAtOneVertexAreSplit) {
    // Two tetrahedra sharing only vertex 0 (the second is the first reflected through
    // it): each fan around 0 is closed, so 0 has as many faces as edges at it and only
    // following the fans tells the two apart.
    std::vector<Vec3> p = kTetraP;
    for (int k = 1; k < 4; ++k) p.push_back(-kTetraP[size_t(k)]);
    const std::vector<std::vector<int>> f = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3},
                                             {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}};
    WarningCapture capture;
    LoadReport rep;
    Mesh m = repairAndBuild(p, f, "cones", {}, &rep);
    EXPECT_EQ(rep.nonManifoldVerticesSplit, 1);
    EXPECT_EQ(rep.nonManifoldEdgesSplit, 0);
    EXPECT_EQ(rep.facesReoriented, 0);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.vertices, 8);
    EXPECT_EQ(s.components, 2);
    EXPECT_EQ(s.eulerCharacteristic, 4);
    EXPECT_NEAR(signedVolume(m), 2.0 / 6.0, 1e-12);
}

TEST(MeshRepair, SameMeshAndReportForOneAndTwoThreads) {
    // Soups large enough for the parallel steps to split their work: tetrahedra in
    // pairs pinched at a shared vertex, and separate ones with every third one's last
    // face flipped; the counts follow from the construction.
    const int n = 1500;
    std::vector<Vec3> pinchedP, flippedP;
    std::vector<std::vector<int>> pinchedF, flippedF;
    for (int i = 0; i < n; ++i) {
        const Vec3 at(3.0 * i, 0, 0);
        const int b = int(pinchedP.size());
        for (const Vec3 &q : kTetraP) pinchedP.push_back(at + q);
        for (int k = 1; k < 4; ++k) pinchedP.push_back(at - kTetraP[size_t(k)]);
        for (const auto &t : std::vector<std::vector<int>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3},
                                                           {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}})
            pinchedF.push_back({b + t[0], b + t[1], b + t[2]});
        const int c = int(flippedP.size());
        for (const Vec3 &q : kTetraP) flippedP.push_back(at + q);
        for (size_t k = 0; k < kTetraF.size(); ++k) {
            std::vector<int> t = {c + kTetraF[k][0], c + kTetraF[k][1], c + kTetraF[k][2]};
            if (i % 3 == 0 && k == 3) std::swap(t[1], t[2]);
            flippedF.push_back(t);
        }
    }
    auto build = [](int threads, const std::vector<Vec3> &p, const std::vector<std::vector<int>> &f,
                    LoadReport &rep) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        WarningCapture quiet;
        return repairAndBuild(p, f, "soup", {}, &rep);
    };
    LoadReport r1, r2;
    Mesh a = build(1, pinchedP, pinchedF, r1), b = build(2, pinchedP, pinchedF, r2);
    EXPECT_EQ(r1.nonManifoldVerticesSplit, n);
    EXPECT_EQ(r2.nonManifoldVerticesSplit, n);
    EXPECT_EQ(a.positions(), b.positions());
    EXPECT_EQ(a.faces(), b.faces());
    EXPECT_EQ(a.nVertices(), 8 * n);
    a = build(1, flippedP, flippedF, r1);
    b = build(2, flippedP, flippedF, r2);
    EXPECT_EQ(r1.facesReoriented, n / 3);
    EXPECT_EQ(r2.facesReoriented, n / 3);
    EXPECT_EQ(r1.nonManifoldVerticesSplit + r2.nonManifoldVerticesSplit, 0);
    EXPECT_EQ(a.faces(), b.faces());
    EXPECT_NEAR(signedVolume(a), n / 6.0, 1e-9);
}

TEST(MeshRepair, ThirdFaceOnAnEdgeIsSplitOff) {
    // Three triangles on edge (0, 1), apexes 2, 3, 4.
    std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
    WarningCapture capture;
    LoadReport rep;
    Mesh m = repairAndBuild(p, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}, "fin", {}, &rep);
    EXPECT_EQ(rep.nonManifoldEdgesSplit, 1);
    EXPECT_EQ(countKind(capture, "nonmanifold-edges"), 1);
    MeshStats s = computeStats(m);
    EXPECT_EQ(s.faces, 3);
    EXPECT_EQ(s.vertices, 7); // both ends of the edge duplicated once
    EXPECT_EQ(s.components, 2);
    EXPECT_EQ(s.eulerCharacteristic, 2);
    EXPECT_EQ(s.boundaryLoops, 2);
}

TEST(MeshRepair, FlippedFaceOfClosedTetrahedronIsReoriented) {
    std::vector<std::vector<int>> f = kTetraF;
    std::swap(f[3][1], f[3][2]);
    WarningCapture capture;
    LoadReport rep;
    Mesh m = repairAndBuild(kTetraP, f, "flip", {}, &rep);
    EXPECT_EQ(rep.facesReoriented, 1);
    EXPECT_EQ(countKind(capture, "reoriented-faces"), 1);
    EXPECT_NEAR(signedVolume(m), 1.0 / 6.0, 1e-12);
    EXPECT_EQ(computeStats(m).eulerCharacteristic, 2);
    LoadOptions strict;
    strict.repair = false;
    EXPECT_THROW(repairAndBuild(kTetraP, f, "flip", strict), InputError);
}

TEST(MeshRepair, MoebiusStripIsRejected) {
    // Eight quads around a band with a half twist: the last quad closes the
    // band with top and bottom exchanged.
    const int n = 8;
    std::vector<Vec3> p;
    for (int i = 0; i < n; ++i) {
        const double u = 2 * std::numbers::pi * i / n;
        for (double w : {0.3, -0.3})
            p.emplace_back((1 + w * std::cos(u / 2)) * std::cos(u), (1 + w * std::cos(u / 2)) * std::sin(u),
                           w * std::sin(u / 2));
    }
    std::vector<std::vector<int>> quads;
    for (int i = 0; i + 1 < n; ++i) quads.push_back({2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2});
    quads.push_back({2 * (n - 1), 2 * (n - 1) + 1, 0, 1});
    try {
        repairAndBuild(p, quads, "moebius.obj");
        ADD_FAILURE() << "a Moebius strip must be rejected";
    } catch (const InputError &e) {
        EXPECT_NE(std::string(e.what()).find("moebius.obj"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("orient"), std::string::npos);
    }
    // The same band without the twist (a cylinder) loads.
    // Closing the same band without exchanging top and bottom gives a
    // (combinatorial) cylinder, which loads.
    quads.back() = {2 * (n - 1), 2 * (n - 1) + 1, 1, 0};
    EXPECT_NO_THROW(repairAndBuild(p, quads, "band.obj"));
}

TEST(MeshRepair, DuplicateVerticesAreMergedAndFacesThatCollapseDropped) {
    // Vertex 4 is a copy of vertex 3; face 1 uses it. Face 4 collapses after merging.
    std::vector<Vec3> p = kTetraP;
    p.push_back(kTetraP[3]);
    std::vector<std::vector<int>> f = kTetraF;
    f[1] = {0, 1, 4};
    f.push_back({3, 4, 0});
    WarningCapture capture;
    LoadReport rep;
    Mesh m = repairAndBuild(p, f, "dup", {}, &rep);
    EXPECT_EQ(rep.duplicateVerticesMerged, 1);
    EXPECT_EQ(rep.degenerateFacesDropped, 1);
    EXPECT_EQ(rep.isolatedVerticesDropped, 0);
    EXPECT_EQ(countKind(capture, "duplicate-vertices"), 1);
    EXPECT_EQ(countKind(capture, "degenerate-faces"), 1);
    expectTetra(m);
}

TEST(MeshRepair, DegenerateDuplicateFacesAndIsolatedVerticesAreDropped) {
    std::vector<Vec3> p = kTetraP;
    p.push_back({0.5, 0, 0});  // 4: on edge (0, 1): face (0, 4, 1) has zero area
    p.push_back({7, 7, 7});    // 5: isolated
    std::vector<std::vector<int>> f = kTetraF;
    f.push_back({0, 0, 1});    // repeated vertex (collapses to a segment)
    f.push_back({0, 4, 1});    // zero area
    f.push_back({1, 2, 3});    // duplicate of face 3
    f.push_back({3, 2, 1});    // duplicate of face 3, reversed
    WarningCapture capture;
    LoadReport rep;
    Mesh m = repairAndBuild(p, f, "mess", {}, &rep);
    EXPECT_EQ(rep.degenerateFacesDropped, 2);
    EXPECT_EQ(rep.duplicateFacesDropped, 2);
    EXPECT_EQ(rep.isolatedVerticesDropped, 2); // 4 lost its only face, 5 never had one
    EXPECT_EQ(countKind(capture, "degenerate-faces"), 1);
    EXPECT_EQ(countKind(capture, "duplicate-faces"), 1);
    EXPECT_EQ(countKind(capture, "isolated-vertices"), 1);
    expectTetra(m);
    LoadOptions strict;
    strict.repair = false;
    EXPECT_THROW(repairAndBuild(p, f, "mess", strict), InputError);
}

TEST(MeshRepair, PolygonsAreFanTriangulatedWithoutWarnings) {
    // A flat pentagon with a repeated consecutive index.
    std::vector<Vec3> p = {{0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {1, 2, 0}, {-1, 1, 0}};
    WarningCapture capture;
    LoadReport rep;
    LoadOptions strict;
    strict.repair = false; // triangulation is not a repair
    Mesh m = repairAndBuild(p, {{0, 1, 1, 2, 3, 4, 0}}, "pentagon", strict, &rep);
    EXPECT_EQ(rep.polygonsTriangulated, 1);
    EXPECT_EQ(m.nFaces(), 3);
    EXPECT_TRUE(capture.warnings().empty());
    double a = 0;
    for (int f = 0; f < m.nFaces(); ++f) a += m.faceArea(f);
    EXPECT_NEAR(a, 5.0, 1e-12); // shoelace formula on the pentagon
}

namespace {

/// Whether 2D point (x, y) lies strictly inside the L-shaped hexagon [0, 2]² minus
/// [0, 1)² (the CGAL data's corner_poly.off face, in the plane z = 1).
bool insideL(double x, double y) { return x > 0 && x < 2 && y > 0 && y < 2 && (x > 1 || y > 1); }

} // namespace

// An L-shaped face (corner_poly.off's top) fanned from its first vertex, the inner
// corner, would lay triangles over the notch; ear-clipped, its four triangles lie in
// the L (every centroid, every edge midpoint inside it) and sum to its area, 3,
// wound as the polygon, with no warning: it is an ordinary face. Convex polygons
// keep their fan from the first vertex.
TEST(MeshRepair, NonConvexPolygonsAreEarClippedAndConvexOnesFanned) {
    std::vector<Vec3> p = {{0, 1, 1}, {1, 1, 1}, {1, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};
    WarningCapture capture;
    LoadReport rep;
    LoadOptions strict;
    strict.repair = false; // triangulating is not a repair
    const Mesh m = repairAndBuild(p, {{0, 1, 2, 3, 4, 5}}, "L", strict, &rep);
    EXPECT_EQ(rep.polygonsTriangulated, 1);
    EXPECT_EQ(rep.nonConvexPolygonsTriangulated, 1);
    EXPECT_EQ(rep.polygonsFanned, 0);
    EXPECT_FALSE(rep.anyRepair());
    EXPECT_TRUE(capture.warnings().empty());
    ASSERT_EQ(m.nFaces(), 4);
    double area = 0;
    for (int f = 0; f < m.nFaces(); ++f) {
        area += m.faceArea(f);
        EXPECT_GT(m.faceNormal(f).z(), 0.999) << "face " << f << " is wound against the polygon";
        Vec3 c = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            const Vec3 a = m.position(m.face(f)[k]), b = m.position(m.face(f)[(k + 1) % 3]);
            c += a / 3;
            const Vec3 mid = 0.5 * (a + b);
            // Edge midpoints on the L's boundary are fine; none may lie in the notch.
            EXPECT_FALSE(mid.x() < 1 - 1e-12 && mid.y() < 1 - 1e-12) << "face " << f << " crosses the notch";
        }
        EXPECT_TRUE(insideL(c.x(), c.y())) << "face " << f << " centroid " << c.transpose();
    }
    EXPECT_NEAR(area, 3.0, 1e-12);

    // A convex hexagon: the fan from vertex 0, as before.
    std::vector<Vec3> hex;
    for (int k = 0; k < 6; ++k) hex.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0);
    LoadReport convexRep;
    const Mesh fan = repairAndBuild(hex, {{0, 1, 2, 3, 4, 5}}, "hexagon", strict, &convexRep);
    EXPECT_EQ(convexRep.nonConvexPolygonsTriangulated, 0);
    ASSERT_EQ(fan.nFaces(), 4);
    for (int f = 0; f < 4; ++f) EXPECT_EQ(fan.face(f), (Face{0, f + 1, f + 2})) << f;
}

// A polygon that crosses itself in its plane (a pentagram's five points in star
// order) has no triangulation on its own corners: it is fanned, counted and warned
// about; with repair off it is rejected. A large non-convex polygon is ear-clipped
// into the right area, and one past the clipping's budget is fanned with a warning.
TEST(MeshRepair, SelfCrossingPolygonsAreFannedWithAWarningAndLargeOnesClipped) {
    std::vector<Vec3> star;
    for (int k = 0; k < 5; ++k) star.emplace_back(std::cos(k * 4 * M_PI / 5), std::sin(k * 4 * M_PI / 5), 0);
    // Not in star order: a flat pentagram has its corners in this order around it.
    WarningCapture capture;
    LoadReport rep;
    const Mesh m = repairAndBuild(star, {{0, 1, 2, 3, 4}}, "pentagram", {}, &rep);
    EXPECT_EQ(rep.polygonsFanned, 1);
    EXPECT_TRUE(rep.anyRepair()); // what makes the strict load below reject it
    EXPECT_EQ(m.nFaces(), 3);
    ASSERT_EQ(capture.warnings().size(), 1u);
    EXPECT_EQ(capture.warnings()[0].kind, "self-crossing-polygons");
    EXPECT_EQ(capture.warnings()[0].where, "pentagram");
    EXPECT_NE(capture.warnings()[0].message.find("fanned"), std::string::npos) << capture.warnings()[0].message;
    LoadOptions strict;
    strict.repair = false;
    EXPECT_THROW(repairAndBuild(star, {{0, 1, 2, 3, 4}}, "pentagram", strict), InputError);

    // Combs: teeth of width 1 and height 10 on a spine of height 1. 1,000 teeth
    // (4,002 corners) are ear-clipped into the comb's area; 4,000 teeth exhaust the
    // budget and are fanned, with a warning, without taking long.
    auto comb = [](int teeth) {
        std::vector<Vec3> points;
        for (int t = 0; t < teeth; ++t) {
            points.emplace_back(2.0 * t, 1, 0);
            points.emplace_back(2.0 * t, 11, 0);
            points.emplace_back(2.0 * t + 1, 11, 0);
            points.emplace_back(2.0 * t + 1, 1, 0);
        }
        points.emplace_back(2.0 * teeth - 1, 0, 0);
        points.emplace_back(0, 0, 0);
        return points;
    };
    auto loopOf = [](size_t n) {
        std::vector<int> loop(n);
        std::iota(loop.begin(), loop.end(), 0);
        return loop;
    };
    const std::vector<Vec3> small = comb(1000);
    LoadReport combRep;
    const Mesh c = repairAndBuild(small, {loopOf(small.size())}, "comb", strict, &combRep);
    EXPECT_EQ(combRep.nonConvexPolygonsTriangulated, 1);
    double area = 0;
    for (int f = 0; f < c.nFaces(); ++f) area += c.faceArea(f);
    EXPECT_NEAR(area, (2.0 * 1000 - 1) * 1 + 1000 * 10.0, 1e-6);
    // The comb runs clockwise seen from +z (teeth left to right, spine back): so do its triangles.
    for (int f = 0; f < c.nFaces(); ++f) EXPECT_LT(c.faceNormal(f).z(), -0.999) << f;

    // Under the sanitizers the budget's 2 x 10^8 tests take about 50 s: a tenth of it
    // and 1,300 teeth (5,202 corners, past the sqrt(2 x 10^7) = 4,472 it clips) run
    // the same path.
#ifdef ROSY_SANITIZED
    const std::vector<Vec3> large = comb(1300);
    LoadOptions budget;
    budget.earClipBudget = 20'000'000;
#else
    const std::vector<Vec3> large = comb(4000);
    const LoadOptions budget;
#endif
    WarningCapture largeCapture;
    LoadReport largeRep;
    const auto t0 = std::chrono::steady_clock::now();
    repairAndBuild(large, {loopOf(large.size())}, "large comb", budget, &largeRep);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(largeRep.largePolygonsFanned, 1);
    EXPECT_TRUE(largeRep.anyRepair());
    // First (then what the overlapping fan brings: zero-area and folded faces).
    ASSERT_GE(largeCapture.warnings().size(), 1u);
    EXPECT_EQ(largeCapture.warnings()[0].kind, "large-nonconvex-polygons");
    EXPECT_NE(largeCapture.warnings()[0].message.find(budget.earClipBudget == 200'000'000 ? "about 14000 corners"
                                                                                            : "about 4000 corners"),
              std::string::npos)
        << largeCapture.warnings()[0].message;
    RecordProperty("large_comb_seconds", std::to_string(seconds));
    RecordProperty("comb_seconds", std::to_string(seconds));
}

TEST(MeshRepair, NothingLeftIsAnError) {
    EXPECT_THROW(repairAndBuild(kTetraP, {{0, 0, 1}}, "soup"), InputError);
    EXPECT_THROW(repairAndBuild(kTetraP, {}, "soup"), InputError);
}

namespace {

/// An n × n grid of unit squares (two triangles each, CCW seen from +z), its
/// vertices listed at index position[k] = grid point stride·k mod n² (stride 1: row
/// by row; a stride coprime to n² scatters neighbours across the file).
void scatteredGrid(int n, int stride, std::vector<Vec3> &positions, std::vector<std::vector<int>> &polygons) {
    const int nV = n * n;
    std::vector<int> indexOf(size_t(nV), 0);
    positions.assign(size_t(nV), Vec3::Zero());
    for (int k = 0; k < nV; ++k) {
        const int g = int((int64_t(stride) * k) % nV);
        indexOf[size_t(g)] = k;
        positions[size_t(k)] = Vec3(g % n, g / n, 0);
    }
    polygons.clear();
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            const int a = indexOf[size_t(y * n + x)], b = indexOf[size_t(y * n + x + 1)],
                      c = indexOf[size_t((y + 1) * n + x + 1)], d = indexOf[size_t((y + 1) * n + x)];
            polygons.push_back({a, b, c});
            polygons.push_back({a, c, d});
        }
}

/// Fraction of face edges joining vertices 4096 or more apart in the numbering.
double farEdgeFraction(const Mesh &m) {
    size_t far = 0;
    for (const Face &f : m.faces())
        for (int k = 0; k < 3; ++k) far += std::abs(f[size_t(k)] - f[size_t((k + 1) % 3)]) >= 4096;
    return double(far) / double(3 * m.nFaces());
}

/// Each face as its three corner positions, rotated to start at the smallest, sorted.
std::vector<std::array<std::array<double, 3>, 3>> facesByPosition(const Mesh &m) {
    std::vector<std::array<std::array<double, 3>, 3>> out;
    for (const Face &f : m.faces()) {
        std::array<std::array<double, 3>, 3> t;
        for (int k = 0; k < 3; ++k) {
            const Vec3 &p = m.position(f[size_t(k)]);
            t[size_t(k)] = {p.x(), p.y(), p.z()};
        }
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end()); // keeps the winding
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

} // namespace

TEST(RenumberForLocality, AScatteredFileIsRenumberedIntoSpatialOrderWithTheSameFaces) {
    // 100 × 100 vertices listed with stride 4099 (coprime to 10 000): almost every face
    // edge joins vertices thousands apart in the file.
    std::vector<Vec3> positions;
    std::vector<std::vector<int>> polygons;
    scatteredGrid(100, 4099, positions, polygons);
    const Mesh asListed = repairAndBuild(positions, polygons, "listed", {}, nullptr);
    // The same faces built without any renumbering: Mesh::fromTriangles on the soup.
    std::vector<Face> tris;
    for (const auto &p : polygons) tris.push_back({p[0], p[1], p[2]});
    const Mesh reference = Mesh::fromTriangles(positions, tris, "reference");
    ASSERT_GT(farEdgeFraction(reference), 0.5);
    EXPECT_LT(farEdgeFraction(asListed), 0.05);
    EXPECT_NE(asListed.positions(), reference.positions()); // renumbered
    EXPECT_EQ(facesByPosition(asListed), facesByPosition(reference)); // the same faces, windings kept
    // Faces follow their vertices: by smallest corner, ascending.
    int last = -1;
    for (const Face &f : asListed.faces()) {
        const int lo = std::min({f[0], f[1], f[2]});
        EXPECT_GE(lo, last);
        last = lo;
    }
}

TEST(RenumberForLocality, AFileInSpatialOrderKeepsItsNumbering) {
    std::vector<Vec3> positions;
    std::vector<std::vector<int>> polygons;
    scatteredGrid(100, 1, positions, polygons);
    const Mesh m = repairAndBuild(positions, polygons, "rows", {}, nullptr);
    EXPECT_EQ(m.positions(), positions);
    ASSERT_EQ(m.nFaces(), int(polygons.size()));
    for (int f = 0; f < m.nFaces(); ++f)
        EXPECT_EQ((std::vector<int>{m.face(f)[0], m.face(f)[1], m.face(f)[2]}), polygons[size_t(f)]);
}
