// End-to-end: run the rosyhatch binary on tiny scenes and check exit codes,
// messages and the written files.

#include "cli_util.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

const std::string kBinary = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";

fs::path workDir() { return rosy::test::testOutputDir("cli"); }

using rosy::test::CliRun;
using rosy::test::slurp;
using rosy::test::svgLayerPaths;

/// Runs rosyhatch with `args` (already shell-quoted) from the work folder.
CliRun run(const std::string &args, const std::string &tag) { return rosy::test::runRosyhatch(workDir(), args, tag); }

fs::path writeScene(const std::string &name, const std::string &text) {
    fs::path p = workDir() / name;
    std::ofstream(p) << text;
    return p;
}

const char *kTinyScene = "mesh: {primitive: icosphere, subdivisions: 2}\n"
                         "camera: {resolution: [48, 40]}\n"
                         "lights: [{type: directional, direction: [1, 1, 1]}]\n"
                         "output: tiny.png\n";

} // namespace

TEST(RenderCli, WritesImageAndPrintsItsPath) {
    fs::path scene = writeScene("tiny.yaml", kTinyScene);
    fs::remove(workDir() / "tiny.png");
    CliRun r = run("render '" + scene.string() + "' --quiet", "ok");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("tiny.png"), std::string::npos) << r.out;
    std::string png = slurp(workDir() / "tiny.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
}

