// rosyhatch studio on large meshes: the display mesh (vertex clustering) is used above
// the threshold, the field sent is the full field sampled at its vertices, payloads
// are bounded by the display mesh, the mesh is streamed, and picks land on the full
// surface. The thresholds are lowered so that a small mesh (head, 2,918 faces) is
// "large": the code paths are the same as at 270k faces, the test stays fast.

#include "field/mesh_io.h"
#include "studio/display_mesh.h"
#include "studio_test_util.h"
#include "studio/server.h"
#include "studio/studio.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

namespace fs = std::filesystem;
using nlohmann::json;
using rosy::field::Vec3;

namespace {


using rosy::test::f32;
using rosy::test::u32;

double area(const rosy::field::Mesh &mesh, const std::vector<rosy::field::Face> &faces, const std::vector<int> &map) {
    double a = 0;
    for (const auto &f : faces) {
        const Vec3 p = mesh.position(map[f[0]]), q = mesh.position(map[f[1]]), r = mesh.position(map[f[2]]);
        a += 0.5 * (q - p).cross(r - p).norm();
    }
    return a;
}

/// Closest ray parameter over all faces (Moller-Trumbore, double precision), or -1.
double bruteForceHit(const rosy::field::Mesh &mesh, const Vec3 &o, const Vec3 &d, int &face) {
    double best = -1;
    face = -1;
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const Vec3 a = mesh.position(mesh.face(f)[0]), e1 = mesh.position(mesh.face(f)[1]) - a,
                   e2 = mesh.position(mesh.face(f)[2]) - a;
        const Vec3 pv = d.cross(e2);
        const double det = e1.dot(pv);
        if (std::abs(det) < 1e-300) continue;
        const Vec3 tv = o - a;
        const double u = tv.dot(pv) / det;
        if (u < 0 || u > 1) continue;
        const Vec3 qv = tv.cross(e1);
        const double v = d.dot(qv) / det;
        if (v < 0 || u + v > 1) continue;
        const double t = e2.dot(qv) / det;
        if (t > 0 && (best < 0 || t < best)) best = t, face = f;
    }
    return best;
}

class StudioDisplay : public rosy::test::StudioFixture {
protected:
    void SetUp() override {
        rosy::studio::StudioOptions o;
        o.displayAbove = 1000;
        o.displayFaces = 800;
        serve("rosy-studio-display-",
              "mesh: " + rosy::test::kHead + "\ncamera:\n  auto: true\n  resolution: [128, 96]\nfield:\n  symmetry: 4\n", o);
    }
};

} // namespace

TEST(DisplayMesh, ClustersALargeMeshAndKeepsASmallOne) {
    const rosy::field::Mesh mesh = rosy::field::loadMesh(rosy::test::kHead);
    const rosy::studio::DisplayMesh same = rosy::studio::makeDisplayMesh(mesh, mesh.nFaces());
    EXPECT_EQ(same.cellSize, 0.0);
    EXPECT_EQ(same.faces, mesh.faces());
    ASSERT_EQ(int(same.fullVertex.size()), mesh.nVertices());
    for (int v = 0; v < mesh.nVertices(); ++v) EXPECT_EQ(same.fullVertex[v], v);

    for (int limit : {1500, 800, 200}) {
        const rosy::studio::DisplayMesh d = rosy::studio::makeDisplayMesh(mesh, limit);
        EXPECT_GT(d.cellSize, 0.0);
        EXPECT_LE(int(d.faces.size()), limit);
        EXPECT_GT(int(d.faces.size()), limit / 4) << "far coarser than asked";
        // Display vertices are distinct vertices of the full mesh, each used by a face.
        std::set<int> full(d.fullVertex.begin(), d.fullVertex.end());
        EXPECT_EQ(full.size(), d.fullVertex.size());
        EXPECT_GE(*full.begin(), 0);
        EXPECT_LT(*full.rbegin(), mesh.nVertices());
        std::vector<int> used(d.fullVertex.size(), 0);
        std::set<std::array<int, 3>> seen;
        for (const auto &f : d.faces) {
            EXPECT_TRUE(f[0] != f[1] && f[1] != f[2] && f[0] != f[2]);
            for (int c : f) ++used[size_t(c)];
            std::array<int, 3> s = f;
            std::sort(s.begin(), s.end());
            EXPECT_TRUE(seen.insert(s).second) << "duplicate face";
        }
        EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
        // The surface is kept: the display mesh's area is close to the mesh's.
        std::vector<int> identity(static_cast<size_t>(mesh.nVertices()));
        for (int v = 0; v < mesh.nVertices(); ++v) identity[v] = v;
        const double a = area(mesh, d.faces, d.fullVertex), full0 = area(mesh, mesh.faces(), identity);
        EXPECT_NEAR(a / full0, 1.0, 0.2) << "at most " << limit << " faces";
    }
}

