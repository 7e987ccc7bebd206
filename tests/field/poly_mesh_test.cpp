// PolyMesh (OpenMesh) conversion and export through OpenMesh's writers, read
// back with our own checked readers. Expected counts and positions are those of
// the hand-built meshes written; nothing is taken from the writer under test.
#include "core/error.h"
#include "field/mesh/mesh_io.h"
#include "field/mesh/poly_mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

#include "tests/test_output.h"

using namespace rosy;
using namespace rosy::field;
namespace fs = std::filesystem;
using rosy::test::slurp;

namespace {

// A unit cube as six counter-clockwise quads (outward normals), corners at
// coordinates that are not short decimals, so a writer that rounds shows.
std::vector<Vec3> cubePositions() {
    const double a = double(float(1.0 / 3.0)), b = double(float(1.0 / 3.0 + 0.7));
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(i & 1 ? b : a, i & 2 ? b : a, i & 4 ? b : a);
    return p;
}
const std::vector<std::vector<int>> kCubeQuads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

class PolyMeshExport : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("rosy_poly_mesh_" + std::to_string(::getpid()) + "_" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string &name) const { return (m_dir / name).string(); }
    fs::path m_dir;
};

Mesh triangulatedCube() { return repairAndBuild(cubePositions(), kCubeQuads, "cube"); }

} // namespace

TEST_F(PolyMeshExport, ToPolyMeshKeepsVerticesAndFacesInOrder) {
    const Mesh mesh = triangulatedCube();
    const PolyMesh poly = toPolyMesh(mesh);
    ASSERT_EQ(int(poly.n_vertices()), 8);
    ASSERT_EQ(int(poly.n_faces()), 12);
    EXPECT_EQ(int(poly.n_edges()), 18); // Euler: 8 - 18 + 12 = 2
    for (int v = 0; v < 8; ++v) {
        const auto p = poly.point(poly.vertex_handle(unsigned(v)));
        EXPECT_EQ(Vec3(p[0], p[1], p[2]), mesh.position(v));
    }
    for (int f = 0; f < 12; ++f) {
        std::vector<int> corners;
        for (const auto vh : poly.fv_range(poly.face_handle(unsigned(f)))) corners.push_back(vh.idx());
        ASSERT_EQ(corners.size(), 3u);
        // OpenMesh may start a face's cycle at another corner; the cycle must match.
        const Face &t = mesh.face(f);
        const int k = int(std::find(corners.begin(), corners.end(), t[0]) - corners.begin());
        ASSERT_LT(k, 3);
        EXPECT_EQ(corners[size_t((k + 1) % 3)], t[1]);
        EXPECT_EQ(corners[size_t((k + 2) % 3)], t[2]);
    }
}

TEST_F(PolyMeshExport, QuadsRoundTripThroughEveryFormat) {
    const PolyMesh quads = polyMeshFromPolygons(cubePositions(), kCubeQuads, "cube");
    ASSERT_EQ(int(quads.n_faces()), 6);
    const std::vector<Vec3> p = cubePositions();
    for (const char *ext : {"obj", "off", "ply", "stl"}) {
        SCOPED_TRACE(ext);
        const std::string out = path(std::string("cube.") + ext);
        writePolyMesh(out, quads);
        LoadReport report;
        const Mesh back = loadMesh(out, {}, &report);
        EXPECT_EQ(back.nVertices(), 8);
        EXPECT_EQ(back.nFaces(), 12);
        // OBJ, OFF and PLY keep the quads (our reader triangulates them); STL has triangles only.
        EXPECT_EQ(report.polygonsTriangulated, std::string(ext) == "stl" ? 0 : 6);
        EXPECT_EQ(report.facesReoriented, 0);
        // Every written position reads back exactly (float coordinates, 9 digits in text).
        std::map<std::array<double, 3>, int> want;
        for (const Vec3 &q : p) ++want[{q.x(), q.y(), q.z()}];
        std::map<std::array<double, 3>, int> got;
        for (int v = 0; v < back.nVertices(); ++v)
            ++got[{back.position(v).x(), back.position(v).y(), back.position(v).z()}];
        EXPECT_EQ(got, want);
        if (std::string(ext) != "stl") {
            for (int v = 0; v < 8; ++v) EXPECT_EQ(back.position(v), p[size_t(v)]) << v;
        }
        // Outward faces: the cube's volume is positive (edge 0.7).
        double volume = 0;
        for (const Face &f : back.faces())
            volume += back.position(f[0]).dot(back.position(f[1]).cross(back.position(f[2]))) / 6;
        EXPECT_NEAR(volume, std::pow(p[7].x() - p[0].x(), 3), 1e-6);
    }
}