// Issue 18: the display names every long stage, the load and field before the
// drawing and each write after it. On a terminal (util-linux `script` provides a
// pseudo-terminal) with ROSY_PROGRESS_DELAY_MS=0, every stage is drawn as it begins.
TEST(RenderCli, ProgressNamesLoadFieldRenderAndEveryWrite) {
    if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` (util-linux)";
    fs::path scene = writeScene("progress.yaml", kTinyScene);
    const fs::path log = workDir() / "progress.log";
    fs::remove(log);
    const std::string cmd = "cd '" + workDir().string() + "' && ROSY_PROGRESS_DELAY_MS=0 script -q -e -c \"'" + kBinary +
                            "' render '" + scene.string() + "' -o p.svg -o p.exr --report p.json\" '" + log.string() +
                            "' >/dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string drawn = slurp(log);
    for (const char *stage : {"preparing: load", "preparing: field", "preparing: bvh", "rendering: hatching",
                              "writing: p.svg (plotter pass)", "writing: p.svg ", "writing: p.exr (channels)",
                              "writing: p.exr ", "writing: p.json "})
        EXPECT_NE(drawn.find(std::string("\r") + stage), std::string::npos) << stage << " in\n" << drawn;
    // Not on a terminal (a file): nothing, with the same forced delay.
    ::setenv("ROSY_PROGRESS_DELAY_MS", "0", 1);
    CliRun quiet = run("render '" + scene.string() + "' -o p.svg", "progress-file");
    ::unsetenv("ROSY_PROGRESS_DELAY_MS");
    EXPECT_EQ(quiet.exitCode, 0) << quiet.err;
    EXPECT_EQ(quiet.err.find("preparing"), std::string::npos) << quiet.err;
}

TEST(RenderCli, BadSceneExitsTwoWithLocatedMessage) {
    fs::path scene = writeScene("bad.yaml", "mesh: {primitive: icosphere}\ncamera: {fov: 500}\n");
    CliRun r = run("render '" + scene.string() + "'", "bad");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err.rfind(scene.string() + ":2:15: error: camera.fov", 0), 0u) << r.err;
}

TEST(RenderCli, UnwritableOutputFolderExitsThreeBeforeRendering) {
    fs::path scene = writeScene("tiny3.yaml", kTinyScene);
    CliRun r = run("render '" + scene.string() + "' -o no-such-folder/x.png", "unwritable");
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_NE(r.err.find("no-such-folder"), std::string::npos) << r.err;
}

TEST(RenderCli, MissingSceneFileExitsThree) {
    CliRun r = run("render does-not-exist.yaml", "missing");
    EXPECT_EQ(r.exitCode, 3) << r.err;
}

// A bare mesh is a scene of its own: `mesh: FILE` with the defaults (automatic camera,
// default light and style), the output named after it in the working folder, --set
// still applying. Its name may hold YAML's own characters.
TEST(RenderCli, BareMeshRendersWithTheDefaultScene) {
    const fs::path mesh = workDir() / "te\"t: #1.off";
    std::ofstream(mesh) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    fs::remove(workDir() / "te\"t: #1.png");
    CliRun r = run("render 'te\"t: #1.off' --quiet --set 'camera.resolution=[40,32]'", "bare-mesh");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string png = slurp(workDir() / "te\"t: #1.png");
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    // the --set reached the scene
    EXPECT_EQ(rosy::test::pngSize(png), std::make_pair(40u, 32u));
    // A missing mesh is a missing input (exit 3), named, as a missing scene is.
    CliRun missing = run("render no-such-mesh.off", "bare-mesh-missing");
    EXPECT_EQ(missing.exitCode, 3) << missing.err;
    EXPECT_NE(missing.err.find("no-such-mesh.off: error: no such file"), std::string::npos) << missing.err;
    fs::create_directories(workDir() / "folder.obj");
    CliRun folder = run("render folder.obj", "bare-mesh-folder");
    EXPECT_EQ(folder.exitCode, 3) << folder.err;
    EXPECT_NE(folder.err.find("folder.obj: error: is a folder, not a mesh file"), std::string::npos) << folder.err;
}

// field and remesh take a bare mesh alone as before; with --set it becomes the scene
// `mesh: FILE`, so the override applies (it was rejected before).
TEST(FieldCli, BareMeshTakesSetOverrides) {
    const std::string mesh = std::string(ROSY_DATA_DIR) + "/meshes/fandisk.off";
    fs::remove(workDir() / "fandisk-n2.json");
    CliRun r = run("field '" + mesh + "' --set field.symmetry=2 --json fandisk-n2.json --quiet", "field-bare-set");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string json = slurp(workDir() / "fandisk-n2.json");
    EXPECT_NE(json.find("\"symmetry\": 2"), std::string::npos) << json.substr(0, 400);
    EXPECT_NE(json.find("\"index_sum\": 2"), std::string::npos); // chi = 2 whatever N
    // remesh: --set reaches the picture's camera
    fs::remove(workDir() / "fandisk-q.png");
    r = run("remesh '" + mesh + "' -o fandisk-q.obj --edge 4% --image fandisk-q.png --set 'camera.resolution=[40,32]' --quiet",
            "remesh-bare-set");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string png = slurp(workDir() / "fandisk-q.png");
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(rosy::test::pngSize(png), std::make_pair(40u, 32u));
    // an unknown extension is neither: --set names the choice
    r = run("field mesh.xyz --set field.symmetry=2", "field-bare-set-bad");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--set overrides keys of a scene file"), std::string::npos) << r.err;
}

// A mesh (or any long text) given where a scene belongs: the message quotes the
// start of it and its length, not the whole file.
TEST(RenderCli, LongScalarSceneIsQuotedShort) {
    std::string text = "OFF 4 4 0";
    for (int i = 0; i < 2000; ++i) text += " 0.123456";
    fs::path scene = writeScene("scalar.yaml", text + "\n");
    CliRun r = run("render '" + scene.string() + "'", "scalar");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.rfind(scene.string() + ":1:1: error: the scene must be a map", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("(" + std::to_string(text.size()) + " characters)"), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), 400u) << r.err;
}

TEST(RenderCli, UnsupportedOutputExtensionExitsTwo) {
    fs::path scene = writeScene("tiny4.yaml", kTinyScene);
    CliRun r = run("render '" + scene.string() + "' -o x.gif", "ext");
    EXPECT_EQ(r.exitCode, 2) << r.err;
}

TEST(RenderCli, UsageErrorsExitTwo) {
    EXPECT_EQ(run("render", "noscene").exitCode, 2);
    EXPECT_EQ(run("render x.yaml --no-such-flag", "badflag").exitCode, 2);
    EXPECT_EQ(run("", "nosub").exitCode, 2);
}

TEST(RenderCli, HelpAndVersionExitZero) {
    CliRun help = run("--help", "help");
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.out.find("render"), std::string::npos);
    CliRun renderHelp = run("render --help", "renderhelp");
    EXPECT_EQ(renderHelp.exitCode, 0);
    EXPECT_NE(renderHelp.out.find("--threads"), std::string::npos);
    CliRun version = run("--version", "version");
    EXPECT_EQ(version.exitCode, 0);
    EXPECT_NE(version.out.find("rosyhatch"), std::string::npos);
}

TEST(RenderCli, SameBytesForOneAndTwoThreads) {
    fs::path scene = writeScene("threads.yaml", "mesh: {primitive: torus, nu: 24, nv: 12}\n"
                                                "camera: {resolution: [64, 48]}\n");
    CliRun a = run("render '" + scene.string() + "' -o t1.png --threads 1 --timings t1.json", "t1");
    CliRun b = run("render '" + scene.string() + "' -o t2.png --threads 2", "t2");
    ASSERT_EQ(a.exitCode, 0) << a.err;
    ASSERT_EQ(b.exitCode, 0) << b.err;
    std::string one = slurp(workDir() / "t1.png"), two = slurp(workDir() / "t2.png");
    ASSERT_FALSE(one.empty());
    EXPECT_EQ(one, two);
    std::string timings = slurp(workDir() / "t1.json");
    EXPECT_NE(timings.find("\"gbuffer\""), std::string::npos) << timings;
    EXPECT_NE(timings.find("\"total\""), std::string::npos) << timings;
}

// --- rosyhatch field --------------------------------------------------------

TEST(FieldCli, ReportsSingularitiesAndPoincareHopf) {
    const std::string mesh = std::string(ROSY_DATA_DIR) + "/meshes/fandisk.off";
    fs::remove(workDir() / "fandisk.json");
    fs::remove(workDir() / "fandisk.ply");
    CliRun r = run("field '" + mesh + "' -n 4 --json fandisk.json --export fandisk.ply", "field-ok");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("Poincare-Hopf holds"), std::string::npos) << r.out;
    const std::string json = slurp(workDir() / "fandisk.json");
    for (const char *key : {"\"mesh\"", "\"vertices\"", "\"faces\"", "\"euler_characteristic\": 2",
                            "\"boundary_loops\": 0", "\"components\": 1", "\"field\"", "\"symmetry\": 4",
                            "\"source\": \"curvature\"", "\"singularities\"", "\"index_numerator\"",
                            "\"index_sum\": 2", "\"holds\": true", "\"timings_ms\"", "\"singularities\": "})
        EXPECT_NE(json.find(key), std::string::npos) << key;
    // The PLY export: header declares N member directions per vertex.
    const std::string ply = slurp(workDir() / "fandisk.ply");
    EXPECT_EQ(ply.rfind("ply\nformat ascii 1.0\n", 0), 0u);
    EXPECT_NE(ply.find("comment symmetry 4"), std::string::npos);
    EXPECT_NE(ply.find("property double m3z"), std::string::npos);
    EXPECT_EQ(ply.find("property double m4x"), std::string::npos);
}

TEST(FieldCli, DesignElementOnAPrimitiveScene) {
    fs::path scene = writeScene("disk.yaml", "mesh: {primitive: disk}\n");
    CliRun r = run("field '" + scene.string() + "' -n 3 --source design --element -1,0.1,0.05,0 --json disk.json",
                   "field-design");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string json = slurp(workDir() / "disk.json");
    EXPECT_NE(json.find("\"index_numerator\": -1"), std::string::npos) << json;
    EXPECT_NE(json.find("\"holds\": true"), std::string::npos);
}

TEST(FieldCli, BadParametersExitTwo) {
    const std::string mesh = std::string(ROSY_DATA_DIR) + "/meshes/fandisk.off";
    for (const std::string args : {"-n 0", "-n 99", "--source magic", "--source design",
                                   "--element 2,0,0,0", "--element 1,x,0,0", "--global-smoothing -3"}) {
        CliRun r = run("field '" + mesh + "' " + args, "field-bad");
        EXPECT_EQ(r.exitCode, 2) << args << ": " << r.err;
        EXPECT_NE(r.err.find("error:"), std::string::npos) << args << ": " << r.err;
    }
    CliRun missing = run("field /nonexistent/mesh.off", "field-missing");
    EXPECT_EQ(missing.exitCode, 3) << missing.err;
    CliRun outDir = run("field '" + mesh + "' --json /nonexistent-dir/x.json", "field-outdir");
    EXPECT_EQ(outDir.exitCode, 3) << outDir.err;
}

// --export-mesh writes the repaired mesh through OpenMesh's writers, with the
// command's other outputs; --timings writes its file (it used to be accepted and
// ignored), with the smoothest field's eigen-solve.
TEST(FieldCli, ExportMeshAndTimingsFileAreWritten) {
    const std::string mesh = std::string(ROSY_DATA_DIR) + "/meshes/fandisk.off";
    for (const char *name : {"fandisk-out.obj", "field-timings.json", "never.obj"}) fs::remove(workDir() / name);
    CliRun r = run("field '" + mesh + "' -n 4 --source smoothest --export-mesh fandisk-out.obj --timings field-timings.json",
                   "field-export");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // The loader's own counts, printed first: "...: V vertices, F faces, ...".
    int nV = 0, nF = 0;
    ASSERT_EQ(std::sscanf(r.out.substr(r.out.find(": ") + 2).c_str(), "%d vertices, %d faces", &nV, &nF), 2) << r.out;
    const std::string obj = slurp(workDir() / "fandisk-out.obj");
    int objV = 0, objF = 0;
    for (size_t at = 0; at < obj.size(); at = obj.find('\n', at) + 1) {
        objV += obj.compare(at, 2, "v ") == 0;
        objF += obj.compare(at, 2, "f ") == 0;
        if (obj.find('\n', at) == std::string::npos) break;
    }
    EXPECT_EQ(objV, nV);
    EXPECT_EQ(objF, nF);
    const std::string timings = slurp(workDir() / "field-timings.json");
    for (const char *key : {"\"load\"", "\"solve\"", "\"total\"", "\"eigen_solve\"", "\"method\"", "\"fallback\""})
        EXPECT_NE(timings.find(key), std::string::npos) << key << " in " << timings;
    // Refused before any work, nothing written, an existing file kept.
    std::ofstream(workDir() / "keep.stl") << "old";
    CliRun stl = run("field '" + mesh + "' --export-mesh keep.stl --export-mesh-directions", "field-export-stl");
    EXPECT_EQ(stl.exitCode, 2) << stl.err;
    EXPECT_NE(stl.err.find("--export-mesh-directions: error:"), std::string::npos) << stl.err;
    EXPECT_EQ(slurp(workDir() / "keep.stl"), "old");
    CliRun ext = run("field '" + mesh + "' --export-mesh mesh.xyz", "field-export-ext");
    EXPECT_EQ(ext.exitCode, 2) << ext.err;
    EXPECT_NE(ext.err.find("--export-mesh: error:"), std::string::npos) << ext.err;
    CliRun dir = run("field '" + mesh + "' --export-mesh /nonexistent-dir/x.obj", "field-export-dir");
    EXPECT_EQ(dir.exitCode, 3) << dir.err;
    CliRun other = run("field '" + mesh + "' --export-mesh never.obj --json /nonexistent-dir/x.json", "field-export-json");
    EXPECT_EQ(other.exitCode, 3) << other.err;
    EXPECT_FALSE(fs::exists(workDir() / "never.obj"));
}

// --image OUT.svg: the field picture's strokes through the SVG writer, on its pen
// layers; an unknown extension is refused before any work.
TEST(RenderCli, FieldPictureAsSvgBesideItsPng) {
    // `render` of a field picture writes the same pen layers as `field --image x.svg`,
    // and the PNG written with it is the PNG written alone, byte for byte.
    fs::path scene = writeScene("render-field-svg.yaml", "mesh: {primitive: disk}\n"
                                                         "camera: {resolution: [128, 128]}\n"
                                                         "picture: {kind: field, separatrices: true}\n"
                                                         "field:\n  source: design\n"
                                                         "  elements: [{position: [0.2, -0.1, 0], order: -1}]\n");
    for (const char *f : {"rf.svg", "rf.png", "rf-alone.png"}) fs::remove(workDir() / f);
    CliRun both = run("render '" + scene.string() + "' -o rf.svg -o rf.png --quiet", "render-field-svg");
    ASSERT_EQ(both.exitCode, 0) << both.err;
    CliRun alone = run("render '" + scene.string() + "' -o rf-alone.png --quiet", "render-field-png");
    ASSERT_EQ(alone.exitCode, 0) << alone.err;
    EXPECT_EQ(slurp(workDir() / "rf.png"), slurp(workDir() / "rf-alone.png"));
    const std::string svg = slurp(workDir() / "rf.svg");
    ASSERT_EQ(svg.rfind("<?xml", 0), 0u) << svg.substr(0, 200);
    auto layerPaths = [&](const std::string &label) { return svgLayerPaths(svg, label); };
    EXPECT_GT(layerPaths("1 streamlines"), 10);
    EXPECT_GE(layerPaths("2 separatrices"), 1);
    EXPECT_EQ(layerPaths("3 singularities"), 1); // the one singularity's dot
    // The report still needs strokes of a hatching.
    CliRun report = run("render '" + scene.string() + "' -o rf.svg --report rf.json --quiet", "render-field-report");
    EXPECT_EQ(report.exitCode, 2) << report.err;
}

TEST(FieldCli, ImageAsSvgWritesPenLayersWithPaths) {
    fs::path scene = writeScene("field-svg.yaml", "mesh: {primitive: disk}\n"
                                                  "camera: {resolution: [128, 128]}\n"
                                                  "field:\n  source: design\n"
                                                  "  elements: [{position: [0.2, -0.1, 0], order: -1}]\n");
    fs::remove(workDir() / "field-pic.svg");
    CliRun r = run("field '" + scene.string() + "' --separatrices --image field-pic.svg --quiet", "field-svg");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string svg = slurp(workDir() / "field-pic.svg");
    ASSERT_EQ(svg.rfind("<?xml", 0), 0u) << svg.substr(0, 200);
    ASSERT_GE(svg.size(), 7u);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
    // Every layer opened is closed, every path is an empty element.
    auto count = [&](const std::string &what, size_t from = 0, size_t to = std::string::npos) {
        int n = 0;
        for (size_t at = svg.find(what, from); at != std::string::npos && at < to; at = svg.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("<g "), count("</g>"));
    EXPECT_EQ(count("<path "), count("\"/>"));
    // Paths per layer: streamlines, separatrices (N + 1 = 5 from the -1/4 singularity,
    // merged where they meet), and exactly one dot for the one singularity.
    auto layerPaths = [&](const std::string &label) { return svgLayerPaths(svg, label); };
    EXPECT_GT(layerPaths("1 streamlines"), 10);
    EXPECT_GE(layerPaths("2 separatrices"), 1);
    EXPECT_EQ(layerPaths("3 singularities"), 1);

    // --image-before: the field before the scene's edit (the +1/4, −1/4 pair: two
    // dots), --image after it (no singularity left: an empty dot layer).
    fs::path edit = writeScene("field-svg-edit.yaml",
                               "mesh: {primitive: disk}\ncamera: {resolution: [128, 128]}\n"
                               "field:\n  source: design\n"
                               "  elements: [{position: [-0.3, 0.05, 0], order: 1}, {position: [0.3, -0.05, 0], order: -1}]\n"
                               "  edits: [{cancel: [0, 1]}]\n");
    CliRun both = run("field '" + edit.string() + "' --image-before before.svg --image after.svg --quiet",
                      "field-svg-before");
    ASSERT_EQ(both.exitCode, 0) << both.err;
    auto dots = [&](const std::string &file) { return svgLayerPaths(slurp(workDir() / file), "3 singularities"); };
    EXPECT_EQ(dots("before.svg"), 2);
    EXPECT_EQ(dots("after.svg"), 0);

    std::ofstream(workDir() / "field-pic.xyz") << "old";
    CliRun bad = run("field '" + scene.string() + "' --image field-pic.xyz", "field-svg-ext");
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(bad.err.find("--image: error:"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find(".svg"), std::string::npos) << bad.err;
    EXPECT_EQ(slurp(workDir() / "field-pic.xyz"), "old");
}

TEST(FieldCli, SceneEditsAndEditFlagsReachTheReport) {
    const std::string block = "mesh: {primitive: disk}\n"
                              "field:\n"
                              "  source: design\n"
                              "  elements:\n"
                              "    - {position: [-0.3, 0.05, 0], order: 1}\n"
                              "    - {position: [0.3, -0.05, 0], order: -1}\n";
    fs::path scene = writeScene("edit.yaml", block + "  edits: [{cancel: [0, 1]}]\n");
    fs::remove(workDir() / "edit.json");
    CliRun r = run("field '" + scene.string() + "' --json edit.json --separatrices", "field-edit");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::string json = slurp(workDir() / "edit.json");
    for (const char *key : {"\"edits\"", "\"op\": \"cancel\"", "\"region_faces\"", "\"singularities_before\"",
                            "\"singularities_after\"", "\"separatrices\"", "\"source\": \"design\"",
                            "\"holds\": true"})
        EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
    // The cancelled pair had indices +1/4 and −1/4; afterwards no singularity is left.
    EXPECT_EQ(json.find("\"index_numerator\": 1", json.find("\"singularities_after\"")), std::string::npos);

    // Flags replace the scene's edits: cancel the same pair by position instead.
    fs::path plain = writeScene("edit-near.yaml", block);
    r = run("field '" + plain.string() + "' --cancel-near -0.3,0.05,0:0.3,-0.05,0 --json near.json", "field-near");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(slurp(workDir() / "near.json").find("\"op\": \"cancel\""), std::string::npos);

    for (const std::string args : {"--cancel 0", "--move 0:0,0", "--cancel 1,1"}) {
        CliRun bad = run("field '" + plain.string() + "' " + args, "field-edit-bad");
        EXPECT_EQ(bad.exitCode, 2) << args << ": " << bad.err;
        EXPECT_NE(bad.err.find("error:"), std::string::npos) << args << ": " << bad.err;
    }
    CliRun same = run("field '" + plain.string() + "' --cancel 0,7", "field-edit-id");
    EXPECT_NE(same.err.find("singularity #7 does not exist"), std::string::npos) << same.err;
}

TEST(StylesCli, ListsEveryShippedPresetWithItsDescription) {
    CliRun r = run("styles", "styles");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    for (const char *name : {"fine-pen", "engraving", "sketch"}) {
        // One line per preset: the name, then its description on the same line.
        size_t at = r.out.find(std::string(name) + " ");
        ASSERT_NE(at, std::string::npos) << name << " missing from:\n" << r.out;
        size_t eol = r.out.find('\n', at);
        EXPECT_GT(eol - at, std::string(name).size() + 10) << "no description for " << name;
    }
    EXPECT_NE(r.out.find("copper-plate engraving"), std::string::npos) << r.out;
}

TEST(StylesCli, UnknownPresetInASceneExitsWithCode2AtItsLine) {
    fs::path scene = writeScene("badstyle.yaml", std::string(kTinyScene) + "style:\n  preset: skecth\n");
    CliRun r = run("render '" + scene.string() + "' --quiet", "badstyle");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find(scene.string() + ":6:11: error: unknown style preset 'skecth'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("did you mean 'sketch'?"), std::string::npos) << r.err;
}
