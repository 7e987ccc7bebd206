// The mesh half of the bad-input catalogue (tests/README.md): every malformed
// file is rejected with `FILE:LINE[:COL]: error: what; how to fix` (or repaired
// with a warning), and awkward but valid meshes give finite fields that satisfy
// Poincare-Hopf. Bad files are generated here; nothing binary is committed.
#include "core/diagnostics.h"
#include "core/error.h"
#include "field/field_builder.h"
#include "field/frames.h"
#include "field/mesh_io.h"
#include "field/mesh_stats.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "field/sparse_solver.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <unistd.h>
#include <utility>

using namespace rosy;
using namespace rosy::field;
namespace fs = std::filesystem;

namespace {

const char *kTetraV = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const std::string kTetraOffFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const char *kTetraObjFaces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
const char *kPlyHeader = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";

std::string offTetra() { return std::string("OFF\n4 4 0\n") + kTetraV + kTetraOffFaces; }
std::string objTetra() {
    std::string s;
    for (const char *l : {"v 0 0 0\n", "v 1 0 0\n", "v 0 1 0\n", "v 0 0 1\n"}) s += l;
    return s + kTetraObjFaces;
}
std::string plyTetra() { return std::string(kPlyHeader) + kTetraV + kTetraOffFaces; }
std::string stlTetra() {
    const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    std::string s = "solid t\n";
    for (const auto &t : f) {
        s += "facet normal 0 0 0\nouter loop\n";
        for (int v : t)
            s += "vertex " + std::to_string(p[v][0]) + " " + std::to_string(p[v][1]) + " " +
                 std::to_string(p[v][2]) + "\n";
        s += "endloop\nendfacet\n";
    }
    return s + "endsolid t\n";
}

void put(std::string &s, const void *data, size_t n) { s.append(static_cast<const char *>(data), n); }

std::string binaryStl(uint32_t declared = 4, float poison = 0) {
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    std::string s(80, ' ');
    put(s, &declared, 4);
    for (const auto &t : f) {
        const float normal[3] = {0, 0, 0};
        put(s, normal, 12);
        for (int v : t) {
            float c[3] = {p[v][0] + poison, p[v][1], p[v][2]};
            put(s, c, 12);
        }
        s.append(2, '\0');
    }
    return s;
}

std::string binaryPly(uint32_t nVertices = 4, float poison = 0) {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(nVertices) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face 4\n"
                    "property list uchar int vertex_indices\nend_header\n";
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto &v : p) {
        float c[3] = {v[0] + poison, v[1], v[2]};
        put(s, c, 12);
    }
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto &t : f) {
        const uint8_t n = 3;
        put(s, &n, 1);
        put(s, t, 12);
    }
    return s;
}

class BadMesh : public ::testing::Test {
protected:
    void SetUp() override {
        const auto *info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() / ("rosy_bad_mesh_" + std::to_string(::getpid()) + "_" + info->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    std::string write(const std::string &name, const std::string &content) {
        const std::string path = (m_dir / name).string();
        std::ofstream(path, std::ios::binary) << content;
        return path;
    }
    /// Loads `content` as `name` and expects an InputError that starts with
    /// `path[:LINE[:COL]]: error: ` and contains `needle`; returns the message.
    std::string rejects(const std::string &name, const std::string &content, const std::string &where,
                        const std::string &needle = "", const LoadOptions &options = {}) {
        const std::string path = write(name, content);
        try {
            loadMesh(path, options);
        } catch (const InputError &e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.rfind(path + where + ": error: ", 0), 0u) << msg;
            EXPECT_NE(msg.find(needle), std::string::npos) << msg;
            // Every message carries a hint after "; ".
            EXPECT_NE(msg.find("; "), std::string::npos) << msg;
            return msg;
        } catch (const std::exception &e) {
            ADD_FAILURE() << name << ": expected InputError, got " << e.what();
            return {};
        }
        ADD_FAILURE() << name << ": expected InputError";
        return {};
    }
    Mesh loads(const std::string &name, const std::string &content, const LoadOptions &options = {}) {
        return loadMesh(write(name, content), options);
    }

    fs::path m_dir;
};

/// Positions and faces as loaded, for comparing two spellings of one file.
void expectSameMesh(const Mesh &a, const Mesh &b) {
    ASSERT_EQ(a.nVertices(), b.nVertices());
    ASSERT_EQ(a.nFaces(), b.nFaces());
    for (int v = 0; v < a.nVertices(); ++v) EXPECT_EQ(a.position(v), b.position(v)) << v;
    for (int f = 0; f < a.nFaces(); ++f) EXPECT_EQ(a.face(f), b.face(f)) << f;
}

/// Sum over faces of k_f / N per connected component (faces joined through edges).
std::vector<double> indexSumPerComponent(const Mesh &mesh, const std::vector<int> &k, int nSym,
                                         std::vector<int> &chi) {
    const int nF = mesh.nFaces();
    std::vector<int> comp(nF, -1);
    int nComp = 0;
    for (int seed = 0; seed < nF; ++seed) {
        if (comp[seed] >= 0) continue;
        std::vector<int> stack{seed};
        comp[seed] = nComp;
        while (!stack.empty()) {
            const int f = stack.back();
            stack.pop_back();
            for (int c = 0; c < 3; ++c) {
                const int t = mesh.twin(3 * f + c);
                if (t >= 0 && comp[t / 3] < 0) {
                    comp[t / 3] = nComp;
                    stack.push_back(t / 3);
                }
            }
        }
        ++nComp;
    }
    // chi_c = V_c - E_c + F_c with edges counted once per halfedge pair.
    std::vector<int> V(nComp, 0), E(nComp, 0), F(nComp, 0);
    std::vector<int> vertexComp(mesh.nVertices(), -1);
    for (int f = 0; f < nF; ++f) {
        ++F[comp[f]];
        for (int c = 0; c < 3; ++c) {
            const int h = 3 * f + c, t = mesh.twin(h);
            if (t < 0 || h < t) ++E[comp[f]];
            const int v = mesh.face(f)[c];
            if (vertexComp[v] < 0) {
                vertexComp[v] = comp[f];
                ++V[comp[f]];
            }
        }
    }
    std::vector<double> sums(nComp, 0.0);
    for (int f = 0; f < nF; ++f) sums[comp[f]] += double(k[f]) / nSym;
    chi.resize(nComp);
    for (int c = 0; c < nComp; ++c) chi[c] = V[c] - E[c] + F[c];
    return sums;
}

Mesh scaled(const Mesh &m, double s) {
    std::vector<Vec3> p;
    std::vector<std::vector<int>> f;
    for (int v = 0; v < m.nVertices(); ++v) p.push_back(m.position(v) * s);
    for (const Face &t : m.faces()) f.push_back({t[0], t[1], t[2]});
    return repairAndBuild(p, f, "scaled");
}

} // namespace

