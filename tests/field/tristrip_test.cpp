// PLY triangle strips (`element tristrips` with `property list int int
// vertex_indices`, -1 restarting a strip), ASCII and binary in both byte orders.
// The expected triangles are worked out by hand below from the strip rule
// (triangle k of a strip is s_k s_k+1 s_k+2, the first two swapped for odd k;
// triangles with a repeated vertex are skipped but still count for the parity).
#include "core/diagnostics.h"
#include "core/error.h"
#include "field/mesh/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

using namespace rosy;
using namespace rosy::field;
namespace fs = std::filesystem;

namespace {

// A 3 x 2 grid in the plane z = 0:   1---3---5
//                                     |   |   |
//                                     0---2---4
const std::vector<Vec3> kGrid = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}};

// One strip with a doubled vertex and a restart:  0 1 2 3 3 5 4 -1 2 3 4
//   k=0 (0,1,2)   k=1 odd (2,1,3)   k=2 (2,3,3) skipped   k=3 odd (3,3,5) skipped
//   k=4 (3,5,4)   restart, k=0 (2,3,4)
// Every one of the four runs clockwise seen from +z (normal -z): e.g. (0,1,2):
// (p1 - p0) x (p2 - p0) = (0,1,0) x (1,0,0) = (0,0,-1).
const std::vector<int> kStrip = {0, 1, 2, 3, 3, 5, 4, -1, 2, 3, 4};
const std::vector<std::array<int, 3>> kExpected = {{0, 1, 2}, {2, 1, 3}, {3, 5, 4}, {2, 3, 4}};

std::string header(const std::string &format, int nStrips = 1) {
    return "ply\nformat " + format + " 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
           "property float z\nelement tristrips " + std::to_string(nStrips) +
           "\nproperty list int int vertex_indices\nend_header\n";
}

std::string asciiPly(const std::vector<int> &strip) {
    std::string s = header("ascii");
    for (const Vec3 &p : kGrid) s += std::to_string(int(p.x())) + " " + std::to_string(int(p.y())) + " 0\n";
    s += std::to_string(strip.size());
    for (int i : strip) {
        s += ' '; // not " " + std::to_string(): GCC 12's -Wrestrict false positive (PR 105651)
        s += std::to_string(i);
    }
    return s + "\n";
}

template <typename T> void putEndian(std::string &s, T x, bool bigEndian) {
    char b[sizeof(T)];
    std::memcpy(b, &x, sizeof(T));
    if (bigEndian) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
}

std::string binaryStripPly(const std::vector<int> &strip, bool bigEndian, int32_t length = -1) {
    std::string s = header(bigEndian ? "binary_big_endian" : "binary_little_endian");
    for (const Vec3 &p : kGrid)
        for (int k = 0; k < 3; ++k) putEndian(s, float(p[k]), bigEndian);
    putEndian(s, length >= 0 ? length : int32_t(strip.size()), bigEndian);
    for (int i : strip) putEndian(s, int32_t(i), bigEndian);
    return s;
}

class TriStrips : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("rosy_tristrips_" + std::to_string(::getpid()) + "_" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string write(const std::string &name, const std::string &content) {
        const std::string path = (m_dir / name).string();
        std::ofstream(path, std::ios::binary) << content;
        return path;
    }
    /// The InputError message of loading `content`, or "" (a test failure) if it loads.
    std::string rejection(const std::string &content) {
        const std::string path = write("bad.ply", content);
        try {
            loadMesh(path);
        } catch (const InputError &e) {
            EXPECT_NE(std::string(e.what()).find("bad.ply"), std::string::npos) << e.what();
            return e.what();
        }
        ADD_FAILURE() << "loaded";
        return {};
    }
    fs::path m_dir;
};

void expectGridTriangles(const Mesh &m) {
    ASSERT_EQ(m.nVertices(), 6);
    for (int v = 0; v < 6; ++v) EXPECT_EQ(m.position(v), kGrid[size_t(v)]) << v;
    ASSERT_EQ(m.nFaces(), int(kExpected.size()));
    // Same triangles with the same winding: compare each rotated to start at its smallest index.
    auto canonical = [](std::array<int, 3> t) {
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        return t;
    };
    std::set<std::array<int, 3>> got, want;
    for (const Face &f : m.faces()) got.insert(canonical({f[0], f[1], f[2]}));
    for (const auto &t : kExpected) want.insert(canonical(t));
    EXPECT_EQ(got, want);
    for (int f = 0; f < m.nFaces(); ++f) {
        const Face &t = m.face(f);
        const Vec3 n = (m.position(t[1]) - m.position(t[0])).cross(m.position(t[2]) - m.position(t[0]));
        EXPECT_LT(n.z(), 0) << "face " << f;
    }
}

} // namespace

