// rosyhatch studio: every endpoint of the HTTP API through httplib's client on an
// ephemeral port, the security checks (token, Host/Origin, traversal, body bound,
// malformed requests), and the promise that the saved scene renders the preview.

#include "core/error.h"
#include "field/design.h"
#include "field/mesh/poly_mesh.h"
#include "field/mesh_io.h"
#include "studio/server.h"
#include "studio/studio.h"
#include "studio_test_util.h"
#include "tests/test_output.h"
#include "field/primitives.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"
#include "../field/scan_like.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {


using rosy::test::slurp;

using rosy::test::f32;
using rosy::test::u32;

/// The JSON of an edit response ("RSE1", length, JSON, field).
json editJson(const std::string &body) {
    if (body.size() < 8 || body.compare(0, 4, "RSE1") != 0) return json();
    return json::parse(body.substr(8, u32(body, 4)));
}

/// Sends `request` as raw bytes and returns the whole answer (the connection is closed by the request).
std::string rawRequest(int port, const std::string &request) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(uint16_t(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr *>(&addr), sizeof addr) != 0) {
        close(fd);
        return "connect failed";
    }
    (void)!write(fd, request.data(), request.size());
    // Read until the server closes. No shutdown(SHUT_WR): a server that answers
    // before reading everything would reset the connection, losing its answer.
    timeval tv{5, 0};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::string out;
    char buf[4096];
    ssize_t n;
    while ((n = read(fd, buf, sizeof buf)) > 0) {
        out.append(buf, size_t(n));
        // Stop at the end of the first answer (headers + Content-Length bytes).
        const size_t end = out.find("\r\n\r\n");
        if (end == std::string::npos) continue;
        std::string head = out.substr(0, end);
        std::transform(head.begin(), head.end(), head.begin(), ::tolower);
        const size_t cl = head.find("content-length: ");
        const size_t length = cl == std::string::npos ? 0 : std::stoul(head.substr(cl + 16));
        if (out.size() >= end + 4 + length) break;
    }
    if (n < 0) out += "\n[read error: " + std::string(std::strerror(errno)) + "]";
    close(fd);
    return out;
}

int statusOf(const std::string &answer) {
    return answer.size() > 12 && answer.rfind("HTTP/1.1 ", 0) == 0 ? std::stoi(answer.substr(9, 3)) : -1;
}

class Studio : public rosy::test::StudioFixture {
protected:
    void SetUp() override {
        serve("rosy-studio-test-", "# a comment the save keeps\nmesh: " + rosy::test::kHead +
                                       "\ncamera:\n  auto: true\n  direction: [-0.6, 0.2, 1.0]\n  fov: 30\n"
                                       "  resolution: [256, 192]\nfield:\n  symmetry: 4\nstyle:\n  ambient: 0.08\n"
                                       "output: head.png\n");
    }
    json state() {
        auto r = client->Get("/api/state");
        return r && r->status == 200 ? json::parse(r->body) : json();
    }
    httplib::Result edit(const json &body) { return client->Post("/api/edit", body.dump(), "application/json"); }
    /// Ids of the closest +1/N, −1/N pair.
    std::pair<int, int> closestPair(const json &s) {
        std::pair<int, int> best{-1, -1};
        double bestD = 1e300;
        for (const auto &a : s["singularities"])
            for (const auto &b : s["singularities"]) {
                if (a["index_numerator"] != 1 || b["index_numerator"] != -1) continue;
                double d = 0;
                for (int c = 0; c < 3; ++c) d += std::pow(a["position"][c].get<double>() - b["position"][c].get<double>(), 2);
                if (d < bestD) bestD = d, best = {a["id"], b["id"]};
            }
        return best;
    }
};

TEST_F(Studio, ServesThePageAndThreeJsWithTheToken) {
    httplib::Client plain("127.0.0.1", port);
    auto page = plain.Get("/?token=" + server->token());
    ASSERT_TRUE(page);
    EXPECT_EQ(page->status, 200);
    EXPECT_NE(page->body.find("app.js"), std::string::npos);
    const std::string cookie = page->get_header_value("Set-Cookie");
    EXPECT_NE(cookie.find(server->token()), std::string::npos);
    EXPECT_NE(cookie.find("HttpOnly"), std::string::npos);
    EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos);
    // The cookie alone opens the rest (module scripts cannot send headers).
    const std::string pair = cookie.substr(0, cookie.find(';'));
    auto app = plain.Get("/app.js", {{"Cookie", "other=1; " + pair}});
    ASSERT_TRUE(app);
    EXPECT_EQ(app->status, 200);
    EXPECT_NE(app->get_header_value("Content-Type").find("javascript"), std::string::npos);
    auto three = client->Get("/three/build/three.module.js");
    ASSERT_TRUE(three);
    EXPECT_EQ(three->status, 200);
    EXPECT_EQ(three->body, slurp("/usr/share/javascript/three/build/three.module.js"));
    auto orbit = client->Get("/three/examples/jsm/controls/OrbitControls.js");
    ASSERT_TRUE(orbit);
    EXPECT_EQ(orbit->status, 200);
    EXPECT_EQ(client->Get("/studio.css")->status, 200);
    EXPECT_EQ(client->Get("/three/three.js")->status, 404); // not on the list
    EXPECT_EQ(client->Get("/api/nothing")->status, 404);
}

