// End-to-end tests of the scene side of the command line: every shipped example
// scene renders (small) without warnings, every validation error class reaches
// the user as FILE:LINE:COL with exit code 2, --set overrides, and
// `rosyhatch compare` (whose picture is read back and measured).

#include <OpenImageIO/imagebuf.h>

#include "cli_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <vector>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

const std::string kBinary = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";

fs::path workDir() { return rosy::test::testOutputDir("scenes-cli"); }

using rosy::test::CliRun;
using rosy::test::slurp;

/// Runs rosyhatch with `args` (already shell-quoted) from the work folder.
CliRun run(const std::string &args, const std::string &tag) { return rosy::test::runRosyhatch(workDir(), args, tag); }

fs::path writeScene(const std::string &name, const std::string &text) {
    const fs::path p = workDir() / name;
    std::ofstream(p) << text;
    return p;
}

// Appends rather than operator+ chains: GCC 12 reports a false -Wrestrict on those.
std::string quoted(const fs::path &p) {
    std::string s(1, '\'');
    s += p.string();
    s += '\'';
    return s;
}

const char *kTiny = "mesh: {primitive: icosphere, subdivisions: 2}\n"
                    "camera: {resolution: [48, 40]}\n"
                    "lights: [{type: directional, direction: [1, 1, 1]}]\n";

} // namespace

// Every scene the project ships renders at 160 x 160 with exit 0 and no warning,
// one test per scene (so ctest spreads them over its jobs).
namespace {
std::vector<std::string> shippedScenes() {
    std::vector<std::string> names;
    for (const auto &entry : fs::directory_iterator(fs::path(ROSY_SOURCE_DIR) / "scenes"))
        if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}
} // namespace

TEST(ExampleScenesRender, AtLeastSixteenScenesAreShipped) { EXPECT_GE(shippedScenes().size(), 16u); }

class ExampleScene : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleScene, RendersWithoutWarnings) {
    const std::string name = GetParam();
    const fs::path scene = fs::path(ROSY_SOURCE_DIR) / "scenes" / (name + ".yaml");
    const fs::path out = workDir() / ("example-" + name + ".png");
    fs::remove(out);
    const CliRun r = run("render " + quoted(scene) + " --set 'camera.resolution=[160, 160]' -o " + quoted(out) +
                             " --quiet",
                         "example-" + name);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("warning:"), std::string::npos) << r.err;
    OIIO::ImageBuf image(out.string());
    ASSERT_TRUE(image.init_spec(out.string(), 0, 0)) << out;
    EXPECT_EQ(image.spec().width, 160);
    EXPECT_EQ(image.spec().height, 160);
}

INSTANTIATE_TEST_SUITE_P(Shipped, ExampleScene, ::testing::ValuesIn(shippedScenes()),
                         [](const ::testing::TestParamInfo<std::string> &info) {
                             std::string id = info.param;
                             for (char &c : id)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return id;
                         });