TEST_F(TriStrips, AsciiStripWithRestartAndDegenerateTrianglesGivesTheHandWorkedTriangles) {
    WarningCapture capture;
    expectGridTriangles(loadMesh(write("a.ply", asciiPly(kStrip))));
    EXPECT_TRUE(capture.warnings().empty()); // skipped strip triangles are not repairs
}

TEST_F(TriStrips, BinaryLittleAndBigEndianGiveTheSameTriangles) {
    expectGridTriangles(loadMesh(write("le.ply", binaryStripPly(kStrip, false))));
    expectGridTriangles(loadMesh(write("be.ply", binaryStripPly(kStrip, true))));
}

TEST_F(TriStrips, FacesAndStripsInOneFileAreBothRead) {
    std::string s = asciiPly({0, 1, 2, 3});
    // One more element after the strips: the right column as a face (2,3,4) and (3,5,4).
    s.replace(s.find("end_header"), 10, "element face 2\nproperty list uchar int vertex_indices\nend_header");
    s += "3 2 3 4\n3 3 5 4\n";
    expectGridTriangles(loadMesh(write("both.ply", s)));
}

TEST_F(TriStrips, IndexOutOfRangeIsRejectedAtItsPlace) {
    std::string msg = rejection(asciiPly({0, 1, 6}));
    EXPECT_NE(msg.find("bad.ply:16:"), std::string::npos) << msg; // the strip's line
    EXPECT_NE(msg.find("'6' outside [0, 6)"), std::string::npos) << msg;
    msg = rejection(asciiPly({0, 1, -2}));
    EXPECT_NE(msg.find("'-2'"), std::string::npos) << msg;
    msg = rejection(binaryStripPly({0, 1, 6}, false));
    EXPECT_NE(msg.find("tristrips 0: strip index (-1 restarts the strip) 6 is out of range [-1, 5]"),
              std::string::npos)
        << msg;
    msg = rejection(binaryStripPly({0, 1, -7}, true));
    EXPECT_NE(msg.find("-7 is out of range [-1, 5]"), std::string::npos) << msg;
}

TEST_F(TriStrips, HugeCountsAreRejectedBeforeAllocating) {
    // A billion strips in a file of a few hundred bytes.
    std::string s = asciiPly(kStrip);
    s.replace(s.find("tristrips 1"), 11, "tristrips 1000000000");
    std::string msg = rejection(s);
    EXPECT_NE(msg.find("header says 6 vertex, 1000000000 tristrips"), std::string::npos) << msg;
    // A strip claiming 2^31 - 1 indices: the list length is checked against the bytes left.
    msg = rejection(binaryStripPly(kStrip, false, 0x7fffffff));
    EXPECT_NE(msg.find("list length 2147483647 is out of range"), std::string::npos) << msg;
    msg = rejection(binaryStripPly(kStrip, true, 0x7fffffff));
    EXPECT_NE(msg.find("list length 2147483647 is out of range"), std::string::npos) << msg;
    // In ASCII the length must match the values on the line.
    s = asciiPly(kStrip);
    s.replace(s.rfind("11 "), 3, "99999999999 ");
    msg = rejection(s);
    EXPECT_NE(msg.find("bad list length '99999999999'"), std::string::npos) << msg;
}

TEST_F(TriStrips, StripsOfOnlyDegenerateTrianglesLeaveNoFaces) {
    const std::string msg = rejection(asciiPly({0, 0, 1, 1, -1, 2, 3}));
    EXPECT_NE(msg.find("no faces"), std::string::npos) << msg;
}

TEST_F(TriStrips, StripTrianglesCountAgainstTheFaceLimit) {
    const std::string path = write("limit.ply", asciiPly(kStrip));
    LoadOptions options;
    options.maxFaces = 3;
    try {
        loadMesh(path, options);
        ADD_FAILURE() << "loaded";
    } catch (const InputError &e) {
        EXPECT_NE(std::string(e.what()).find("4 faces, more than the limit of 3"), std::string::npos) << e.what();
    }
}
