// The scene half of the bad-input catalogue (tests/README.md): each hostile or
// mistaken scene file is an InputError at `FILE:LINE:COL` with a hint, never a
// crash, a hang or a huge allocation. Lines and columns below are counted by
// hand in each YAML text (1-based).

#include "core/error.h"
#include "field/mesh_io.h"
#include "field/frames.h"
#include "field/primitives.h"
#include "scenes/scene.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include "tests/test_output.h"

using namespace rosy::scenes;
namespace fs = std::filesystem;

namespace {

fs::path dir() { return rosy::test::testOutputDir("bad_scenes"); }

std::string path() { return (dir() / "s.yaml").string(); }

/// The InputError message parseScene gives for `text` ("" if none).
std::string parseError(const std::string &text) {
    try {
        parseScene(text, path());
    } catch (const rosy::InputError &e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text.substr(0, 300);
    return {};
}

/// The InputError message buildScene gives after a successful parse.
std::string buildError(const std::string &text) {
    try {
        buildScene(parseScene(text, path()));
    } catch (const rosy::InputError &e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

/// The InputError message of building the scene's field.
std::string buildErrorField(const std::string &text) {
    try {
        const SceneDesc desc = parseScene(text, path());
        const Scene scene = buildScene(desc);
        const rosy::field::TangentFrames frames(scene.mesh);
        rosy::field::buildField(frames, desc.field.spec);
    } catch (const rosy::InputError &e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

using rosy::test::contains;
using rosy::test::startsWith;

} // namespace

TEST(BadScene, SyntaxErrorIsLocated) {
    const std::string msg = parseError("mesh: {primitive: icosphere\ncamera: [\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:7: error: YAML syntax error")) << msg;
}

TEST(BadScene, NestingDeeperThanTheLimitIsRejected) {
    // 33 levels: one over the documented limit of 32. The deepest list that is
    // still allowed sits at column 32 (the root map is level 1).
    std::string deep = "mesh: {primitive: icosphere}\nx: " + std::string(32, '[') + std::string(32, ']') + "\n";
    std::string msg = parseError(deep);
    EXPECT_TRUE(startsWith(msg, path() + ":2:")) << msg;
    EXPECT_TRUE(contains(msg, "nesting deeper than 32 levels")) << msg;
    // 100 000 levels: yaml-cpp's own guard (depth 2000) stops it, still located, no stack overflow.
    deep = "mesh: {primitive: icosphere}\nx: " + std::string(100000, '[') + std::string(100000, ']') + "\n";
    msg = parseError(deep);
    EXPECT_TRUE(startsWith(msg, path() + ":2:")) << msg;
    // 31 levels pass the shape check (and then fail as an unknown key, at line 2 column 1).
    const std::string ok = "mesh: {primitive: icosphere}\nx: " + std::string(31, '[') + std::string(31, ']') + "\n";
    EXPECT_TRUE(startsWith(parseError(ok), path() + ":2:1: error: unknown key 'x'")) << parseError(ok);
}

TEST(BadScene, AliasBombIsStoppedByTheValueBudget) {
    // Eleven levels of nine aliases each expand to 9^12 ~ 2.8e11 values.
    std::string text = "mesh: {primitive: icosphere}\nstyle:\n  a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
    for (int i = 1; i < 12; ++i) {
        const std::string prev = "*a" + std::to_string(i - 1);
        text += "  a" + std::to_string(i) + ": &a" + std::to_string(i) + " [" + prev;
        for (int k = 1; k < 9; ++k) text += ", " + prev;
        text += "]\n";
    }
    const auto t0 = std::chrono::steady_clock::now();
    const std::string msg = parseError(text);
    EXPECT_TRUE(startsWith(msg, path() + ":")) << msg;
    EXPECT_TRUE(contains(msg, "more than 100000 values")) << msg;
    // Not a timing assertion on speed, a guard against an effectively endless walk.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 60.0);
}

TEST(BadScene, CyclicAliasIsRejected) {
    std::string msg = parseError("mesh: {primitive: icosphere}\nlights: &a [*a]\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:9: error: an alias refers to a node that contains it")) << msg;
    msg = parseError("mesh: &m {primitive: icosphere, radius: *m}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:7: error: an alias refers to a node that contains it")) << msg;
}

TEST(BadScene, DuplicateKeysNameBothLines) {
    const std::string msg = parseError("mesh: {primitive: icosphere}\ncamera: {fov: 30}\ncamera: {fov: 40}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":3:1: error: duplicate key 'camera' in the scene (first set at line 2)"))
        << msg;
}

TEST(BadScene, UnknownKeySuggestsTheNearest) {
    const std::string msg = parseError("mesh: {primitive: icosphere}\ncamra: {fov: 30}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:1: error: unknown key 'camra'")) << msg;
    EXPECT_TRUE(contains(msg, "did you mean 'camera'?")) << msg;
}

TEST(BadScene, WrongTypeNamesTheNodesOwnLine) {
    const std::string msg = parseError("mesh: {primitive: icosphere}\ncamera:\n  fov: [1, 2]\n");
    EXPECT_TRUE(startsWith(msg, path() + ":3:8: error: camera.fov (degrees) must be a number, got a list")) << msg;
}

TEST(BadScene, OutOfRangeNumbers) {
    std::string msg = parseError("mesh: {primitive: icosphere}\ncamera: {fov: 1e999}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:15: error: camera.fov (degrees) must be a")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\ncamera: {fov: .nan}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:15: error: camera.fov (degrees) must be a finite number")) << msg;
    msg = parseError("mesh: {primitive: icosphere, subdivisions: -2}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:44: error: mesh.subdivisions must be in [0, 8], got -2")) << msg;
    msg = parseError("mesh: {primitive: icosphere, subdivisions: 2.5}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:44: error: mesh.subdivisions must be a whole number")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\ncamera: {resolution: [-5, 10]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:23: error: camera.resolution width must be in [1, 16384]")) << msg;
}

TEST(BadScene, ResolutionThatWouldExhaustMemoryIsRejectedBeforeAllocating) {
    // 16384 x 16384 passes the per-side check but is 268 million pixels.
    const std::string msg = parseError("mesh: {primitive: icosphere}\ncamera: {resolution: [16384, 16384]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:22: error: camera.resolution 16384 x 16384 is 268435456 pixels")) << msg;
    // Exactly at the limit is fine.
    EXPECT_NO_THROW(parseScene("mesh: {primitive: icosphere}\ncamera: {resolution: [4096, 4096]}\n", path()));
    EXPECT_NO_THROW(parseScene("mesh: {primitive: icosphere}\ncamera: {resolution: [16384, 1024]}\n", path()));
}

TEST(BadScene, DegenerateCameras) {
    std::string msg = parseError("mesh: {primitive: icosphere}\ncamera: {position: [0, 0, 5], look_at: [0, 0, 5]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:40: error: camera.look_at equals camera.position")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\ncamera: {position: [0, 5, 0], look_at: [0, 0, 0]}\n");
    EXPECT_TRUE(contains(msg, "camera.up is parallel to the viewing direction")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\ncamera: {fov: 0}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:15: error: camera.fov")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\ncamera: {direction: [0, 0, 0]}\n");
    EXPECT_TRUE(contains(msg, "camera.direction must not be [0, 0, 0]")) << msg;
}

TEST(BadScene, CameraThatSeesNothing) {
    // Looking away from the unit sphere: it is entirely behind the camera.
    std::string msg = buildError("mesh: {primitive: icosphere}\n"
                                 "camera: {position: [0, 0, 5], look_at: [0, 0, 10]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:40: error: the camera sees none of the mesh")) << msg;
    // Beside the view: the sphere at x = 0 seen from x = 100 looking down -z with a 10 degree cone.
    msg = buildError("mesh: {primitive: icosphere}\n"
                     "camera: {position: [100, 0, 5], look_at: [100, 0, 0], fov: 10}\n");
    EXPECT_TRUE(contains(msg, "the camera sees none of the mesh")) << msg;
    // Orthographic, shifted sideways by more than half its view plus the radius.
    msg = buildError("mesh: {primitive: icosphere}\n"
                     "camera: {projection: orthographic, position: [4, 0, 5], look_at: [4, 0, 0], height: 2}\n");
    EXPECT_TRUE(contains(msg, "the camera sees none of the mesh")) << msg;
    // The test is conservative: a camera that sees only a sliver is accepted.
    EXPECT_NO_THROW(buildScene(parseScene("mesh: {primitive: icosphere}\n"
                                          "camera: {position: [1.5, 0, 5], look_at: [1.5, 0, 0], fov: 20}\n",
                                          path())));
}