TEST_F(Studio, RefusesAMissingOrWrongToken) {
    httplib::Client plain("127.0.0.1", port);
    EXPECT_EQ(plain.Get("/api/state")->status, 403);
    EXPECT_EQ(plain.Get("/")->status, 403);
    std::string wrong = server->token();
    wrong[0] = wrong[0] == 'a' ? 'b' : 'a';
    EXPECT_EQ(plain.Get("/api/state", {{"X-Rosy-Token", wrong}})->status, 403);
    EXPECT_EQ(plain.Get("/api/state?token=" + wrong)->status, 403);
    EXPECT_EQ(plain.Get("/api/state", {{"X-Rosy-Token", server->token() + "0"}})->status, 403);
    EXPECT_EQ(plain.Get("/api/state", {{"Cookie", "rosyhatch_studio_token_1=" + server->token()}})->status, 403);
    EXPECT_EQ(plain.Post("/api/undo", "", "text/plain")->status, 403);
    EXPECT_EQ(plain.Get("/api/state", {{"X-Rosy-Token", server->token()}})->status, 200);
    EXPECT_EQ(server->token().size(), 32u);
}

TEST_F(Studio, RefusesForeignHostAndOriginHeaders) {
    const std::string p = std::to_string(port);
    auto evilHost = client->Get("/api/state", {{"Host", "evil.example:" + p}});
    ASSERT_TRUE(evilHost);
    EXPECT_EQ(evilHost->status, 403);
    EXPECT_NE(evilHost->body.find("DNS rebinding"), std::string::npos);
    EXPECT_EQ(client->Get("/api/state", {{"Host", "127.0.0.1:1"}})->status, 403);
    EXPECT_EQ(client->Get("/api/state", {{"Host", "localhost:" + p}})->status, 200);
    EXPECT_EQ(client->Get("/api/state", {{"Origin", "http://evil.example"}})->status, 403);
    EXPECT_EQ(client->Post("/api/undo", {{"Origin", "http://127.0.0.1:" + p + ".evil.example"}}, "", "text/plain")->status,
              403);
    EXPECT_EQ(client->Get("/api/state", {{"Origin", "http://127.0.0.1:" + p}})->status, 200);
    // Without any Host header (HTTP/1.0 style) the request is refused too.
    EXPECT_EQ(statusOf(rawRequest(port, "GET /api/state?token=" + server->token() + " HTTP/1.1\r\nConnection: close\r\n\r\n")),
              403);
}

TEST_F(Studio, RefusesPathTraversal) {
    const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\nX-Rosy-Token: " + server->token() +
                             "\r\nConnection: close\r\n\r\n";
    for (const std::string target :
         {"/../../../../etc/passwd", "/three/../../../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd",
          "/%2E%2E%2F%2E%2E%2Fetc%2Fpasswd", "/three/build/..%2f..%2f..%2f..%2fetc%2fpasswd", "//etc/passwd",
          "/..\\..\\etc\\passwd", "/%252e%252e/etc/passwd", "/app.js%00.png", "etc/passwd",
          "http://127.0.0.1/etc/passwd"}) {
        const std::string answer = rawRequest(port, "GET " + target + " HTTP/1.1\r\n" + host);
        EXPECT_EQ(statusOf(answer), 400) << target << "\n" << answer;
        EXPECT_EQ(answer.find("root:"), std::string::npos) << target;
    }
    // Absolute paths and files outside the list are simply not there.
    for (const std::string target : {"/etc/passwd", "/usr/share/javascript/three/three.js", "/index.html", "/web/app.js"}) {
        auto r = client->Get(target);
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 404) << target;
    }
}