TEST_F(StudioDisplay, AboveTheThresholdThePageGetsTheDisplayMeshStreamed) {
    const rosy::field::Mesh mesh = rosy::field::loadMesh(rosy::test::kHead);
    const json s = json::parse(client->Get("/api/state")->body);
    EXPECT_EQ(s["faces"], mesh.nFaces()); // the library's mesh
    EXPECT_TRUE(s["display"]["decimated"].get<bool>());
    const int nV = s["display"]["vertices"], nF = s["display"]["faces"];
    EXPECT_LE(nF, 800);
    EXPECT_LT(nV, mesh.nVertices() / 2);

    auto m = client->Get("/api/mesh");
    ASSERT_TRUE(m);
    ASSERT_EQ(m->status, 200);
    EXPECT_EQ(m->get_header_value("Transfer-Encoding"), "chunked");
    const std::string &b = m->body;
    ASSERT_EQ(b.compare(0, 4, "RSM1"), 0);
    ASSERT_EQ(int(u32(b, 4)), nV);
    ASSERT_EQ(int(u32(b, 8)), nF);
    EXPECT_EQ(u32(b, 12), 1u); // decimated: the full vertex ids follow the corners
    // Bounded by the display mesh, not the full one.
    ASSERT_EQ(b.size(), 16 + 16 * size_t(nV) + 12 * size_t(nF));
    const size_t ids = 16 + 12 * size_t(nV) + 12 * size_t(nF);
    std::vector<int> fullOf(static_cast<size_t>(nV));
    for (int i = 0; i < nV; ++i) {
        fullOf[i] = int(u32(b, ids + 4 * i));
        ASSERT_LT(fullOf[i], mesh.nVertices());
        for (int c = 0; c < 3; ++c) EXPECT_EQ(f32(b, 16 + 12 * i + 4 * c), float(mesh.position(fullOf[i])[c]));
    }
    for (int f = 0; f < nF; ++f)
        for (int c = 0; c < 3; ++c) EXPECT_LT(int(u32(b, 16 + 12 * nV + 12 * f + 4 * c)), nV);

    // The field: the full mesh's field sampled at the display vertices, bit for bit
    // what a studio showing the whole mesh sends for those vertices, before and after
    // an edit (the incremental update of the sent directions included).
    rosy::studio::Studio whole(scenePath);
    auto sameField = [&](const std::string &fb, const std::string &wb) {
        ASSERT_EQ(fb.compare(0, 4, "RSF1"), 0);
        ASSERT_EQ(int(u32(fb, 4)), nV);
        ASSERT_EQ(fb.size(), 16 + 24 * size_t(nV));
        const int wV = int(u32(wb, 4));
        ASSERT_EQ(wV, mesh.nVertices());
        int differ = 0;
        for (int i = 0; i < nV; ++i)
            for (int c = 0; c < 3; ++c) {
                differ += std::memcmp(fb.data() + 16 + 12 * i + 4 * c, wb.data() + 16 + 12 * fullOf[i] + 4 * c, 4) != 0;
                differ += std::memcmp(fb.data() + 16 + 12 * nV + 12 * i + 4 * c,
                                      wb.data() + 16 + 12 * wV + 12 * fullOf[i] + 4 * c, 4) != 0;
            }
        EXPECT_EQ(differ, 0);
    };
    sameField(client->Get("/api/field")->body, whole.fieldBinary());
    const Vec3 p = mesh.position(fullOf[nV / 2]);
    const std::string add =
        json{{"op", "add_element"}, {"position", {p.x(), p.y(), p.z()}}, {"order", 1}, {"phase", 0}}.dump();
    auto r = client->Post("/api/edit", add, "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const size_t jsonBytes = u32(r->body, 4);
    whole.edit(add);
    sameField(r->body.substr(8 + jsonBytes), whole.fieldBinary());
    EXPECT_LT(r->body.size(), 8 + jsonBytes + 16 + 24 * size_t(mesh.nVertices()) / 2);
}

TEST_F(StudioDisplay, PicksLandOnTheFullSurface) {
    const rosy::field::Mesh mesh = rosy::field::loadMesh(rosy::test::kHead);
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    const Vec3 centre = 0.5 * (lo + hi);
    const double diag = (hi - lo).norm();
    int hits = 0;
    for (const Vec3 &toward : {Vec3(0, 0, 1), Vec3(1, 0.2, 0.1), Vec3(-0.3, 1, 0.5), Vec3(0.2, -0.4, -1)}) {
        const Vec3 d = -toward.normalized();
        const Vec3 o = centre - 2 * diag * d + 0.05 * diag * Vec3(0.3, -0.2, 0.1);
        auto r = client->Post("/api/pick", json{{"origin", {o.x(), o.y(), o.z()}}, {"direction", {d.x(), d.y(), d.z()}}}.dump(),
                              "application/json");
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 200) << r->body;
        const json j = json::parse(r->body);
        int face = -1;
        const double t = bruteForceHit(mesh, o, d, face);
        ASSERT_EQ(j["hit"].get<bool>(), t > 0);
        if (t <= 0) continue;
        ++hits;
        const Vec3 q(j["position"][0], j["position"][1], j["position"][2]);
        // The first surface point along the ray, on the full mesh (Embree works in floats).
        EXPECT_LT((q - (o + t * d)).norm(), 1e-5 * diag);
        EXPECT_EQ(j["face"].get<int>(), face);
        const rosy::field::Face &f = mesh.face(face);
        const Vec3 n = (mesh.position(f[1]) - mesh.position(f[0])).cross(mesh.position(f[2]) - mesh.position(f[0]));
        EXPECT_LT(std::abs(n.normalized().dot(q - mesh.position(f[0]))), 1e-9 * diag) << "off the face's plane";
        // An element there is on the surface: the library takes it.
        auto e = client->Post("/api/edit",
                              json{{"op", "add_element"}, {"position", j["position"]}, {"order", 0}, {"direction", {1, 0, 0}}}
                                  .dump(),
                              "application/json");
        ASSERT_TRUE(e);
        ASSERT_EQ(e->status, 200) << e->body;
        // The state gives it its face's normal (the page turns directions about it).
        const json st = json::parse(e->body.substr(8, u32(e->body, 4)));
        const json &nj = st["elements"].back()["normal"];
        EXPECT_GT(Vec3(nj[0], nj[1], nj[2]).dot(n.normalized()), 0.999);
    }
    EXPECT_GE(hits, 3);
    // A miss, and refused bodies.
    auto miss = client->Post("/api/pick", json{{"origin", {centre.x() + 2 * diag, centre.y(), centre.z()}},
                                               {"direction", {1, 0, 0}}}.dump(),
                             "application/json");
    ASSERT_TRUE(miss);
    EXPECT_EQ(json::parse(miss->body), json({{"hit", false}}));
    for (const char *bad : {"{", "[]", "{\"origin\": [0,0,0]}", "{\"origin\": [0,0,0], \"direction\": [0,0,0]}",
                            "{\"origin\": [0,0,0], \"direction\": [1,0,0], \"x\": 1}",
                            "{\"origin\": [0,0], \"direction\": [1,0,0]}"}) {
        auto r = client->Post("/api/pick", bad, "application/json");
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 400) << bad;
        EXPECT_NE(r->body.find("error"), std::string::npos) << r->body;
    }
}