TEST(BadScene, CameraInsideTheMesh) {
    const std::string msg = buildError("mesh: {primitive: icosphere}\n"
                                       "camera: {position: [0, 0, 0.2], look_at: [0, 0, -1]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:20: error: camera.position is inside the mesh")) << msg;
    // Inside a torus's hole is outside the surface: fine.
    EXPECT_NO_THROW(buildScene(parseScene("mesh: {primitive: torus}\n"
                                          "camera: {position: [0, 0, 0], look_at: [1, 0, 0]}\n",
                                          path())));
    // An open surface (a grid) has no inside.
    EXPECT_NO_THROW(buildScene(parseScene("mesh: {primitive: grid}\n"
                                          "camera: {position: [0.5, 0.5, 0.01], look_at: [0.5, 0.5, 1]}\n",
                                          path())));
}

TEST(BadScene, MissingUnreadableOrFolderMeshPaths) {
    std::string msg = parseError("mesh: none.off\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:7: error: mesh file '")) << msg;
    fs::create_directories(dir() / "folder.off");
    msg = parseError("mesh: folder.off\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:7: error: mesh '")) << msg;
    EXPECT_TRUE(contains(msg, "is a folder")) << msg;
    // Unreadable: an IoError naming the file (exit 3). Root reads everything, so
    // only an unprivileged run can check it.
    const fs::path locked = dir() / "locked.off";
    std::ofstream(locked) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    fs::permissions(locked, fs::perms::none);
    if (::geteuid() != 0) {
        const SceneDesc desc = parseScene("mesh: locked.off\n", path());
        try {
            buildScene(desc);
            ADD_FAILURE() << "an unreadable mesh was read";
        } catch (const rosy::IoError &e) {
            EXPECT_TRUE(contains(e.what(), "locked.off: error: cannot open the file for reading")) << e.what();
        }
    }
    fs::permissions(locked, fs::perms::owner_all);
}