TEST_F(Studio, MalformedRequestsGet400AndTheServerKeepsRunning) {
    EXPECT_EQ(statusOf(rawRequest(port, "GARBAGE\r\n\r\n")), 400);
    EXPECT_EQ(statusOf(rawRequest(port, "GET\r\n\r\n")), 400);
    for (const std::string body : {"not json", "[1,2]", "{}", "{\"op\": 3}", "{\"op\": \"explode\"}",
                                   "{\"op\": \"cancel\", \"a\": 100000, \"b\": 0}",
                                   "{\"op\": \"cancel\", \"a\": 0, \"b\": 0}",
                                   "{\"op\": \"add_element\", \"position\": [0, 0]}",
                                   "{\"op\": \"add_element\", \"position\": [1e400, 0, 0]}",
                                   "{\"op\": \"add_element\", \"position\": [0, 0, 0], \"order\": 2}",
                                   "{\"op\": \"add_element\", \"position\": [50, 50, 50], \"order\": 0}",
                                   "{\"op\": \"set\", \"symmetry\": 0}", "{\"op\": \"set\", \"source\": \"magic\"}",
                                   "{\"op\": \"set\", \"bogus\": 1}", "{\"op\": \"delete_element\", \"index\": 0}",
                                   "{\"op\": \"move_singularity\", \"id\": 0, \"to\": [90, 0, 0]}"}) {
        auto r = client->Post("/api/edit", body, "application/json");
        ASSERT_TRUE(r) << body;
        EXPECT_EQ(r->status, 400) << body;
        EXPECT_NE(r->body.find("error"), std::string::npos) << body << ": " << r->body;
    }
    auto off = edit({{"op", "add_element"}, {"position", {50, 50, 50}}, {"order", 0}});
    EXPECT_NE(off->body.find("from the surface"), std::string::npos) << off->body;
    EXPECT_EQ(client->Post("/api/undo", "", "text/plain")->status, 400); // nothing to undo
    EXPECT_EQ(client->Post("/api/preview?size=5", "", "text/plain")->status, 400);
    EXPECT_EQ(client->Post("/api/preview?size=abc", "", "text/plain")->status, 400);
    EXPECT_EQ(client->Post("/api/preview?size=64&of=edited", "", "text/plain")->status, 400);
    // A body over the bound is refused before it is read whole.
    auto big = client->Post("/api/edit", std::string(200 * 1024, ' '), "application/json");
    ASSERT_TRUE(big);
    EXPECT_EQ(big->status, 413);
    // None of that changed anything or stopped the server.
    const json s = state();
    ASSERT_TRUE(s.is_object());
    EXPECT_TRUE(s["elements"].empty());
    EXPECT_TRUE(s["edits"].empty());
    EXPECT_FALSE(s["can_undo"].get<bool>());
}

TEST_F(Studio, MeshAndFieldAreCompactBinary) {
    const rosy::field::Mesh mesh = rosy::field::loadMesh(rosy::test::kHead);
    auto m = client->Get("/api/mesh");
    ASSERT_TRUE(m);
    ASSERT_EQ(m->status, 200);
    const std::string &b = m->body;
    ASSERT_EQ(b.compare(0, 4, "RSM1"), 0);
    const uint32_t nV = u32(b, 4), nF = u32(b, 8);
    EXPECT_EQ(int(nV), mesh.nVertices());
    EXPECT_EQ(int(nF), mesh.nFaces());
    ASSERT_EQ(b.size(), 16 + 12 * size_t(nV) + 12 * size_t(nF));
    for (int v : {0, int(nV) / 2, int(nV) - 1})
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(f32(b, 16 + 12 * v + 4 * c), float(mesh.position(v)[c]));
    for (int f : {0, int(nF) - 1})
        for (int c = 0; c < 3; ++c) EXPECT_EQ(int(u32(b, 16 + 12 * nV + 12 * f + 4 * c)), mesh.face(f)[c]);

    auto fr = client->Get("/api/field");
    ASSERT_TRUE(fr);
    const std::string &fb = fr->body;
    ASSERT_EQ(fb.compare(0, 4, "RSF1"), 0);
    EXPECT_EQ(u32(fb, 4), nV);
    EXPECT_EQ(u32(fb, 8), 4u);
    ASSERT_EQ(fb.size(), 16 + 24 * size_t(nV));
    int unit = 0;
    for (uint32_t v = 0; v < nV; ++v) {
        const size_t d = 16 + 12 * size_t(v), n = 16 + 12 * size_t(nV) + 12 * size_t(v);
        double dd = 0, nn = 0, dn = 0;
        for (int c = 0; c < 3; ++c) {
            dd += f32(fb, d + 4 * c) * f32(fb, d + 4 * c);
            nn += f32(fb, n + 4 * c) * f32(fb, n + 4 * c);
            dn += f32(fb, d + 4 * c) * f32(fb, n + 4 * c);
        }
        EXPECT_NEAR(nn, 1.0, 1e-5);
        if (dd > 0.5) {
            ++unit;
            EXPECT_NEAR(dd, 1.0, 1e-5);
            EXPECT_NEAR(dn, 0.0, 1e-4) << "direction not tangent at vertex " << v;
        }
    }
    EXPECT_GT(unit, int(nV) * 9 / 10);

    auto sing = client->Get("/api/singularities");
    ASSERT_TRUE(sing);
    const json sj = json::parse(sing->body);
    const json st = state();
    EXPECT_EQ(sj["singularities"], st["singularities"]);
    // Poincaré–Hopf: index sum + boundary index = V − E + F of the mesh file.
    EXPECT_NEAR(st["index_sum"].get<double>() + st["boundary_index"].get<double>(),
                double(mesh.nVertices() - mesh.nEdges() + mesh.nFaces()), 1e-9);
    auto sep = client->Get("/api/separatrices");
    ASSERT_TRUE(sep);
    const json sp = json::parse(sep->body);
    ASSERT_FALSE(sp["separatrices"].empty());
    for (const auto &s : sp["separatrices"]) EXPECT_LT(s["singularity"].get<size_t>(), sj["singularities"].size());
}