TEST_F(PolyMeshExport, RepairedMeshRoundTripsWithItsFaces) {
    const Mesh mesh = triangulatedCube();
    for (const char *ext : {"obj", "off", "ply"}) {
        SCOPED_TRACE(ext);
        const std::string out = path(std::string("tri.") + ext);
        writePolyMesh(out, toPolyMesh(mesh));
        const Mesh back = loadMesh(out);
        ASSERT_EQ(back.nFaces(), mesh.nFaces());
        for (int f = 0; f < mesh.nFaces(); ++f) {
            // Same cycle of corners, possibly rotated.
            const Face &a = mesh.face(f), &b = back.face(f);
            const int k = int(std::find(b.begin(), b.end(), a[0]) - b.begin());
            ASSERT_LT(k, 3) << f;
            EXPECT_EQ(b[size_t((k + 1) % 3)], a[1]);
            EXPECT_EQ(b[size_t((k + 2) % 3)], a[2]);
        }
    }
}

TEST_F(PolyMeshExport, DirectionsGoIntoTheNormalSlotOfEachFormat) {
    const Mesh mesh = triangulatedCube();
    MeshExportOptions options;
    for (int v = 0; v < mesh.nVertices(); ++v) options.vertexDirections.push_back(Vec3(0, 0, 1));
    writePolyMesh(path("d.ply"), toPolyMesh(mesh), options);
    writePolyMesh(path("d.obj"), toPolyMesh(mesh), options);
    writePolyMesh(path("d.off"), toPolyMesh(mesh), options);
    EXPECT_NE(slurp(path("d.ply")).find("property float nx"), std::string::npos);
    EXPECT_NE(slurp(path("d.obj")).find("vn 0 0 1"), std::string::npos);
    EXPECT_EQ(slurp(path("d.off")).rfind("NOFF", 0), 0u);
    // Our readers skip the extra data and read the same mesh.
    for (const char *name : {"d.ply", "d.obj", "d.off"}) EXPECT_EQ(loadMesh(path(name)).nFaces(), 12) << name;
}

TEST_F(PolyMeshExport, BadRequestsAreInputErrorsAndLeaveTheOldFile) {
    const PolyMesh poly = toPolyMesh(triangulatedCube());
    const std::string old = path("keep.stl");
    std::ofstream(old) << "previous content";
    MeshExportOptions options;
    options.vertexDirections.assign(8, Vec3(1, 0, 0));
    EXPECT_THROW(writePolyMesh(old, poly, options), InputError); // STL has no per-vertex data
    options.vertexDirections.resize(3);
    EXPECT_THROW(writePolyMesh(path("short.ply"), poly, options), InputError);
    EXPECT_THROW(writePolyMesh(path("mesh.xyz"), poly), InputError);
    EXPECT_THROW(writePolyMesh(path("no/such/folder/mesh.obj"), poly), IoError);
    EXPECT_EQ(slurp(old), "previous content");
    EXPECT_FALSE(fs::exists(path("short.ply")));
    EXPECT_TRUE(isMeshExportPath("a/b.PLY"));
    EXPECT_FALSE(isMeshExportPath("a.ply/b"));
}

TEST_F(PolyMeshExport, NonManifoldPolygonsAreRejectedWithTheirNumber) {
    // Three triangles on one edge (0,1): OpenMesh's halfedges cannot hold the third.
    const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    try {
        polyMeshFromPolygons(p, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}, "fin");
        ADD_FAILURE() << "accepted";
    } catch (const InputError &e) {
        EXPECT_NE(std::string(e.what()).find("polygon 2"), std::string::npos) << e.what();
    }
    EXPECT_THROW(polyMeshFromPolygons(p, {{0, 1, 9}}, "range"), InputError);
}