TEST(BadScene, EmptyFileSeveralDocumentsAndNonMapRoots) {
    EXPECT_TRUE(startsWith(parseError(""), path() + ":1:1: error: the scene file is empty"));
    EXPECT_TRUE(startsWith(parseError("# only a comment\n"), path() + ":1:1: error: the scene file is empty"));
    std::string msg = parseError("mesh: {primitive: icosphere}\n---\nmesh: {primitive: torus}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":3:1: error: the file holds several YAML documents")) << msg;
    msg = parseError("- mesh\n- camera\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:1: error: the scene must be a map")) << msg;
    msg = parseError("just a string\n");
    EXPECT_TRUE(startsWith(msg, path() + ":1:1: error: the scene must be a map")) << msg;
}

TEST(BadScene, FaceLimitReachesTheMeshLoader) {
    std::ofstream(dir() / "tet.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const SceneDesc desc = parseScene("mesh: tet.off\n", path());
    rosy::field::LoadOptions options;
    options.maxFaces = 3;
    try {
        buildScene(desc, options);
        ADD_FAILURE() << "the face limit was ignored";
    } catch (const rosy::InputError &e) {
        EXPECT_TRUE(contains(e.what(), "tet.off:2:1: error: the file has 4 faces, more than the limit of 3"))
            << e.what();
    }
    EXPECT_EQ(buildScene(desc).mesh.nFaces(), 4);
}

TEST(BadScene, FieldElementsOffTheMeshOrWithInvalidOrder) {
    std::string msg = buildErrorField("mesh: {primitive: icosphere}\n"
                                      "field: {source: design, elements: [{position: [50, 0, 0], order: 1}]}\n");
    EXPECT_TRUE(contains(msg, "design element at")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\n"
                     "field: {source: design, elements: [{position: [1, 0, 0], order: 2}]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:")) << msg;
    EXPECT_TRUE(contains(msg, "order")) << msg;
}