TEST_F(Studio, CancelMoveElementsUndoRedo) {
    const json s0 = state();
    const size_t n0 = s0["singularities"].size();
    ASSERT_GE(n0, 4u);
    const auto [a, b] = closestPair(s0);
    ASSERT_GE(a, 0);
    // Same signs are refused with a reason.
    int other = -1;
    for (const auto &s : s0["singularities"])
        if (s["index_numerator"] == 1 && s["id"] != a) other = s["id"];
    auto same = edit({{"op", "cancel"}, {"a", a}, {"b", other}});
    EXPECT_EQ(same->status, 400);
    EXPECT_NE(same->body.find("+1/N and a -1/N"), std::string::npos) << same->body;

    auto r = edit({{"op", "cancel"}, {"a", a}, {"b", b}});
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    json s1 = editJson(r->body);
    EXPECT_EQ(s1["singularities"].size(), n0 - 2);
    EXPECT_EQ(s1["index_sum"], s0["index_sum"]);
    ASSERT_EQ(s1["edits"].size(), 1u);
    EXPECT_EQ(s1["edits"][0]["op"], "cancel_near");
    // The response carries the field too.
    const uint32_t jsonBytes = u32(r->body, 4);
    EXPECT_EQ(jsonBytes % 4, 0u);
    EXPECT_EQ(r->body.compare(8 + jsonBytes, 4, "RSF1"), 0);
    EXPECT_EQ(r->body.substr(8 + jsonBytes), client->Get("/api/field")->body);

    // Move a first-order singularity a short way toward its nearest neighbour vertex ring.
    const json &mover = s1["singularities"][0];
    std::vector<double> to = mover["position"];
    const json st = state();
    ASSERT_TRUE(st["can_undo"].get<bool>());
    // A regular element; then a singular one, whose singularity lands where it was put.
    auto add = edit({{"op", "add_element"}, {"position", mover["position"]}, {"order", 0}, {"direction", {0, 1, 0}}});
    ASSERT_EQ(add->status, 200) << add->body;
    json s2 = editJson(add->body);
    EXPECT_EQ(s2["elements"].size(), 1u);
    auto upd = edit({{"op", "update_element"}, {"index", 0}, {"direction", {1, 0, 0}}});
    ASSERT_EQ(upd->status, 200) << upd->body;
    EXPECT_EQ(editJson(upd->body)["elements"][0]["direction"], json({1.0, 0.0, 0.0}));
    auto del = edit({{"op", "delete_element"}, {"index", 0}});
    ASSERT_EQ(del->status, 200) << del->body;
    json s3 = editJson(del->body);
    EXPECT_TRUE(s3["elements"].empty());
    EXPECT_EQ(s3["singularities"], s1["singularities"]); // same field as before the element

    // Undo walks back: delete, update, add, cancel; redo forward again.
    for (int i = 0; i < 3; ++i) ASSERT_EQ(client->Post("/api/undo", "", "text/plain")->status, 200);
    auto u = client->Post("/api/undo", "", "text/plain");
    ASSERT_EQ(u->status, 200);
    json su = editJson(u->body);
    EXPECT_EQ(su["singularities"], s0["singularities"]);
    EXPECT_FALSE(su["can_undo"].get<bool>());
    auto re = client->Post("/api/redo", "", "text/plain");
    ASSERT_EQ(re->status, 200);
    EXPECT_EQ(editJson(re->body)["singularities"], s1["singularities"]);

    // Delete the cancel: the field is the original again.
    auto de = edit({{"op", "delete_edit"}, {"index", 0}});
    ASSERT_EQ(de->status, 200) << de->body;
    EXPECT_EQ(editJson(de->body)["singularities"], s0["singularities"]);
    // A new edit clears the redo list.
    EXPECT_FALSE(editJson(de->body)["can_redo"].get<bool>());

    // Move: a singularity moved onto another's spot is refused; moved to its own spot is a no-op.
    auto moveOnto = edit({{"op", "move_singularity"}, {"id", 0}, {"to", s0["singularities"][1]["position"]}});
    EXPECT_EQ(moveOnto->status, 400) << moveOnto->body;
    auto stay = edit({{"op", "move_singularity"}, {"id", 0}, {"to", s0["singularities"][0]["position"]}});
    ASSERT_EQ(stay->status, 200) << stay->body;
    EXPECT_EQ(editJson(stay->body)["singularities"], s0["singularities"]);
}