// --- mesh format ---------------------------------------------------------------

TEST_F(BadMesh, EmptyFileInEveryFormat) {
    for (const char *name : {"e.off", "e.obj", "e.ply", "e.stl"}) rejects(name, "", "", "empty");
    rejects("blank.off", " \n\r\n\t\n", "", "empty");
}

TEST_F(BadMesh, BinaryGarbageAndContentNotMatchingTheExtension) {
    std::string garbage;
    for (int i = 0; i < 1024; ++i) garbage += char((i * 37 + 11) & 0xff);
    rejects("g.off", garbage, ":1:1", "OFF header");
    rejects("g.ply", garbage, ":1:1", "PLY header");
    rejects("g.stl", garbage, ":1:1", "neither ASCII STL");
    rejects("g.obj", garbage, "", "no faces");
    rejects("obj.off", objTetra(), ":1:1", "OFF header");
    rejects("ply.stl", plyTetra(), ":1:1", "neither ASCII STL");
    rejects("off.ply", offTetra(), ":1:1", "PLY header");
}

TEST_F(BadMesh, TruncatedAsciiFilesNameTheirPlace) {
    // The face lines stop early: the counts line is named.
    rejects("t.off", std::string("OFF\n4 4 0\n") + kTetraV + "3 0 2 1\n3 0 1", ":2:1", "header says");
    // Long enough for the header's minimum, but the last face line is missing.
    rejects("t3.off", std::string("OFF\n4 4 0\n") + kTetraV + kTetraOffFaces.substr(0, 24) + "           ", ":2:1",
            "holds only");
    // A vertex cut in the middle of its coordinates.
    rejects("t2.off", "OFF\n4 4 0\n0 0 0\n1 0", ":2:1", "header says");
    rejects("t.obj", "v 0 0 0\nv 1 0\n", ":2:1", "fewer than 3 coordinates");
    rejects("t.ply", std::string(kPlyHeader) + kTetraV + "3 0 2 1\n3 0 1", ":1:1", "header says");
    rejects("t.stl", "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0", ":5:1",
            "fewer than 3 coordinates");
}

TEST_F(BadMesh, LargeOffFilesNameTheirFirstBadLine) {
    // ASCII OFF lines are parsed in parallel chunks of 4,096: the error named must
    // still be the first in the file, as a reading in order finds it. A 100 x 100
    // grid: vertex i on line 3 + i, face j on line 3 + 10,201 + j.
    const int n = 100, nV = (n + 1) * (n + 1), nF = 2 * n * n;
    std::vector<std::string> lines = {"OFF", std::to_string(nV) + " " + std::to_string(nF) + " 0"};
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) lines.push_back(std::to_string(i) + " " + std::to_string(j) + " 0");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            lines.push_back("3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c));
            lines.push_back("3 " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d));
        }
    auto file = [&](std::vector<std::pair<int, std::string>> edits) {
        std::vector<std::string> l = lines;
        for (const auto &[at, text] : edits) l[size_t(at)] = text;
        std::string s;
        for (const std::string &x : l) s += x + "\n";
        return s;
    };
    const int vLine = 3, fLine = 3 + nV; // 1-based line of vertex 0, face 0
    const std::string ok = file({});
    EXPECT_NO_THROW(loadMesh(write("ok.off", ok), {}));
    // Two bad vertices, the later in an earlier-finishing chunk or not: the first named.
    rejects("v.off", file({{vLine - 1 + 9000, "1 2 x"}, {vLine - 1 + 300, "1 y 2"}}),
            ":" + std::to_string(vLine + 300) + ":3", "expected a coordinate");
    // A bad face and a bad vertex: the vertex (earlier in the file).
    rejects("vf.off", file({{fLine - 1 + 100, "3 0 1 999999"}, {vLine - 1 + 9500, "1 2"}}),
            ":" + std::to_string(vLine + 9500) + ":1", "fewer than 3 coordinates");
    // Two bad faces: the first.
    rejects("f.off", file({{fLine - 1 + 15000, "3 0 1 -4"}, {fLine - 1 + 7000, "3 0 1 999999"}}),
            ":" + std::to_string(fLine + 7000) + ":7", "face 7000 uses vertex index '999999'");
    // A comment line (Geomview's OFF allows them) is skipped: a bad face after it is
    // named by its own line, and numbered as the faces before it count.
    rejects("fc.off", file({{fLine - 1 + 12000, "# note"}, {fLine - 1 + 500, "3 0 1 999999"}}),
            ":" + std::to_string(fLine + 500) + ":7", "face 500 uses vertex index");
    rejects("c.off", file({{fLine - 1 + 12000, "# note"}, {fLine - 1 + 15000, "3 0 1 999999"}}),
            ":" + std::to_string(fLine + 15000) + ":7", "face 14999 uses vertex index");
}