TEST(BadScene, AmbientOcclusionValuesAreCheckedWithTheirPlace) {
    const std::string m = "mesh: {primitive: icosphere}\n";
    std::string msg = parseError(m + "ambient_occlusion: {samples: 0}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:30: error: ambient_occlusion.samples must be in [1, 1024], got 0")) << msg;
    msg = parseError(m + "ambient_occlusion: {samples: 2.5}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:30: error: ambient_occlusion.samples must be a whole number")) << msg;
    msg = parseError(m + "ambient_occlusion: {radius: 0}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:29: error: ambient_occlusion.radius must be greater than 0")) << msg;
    msg = parseError(m + "ambient_occlusion: {radius: -1}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:29: error: ambient_occlusion.radius must be in [0, 10], got -1")) << msg;
    msg = parseError(m + "ambient_occlusion: {radius: .inf}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:29: error: ambient_occlusion.radius must be a finite number")) << msg;
    msg = parseError(m + "ambient_occlusion: maybe\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:20: error: ambient_occlusion must be true or false")) << msg;
    msg = parseError(m + "ambient_occlusion: [16, 0.1]\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:20: error: ambient_occlusion must be true, false or a map")) << msg;
    msg = parseError(m + "ambient_occlusion: {sample: 4}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:21: error: unknown key 'sample' in ambient_occlusion")) << msg;
    EXPECT_TRUE(contains(msg, "samples")) << msg;
}