TEST_F(Studio, SingularElementAndSettings) {
    const json s0 = state();
    // A +1 element with the curvature source puts a +1/4 singularity into its face.
    const std::vector<double> p = s0["singularities"][0]["position"];
    auto r = edit({{"op", "set"}, {"symmetry", 2}});
    ASSERT_EQ(r->status, 200) << r->body;
    json s = editJson(r->body);
    EXPECT_EQ(s["symmetry"], 2);
    EXPECT_EQ(u32(r->body, 8 + u32(r->body, 4) + 8), 2u); // N in the field header
    EXPECT_NEAR(s["index_sum"].get<double>() + s["boundary_index"].get<double>(),
                s0["index_sum"].get<double>() + s0["boundary_index"].get<double>(), 1e-9); // χ for any N
    auto d = edit({{"op", "set"}, {"source", "design"}});
    EXPECT_EQ(d->status, 400); // no elements yet
    EXPECT_NE(d->body.find("element"), std::string::npos) << d->body;
    auto e = edit({{"op", "add_element"}, {"position", {0, 0, 0}}, {"order", 1}, {"phase", 30}});
    // (0,0,0) may be inside the head: far from the surface it is refused, near it snapped.
    EXPECT_EQ(e->status, 400);
    EXPECT_NE(e->body.find("from the surface"), std::string::npos) << e->body;
    // On a singularity's own spot it is taken, and a +1/2 singularity sits in the element's face.
    auto on = edit({{"op", "add_element"}, {"position", p}, {"order", 1}, {"phase", 30}});
    ASSERT_EQ(on->status, 200) << on->body;
    const json so = editJson(on->body);
    EXPECT_EQ(so["elements"].size(), 1u);
    const rosy::field::Mesh mesh = rosy::field::loadMesh(rosy::test::kHead);
    const int face = rosy::field::snapToSurface(mesh, rosy::field::Vec3(p[0], p[1], p[2])).face;
    std::vector<int> faces;
    for (const auto &q : so["singularities"])
        if (q["index_numerator"] == 1) faces.push_back(q["face"]);
    EXPECT_NE(std::find(faces.begin(), faces.end(), face), faces.end()) << "no +1/2 singularity in face " << face;
    auto sm = edit({{"op", "set"}, {"source", "smoothest"}, {"symmetry", 4}});
    ASSERT_EQ(sm->status, 200) << sm->body;
    EXPECT_EQ(editJson(sm->body)["source"], "smoothest");
    auto len = edit({{"op", "set"}, {"source", "curvature"}, {"smoothing_length", 20}});
    EXPECT_EQ(len->status, 400); // out of [1e-6, 10]
}

TEST_F(Studio, SavedSceneRendersExactlyThePreview) {
    const json s0 = state();
    const auto [a, b] = closestPair(s0);
    ASSERT_EQ(edit({{"op", "cancel"}, {"a", a}, {"b", b}})->status, 200);
    const std::vector<double> p = s0["singularities"][a]["position"];
    ASSERT_EQ(edit({{"op", "add_element"}, {"position", {p[0] + 1.0 / 3000, p[1], p[2]}}, {"order", 0},
                    {"direction", {0.3, 1.0 / 3.0, 0.1}}})
                  ->status,
              200);
    auto preview = client->Post("/api/preview?size=128", "", "text/plain");
    ASSERT_TRUE(preview);
    ASSERT_EQ(preview->status, 200) << preview->body;
    EXPECT_EQ(preview->get_header_value("Content-Type"), "image/png");
    EXPECT_EQ(preview->body.compare(1, 3, "PNG"), 0);

    // Bad names are refused; a good one lands beside the scene.
    for (const std::string bad : {"../x.yaml", "%2F..%2Fx.yaml", "x.off", ".x.yaml", "sub%2Fx.yaml"}) {
        auto r = client->Post("/api/save?name=" + bad, "", "text/plain");
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 400) << bad << ": " << r->body;
    }
    auto saved = client->Post("/api/save?name=edited.yaml", "", "text/plain");
    ASSERT_TRUE(saved);
    ASSERT_EQ(saved->status, 200) << saved->body;
    const fs::path savedPath = dir / "edited.yaml";
    EXPECT_EQ(json::parse(saved->body)["path"], savedPath.string());
    const std::string text = slurp(savedPath);
    EXPECT_NE(text.find("# a comment the save keeps"), std::string::npos);
    EXPECT_NE(text.find("cancel_near"), std::string::npos);
    EXPECT_NE(text.find("elements:"), std::string::npos);
    // The field sent after the edits (directions updated where they changed) is the
    // field of the saved scene built from scratch.
    EXPECT_TRUE(rosy::studio::Studio(savedPath.string()).fieldBinary() == client->Get("/api/field")->body);
    for (const auto &entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().rfind(".rosyhatch-", 0), std::string::npos) << entry.path();

    // The real program renders the saved scene (resolution scaled as the preview's: 256x192 -> 128x96).
    const std::string exe = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";
    const fs::path out = dir / "render.png", original = dir / "original.png";
    ASSERT_EQ(std::system((exe + " render " + savedPath.string() + " --set 'camera.resolution=[128,96]' -q -o " +
                           out.string() + " > /dev/null 2>&1")
                              .c_str()),
              0);
    EXPECT_TRUE(slurp(out) == preview->body) << "the saved scene's render differs from the preview";
    // The test can fail: the unedited scene draws something else.
    ASSERT_EQ(std::system((exe + " render " + scenePath + " --set 'camera.resolution=[128,96]' -q -o " +
                           original.string() + " > /dev/null 2>&1")
                              .c_str()),
              0);
    EXPECT_FALSE(slurp(original) == preview->body);
    // The original beside the edited one (`of=original`): the scene as the file gave it,
    // byte for byte what the real program renders of the unedited scene.
    auto before = client->Post("/api/preview?size=128&of=original", "", "text/plain");
    ASSERT_TRUE(before);
    ASSERT_EQ(before->status, 200) << before->body;
    EXPECT_TRUE(slurp(original) == before->body) << "the original preview differs from a render of the scene file";

    // In place: the scene file itself is replaced.
    auto inPlace = client->Post("/api/save", "", "text/plain");
    ASSERT_EQ(inPlace->status, 200) << inPlace->body;
    EXPECT_EQ(slurp(scenePath), text);
}