// Geomview's OFF lets '#' begin a comment running to the end of the line: lines of
// comments before the header, after it, between the vertices and the faces, and
// comments after the values all load to the mesh of the same file without them (the
// CGAL data's cube_poly.off, prim.off and mesh_with_colors.off have such lines).
TEST_F(BadMesh, OffCommentsAnywhereAreSkipped) {
    const std::string clean = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const std::string commented =
        "# written by hand\n\n  # indented\nOFF # the keyword\n# counts next\n4 4 0 # V F E\n"
        "0 0 0\n# the other three\n1 0 0   # x\n0 1 0#y\n0 0 1\n\n# faces\n3 0 2 1 # bottom\n"
        "3 0 1 3\n3 0 3 2 0.5 0.5 0.5 # with a colour\n3 1 2 3\n# the end\n";
    const Mesh a = loadMesh(write("clean.off", clean)), b = loadMesh(write("commented.off", commented));
    EXPECT_EQ(b.positions(), a.positions());
    EXPECT_EQ(b.faces(), a.faces());
    // A comment where the keyword should be is still no header; errors keep their lines.
    rejects("nokey.off", "# nothing but\n# comments\n", ":1:1", "expected an OFF header line");
    rejects("badkey.off", "# a comment\nOFX\n3 1 0\n", ":2:1", "expected an OFF header line");
    rejects("badv.off", "# c\nOFF\n3 1 0\n# c\n0 0 0\n1 x 0 # c\n0 1 0\n3 0 1 2\n", ":6:3",
            "expected a coordinate");
}

TEST_F(BadMesh, TruncatedBinaryPlyAndStl) {
    const std::string ply = binaryPly();
    rejects("t.ply", ply.substr(0, ply.size() - 7), ":1:1", "header says");
    // A binary STL cut short no longer has the size 84 + 50 n; it is not ASCII either.
    const std::string stl = binaryStl();
    rejects("t.stl", stl.substr(0, stl.size() - 30), ":1:1", "not 84 + 50 n bytes");
}

TEST_F(BadMesh, HeaderCountsBeyondTheFileSizeAreRejectedBeforeAllocating) {
    // Each header asks for gigabytes; the file holds a few bytes. Rejected from
    // the header alone (an allocation of that size would throw bad_alloc or be
    // killed, which the test would see).
    rejects("h.off", "OFF\n1000000000 4 0\n" + std::string(kTetraV), ":2:1", "header says");
    // More faces than the face limit: that check comes first.
    rejects("hf.off", "OFF\n4 1000000000 0\n" + std::string(kTetraV), ":2:1", "more than the limit");
    rejects("h2.off", "OFF\n2147483647 4 0\n" + std::string(kTetraV), ":2:1", "header says");
    rejects("h.ply", binaryPly(4000000000u), ":1:1", "header says");
    // Binary STL with a count of 2^32 - 1 but 4 triangles: the size does not match.
    rejects("h.stl", binaryStl(0xffffffffu), ":1:1", "not 84 + 50 n bytes");
    // Binary OFF.
    std::string boff = "OFF BINARY\n";
    const uint32_t counts[3] = {100000000, 4, 0};
    put(boff, counts, 12);
    rejects("h_bin.off", boff, ":2:1", "header says");
}

TEST_F(BadMesh, NegativeAndNonNumericCounts) {
    rejects("n.off", "OFF\n-4 4 0\n" + std::string(kTetraV) + kTetraOffFaces, ":2:1", "counts");
    rejects("x.off", "OFF\nfour 4 0\n" + std::string(kTetraV) + kTetraOffFaces, ":2:1", "counts");
    rejects("huge.off", "OFF\n99999999999999999999 4 0\n" + std::string(kTetraV), ":2:1", "counts");
    std::string ply = plyTetra();
    ply.replace(ply.find("vertex 4"), 8, "vertex -4");
    rejects("n.ply", ply, ":3:16", "COUNT >= 0");
    rejects("nface.off", "OFF\n4 1 0\n" + std::string(kTetraV) + "-3 0 1 2\n", ":7:1", "face 0 could not be parsed");
}

TEST_F(BadMesh, ObjIndexZeroOutOfRangeOrHuge) {
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    rejects("zero.obj", v + "f 0 3 2\n", ":5:3", "'0'");
    rejects("range.obj", v + "f 1 2 5\n", ":5:7", "only 4 vertices");
    rejects("neg.obj", v + "f 1 2 -5\n", ":5:7", "'-5'");
    rejects("huge.obj", v + "f 1 2 99999999999999999999999\n", ":5:7", "99999999999999999999999");
    // Index defined only later in the file: OBJ refers to vertices read so far.
    rejects("later.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n", ":2:5", "only 1 vertices");
    // OFF and PLY indices are 0-based, checked the same way.
    rejects("range.off", "OFF\n4 1 0\n" + std::string(kTetraV) + "3 0 1 4\n", ":7:7", "outside [0, 4)");
    rejects("range.ply", std::string(kPlyHeader) + kTetraV + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 7\n", ":17:7",
            "outside [0, 4)");
}

TEST_F(BadMesh, ObjNegativeIndicesCountBackFromTheLastVertex) {
    // -1 is the most recent vertex (OBJ spec), so -4..-1 are 1..4 here.
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    const Mesh relative = loads("rel.obj", v + "f -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n");
    const Mesh absolute = loads("abs.obj", v + kTetraObjFaces);
    expectSameMesh(relative, absolute);
    // Relative to the vertices read *so far*: a second tetrahedron after the first.
    const Mesh two = loads("two.obj", v + "f -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n" +
                                          "v 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n" +
                                          "f -4 -2 -3\nf -4 -3 -1\nf -4 -1 -2\nf -3 -2 -1\n");
    const MeshStats s = computeStats(two);
    EXPECT_EQ(s.components, 2);
    EXPECT_EQ(s.vertices, 8);
    EXPECT_EQ(s.eulerCharacteristic, 4);
}