// yaml-cpp 0.7's LoadAll never returns on a stray top-level ',' (the fuzzer's
// scene hang, tests/fuzz/scene/crashers/comma_loadall_hang.yaml): a syntax error
// at the comma instead, in well under the test's timeout.
TEST(BadScene, StrayTopLevelCommaIsASyntaxErrorNotAHang) {
    std::string msg = parseError(",");
    EXPECT_TRUE(startsWith(msg, path() + ":1:1: error: YAML syntax error: unexpected ','")) << msg;
    msg = parseError("# a comment\n\n  ,\n");
    EXPECT_TRUE(startsWith(msg, path() + ":3:3: error: YAML syntax error: unexpected ','")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\n---\n,\n");
    EXPECT_TRUE(startsWith(msg, path() + ":3:1: error: YAML syntax error: unexpected ','")) << msg;
}

// ---------------------------------------------------------------------------
// Issue 16 ("Reliability II"): limits that used to be skipped.
// ---------------------------------------------------------------------------

// Primitives ignored --max-faces (a 4096 x 4096 torus reached 17 GB). The count
// comes from the parameters, and must be the count the builder produces.
TEST(BadScene, PrimitiveFaceCountsAreExactAndTheLimitIsCheckedBeforeBuilding) {
    const std::vector<std::string> scenes = {
        "mesh: {primitive: icosphere, subdivisions: 2}", "mesh: {primitive: ellipsoid, subdivisions: 1}",
        "mesh: {primitive: torus, nu: 10, nv: 7}",       "mesh: {primitive: genus2, resolution: 20}",
        "mesh: {primitive: cube, n: 3}",                 "mesh: {primitive: tetrahedron, subdivisions: 2}",
        "mesh: {primitive: octahedron, subdivisions: 1}", "mesh: {primitive: dodecahedron, subdivisions: 1}",
        "mesh: {primitive: icosahedron}",                "mesh: {primitive: disk, rings: 5}",
        "mesh: {primitive: grid, n: 6}",                 "mesh: {primitive: cylinder, n_around: 9, n_along: 4}",
        "mesh: {primitive: rounded_cube_pair, n: 3}"};
    ASSERT_EQ(scenes.size(), primitiveNames().size());
    for (const std::string &text : scenes) {
        SCOPED_TRACE(text);
        const SceneDesc desc = parseScene(text + "\ncamera: {resolution: [16, 16]}\n", path());
        const long long count = primitiveFaceCount(desc.mesh);
        EXPECT_EQ(buildScene(desc).mesh.nFaces(), count);
        EXPECT_NO_THROW(buildScene(desc, rosy::field::LoadOptions{count}));
        try {
            buildScene(desc, rosy::field::LoadOptions{count - 1});
            ADD_FAILURE() << "the limit was not applied";
        } catch (const rosy::InputError &e) {
            EXPECT_TRUE(contains(e.what(), "faces, more than the limit of " + std::to_string(count - 1))) << e.what();
            EXPECT_TRUE(startsWith(e.what(), path() + ":1:19: error: the ")) << e.what();
        }
    }
    // The 33.5-million-face torus is refused by the default limit without being built.
    const SceneDesc big = parseScene("mesh: {primitive: torus, nu: 4096, nv: 4096}\n", path());
    EXPECT_EQ(primitiveFaceCount(big.mesh), 33554432);
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_THROW(buildScene(big), rosy::InputError);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

// --set values went straight to yaml-cpp and the walkers: a 9-level alias bomb
// passed 6 GB in 40 s where the same text in a file is refused at once.
TEST(BadScene, SetValuesMeetTheNestingAliasAndCycleLimits) {
    const std::string scene = "mesh: {primitive: icosphere}\n";
    auto setError = [&](const std::vector<std::string> &overrides) {
        try {
            parseScene(scene, path(), overrides);
        } catch (const rosy::InputError &e) {
            return std::string(e.what());
        }
        return std::string();
    };
    std::string bomb = "[&a0 [x, x, x, x, x, x, x, x, x]";
    for (int i = 1; i <= 9; ++i) {
        const std::string prev = "*a" + std::to_string(i - 1);
        bomb += ", &a" + std::to_string(i) + " [" + prev;
        for (int k = 1; k < 9; ++k) bomb += ", " + prev;
        bomb += "]";
    }
    bomb += "]";
    const auto t0 = std::chrono::steady_clock::now();
    std::string msg = setError({"lights=" + bomb});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
    EXPECT_TRUE(startsWith(msg, "--set lights=[&a0")) << msg;
    EXPECT_TRUE(contains(msg, "error: the value expands to more than 10000 values")) << msg;
    msg = setError({"camera.fov=" + std::string(40, '[') + std::string(40, ']')});
    EXPECT_TRUE(contains(msg, "error: nesting deeper than 32 levels")) << msg;
    // Block nesting is found by the walk, not by the bracket count.
    std::string block = "\n";
    for (int i = 0; i < 40; ++i) block += std::string(size_t(2 * i), ' ') + "k" + std::to_string(i) + ":\n";
    block += std::string(80, ' ') + "v\n";
    msg = setError({"style=" + block});
    EXPECT_TRUE(contains(msg, "error: nesting deeper than 32 levels")) << msg;
    msg = setError({"lights=&a [*a]"});
    EXPECT_TRUE(startsWith(msg, "--set lights=&a [*a]: error: an alias refers to a node that contains it")) << msg;
    // Several values together stay within the budget.
    std::string list = "[0";
    for (int i = 1; i < 6000; ++i) list += ", " + std::to_string(i);
    list += "]";
    msg = setError({"a=" + list, "b=" + list});
    EXPECT_TRUE(contains(msg, "error: the --set values hold more than 10000 values together")) << msg;
    // A value YAML reads as null is not called "empty".
    msg = setError({"camera.fov=,"});
    EXPECT_TRUE(startsWith(msg, "--set camera.fov=,: error: ',' is no value in YAML (null)")) << msg;
    msg = setError({"camera.fov="});
    EXPECT_TRUE(startsWith(msg, "--set camera.fov=: error: the value of 'camera.fov' is empty")) << msg;
    // An ordinary value still works.
    EXPECT_EQ(setError({"camera.fov=40", "lights=[{type: directional, direction: [1, 1, 1]}]"}), "");
}

TEST(BadScene, WholeNumbersMayBeWrittenWithAPoint) {
    SceneDesc d = parseScene("mesh: {primitive: torus, nu: 12.0}\ncamera: {resolution: [128.0, 1.28e2]}\n", path());
    EXPECT_EQ(d.camera.resolution.value[0], 128);
    EXPECT_EQ(d.camera.resolution.value[1], 128);
    EXPECT_EQ(d.mesh.params.at("nu").value, 12);
    std::string msg = parseError("mesh: {primitive: icosphere}\ncamera: {resolution: [128.5, 128]}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:23: error: camera.resolution width must be a whole number, got 128.5"))
        << msg;
    msg = parseError("mesh: {primitive: icosphere}\nseed: -3.0\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:7: error: seed must be in [0, 4294967295], got -3")) << msg;
    msg = parseError("mesh: {primitive: icosphere}\nstyle: {seed: 5e9}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:15: error: style.seed must be in [0, 4294967295], got 5e+09")) << msg;
}