// The studio keeps what the field derives from the mesh alone across edits
// (field::FieldCache), and the saved scene must still give the preview byte for
// byte: after every element added (and N, source and elements changed), the
// studio's field is bit for bit the field a cold run of the pipeline builds from
// the scene text it would save, with the same singularities.
TEST_F(Studio, ElementAdditionsGiveTheColdPipelinesFieldBitForBit) {
    const json s0 = state();
    const std::vector<double> p = s0["singularities"][0]["position"], q = s0["singularities"][1]["position"];
    const std::vector<json> edits = {
        {{"op", "add_element"}, {"position", p}, {"order", 1}, {"phase", 30}},
        {{"op", "add_element"}, {"position", q}, {"order", -1}},
        {{"op", "add_element"}, {"position", {p[0] + 1.0 / 300, p[1], p[2]}}, {"order", 0},
         {"direction", {0.3, 1.0 / 3.0, 0.1}}},
        {{"op", "set"}, {"symmetry", 2}},
        {{"op", "add_element"}, {"position", {q[0], q[1] + 1.0 / 700, q[2]}}, {"order", 1}, {"strength", 0.5}},
        {{"op", "set"}, {"symmetry", 4}, {"smoothing_length", 0.05}},
        {{"op", "set"}, {"source", "design"}},
        {{"op", "set"}, {"source", "curvature"}},
        {{"op", "delete_element"}, {"index", 0}},
    };
    rosy::field::RosyField before = studio->field();
    for (size_t k = 0; k < edits.size(); ++k) {
        auto r = edit(edits[k]);
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 200) << edits[k].dump() << ": " << r->body;
        const rosy::field::RosyField warm = studio->field();
        EXPECT_FALSE(warm.nSym == before.nSym && warm.u == before.u) << "edit " << k << " changed nothing";
        before = warm;
        // Cold: a fresh scene loaded from the text the studio would save.
        const rosy::scenes::SceneDesc desc = rosy::scenes::parseScene(studio->sceneText(), scenePath);
        const rosy::scenes::SceneField cold = rosy::scenes::buildSceneField(desc);
        const rosy::field::RosyField &f = cold.field.field.field;
        ASSERT_EQ(f.nSym, warm.nSym) << "edit " << k;
        ASSERT_EQ(f.u.size(), warm.u.size());
        int differ = 0;
        for (int v = 0; v < f.u.size(); ++v) differ += !(f.u[v] == warm.u[v]);
        EXPECT_EQ(differ, 0) << "edit " << k << ": vertices whose field differs from a cold build";
        const json sings = json::parse(studio->singularitiesJson())["singularities"];
        ASSERT_EQ(sings.size(), cold.field.singularities.singularities.size()) << "edit " << k;
        for (size_t i = 0; i < sings.size(); ++i) {
            EXPECT_EQ(sings[i]["face"], cold.field.singularities.singularities[i].face);
            EXPECT_EQ(sings[i]["index_numerator"], cold.field.singularities.singularities[i].indexNumerator);
        }
    }
}