TEST_F(BadMesh, NonFiniteAndAbsurdCoordinates) {
    rejects("nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n" + std::string(kTetraOffFaces), ":4:3",
            "non-finite");
    rejects("inf.obj", "v 0 0 0\nv 1 0 -inf\nv 0 1 0\nf 1 2 3\n", ":2:7", "non-finite");
    rejects("big.off", "OFF\n4 4 0\n0 0 0\n1e300 0 0\n0 1 0\n0 0 1\n" + std::string(kTetraOffFaces), ":4:1",
            "absurd coordinate");
    // Overflows a double: from_chars reports out of range.
    rejects("over.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n", ":2:3", "non-finite");
    rejects("nan.ply", std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 NaN 0\n0 0 1\n" + kTetraOffFaces, ":12:3",
            "non-finite");
    rejects("nan.stl", binaryStl(4, std::numeric_limits<float>::quiet_NaN()), "", "triangle 0");
    rejects("inf_bin.ply", binaryPly(4, std::numeric_limits<float>::infinity()), "", "vertex 0");
    rejects("big_bin.ply", binaryPly(4, 1e30f), "", "absurd");
    // Soups built by code are checked too.
    EXPECT_THROW(repairAndBuild({{0, 0, 0}, {1e16, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, "soup"), InputError);
}

TEST_F(BadMesh, CrlfBomTabsAndNoFinalNewlineParseLikeThePlainFile) {
    // Built char by char: string::insert trips GCC 12's false -Wrestrict.
    const auto crlf = [](const std::string &s) {
        std::string out;
        for (char c : s) {
            if (c == '\n') out.push_back('\r');
            out.push_back(c);
        }
        return out;
    };
    const auto tabs = [](std::string s) {
        std::replace(s.begin(), s.end(), ' ', '\t');
        return s;
    };
    const std::string bom = "\xEF\xBB\xBF";
    const auto chop = [](std::string s) { return s.substr(0, s.size() - 1); };
    struct Format {
        std::string ext, text;
    };
    for (const Format &f : {Format{".off", offTetra()}, Format{".obj", objTetra()}, Format{".ply", plyTetra()},
                            Format{".stl", stlTetra()}}) {
        SCOPED_TRACE(f.ext);
        const Mesh plain = loads("plain" + f.ext, f.text);
        EXPECT_EQ(plain.nFaces(), 4);
        expectSameMesh(loads("crlf" + f.ext, crlf(f.text)), plain);
        expectSameMesh(loads("bom" + f.ext, bom + f.text), plain);
        expectSameMesh(loads("bomcrlf" + f.ext, bom + crlf(f.text)), plain);
        expectSameMesh(loads("nonl" + f.ext, chop(f.text)), plain);
        if (f.ext != ".ply") expectSameMesh(loads("tabs" + f.ext, tabs(f.text)), plain);
    }
    // A binary PLY with a BOM still goes through the binary branch of our PLY reader.
    expectSameMesh(loads("bom_bin.ply", bom + binaryPly()), loads("plain_bin.ply", binaryPly()));
}

TEST_F(BadMesh, FaceLimitIsCheckedBeforeReading) {
    LoadOptions opt;
    opt.maxFaces = 3;
    rejects("l.off", offTetra(), ":2:1", "more than the limit of 3", opt);
    rejects("l.ply", plyTetra(), ":7:1", "more than the limit of 3", opt);
    rejects("l.obj", objTetra(), ":8:1", "more than the limit of 3", opt);
    rejects("l.stl", stlTetra(), ":23:1", "more than the limit of 3", opt);
    rejects("lb.stl", binaryStl(), "", "more than the limit of 3", opt);
    rejects("lb.ply", binaryPly(), ":7:1", "more than the limit of 3", opt);
    // The default is documented as 20 million.
    EXPECT_EQ(LoadOptions{}.maxFaces, 20'000'000);
    opt.maxFaces = 4;
    EXPECT_EQ(loads("ok.off", offTetra(), opt).nFaces(), 4);
}

// --- mesh topology -------------------------------------------------------------

TEST_F(BadMesh, FacesWithRepeatedVerticesAreDroppedWithAWarning) {
    WarningCapture capture;
    LoadReport rep;
    const Mesh m = loadMesh(write("rep.off", "OFF\n4 6 0\n" + std::string(kTetraV) + kTetraOffFaces +
                                                 "3 0 0 1\n4 1 2 2 1\n"),
                            {}, &rep);
    EXPECT_EQ(rep.degenerateFacesDropped, 2);
    EXPECT_TRUE(capture.has("degenerate-faces"));
    EXPECT_EQ(m.nFaces(), 4);
}

namespace {
/// A FieldSpec per source (curvature, smoothest, design) and Laplace weighting; the
/// design ones hold one element of `order` at `at`.
std::vector<FieldSpec> everySourceAndWeighting(const Vec3 &at, int order) {
    std::vector<FieldSpec> specs;
    for (LaplaceWeights w : {LaplaceWeights::MeanValue, LaplaceWeights::Cotan})
        for (FieldSource source : {FieldSource::Curvature, FieldSource::Smoothest, FieldSource::Design}) {
            FieldSpec spec;
            spec.weights = w;
            spec.source = source;
            if (source == FieldSource::Design) {
                DesignElement el;
                el.order = order;
                el.position = at;
                spec.elements.push_back(el);
            }
            specs.push_back(spec);
        }
    return specs;
}
} // namespace

TEST_F(BadMesh, NeedleFacesGiveAFiniteFieldOnBothWeightings) {
    // An octahedron with vertex 6 just outside the middle of edge (0, 1) and the
    // needle (0, 1, 6) filling the gap: its corner at 6 is pi - 4e-7, so its
    // cotangent is about -2.5e6 and must be clamped, not turned into NaN.
    // (Zero-area faces never get here: loading drops them, see MeshRepair.)
    const std::vector<Vec3> p = {{1, 0, 0},  {0, 1, 0},  {-1, 0, 0}, {0, -1, 0},
                                 {0, 0, 1},  {0, 0, -1}, {0.5 + 1e-7, 0.5 + 1e-7, 0}};
    const std::vector<std::vector<int>> f = {{0, 6, 4}, {6, 1, 4}, {0, 1, 6}, {1, 2, 4}, {2, 3, 4},
                                             {3, 0, 4}, {1, 0, 5}, {2, 1, 5}, {3, 2, 5}, {0, 3, 5}};
    WarningCapture capture;
    const Mesh mesh = repairAndBuild(p, f, "needles");
    EXPECT_EQ(computeStats(mesh).eulerCharacteristic, 2);
    const TangentFrames frames(mesh);
    for (const FieldSpec &spec : everySourceAndWeighting(Vec3(0, 0, 1), 1)) {
        const FieldResult r = buildField(frames, spec);
        ASSERT_TRUE(r.field.u.allFinite()) << toString(spec.source);
        const SingularityReport rep = findSingularities(frames, r.field);
        EXPECT_EQ(rep.indexNumeratorSum, 2 * spec.nSym) << toString(spec.source);
        for (const Singularity &s : rep.singularities) EXPECT_TRUE(s.position.allFinite());
    }
}

TEST_F(BadMesh, BoundaryMeshSatisfiesPoincareHopfWithTheBoundaryIndex) {
    const Mesh disk = makeDisk(8);
    const TangentFrames frames(disk);
    const FieldResult r = buildField(frames, FieldSpec{});
    const SingularityReport rep = findSingularities(frames, r.field);
    // A disk: chi = 1 (one face, one boundary loop, no handle).
    EXPECT_NEAR(rep.totalIndex(4), 1.0, 1e-9);
    EXPECT_EQ(computeStats(disk).boundaryLoops, 1);
}

TEST_F(BadMesh, SeveralComponentsSatisfyPoincareHopfEachOnTheirOwn) {
    // A sphere (chi 2), a torus (chi 0) and a genus-2 surface (chi -2) in one file.
    std::vector<Vec3> p;
    std::vector<std::vector<int>> f;
    int c = 0;
    for (const Mesh &m : {makeEllipsoid(2, 1.5, 1.0, 0.75), makeTorus(1.0, 0.35, 24, 12), makeGenus2(24)}) {
        const int base = int(p.size());
        for (int v = 0; v < m.nVertices(); ++v) p.push_back(m.position(v) + Vec3(5.0 * c, 0, 0));
        for (const Face &t : m.faces()) f.push_back({base + t[0], base + t[1], base + t[2]});
        ++c;
    }
    const Mesh mesh = repairAndBuild(p, f, "three");
    ASSERT_EQ(computeStats(mesh).components, 3);
    const TangentFrames frames(mesh);
    for (FieldSource source : {FieldSource::Curvature, FieldSource::Smoothest}) {
        FieldSpec spec;
        spec.source = source;
        const FieldResult r = buildField(frames, spec);
        const std::vector<int> k = faceIndexNumerators(frames, r.field);
        std::vector<int> chi;
        const std::vector<double> sums = indexSumPerComponent(mesh, k, spec.nSym, chi);
        ASSERT_EQ(sums.size(), 3u);
        // chi per component from the topology alone: 2, 0, -2.
        EXPECT_EQ(chi, (std::vector<int>{2, 0, -2}));
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(sums[i], chi[i], 1e-12) << toString(source) << " component " << i;
    }
}

TEST_F(BadMesh, NonPlanarPolygonsAreFanTriangulatedWithoutWarnings) {
    // A cube whose top face is a twisted (non-planar) quad, plus one hexagon split.
    WarningCapture capture;
    const Mesh m = loads("twist.obj",
                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1.3\nv 1 1 1\nv 0 1 1.3\n"
                         "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
    EXPECT_EQ(m.nFaces(), 12);
    EXPECT_EQ(computeStats(m).eulerCharacteristic, 2);
    EXPECT_TRUE(capture.warnings().empty());
}

TEST_F(BadMesh, ExtremeScalesGiveTheSameFieldAsUnitScale) {
    // Powers of two near 1e-9 and 1e9 scale every coordinate exactly, so a
    // scale-free pipeline must give the same singularities and the same angles.
    const Mesh unit = makeEllipsoid(3, 1.5, 1.0, 0.75);
    const TangentFrames f1(unit);
    const FieldResult r1 = buildField(f1, FieldSpec{});
    const SingularityReport s1 = findSingularities(f1, r1.field);
    for (double s : {std::ldexp(1.0, -30), std::ldexp(1.0, 30), 1e-9, 1e9}) {
        SCOPED_TRACE(s);
        const Mesh m = scaled(unit, s);
        const TangentFrames fs(m);
        const FieldResult r = buildField(fs, FieldSpec{});
        ASSERT_TRUE(r.field.u.allFinite());
        const SingularityReport rep = findSingularities(fs, r.field);
        EXPECT_EQ(rep.indexNumeratorSum, s1.indexNumeratorSum);
        ASSERT_EQ(rep.singularities.size(), s1.singularities.size());
        for (size_t i = 0; i < rep.singularities.size(); ++i)
            EXPECT_EQ(rep.singularities[i].face, s1.singularities[i].face);
        double worst = 0;
        for (int v = 0; v < m.nVertices(); ++v)
            worst = std::max(worst, std::abs(std::arg(r.field.u[v] / r1.field.u[v])));
        // Exact at 2^+-30; at 1e+-9 rounding changes the PCG iterates, which
        // stop at a relative residual of kFieldTolerance (1e-4): well under a degree.
        EXPECT_LT(worst, s == std::ldexp(1.0, -30) || s == std::ldexp(1.0, 30) ? 1e-9 : 0.01);
    }
}

// The fuzzer's disk at 1e-73 (tests/fuzz/field/crashers/disk_scaled_1e-73_*): below
// kMinMeshSize across, a mesh is a clean error naming its size; just above it
// (2e-15 across) and at 2e-12 the field is finite and Poincaré–Hopf holds.
TEST_F(BadMesh, MeshesBelowTheMinimumSizeAreRejectedAboveItWork) {
    const Mesh disk = makeDisk(4);
    const std::vector<Face> faces = disk.faces();
    auto scaledPositions = [&](double s) {
        std::vector<Vec3> p = disk.positions();
        for (Vec3 &q : p) q *= s;
        return p;
    };
    for (double s : {1e-73, 1e-20, 1e-16}) {
        SCOPED_TRACE(s);
        try {
            (void)Mesh::fromTriangles(scaledPositions(s), faces, "tiny");
            ADD_FAILURE() << "accepted a mesh " << 2 * s << " across";
        } catch (const InputError &e) {
            EXPECT_NE(std::string(e.what()).find("below the limit of 1e-15"), std::string::npos) << e.what();
        }
    }
    for (double s : {1e-15, 1e-12}) { // 2e-15 and 2e-12 across (the disk has radius 1)
        SCOPED_TRACE(s);
        const Mesh m = Mesh::fromTriangles(scaledPositions(s), faces, "small");
        const TangentFrames frames(m);
        WarningCapture quiet;
        const FieldResult r = buildField(frames, FieldSpec{});
        ASSERT_TRUE(r.field.u.allFinite());
        const SingularityReport rep = findSingularities(frames, r.field);
        EXPECT_NEAR(rep.totalIndex(4), 1.0, 1e-6); // a disk: χ = 1
    }
}

// --- fields --------------------------------------------------------------------

namespace {
// The fallback is exactly the globally smoothest field, announced by a warning.
void expectSmoothestFallback(const Mesh &m, const CurvatureOptions &curvature = {}) {
    WarningCapture capture;
    const TangentFrames frames(m);
    FieldSpec spec;
    spec.curvature = curvature;
    const FieldResult r = buildField(frames, spec);
    EXPECT_TRUE(capture.has("no-curvature-direction")) << m.name();
    ASSERT_TRUE(r.field.u.allFinite());
    // The fallback is a unit-strength field, not zeros.
    EXPECT_GT(r.field.u.cwiseAbs().minCoeff(), 0.0);
    EXPECT_EQ(r.field.u, smoothestField(frames, spec.nSym).field.u) << m.name();
}
} // namespace

TEST_F(BadMesh, PlanarMeshFallsBackToTheSmoothestFieldWithAWarning) { expectSmoothestFallback(makeGrid(8)); }

// A discrete sphere's principal directions are noise (rounding with Max normals,
// discretisation error with angle-weighted ones); curvatureField() would normalise
// that noise to full strength, so buildField() checks curvatureAnisotropy() first.
TEST_F(BadMesh, UmbilicSphereFallsBackToTheSmoothestFieldWithAWarning) {
    for (double s : {1.0, 1e-9, 1e9}) expectSmoothestFallback(scaled(makeIcosphere(3), s));
    expectSmoothestFallback(makeIcosphere(3), {.normals = NormalWeighting::Angle});
    expectSmoothestFallback(makeIcosphere(1), {.normals = NormalWeighting::Angle});
}

// ρ against closed forms (not against the code): on a torus with radii R > r,
// k1 = 1/r and k2 = cos θ / (R + r cos θ) with dA ∝ (R + r cos θ) dθ, so
// ∫|k1 - k2| dA ∝ 2πR/r and ∫(|k1| + |k2|) dA ∝ 2πR/r + 4: ρ = πR / (πR + 2r).
// An open cylinder has k2 = 0: ρ = 1.
TEST(CurvatureAnisotropy, MatchesClosedFormsAndIsScaleInvariant) {
    const double pi = std::acos(-1.0);
    for (auto [R, r] : {std::pair{2.0, 0.6}, std::pair{1.5, 1.0}}) {
        const Mesh torus = makeTorus(R, r, 128, 64);
        const double rho = curvatureAnisotropy(computeCurvature(torus));
        EXPECT_NEAR(rho, pi * R / (pi * R + 2 * r), 0.01) << "R " << R << " r " << r;
        for (double s : {1e-9, 1e9})
            EXPECT_NEAR(curvatureAnisotropy(computeCurvature(scaled(torus, s))), rho, 1e-9 * rho) << s;
    }
    EXPECT_GT(curvatureAnisotropy(computeCurvature(makeCylinder(1.0, 2.0, 64, 16))), 0.95);
    EXPECT_EQ(curvatureAnisotropy(computeCurvature(makeGrid(4))), 0.0); // 0/0: planar
    EXPECT_EQ(curvatureAnisotropy({}), 0.0);
}

// The threshold leaves real shapes alone: an ellipsoid whose axes differ by 10%
// keeps its curvature field with no warning (its ρ is several times the threshold).
TEST(CurvatureAnisotropy, ASlightlyOblongEllipsoidKeepsItsCurvatureField) {
    const Mesh m = makeEllipsoid(4, 1.1, 1.0, 1.0);
    const std::vector<VertexCurvature> curv = computeCurvature(m);
    EXPECT_GT(curvatureAnisotropy(curv), 2 * kMinCurvatureAnisotropy);
    WarningCapture capture;
    const TangentFrames frames(m);
    FieldSpec spec;
    spec.smoothingLength = 0;
    const FieldResult r = buildField(frames, spec);
    EXPECT_FALSE(capture.has("no-curvature-direction"));
    EXPECT_EQ(r.field.u, curvatureField(frames, curv, spec.nSym).u);
}

TEST(SolverFailure, NamesTheCause) {
    // An indefinite and a singular matrix: the solvers check info() and say why.
    SparseMatrixC a(2, 2);
    a.insert(0, 0) = 1.0;
    a.insert(1, 1) = -1.0;
    try {
        HermitianSolver s(a);
        const Eigen::VectorXcd x = s.solve(Eigen::VectorXcd::Ones(2));
        // LDLT may factor an indefinite diagonal; then the answer must be right.
        EXPECT_NEAR(std::abs(x[1] + 1.0), 0.0, 1e-12);
    } catch (const std::runtime_error &e) {
        EXPECT_NE(std::string(e.what()).find("LDLT"), std::string::npos) << e.what();
    }
    SparseMatrixC zero(3, 3);
    zero.insert(0, 0) = 1.0;
    try {
        solveGeneral(zero, Eigen::VectorXcd::Ones(3));
        ADD_FAILURE() << "a singular system was solved";
    } catch (const std::runtime_error &e) {
        EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
    }
}

// The fuzzer's PLY hang (tests/fuzz/mesh_ply/crashers/propertyless_*): an element
// without properties has no data, so the header-versus-file-size check cannot bound
// its count; it must be skipped, not counted through (10^11 iterations before).
TEST_F(BadMesh, PlyElementsWithoutPropertiesAreSkippedWhateverTheirCount) {
    const std::string junk = "element junk 100000000000\nelement other 444444\n";
    std::string ascii = plyTetra();
    ascii.insert(ascii.find("element vertex"), junk);
    std::string binary = binaryPly();
    binary.insert(binary.find("element vertex"), junk);
    const auto t0 = std::chrono::steady_clock::now();
    expectSameMesh(loads("junk_ascii.ply", ascii), loads("plain.ply", plyTetra()));
    expectSameMesh(loads("junk_binary.ply", binary), loads("plain_binary.ply", binaryPly()));
    // Generous even for a sanitizer build; the loop it replaces ran for hours.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
    // A vertex or face element without properties is still an error, not skipped.
    std::string noXyz = "ply\nformat ascii 1.0\nelement vertex 4\nelement face 0\n"
                        "property list uchar int vertex_indices\nend_header\n";
    rejects("noxyz.ply", noXyz, "", "no x, y and z properties");
}

// Binary OFF and PLY are read by our own bounds-checked readers (OpenMesh's
// looped or crashed on the fuzzer's findings in tests/fuzz/*/crashers/).
TEST_F(BadMesh, BinaryOffAndBigEndianPlyReadLikeTheirAsciiSpelling) {
    // Geomview binary OFF of the tetrahedron: little-endian 32-bit counts, float
    // coordinates, per face its vertex count, indices and colour-component count.
    std::string off = "OFF BINARY\n";
    const uint32_t counts[3] = {4, 4, 0};
    put(off, counts, 12);
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto &v : p) put(off, v, 12);
    const int32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto &t : f) {
        const int32_t n = 3, colours = 0;
        put(off, &n, 4);
        put(off, t, 12);
        put(off, &colours, 4);
    }
    expectSameMesh(loads("bin.off", off), loads("ascii.off", offTetra()));

    // The same PLY in both byte orders: every value's bytes reversed by hand.
    auto be = [](std::string &s, const void *data, size_t n) {
        const char *c = static_cast<const char *>(data);
        for (size_t i = n; i-- > 0;) s.push_back(c[i]);
    };
    std::string ply = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto &v : p)
        for (float c : v) be(ply, &c, 4);
    for (const auto &t : f) {
        const uint8_t n = 3;
        put(ply, &n, 1);
        for (int32_t i : t) be(ply, &i, 4);
    }
    expectSameMesh(loads("be.ply", ply), loads("ascii.ply", plyTetra()));
    expectSameMesh(loads("le.ply", binaryPly()), loads("ascii2.ply", plyTetra()));
}