// Each class of scene error, through the real executable: the first line of
// stderr starts with FILE:LINE:COL (counted by hand in the text) and the exit
// code is 2; nothing is written.
TEST(ValidationErrorsCli, EveryClassExitsTwoWithFileLineColumn) {
    struct Case {
        const char *name, *text, *where, *what;
    };
    const Case cases[] = {
        {"syntax", "mesh: {primitive: icosphere}\noutput: a: b\n", ":2:10", "YAML syntax error"},
        {"unknown-key", "mesh: {primitive: icosphere}\ncamera: {fvo: 30}\n", ":2:10", "did you mean 'fov'?"},
        {"duplicate-key", "mesh: {primitive: icosphere}\nmesh: {primitive: torus}\n", ":2:1", "duplicate key 'mesh'"},
        {"wrong-type", "mesh: {primitive: icosphere}\ncamera: {fov: wide}\n", ":2:15", "must be a number"},
        {"resolution-range", "mesh: {primitive: icosphere}\ncamera: {resolution: [64, 16385]}\n", ":2:27",
         "camera.resolution height must be in [1, 16384]"},
        {"symmetry-range", "mesh: {primitive: icosphere}\nfield: {symmetry: 13}\n", ":2:19",
         "field.symmetry must be in [1, 12]"},
        {"probability-range", "mesh: {primitive: icosphere}\nstyle: {hatch: {cross_density: 1.5}}\n", ":2:32",
         "style.hatch.cross_density must be in [0, 1]"},
        {"missing-mesh", "mesh: nowhere/none.off\n", ":1:7", "nowhere/none.off' does not exist"},
        {"unknown-preset", "mesh: {primitive: icosphere}\nstyle: {preset: skecth}\n", ":2:17", "did you mean 'sketch'?"},
        {"unknown-primitive", "mesh: {primitive: icosphre}\n", ":1:19", "did you mean 'icosphere'?"},
        {"bad-edit", "mesh: {primitive: icosphere}\nfield: {edits: [{cancle: [0, 1]}]}\n", ":2:18",
         "did you mean 'cancel'?"},
        {"picture-kind", "mesh: {primitive: icosphere}\npicture: {kind: feild}\n", ":2:17", "unknown picture kind"},
    };
    for (const Case &c : cases) {
        SCOPED_TRACE(c.name);
        const fs::path scene = writeScene(std::string("err-") + c.name + ".yaml", c.text);
        const fs::path out = workDir() / (std::string("err-") + c.name + ".png");
        fs::remove(out);
        const CliRun r = run("render " + quoted(scene) + " -o " + quoted(out), std::string("err-") + c.name);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_EQ(r.err.rfind(scene.string() + c.where + ": error: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(c.what), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

TEST(ValidationErrorsCli, AFailedRenderLeavesTheExistingOutputUntouched) {
    const fs::path out = workDir() / "keep.png";
    std::ofstream(out) << "previous";
    const fs::path scene = writeScene("keep.yaml", "mesh: {primitive: icosphere}\ncamera: {fov: 500}\n");
    const CliRun r = run("render " + quoted(scene) + " -o " + quoted(out), "keep");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(slurp(out), "previous");
}

TEST(SetCli, OverridesReachRenderFieldAndCompare) {
    const fs::path scene = writeScene("set.yaml", kTiny);
    const CliRun r = run("render " + quoted(scene) + " --set 'camera.resolution=[30, 20]' --set field.symmetry=2 -o set.png "
                         "--report set.json --quiet",
                         "set-render");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    OIIO::ImageBuf image((workDir() / "set.png").string());
    ASSERT_TRUE(image.init_spec((workDir() / "set.png").string(), 0, 0));
    EXPECT_EQ(image.spec().width, 30);
    EXPECT_EQ(image.spec().height, 20);
    EXPECT_NE(slurp(workDir() / "set.json").find("\"symmetry\": 2"), std::string::npos);

    // An icosphere's smoothest 3-RoSy: indices k/3 summing to chi = 2.
    const CliRun f = run("field " + quoted(scene) + " --set field.symmetry=3 --set field.source=smoothest", "set-field");
    ASSERT_EQ(f.exitCode, 0) << f.err;
    EXPECT_NE(f.out.find("field: 3-RoSy from smoothest"), std::string::npos) << f.out;
    EXPECT_NE(f.out.find("Poincare-Hopf holds"), std::string::npos) << f.out;

    const CliRun c = run("compare " + quoted(scene) + " --set 'camera.resolution=[40, 30]' -o set-compare.png --quiet",
                         "set-compare");
    ASSERT_EQ(c.exitCode, 0) << c.err;
}

TEST(SetCli, BadOverridesExitTwoNamingTheOverride) {
    const fs::path scene = writeScene("setbad.yaml", kTiny);
    for (const std::string cmd : {"render", "field", "compare"}) {
        SCOPED_TRACE(cmd);
        const std::string out = cmd == "field" ? "" : " -o setbad.png";
        const CliRun r = run(cmd + " " + quoted(scene) + " --set field.symmetry=0" + out, "setbad-" + cmd);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_EQ(r.err.rfind("--set field.symmetry=0: error: field.symmetry must be in [1, 12]", 0), 0u) << r.err;
    }
    const CliRun key = run("render " + quoted(scene) + " --set 'camera.resolutoin=[8,8]'", "setbad-key");
    EXPECT_EQ(key.exitCode, 2);
    EXPECT_EQ(key.err.rfind("--set camera.resolutoin=[8,8]: error: unknown key 'resolutoin' in camera", 0), 0u)
        << key.err;
    const CliRun form = run("render " + quoted(scene) + " --set novalue", "setbad-form");
    EXPECT_EQ(form.exitCode, 2);
    EXPECT_EQ(form.err.rfind("--set novalue: error: an override needs KEY=VALUE", 0), 0u) << form.err;
    // A bare mesh with --set is the scene `mesh: FILE` (FieldCli.BareMeshTakesSetOverrides);
    // a file that is neither a scene nor a mesh cannot take one.
    const CliRun mesh = run("field fandisk.txt --set field.symmetry=2", "setbad-mesh");
    EXPECT_EQ(mesh.exitCode, 2) << mesh.err;
    EXPECT_EQ(mesh.err.rfind("--set field.symmetry=2: error: --set overrides keys of a scene file", 0), 0u) << mesh.err;
}

namespace {

/// The singularity count `rosyhatch field` reports for `scene` at symmetry n.
int fieldSingularities(const fs::path &scene, int n, const std::string &extra = {}) {
    const CliRun r = run("field " + quoted(scene) + " -n " + std::to_string(n) + " " + extra, "count");
    std::smatch m;
    if (r.exitCode != 0 || !std::regex_search(r.out, m, std::regex("singularities: ([0-9]+)"))) return -1;
    return std::stoi(m[1]);
}

/// Fraction of pixels in [x0, x1) x [y0, y1) darker than half grey.
double inkFraction(const OIIO::ImageBuf &image, int x0, int x1, int y0, int y1) {
    int dark = 0, all = 0;
    float px[4];
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            image.getpixel(x, y, px, 3);
            dark += (px[0] + px[1] + px[2]) / 3 < 0.5f;
            ++all;
        }
    return all ? double(dark) / all : 0.0;
}

} // namespace

TEST(CompareCli, SymmetryPanelsAreLabeledWithTheirFieldAndCount) {
    const fs::path scene = writeScene("cmp.yaml", "mesh: {primitive: torus, nu: 48, nv: 24}\n"
                                                  "camera: {direction: [0.2, 1, 0.9], resolution: [160, 120]}\n"
                                                  "field: {source: design, elements: [{position: [1.35, 0, 0], "
                                                  "order: 1}, {position: [-1.35, 0, 0], order: -1}]}\n");
    const fs::path out = workDir() / "cmp.png";
    fs::remove(out);
    const CliRun r = run("compare " + quoted(scene) + " --symmetry 2,4 -o " + quoted(out), "cmp");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // The labels name each field and its count, which `rosyhatch field` finds independently.
    for (int n : {2, 4}) {
        const int count = fieldSingularities(scene, n);
        ASSERT_GE(count, 2) << "n = " << n;
        const std::string label = std::to_string(n) + "-RoSy: " + std::to_string(count) + " singularities";
        EXPECT_NE(r.err.find(label), std::string::npos) << label << "\n" << r.err;
    }
    OIIO::ImageBuf image(out.string());
    ASSERT_TRUE(image.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    const int w = 160, h = 120, gap = 4; // gap: max(4, min(w, h) / 32)
    ASSERT_EQ(image.spec().width, 2 * w + 3 * gap);
    ASSERT_GT(image.spec().height, h + 2 * gap);
    const int H = image.spec().height;
    for (int k = 0; k < 2; ++k) {
        const int x0 = gap + k * (w + gap);
        // Each panel holds a drawing, and under it a label in ink; the gaps stay paper.
        EXPECT_GT(inkFraction(image, x0, x0 + w, gap, gap + h), 0.01) << "panel " << k;
        EXPECT_GT(inkFraction(image, x0, x0 + w, gap + h + 1, H), 0.02) << "label " << k;
        EXPECT_EQ(inkFraction(image, x0 - gap, x0, 0, H), 0.0) << "gap before panel " << k;
    }
    EXPECT_EQ(inkFraction(image, 0, image.spec().width, 0, gap), 0.0);
}

TEST(CompareCli, EditedAndSmoothedVariants) {
    // Four design singularities on a sphere; the edited variant cancels pairs,
    // the smoothed one relaxes the field: neither may have more singularities
    // than the original, and Poincare-Hopf keeps every count even here (chi = 2,
    // index sum 2 from first-order ±1/4: #pos - #neg = 8).
    const fs::path scene = writeScene("variants.yaml", "mesh: {primitive: icosphere, subdivisions: 3}\n"
                                                       "camera: {resolution: [96, 96]}\n"
                                                       "field: {source: smoothest}\n");
    const CliRun r =
        run("compare " + quoted(scene) + " --variants original,edited,smoothed -o variants.png", "variants");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::smatch m;
    std::vector<int> counts;
    std::string err = r.err;
    while (std::regex_search(err, m, std::regex(": ([0-9]+) singularit"))) {
        counts.push_back(std::stoi(m[1]));
        err = m.suffix();
    }
    ASSERT_EQ(counts.size(), 3u) << r.err;
    EXPECT_EQ(counts[0], fieldSingularities(scene, 4));
    EXPECT_LE(counts[1], counts[0]);
    EXPECT_LE(counts[2], counts[0]);
    for (int c : counts) EXPECT_GE(c, 8); // at least eight +1/4 singularities on a sphere
    EXPECT_NE(r.err.find("(b) 4-RoSy,"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("smoothed"), std::string::npos) << r.err;
    OIIO::ImageBuf image((workDir() / "variants.png").string());
    ASSERT_TRUE(image.init_spec((workDir() / "variants.png").string(), 0, 0));
    EXPECT_EQ(image.spec().width, 3 * 96 + 4 * 4);
}

TEST(CompareCli, BadArgumentsExitTwo) {
    const fs::path scene = writeScene("cmpbad.yaml", kTiny);
    for (const std::string args : {"--symmetry 2,x", "--symmetry 0,4", "--variants edited,blurred",
                                   "--symmetry 2 --variants edited", "--smoothing 0", "-o out.gif"}) {
        const std::string outArg = args.find("-o ") == std::string::npos ? " -o cmpbad.png" : "";
        const CliRun r = run("compare " + quoted(scene) + " " + args + outArg, "cmpbad");
        EXPECT_EQ(r.exitCode, 2) << args << ": " << r.err;
        EXPECT_NE(r.err.find("error:"), std::string::npos) << args << ": " << r.err;
    }
    EXPECT_EQ(run("compare " + quoted(scene) + " -o nowhere/x.png", "cmpbad-dir").exitCode, 3);
}

// --- output lists, threads, seed, mesh.transform through the executable -----------

namespace {

/// Mean absolute difference of the first channel of two images of the same size
/// (values in [0, 1]) after averaging over `block` x `block` pixel tiles, which turns
/// individual lines into tone; -1 if they cannot be read or differ in size.
double meanAbsDiff(const fs::path &a, const fs::path &b, int block = 1) {
    OIIO::ImageBuf A(a.string()), B(b.string());
    if (!A.read(0, 0, true, OIIO::TypeDesc::FLOAT) || !B.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return -1;
    const OIIO::ImageSpec &sa = A.spec(), &sb = B.spec();
    if (sa.width != sb.width || sa.height != sb.height) return -1;
    double sum = 0;
    int tiles = 0;
    float pa[8], pb[8];
    for (int y0 = 0; y0 + block <= sa.height; y0 += block)
        for (int x0 = 0; x0 + block <= sa.width; x0 += block) {
            double ta = 0, tb = 0;
            for (int y = y0; y < y0 + block; ++y)
                for (int x = x0; x < x0 + block; ++x) {
                    A.getpixel(x, y, pa, 8);
                    B.getpixel(x, y, pb, 8);
                    ta += pa[0];
                    tb += pb[0];
                }
            sum += std::abs(ta - tb) / (block * block);
            ++tiles;
        }
    return tiles ? sum / tiles : -1;
}

std::vector<std::string> lines(const std::string &s) {
    std::vector<std::string> out;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

} // namespace

// One render, every listed output: PNG, SVG and EXR. The PNG is byte-identical to the
// same scene rendered alone to one PNG (renders are deterministic), so it came from
// the same drawing.
TEST(SceneOutputsCli, OneRenderWritesEveryListedOutput) {
    const fs::path dir = workDir();
    for (const char *f : {"multi.png", "multi.svg", "multi.exr", "single.png"}) fs::remove(dir / f);
    const fs::path scene =
        writeScene("multi.yaml", std::string(kTiny) + "output: [multi.png, multi.svg, multi.exr]\n");
    const CliRun r = run("render " + quoted(scene) + " -q", "multi");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(lines(r.out), (std::vector<std::string>{"multi.png", "multi.svg", "multi.exr"}));
    EXPECT_NE(slurp(dir / "multi.svg").find("<svg"), std::string::npos);
    OIIO::ImageBuf exr((dir / "multi.exr").string());
    ASSERT_TRUE(exr.init_spec((dir / "multi.exr").string(), 0, 0));
    EXPECT_EQ(exr.spec().width, 48);
    EXPECT_GT(exr.spec().nchannels, 4); // the ink layers and field channels
    // An SVG in the list puts the render in print mode (lengths in mm on the
    // page): a PNG alone matches it with --paper (the style's page, A4).
    const CliRun alone = run("render " + quoted(scene) + " -o single.png --paper a4 -q", "multi-single");
    ASSERT_EQ(alone.exitCode, 0) << alone.err;
    EXPECT_EQ(slurp(dir / "multi.png"), slurp(dir / "single.png"));
}

// Print mode is the pipeline's (PipelineOptions::print): the CLI passes its
// choice and reads back what was chosen for the SVG's pen and the report.
TEST(SceneOutputsCli, PrintModeWarnsAndReportsWhatThePipelineChose) {
    const fs::path dir = workDir();
    const fs::path scene = writeScene("pen.yaml", kTiny);
    const CliRun r =
        run("render " + quoted(scene) + " -o pen.svg --pen-mm 0.05 --report pen.json --timings pen-t.json", "pen");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning: the pen is 0.05 mm wide"), std::string::npos) << r.err;
    const nlohmann::json report = nlohmann::json::parse(slurp(dir / "pen.json"));
    EXPECT_EQ(report.at("pen_width_mm").get<double>(), 0.05);
    EXPECT_GE(report.at("warnings").at("print").get<int>(), 1);
    // SVG only: traced for the page.px_mm grid (0.17 mm on A4 needs 1,118 px), not at
    // the scene's 48 x 40, within the budget of 4 x its longer side (said so).
    EXPECT_EQ(report.at("width").get<int>(), 4 * 48);
    EXPECT_NEAR(report.at("mm_per_px").get<double>(), 190.0 / (4 * 40), 1e-9); // A4 landscape: 190 mm high
    EXPECT_NE(r.err.find("warning: the page needs more than 192 px"), std::string::npos) << r.err;
    // The spacing gain of the trace kept by the ink calibration (renderer/illustration.h).
    const double gain = report.at("spacing_gain").get<double>();
    EXPECT_TRUE(gain >= 0.5 && gain <= 2.0) << gain;
    // How near the kept trace came to the tone's ink, and how much of that was asked
    // at the pen's densest spacing (shares; the warning's figures).
    EXPECT_GT(report.at("ink_fill").get<double>(), 0.0);
    const double atMin = report.at("ink_at_min_spacing").get<double>();
    EXPECT_TRUE(atMin >= 0.0 && atMin <= 1.0) << atMin;
    EXPECT_NE(slurp(dir / "pen.svg").find("stroke-width=\"0.05\""), std::string::npos);
    // A PNG alone is not in print mode: no pen in the report.
    const CliRun png =
        run("render " + quoted(scene) + " -o pen.png --report pen-png.json --timings png-t.json -q", "pen-png");
    ASSERT_EQ(png.exitCode, 0) << png.err;
    EXPECT_FALSE(nlohmann::json::parse(slurp(dir / "pen-png.json")).contains("pen_width_mm"));
    // An SVG alone skips the raster stage (issue 18); the PNG needs it.
    const nlohmann::json svgTimes = nlohmann::json::parse(slurp(dir / "pen-t.json"));
    EXPECT_TRUE(svgTimes.contains("hatching")) << svgTimes.dump();
    EXPECT_FALSE(svgTimes.contains("raster")) << svgTimes.dump();
    EXPECT_TRUE(nlohmann::json::parse(slurp(dir / "png-t.json")).contains("raster"));
}

// -o (repeatable) replaces the scene's list: only the command line's files appear.
TEST(SceneOutputsCli, RepeatedDashOReplacesTheScenesList) {
    const fs::path dir = workDir();
    for (const char *f : {"sa.png", "sb.png", "ca.png", "cb.exr"}) fs::remove(dir / f);
    const fs::path scene = writeScene("olist.yaml", std::string(kTiny) + "output: [sa.png, sb.png]\n");
    const CliRun r = run("render " + quoted(scene) + " -o ca.png -o cb.exr -q", "olist");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "ca.png"));
    EXPECT_TRUE(fs::exists(dir / "cb.exr"));
    EXPECT_FALSE(fs::exists(dir / "sa.png"));
    EXPECT_FALSE(fs::exists(dir / "sb.png"));
    const CliRun twice = run("render " + quoted(scene) + " -o ca.png -o ca.png -q", "olist-twice");
    EXPECT_EQ(twice.exitCode, 2) << twice.err;
}

// Every output is checked before rendering: if any cannot be written (exit 3),
// nothing is written, and a file already there keeps its content.
TEST(SceneOutputsCli, NothingIsWrittenWhenAnyOutputIsUnwritable) {
    const fs::path dir = workDir();
    fs::remove(dir / "fresh.png");
    fs::remove_all(dir / "no-such-folder");
    std::ofstream(dir / "keep.png") << "old";
    const fs::path scene =
        writeScene("unwritable.yaml", std::string(kTiny) + "output: [keep.png, fresh.svg, no-such-folder/x.png]\n");
    const CliRun r = run("render " + quoted(scene) + " -q", "unwritable");
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_NE(r.err.find("no-such-folder"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(dir / "keep.png"), "old");
    EXPECT_FALSE(fs::exists(dir / "fresh.svg"));
    const CliRun cli = run("render " + quoted(scene) + " -o fresh.png -o no-such-folder/y.exr -q", "unwritable-cli");
    EXPECT_EQ(cli.exitCode, 3) << cli.err;
    EXPECT_FALSE(fs::exists(dir / "fresh.png"));
}

// `threads` is range-checked at its place; the drawing does not depend on the
// thread count, whether it comes from the scene or from --threads.
TEST(SceneThreadsCli, SceneThreadsAndTheCliOverride) {
    const fs::path dir = workDir();
    const fs::path one = writeScene("threads1.yaml", std::string(kTiny) + "threads: 1\n");
    ASSERT_EQ(run("render " + quoted(one) + " -o threads1.png -q", "threads1").exitCode, 0);
    ASSERT_EQ(run("render " + quoted(one) + " --threads 2 -o threads2.png -q", "threads2").exitCode, 0);
    EXPECT_EQ(slurp(dir / "threads1.png"), slurp(dir / "threads2.png"));
    const fs::path bad = writeScene("threadsbad.yaml", std::string(kTiny) + "threads: 9999\n");
    const CliRun r = run("render " + quoted(bad) + " -o threadsbad.png -q", "threadsbad");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err.rfind(bad.string() + ":4:10: error: threads must be in [0, 4096], got 9999", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir / "threadsbad.png"));
}

// The top-level seed drives the style's random jitter (sketch preset): another seed
// draws differently; a style.seed in the scene wins over the top-level one.
TEST(SceneSeedCli, TopLevelSeedDrivesTheJitterAndStyleSeedWins) {
    const fs::path dir = workDir();
    const std::string base = "mesh: {primitive: torus}\ncamera: {resolution: [128, 128]}\n";
    auto render = [&](const std::string &name, const std::string &extra) {
        const fs::path scene = writeScene(name + ".yaml", base + extra);
        const CliRun r = run("render " + quoted(scene) + " -o " + name + ".png -q", name);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return slurp(dir / (name + ".png"));
    };
    const std::string s3 = render("seed3", "style: {preset: sketch}\nseed: 3\n");
    const std::string s4 = render("seed4", "style: {preset: sketch}\nseed: 4\n");
    const std::string style3 = render("styleseed3", "style: {preset: sketch, seed: 3}\n");
    const std::string both = render("bothseeds", "style: {preset: sketch, seed: 3}\nseed: 4\n");
    EXPECT_NE(s3, s4);
    EXPECT_EQ(s3, style3);
    EXPECT_EQ(both, style3);
    const CliRun bad = run("render " + quoted(writeScene("seedbad.yaml", base + "seed: -1\n")) + " -q", "seedbad");
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_NE(bad.err.find("seedbad.yaml:3:7: error: seed must be in [0, 4294967295]"), std::string::npos) << bad.err;
}

// The bunny scaled by 3 and moved far away, auto-framed, is the same picture: the
// camera frames the transformed mesh. Turned by 90 degrees it is clearly another one,
// which shows the comparison can fail.
TEST(MeshTransformCli, ScaledTranslatedBunnyRendersTheSamePicture) {
    const std::string bunny = std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off";
    if (!fs::exists(bunny)) GTEST_SKIP() << "no " << bunny;
    const std::string cam = "camera: {resolution: [160, 160], direction: [-0.35, 0.3, 1.0]}\n";
    auto render = [&](const std::string &name, const std::string &transform) {
        const fs::path scene = writeScene(name + ".yaml", "mesh: {file: " + bunny + transform + "}\n" + cam);
        const CliRun r = run("render " + quoted(scene) + " -o " + name + ".png -q", name);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return workDir() / (name + ".png");
    };
    const fs::path plain = render("bunny-plain", "");
    const fs::path moved = render("bunny-moved", ", transform: {scale: 3, translate: [10, -4, 25]}");
    const fs::path turned = render("bunny-turned", ", transform: {rotate: [0, 90, 0]}");
    const double same = meanAbsDiff(plain, moved), other = meanAbsDiff(plain, turned);
    const double same8 = meanAbsDiff(plain, moved, 8), other8 = meanAbsDiff(plain, turned, 8);
    std::cerr << "mean |diff|: moved " << same << ", turned " << other << "; 8x8 tiles: moved " << same8
              << ", turned " << other8 << "\n";
    // Rounding differences move a few strokes by a pixel (measured: 0.008 per pixel,
    // 0.003 over 8 x 8 tiles); a different view differs in tone (0.08 and 0.05).
    ASSERT_GE(same, 0);
    EXPECT_LT(same, 0.02);
    EXPECT_LT(same8, 0.01);
    EXPECT_GT(other8, 0.03);
}

TEST(CompareCli, ReportHoldsEachPanelsSeamsAndStrokesNearSingularities) {
    const fs::path scene = writeScene("cmp-report.yaml", "mesh: {primitive: torus, nu: 48, nv: 24}\n"
                                                         "camera: {direction: [0.2, 1, 0.9], resolution: [160, 120]}\n");
    const fs::path out = workDir() / "cmp-report.png", report = workDir() / "cmp-report.json";
    fs::remove(report);
    const CliRun r = run("compare " + quoted(scene) + " --symmetry 2,4 -o " + quoted(out) + " --report " + quoted(report),
                         "cmp-report");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // stderr: each label followed by its figures.
    const std::regex line(R"(\(([ab])\) ([24])-RoSy: \d+ singularit(y|ies); seam_fraction (\d\.\d{4}), strokes_near_singularities (\d+))");
    const std::string err = r.err;
    EXPECT_EQ(std::distance(std::sregex_iterator(err.begin(), err.end(), line), std::sregex_iterator()), 2) << err;
    // The report: two panels, 2-RoSy then 4-RoSy, each with the same figures.
    const std::string json = slurp(report);
    const nlohmann::json doc = nlohmann::json::parse(json);
    const nlohmann::json &panels = doc.at("panels");
    ASSERT_EQ(panels.size(), 2u) << json;
    for (size_t k = 0; k < panels.size(); ++k) {
        const nlohmann::json &panel = panels[k];
        EXPECT_EQ(panel.at("symmetry").get<int>(), k == 0 ? 2 : 4) << json;
        EXPECT_GE(panel.at("singularities").get<int>(), 0);
        const double seam = panel.at("seam_fraction").get<double>();
        EXPECT_GE(seam, 0.0);
        EXPECT_LE(seam, 1.0);
        const double stubs = panel.at("stub_fraction").get<double>();
        EXPECT_GE(stubs, 0.0);
        EXPECT_LE(stubs, 1.0);
        EXPECT_EQ(panel.at("strokes_near_singularities").get<int>(), 0); // strokes keep clear of singularities
    }
}

TEST(InspectCli, PrintsSeamFractionAndDrawsTheSeams) {
    const fs::path scene = writeScene("inspect-seams.yaml", "mesh: {primitive: torus}\n"
                                                            "camera: {resolution: [200, 160]}\n"
                                                            "style: {ambient: 0.02}\n");
    const fs::path exr = workDir() / "inspect-seams.exr", png = workDir() / "inspect-seams.png",
                   json = workDir() / "inspect-seams.json";
    for (const fs::path &p : {exr, png, json}) fs::remove(p);
    ASSERT_EQ(run("render " + quoted(scene) + " -o " + quoted(exr) + " --quiet", "inspect-seams-render").exitCode, 0);
    const CliRun r = run("inspect " + quoted(exr) + " --json " + quoted(json) + " --seams " + quoted(png), "inspect-seams");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(seam_fraction: (\d\.\d{4}) \((\d+) of (\d+) cross-hatched px, cross density 0\.45 from the file\))")))
        << r.out;
    EXPECT_GT(std::stoll(m[3]), 0); // the dark side is cross-hatched
    const std::string text = slurp(json);
    EXPECT_EQ(nlohmann::json::parse(text).at("seam_pixels").get<long long>(), std::stoll(m[2])) << text;
    OIIO::ImageBuf picture(png.string());
    ASSERT_TRUE(picture.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    EXPECT_EQ(picture.spec().width, 200);
    EXPECT_EQ(picture.spec().height, 160);
    // A picture name inspect cannot write is refused before any work, exit 2.
    EXPECT_EQ(run("inspect " + quoted(exr) + " --seams " + quoted(workDir() / "x.seams"), "inspect-seams-bad").exitCode, 2);
}