TEST_F(Studio, ConcurrentRequestsSeeOneField) {
    const json s0 = state();
    const std::vector<double> p = s0["singularities"][0]["position"];
    std::atomic<int> ok{0}, failed{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            httplib::Client c("127.0.0.1", port);
            c.set_default_headers({{"X-Rosy-Token", server->token()}});
            for (int i = 0; i < 3; ++i) {
                json body = {{"op", "add_element"}, {"position", p}, {"order", 0}, {"direction", {1, t, i}}};
                auto r = c.Post("/api/edit", body.dump(), "application/json");
                (r && r->status == 200 ? ok : failed)++;
                auto g = c.Get(t % 2 ? "/api/field" : "/api/state");
                if (!g || g->status != 200) failed++;
            }
        });
    for (auto &t : threads) t.join();
    EXPECT_EQ(failed.load(), 0);
    EXPECT_EQ(ok.load(), 12);
    EXPECT_EQ(state()["elements"].size(), 12u);
}

} // namespace

namespace {

/// Exit code of `command`, stopped after 60 s (a studio that starts when it should
/// not would serve forever: 124 then).
int runExit(const std::string &command) {
    const int status = std::system(("timeout 60 " + command).c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(StudioCli, ExitCodesAndTheUrlItServes) {
    const std::string exe = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";
    const fs::path dir = fs::temp_directory_path() / ("rosy-studio-cli-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path err = dir / "err.txt";
    // A missing scene is an I/O error, a broken one rejected input.
    EXPECT_EQ(runExit(exe + " studio " + (dir / "none.yaml").string() + " 2> " + err.string()), 3);
    std::ofstream(dir / "bad.yaml") << "mesh: [unclosed\n";
    EXPECT_EQ(runExit(exe + " studio " + (dir / "bad.yaml").string() + " 2> " + err.string()), 2);
    EXPECT_NE(slurp(err).find("bad.yaml:"), std::string::npos) << slurp(err);
    EXPECT_EQ(runExit(exe + " studio " + (dir / "bad.yaml").string() + " --port 70000 2> " + err.string()), 2);
    EXPECT_EQ(runExit(exe + " studio " + (dir / "bad.yaml").string() + " --display-above 1 2> " + err.string()), 2);
    EXPECT_NE(slurp(err).find("--display-above"), std::string::npos) << slurp(err);
    // A port already taken: exit 3 naming it.
    const fs::path scene = dir / "head.yaml";
    std::ofstream(scene) << "mesh: " << rosy::test::kHead << "\n";
    rosy::studio::Studio st(scene.string());
    rosy::studio::StudioServer taken(st, {});
    const int port = taken.bind();
    EXPECT_EQ(runExit(exe + " studio " + scene.string() + " --port " + std::to_string(port) + " 2> " + err.string()), 3);
    EXPECT_NE(slurp(err).find("cannot listen"), std::string::npos) << slurp(err);
    // Started for real: it prints the URL, which serves the state with its token.
    // The child is stopped (SIGTERM) and reaped however the test ends.
    struct Child {
        FILE *out = nullptr;
        int pid = -1;
        ~Child() {
            if (pid > 0) kill(pid, SIGTERM);
            if (out) pclose(out);
        }
    } child;
    child.out = popen(("echo $$; exec " + exe + " studio " + scene.string() + " 2>/dev/null").c_str(), "r");
    ASSERT_NE(child.out, nullptr);
    char line[512];
    std::vector<std::string> lines;
    if (fgets(line, sizeof line, child.out)) {
        lines.emplace_back(line);
        child.pid = std::stoi(lines[0]);
    }
    while (lines.size() < 3 && fgets(line, sizeof line, child.out)) lines.emplace_back(line);
    ASSERT_EQ(lines.size(), 3u);
    const std::string url = lines[2].substr(0, lines[2].find('\n'));
    ASSERT_EQ(url.rfind("http://127.0.0.1:", 0), 0u) << url;
    const int served = std::stoi(url.substr(17));
    const std::string token = url.substr(url.find("token=") + 6);
    EXPECT_EQ(token.size(), 32u);
    httplib::Client c("127.0.0.1", served);
    auto r = c.Get("/api/state?token=" + token);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(c.Get("/api/state")->status, 403);
    fs::remove_all(dir);
}

} // namespace

// A noisy scan (field/scan_noise.h) in the studio: the field is designed on the
// smoothed copy the pipeline uses, so its singularities stay the shape's few through
// edits (found on the scan's own frames they would be the noise's thousands), and the
// preview is shaded and projected from the copy as `render` draws the saved scene.
TEST(StudioScan, NoisyScanIsDesignedOnTheSmoothedCopyAndPreviewsAsRenderDraws) {
    std::string dirTemplate = (fs::temp_directory_path() / "rosy-studio-scan-XXXXXX").string();
    ASSERT_NE(mkdtemp(dirTemplate.data()), nullptr);
    const fs::path dir = dirTemplate;
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{dir};
    const fs::path meshPath = dir / "scan.off", scenePath = dir / "scan.yaml";
    rosy::field::writePolyMesh(meshPath.string(),
                               rosy::field::toPolyMesh(rosy::test::makeScanLike(
                                   rosy::field::makeEllipsoid(rosy::test::kScanEllipsoidLevel, 1.0, 0.7, 0.5),
                                   rosy::test::kScanEllipsoidNoise)));
    std::ofstream(scenePath) << "mesh: scan.off\ncamera: {auto: true, direction: [1, 0.4, 0.7], resolution: [128, 96]}\n";

    const rosy::scenes::SceneField cold = rosy::scenes::buildSceneField(rosy::scenes::parseSceneFile(scenePath.string()));
    ASSERT_TRUE(cold.field.smoothedSurface) << "the test mesh must be judged a noisy scan";
    rosy::studio::Studio studio(scenePath.string());
    EXPECT_TRUE(studio.field().u == cold.field.field.field.u); // the pipeline's, carried back
    const json s0 = json::parse(studio.singularitiesJson());
    EXPECT_EQ(s0["singularities"].size(), cold.field.singularities.singularities.size());
    EXPECT_LE(s0["singularities"].size(), 20u);

    // An element added: on a scan judged noise by a wide margin, the judgement carries
    // and the field on the scan itself is not built again (only its copy's); near the
    // threshold (the sanitizers' coarser ellipsoid) every rebuild judges anew. Either
    // way the same few singularities, and the render below judges from scratch.
    const bool carries = rosy::scenes::noiseJudgementCarries(cold.field);
#ifndef ROSY_SANITIZED
    EXPECT_TRUE(carries) << "density " << cold.field.noisyDensity;
#endif
    std::vector<double> at = s0["singularities"][0]["position"];
    for (double &c : at) c = -c; // the ellipsoid's antipode, on its surface
    studio.edit(json{{"op", "add_element"}, {"position", at}, {"order", 0}, {"direction", {0.3, 0.9, 0.1}}}.dump());
    bool ownField = false, copyField = false;
    for (const auto &[stage, ms] : studio.lastEditTimings()) {
        ownField |= stage == "field";
        copyField |= stage == "scan_field";
    }
    EXPECT_TRUE(copyField);
    EXPECT_EQ(ownField, !carries);
    const json s0e = json::parse(studio.singularitiesJson());
    EXPECT_LE(s0e["singularities"].size(), 20u);

    // Move a singularity a step along the surface: the same few, one of them there.
    std::vector<double> to = s0e["singularities"][0]["position"];
    to[0] += to[0] > 0 ? -0.04 : 0.04;
    studio.edit(json{{"op", "move_singularity"}, {"id", 0}, {"to", to}}.dump());
    const json s1 = json::parse(studio.singularitiesJson());
    EXPECT_EQ(s1["singularities"].size(), s0e["singularities"].size());
    double nearest = 1e300;
    for (const auto &sg : s1["singularities"]) {
        double d = 0;
        for (int c = 0; c < 3; ++c) d += std::pow(sg["position"][c].get<double>() - to[size_t(c)], 2);
        nearest = std::min(nearest, std::sqrt(d));
    }
    EXPECT_LT(nearest, 0.05);
    const json seps = json::parse(studio.separatricesJson());
    EXPECT_LE(seps["separatrices"].size(), 8 * s1["singularities"].size());
    // The directions sent lie in the copy's tangent planes, and so do the normals sent
    // with them (the page turns the arms about them): the scan's own are off by the noise.
    const std::string fieldBin = studio.fieldBinary();
    ASSERT_EQ(fieldBin.compare(0, 4, "RSF1"), 0);
    const uint32_t nV = u32(fieldBin, 4);
    ASSERT_EQ(fieldBin.size(), 16 + 24 * size_t(nV));
    double worst = 0;
    for (uint32_t v = 0; v < nV; ++v) {
        double dot = 0;
        for (int c = 0; c < 3; ++c) dot += f32(fieldBin, 16 + 12 * v + 4 * c) * f32(fieldBin, 16 + 12 * (nV + v) + 4 * c);
        worst = std::max(worst, std::abs(dot));
    }
    EXPECT_LT(worst, 1e-5);

    // The saved scene's render is the preview, byte for byte (its tone is the copy's).
    const std::string preview = studio.previewPng(128);
    EXPECT_EQ(preview.compare(1, 3, "PNG"), 0);
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "the render of the saved scene (a third field on the scan, ~15 s under the sanitizers) is "
                    "compared in the normal build";
#endif
    const std::string saved = studio.save("edited.yaml");
    const std::string exe = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";
    const fs::path out = dir / "render.png";
    ASSERT_EQ(std::system((exe + " render " + saved + " -q -o " + out.string() + " > /dev/null 2>&1").c_str()), 0);
    EXPECT_TRUE(slurp(out) == preview) << "the saved scene's render differs from the preview";
}