TEST_F(BadMesh, BinaryRecordsThatLieAreRejectedNotFollowed) {
    // A face claiming 2^31 - 1 corners in a file of a few bytes, and an index past the vertices.
    std::string off = "OFF BINARY\n";
    const uint32_t counts[3] = {4, 1, 0};
    put(off, counts, 12);
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto &v : p) put(off, v, 12);
    std::string huge = off;
    const int32_t big = 2147483647, zero = 0;
    put(huge, &big, 4);
    for (int k = 0; k < 4; ++k) put(huge, &zero, 4); // enough bytes for the header's size check
    rejects("huge.off", huge, "", "vertex count 2147483647 is out of range");
    std::string past = off;
    const int32_t face[4] = {3, 0, 1, 9};
    put(past, face, 16);
    put(past, &zero, 4);
    rejects("past.off", past, "", "vertex index 9 is out of range [0, 3]");
    // A PLY version other than 1.0 is named at its column.
    std::string ply = binaryPly();
    ply.replace(ply.find("1.0"), 3, "2.0");
    rejects("v2.ply", ply, ":2:29", "format binary_little_endian 1.0");
    // Every committed fuzzer finding for these readers is now a clean rejection; those
    // named *_strict_load (the harness's check that a load with repair off rejects
    // exactly the files that need a repair) load with a repair reported, and are
    // rejected with repair off.
    LoadOptions strict;
    strict.repair = false;
    for (const char *dir : {"mesh_off", "mesh_obj", "mesh_ply"})
        for (const auto &entry : fs::directory_iterator(fs::path(ROSY_SOURCE_DIR) / "tests/fuzz" / dir / "crashers")) {
            if (entry.path().extension() == ".md") continue;
            SCOPED_TRACE(entry.path().string());
            if (entry.path().stem().string().find("strict_load") != std::string::npos) {
                WarningCapture capture;
                LoadReport report;
                EXPECT_NO_THROW(loadMesh(entry.path().string(), {}, &report));
                EXPECT_TRUE(report.anyRepair());
                EXPECT_THROW(loadMesh(entry.path().string(), strict), InputError);
                continue;
            }
            EXPECT_THROW(loadMesh(entry.path().string()), InputError);
        }
}