TEST(BadScene, SmoothingLengthAndPaperSizeRangesNameTheSetting) {
    std::string msg = parseError("mesh: {primitive: icosphere}\nfield: {smoothing_length: 1e-200}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:27: error: field.smoothing_length must be 0 (raw curvature directions) "
                                        "or in [1e-06, 10], got 1e-200"))
        << msg;
    EXPECT_NO_THROW(parseScene("mesh: {primitive: icosphere}\nfield: {smoothing_length: 0}\n", path()));
    EXPECT_NO_THROW(parseScene("mesh: {primitive: icosphere}\nfield: {smoothing_length: 1e-6}\n", path()));
    msg = parseError("mesh: {primitive: icosphere}\nstyle: {page: {size: 1e308x1e308}}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:22: error: style.page.size: paper size '1e308x1e308' is out of range: "
                                        "each side must be in [1, 100000] mm"))
        << msg;
    msg = parseError("mesh: {primitive: icosphere}\nstyle: {page: {size: b5}}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":2:22: error: style.page.size: unknown paper size 'b5'")) << msg;
    EXPECT_NO_THROW(parseScene("mesh: {primitive: icosphere}\nstyle: {page: {size: 100000x30}}\n", path()));
}

TEST(BadScene, NonRegularMeshesAndPresetFoldersAreNamedForWhatTheyAre) {
    const fs::path d = dir() / "kinds";
    fs::remove_all(d);
    fs::create_directories(d / "looks.yaml");
    ASSERT_EQ(::mkfifo((d / "pipe.off").c_str(), 0600), 0);
    const std::string scene = (d / "s.yaml").string();
    auto error = [&](const std::string &text) {
        try {
            parseScene(text, scene);
        } catch (const rosy::InputError &e) {
            return std::string(e.what());
        }
        return std::string();
    };
    std::string msg = error("mesh: pipe.off\n");
    EXPECT_TRUE(startsWith(msg, scene + ":1:7: error: mesh '" + (d / "pipe.off").string() +
                                    "' is not a regular file (a device, pipe or socket)"))
        << msg;
    msg = error("mesh: {primitive: icosphere}\nstyle: {preset: looks.yaml}\n");
    EXPECT_TRUE(startsWith(msg, scene + ":2:17: error: style preset '" + (d / "looks.yaml").string() +
                                    "' is a folder, not a file"))
        << msg;
}

TEST(BadScene, UnknownHatchLinesNameTheKeyAndTheChoices) {
    const std::string msg = parseError("mesh: {primitive: torus}\nstyle:\n  hatch: {lines: grid}\n");
    EXPECT_TRUE(startsWith(msg, path() + ":3:18: error: style.hatch.lines must be field or quad_mesh, got 'grid'"))
        << msg;
    EXPECT_NO_THROW(parseScene("mesh: {primitive: torus}\nstyle: {hatch: {lines: quad_mesh, quad_edge_px: 8}}\n", path()));
    EXPECT_NE(parseError("mesh: {primitive: torus}\nstyle: {hatch: {quad_edge_px: 1}}\n").find("quad_edge_px"),
              std::string::npos);
}