// The fuzzer's NaN (tests/fuzz/field/crashers/all_faces_zero_area_nan_field.bin):
// a closed component whose faces all have zero area (here a tetrahedron flattened
// onto a line, which Mesh::fromTriangles accepts: it checks topology, not geometry).
// Every source must give a clean InputError or a finite field, never NaN.
TEST_F(BadMesh, ComponentWithOnlyZeroAreaFacesIsAnErrorNotNaN) {
    const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    const std::vector<Face> f = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const Mesh mesh = Mesh::fromTriangles(p, f, "flat-tet");
    WarningCapture capture;
    const TangentFrames frames(mesh);
    for (const FieldSpec &spec : everySourceAndWeighting(Vec3(1, 0, 0), 0)) {
        try {
            const FieldResult r = buildField(frames, spec);
            EXPECT_TRUE(r.field.u.allFinite()) << toString(spec.source);
        } catch (const InputError &e) {
            const std::string msg = e.what();
            EXPECT_TRUE(msg.find("zero total area") != std::string::npos ||
                        (spec.source == FieldSource::Design && msg.find("degenerate face") != std::string::npos))
                << msg;
        }
    }
}

// The fuzzer's degenerate meshes (tests/fuzz/field/crashers/degenerate_*): valid
// topology, geometry that makes the field system numerically singular (here a cube
// 1e-18 across with one vertex pulled 1e-6 away, a needle 10^12 times longer than
// the rest). A solver's failed factorization or solve must reach the user as an
// InputError naming the mesh and the cause, never as an internal error.
TEST_F(BadMesh, DegenerateGeometryThatDefeatsTheSolverIsAnInputError) {
    const std::string off =
        "OFF\n26 48 0\n-1.0000000000000001e-18 1.0000000000000001e-18 0\n"
        "-1.0000000000000001e-18 0 -1.0000000000000001e-18\n-1.0000000000000001e-18 0 0\n"
        "-1.0000000000000001e-18 -1.0000000000000001e-18 0\n"
        "-1.0000000000000001e-18 0 1.0000000000000001e-18\n"
        "-1.0000000000000001e-18 -1.0000000000000001e-18 1.0000000000000001e-18\n"
        "-1.0000000000000001e-18 1.0000000000000001e-18 -1.0000000000000001e-18\n"
        "-1.0000000000000001e-18 1.0000000000000001e-18 0\n"
        "-1.0000000000000001e-18 1.0000000000000001e-18 1.0000000000000001e-18\n"
        "0 1.0000000000000001e-18 0\n1.0000000000000001e-18 0 -1.0000000000000001e-18\n"
        "1.0000000000000001e-18 0 0\n1.0000000000000001e-18 -1.0000000000000001e-18 0\n"
        "1.0000000000000001e-18 0 1.0000000000000001e-18\n"
        "1.0000000000000001e-18 -1.0000000000000001e-18 1.0000000000000001e-18\n"
        "1.0000000000000001e-18 1.0000000000000001e-18 -1.0000000000000001e-18\n"
        "1.0000000000000001e-18 1.0000000000000001e-18 0\n"
        "1.0000000000000001e-18 1.0000000000000001e-18 1.0000000000000001e-18\n"
        "5.0000000000000004e-19 5.0000000000000004e-19 0\n"
        "0 -1.0000000000000001e-18 -1.0000000000000001e-18\n"
        "9.9999999999999995e-07 4.9999999999899995e-07 2.5000000000099996e-07\n"
        "0 1.0000000000000001e-18 0\n0 1.0000000000000001e-18 -1.0000000000000001e-18\n"
        "0 1.0000000000000001e-18 1.0000000000000001e-18\n0 0 -1.0000000000000001e-18\n"
        "0 0 1.0000000000000001e-18\n3 0 3 2\n3 0 2 1\n3 3 5 4\n3 3 4 2\n3 1 2 7\n3 1 7 6\n"
        "3 2 4 8\n3 2 8 7\n3 9 10 11\n3 9 11 12\n3 12 11 13\n3 12 13 14\n3 10 15 16\n3 10 16 11\n"
        "3 11 16 17\n3 11 17 13\n3 0 19 18\n3 0 18 3\n3 19 9 12\n3 19 12 18\n3 3 18 20\n3 3 20 5\n"
        "3 18 12 14\n3 18 14 20\n3 6 7 21\n3 6 21 22\n3 22 21 16\n3 22 16 15\n3 7 8 23\n3 7 23 21\n"
        "3 21 23 17\n3 21 17 16\n3 0 1 24\n3 0 24 19\n3 1 6 22\n3 1 22 24\n3 19 24 10\n3 19 10 9\n"
        "3 24 22 15\n3 24 15 10\n3 5 20 25\n3 5 25 4\n3 4 25 23\n3 4 23 8\n3 20 14 13\n3 20 13 25\n"
        "3 25 13 17\n3 25 17 23\n";
    WarningCapture quiet;
    const Mesh mesh = loadMesh(write("needle-cube.off", off));
    const TangentFrames frames(mesh);
    for (int nSym : {3, 4, 12}) {
        FieldSpec spec;
        spec.nSym = nSym;
        spec.smoothingLength = 0.04;
        try {
            const FieldResult r = buildField(frames, spec);
            EXPECT_TRUE(r.field.u.allFinite()) << nSym;
        } catch (const InputError &e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("needle-cube.off"), std::string::npos) << msg;
        }
    }
}
