// Scene parsing: a valid scene and the exact FILE:LINE:COL of each error class.
// Line/column numbers below are counted by hand in the YAML text of each test
// (1-based; yaml-cpp's 0-based marks must be shifted).

#include "field/primitives.h"
#include "scenes/scene.h"

#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <filesystem>
#include <fstream>

#include "tests/test_output.h"

using namespace rosy::scenes;
namespace fs = std::filesystem;

namespace {

/// A folder with a placeholder mesh file (parsing only checks it exists).
fs::path sceneDir() {
    const fs::path dir = rosy::test::testOutputDir("scenes");
    std::ofstream(dir / "thing.off") << "OFF\n";
    return dir;
}

std::string scenePath() { return (sceneDir() / "s.yaml").string(); }

/// The message of the InputError parseScene throws for `text`.
std::string errorOf(const std::string &text) {
    try {
        parseScene(text, scenePath());
    } catch (const rosy::InputError &e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

using rosy::test::contains;
using rosy::test::startsWith;

} // namespace

TEST(ParseScene, ValidSceneWithEveryKey) {
    SceneDesc d = parseScene("mesh: thing.off\n"
                             "camera: {position: [0, 1, 5], look_at: [0, 0, 0], up: [0, 1, 0], fov: 40,\n"
                             "         resolution: [320, 200]}\n"
                             "lights:\n"
                             "  - {type: directional, direction: [1, 1, 1], intensity: 0.5}\n"
                             "  - {type: point, position: [2, 3, 4]}\n"
                             "shadows: false\n"
                             "style: {paper: [1, 0.9, 0.8], ink: [0.1, 0.1, 0.2], ambient: 0.3}\n"
                             "output: out.exr\n",
                             scenePath());
    ASSERT_TRUE(d.mesh.file.has_value());
    EXPECT_EQ(fs::path(d.mesh.file->value), (sceneDir() / "thing.off").lexically_normal());
    EXPECT_EQ(d.mesh.file->loc.line, 1);
    EXPECT_EQ(d.mesh.file->loc.col, 7);
    EXPECT_FALSE(d.camera.automatic);
    EXPECT_EQ(d.camera.position.value, Vec3(0, 1, 5));
    EXPECT_EQ(d.camera.fov.value, 40.0);
    EXPECT_EQ(d.camera.resolution.value[0], 320);
    EXPECT_EQ(d.camera.resolution.value[1], 200);
    EXPECT_EQ(d.camera.resolution.loc.line, 3);
    ASSERT_EQ(d.lights.size(), 2u);
    EXPECT_EQ(d.lights[0].light.intensity, 0.5);
    EXPECT_EQ(d.lights[1].light.type, rosy::renderer::Light::Type::Point);
    EXPECT_EQ(d.lights[1].light.position, Vec3(2, 3, 4));
    EXPECT_EQ(d.lights[1].light.intensity, 1.0);
    EXPECT_FALSE(d.shadows.value);
    EXPECT_EQ(d.style.style.ambient, 0.3);
    EXPECT_EQ(d.style.style.ink[2], 0.2);
    EXPECT_EQ(d.output.value, "out.exr");
}

TEST(ParseScene, DefaultsGiveAutoCameraAndOutputFromSceneName) {
    SceneDesc d = parseScene("mesh: {primitive: torus, nu: 12}\n", scenePath());
    EXPECT_TRUE(d.camera.automatic);
    EXPECT_FALSE(d.lightsGiven);
    EXPECT_EQ(d.output.value, "s.png");
    ASSERT_TRUE(d.mesh.primitive.has_value());
    EXPECT_EQ(d.mesh.params.at("nu").value, 12.0);
    EXPECT_EQ(d.mesh.params.at("nv").loc.line, 0); // a default, not from the file
}

TEST(ParseScene, SyntaxErrorNamesItsPlace) {
    std::string msg = errorOf("camera: {fov: [1, 2\nmesh: thing.off\n");
    EXPECT_TRUE(startsWith(msg, scenePath() + ":"));
    EXPECT_TRUE(contains(msg, ": error: YAML syntax error")) << msg;
    std::string tabs = errorOf("mesh: thing.off\noutput: a.png\n  bad: [\n");
    EXPECT_TRUE(contains(tabs, ": error: YAML syntax error")) << tabs;
}

TEST(ParseScene, SyntaxErrorLineAndColumnAreOneBased) {
    // "a: b" is not a valid plain value: the offending ':' is line 2, column 10.
    std::string msg = errorOf("mesh: thing.off\noutput: a: b\n");
    EXPECT_TRUE(startsWith(msg, scenePath() + ":2:10: error: YAML syntax error")) << msg;
}

TEST(ParseScene, UnknownKeySuggestsTheClosest) {
    std::string msg = errorOf("mesh: thing.off\ncamera:\n  fvo: 30\n");
    EXPECT_TRUE(startsWith(msg, scenePath() + ":3:3: error: unknown key 'fvo' in camera")) << msg;
    EXPECT_TRUE(contains(msg, "did you mean 'fov'?")) << msg;
    std::string top = errorOf("mesh: thing.off\nlihgts: []\n");
    EXPECT_TRUE(startsWith(top, scenePath() + ":2:1: error: unknown key 'lihgts'")) << top;
    EXPECT_TRUE(contains(top, "did you mean 'lights'?")) << top;
    std::string prim = errorOf("mesh: {primitive: icosphere, subdivsions: 2}\n");
    EXPECT_TRUE(startsWith(prim, scenePath() + ":1:30: error: unknown key 'subdivsions'")) << prim;
    EXPECT_TRUE(contains(prim, "did you mean 'subdivisions'?")) << prim;
    std::string name = errorOf("mesh: {primitive: icosphre}\n");
    EXPECT_TRUE(startsWith(name, scenePath() + ":1:19: error: unknown primitive 'icosphre'")) << name;
    EXPECT_TRUE(contains(name, "did you mean 'icosphere'?")) << name;
}

TEST(ParseScene, WrongTypeNamesTheValue) {
    std::string msg = errorOf("mesh: thing.off\ncamera:\n  fov: wide\n");
    EXPECT_TRUE(startsWith(msg, scenePath() + ":3:8: error: camera.fov (degrees) must be a number")) << msg;
    std::string vec = errorOf("mesh: thing.off\ncamera: {position: [1, 2], look_at: [0, 0, 0]}\n");
    EXPECT_TRUE(startsWith(vec, scenePath() + ":2:20: error: camera.position must be a list of 3")) << vec;
    std::string elem = errorOf("mesh: thing.off\nlights:\n  - {type: point, position: [1, x, 3]}\n");
    EXPECT_TRUE(startsWith(elem, scenePath() + ":3:33: error: lights[0].position[1] must be a number")) << elem;
    std::string integer = errorOf("mesh: thing.off\ncamera: {resolution: [64.5, 64]}\n");
    EXPECT_TRUE(startsWith(integer, scenePath() + ":2:23: error: camera.resolution width must be a whole number"))
        << integer;
}

TEST(ParseScene, OutOfRangeNamesTheValue) {
    std::string msg = errorOf("mesh: thing.off\ncamera:\n  resolution: [800, 16385]\n");
    EXPECT_TRUE(startsWith(msg, scenePath() + ":3:21: error: camera.resolution height must be in [1, 16384]"))
        << msg;
    std::string zero = errorOf("mesh: thing.off\ncamera:\n  resolution: [0, 10]\n");
    EXPECT_TRUE(startsWith(zero, scenePath() + ":3:16: error: camera.resolution width must be in [1, 16384]"))
        << zero;
    std::string fov = errorOf("mesh: thing.off\ncamera: {fov: 180}\n");
    EXPECT_TRUE(startsWith(fov, scenePath() + ":2:15: error: camera.fov (degrees) must be in [1, 179]")) << fov;
    std::string nan = errorOf("mesh: thing.off\nlights: [{type: directional, direction: [1, .nan, 0]}]\n");
    EXPECT_TRUE(startsWith(nan, scenePath() + ":2:45: error: lights[0].direction[1] must be a finite number"))
        << nan;
}

TEST(ParseScene, DuplicateKeyNamesBothLines) {
    std::string msg = errorOf("mesh: thing.off\ncamera:\n  fov: 30\n  up: [0, 1, 0]\n  fov: 40\n");
    EXPECT_TRUE(startsWith(msg, scenePath() + ":5:3: error: duplicate key 'fov' in camera (first set at line 3)"))
        << msg;
    std::string top = errorOf("mesh: thing.off\nmesh: thing.off\n");
    EXPECT_TRUE(startsWith(top, scenePath() + ":2:1: error: duplicate key 'mesh'")) << top;
}

TEST(ParseScene, MissingMeshFileNamesResolvedPath) {
    std::string msg = errorOf("output: x.png\nmesh: sub/none.off\n");
    std::string resolved = (sceneDir() / "sub" / "none.off").lexically_normal().string();
    EXPECT_TRUE(startsWith(msg, scenePath() + ":2:7: error: mesh file '" + resolved + "' does not exist")) << msg;
}

TEST(ParseScene, InconsistentCameraIsAnError) {
    std::string same = errorOf("mesh: thing.off\ncamera: {position: [1, 1, 1], look_at: [1, 1, 1]}\n");
    EXPECT_TRUE(startsWith(same, scenePath() + ":2:40: error: camera.look_at equals camera.position")) << same;
    std::string up = errorOf("mesh: thing.off\ncamera: {position: [0, 5, 0], look_at: [0, 0, 0], up: [0, 1, 0]}\n");
    EXPECT_TRUE(startsWith(up, scenePath() + ":2:55: error: camera.up is parallel")) << up;
    std::string mixed = errorOf("mesh: thing.off\ncamera: {auto: true, position: [0, 0, 5]}\n");
    EXPECT_TRUE(contains(mixed, "error: an automatic camera takes no position")) << mixed;
}

TEST(ParseScene, MissingMeshAndBadOutput) {
    EXPECT_TRUE(startsWith(errorOf("output: a.png\n"), scenePath() + ":1:1: error: the scene has no mesh"));
    std::string out = errorOf("mesh: thing.off\noutput: a.gif\n");
    EXPECT_TRUE(startsWith(out, scenePath() + ":2:9: error: output 'a.gif' has an unsupported extension")) << out;
}

TEST(ParseSceneFile, MissingFileIsAnIoError) {
    EXPECT_THROW(parseSceneFile((sceneDir() / "nope.yaml").string()), rosy::IoError);
}

TEST(EditDistance, CountsEdits) {
    EXPECT_EQ(editDistance("kitten", "sitting"), 3);
    EXPECT_EQ(editDistance("", "abc"), 3);
    EXPECT_EQ(editDistance("fov", "fov"), 0);
    EXPECT_EQ(editDistance("fvo", "fov"), 2);
}

TEST(ParseSceneField, FeatureAngleIsOffUnlessGiven) {
    // field.features.angle: the field aligned to creases sharper than the angle and
    // to the boundary (field/features.h); off by default so every render stays as it was.
    EXPECT_EQ(parseScene("mesh: thing.off\nfield: {symmetry: 4}\n", scenePath()).field.spec.featureAngleDeg, 0);
    EXPECT_EQ(parseScene("mesh: thing.off\nfield: {features: {angle: 40}}\n", scenePath()).field.spec.featureAngleDeg,
              40);
    EXPECT_THROW(parseScene("mesh: thing.off\nfield: {features: {angle: 200}}\n", scenePath()), rosy::InputError);
    EXPECT_THROW(parseScene("mesh: thing.off\nfield: {features: {angel: 40}}\n", scenePath()), rosy::InputError);
}

TEST(ParseSceneField, ValidBlockWithElementsAndEdits) {
    SceneDesc d = parseScene("mesh: thing.off\n"
                             "field:\n"
                             "  symmetry: 2\n"
                             "  source: design\n"
                             "  smoothing_length: 0.1\n"
                             "  elements:\n"
                             "    - {position: [0, 1, 0], order: 1, phase: 90, strength: 2}\n"
                             "    - {position: [1, 0, 0], direction: [0, 0, 1]}\n"
                             "  edits:\n"
                             "    - {cancel: [0, 1]}\n"
                             "    - {move: {singularity: 2, to: [0, 0, 1]}}\n"
                             "    - {cancel_near: [[0, 0, 0], [1, 1, 1]]}\n",
                             scenePath());
    ASSERT_TRUE(d.field.given);
    EXPECT_EQ(d.field.spec.nSym, 2);
    EXPECT_EQ(d.field.symmetryLoc.line, 3);
    EXPECT_EQ(d.field.symmetryLoc.col, 13);
    EXPECT_EQ(d.field.spec.source, rosy::field::FieldSource::Design);
    EXPECT_DOUBLE_EQ(d.field.spec.smoothingLength, 0.1);
    ASSERT_EQ(d.field.spec.elements.size(), 2u);
    EXPECT_EQ(d.field.spec.elements[0].order, 1);
    EXPECT_NEAR(d.field.spec.elements[0].phaseRad, M_PI / 2, 1e-15);
    EXPECT_DOUBLE_EQ(d.field.spec.elements[0].strength, 2.0);
    EXPECT_EQ(d.field.spec.elements[0].position, Vec3(0, 1, 0));
    EXPECT_EQ(d.field.spec.elements[1].order, 0);
    EXPECT_EQ(d.field.spec.elements[1].direction, Vec3(0, 0, 1));
    EXPECT_EQ(d.field.spec.elements[1].label, scenePath() + ":8:7");
    ASSERT_EQ(d.field.edits.size(), 3u);
    EXPECT_EQ(d.field.edits[0].op, FieldEditDesc::Op::Cancel);
    EXPECT_EQ(d.field.edits[0].a, 0);
    EXPECT_EQ(d.field.edits[0].b, 1);
    EXPECT_EQ(d.field.edits[0].loc.line, 10);
    EXPECT_EQ(d.field.edits[0].loc.col, 7);
    EXPECT_EQ(d.field.edits[1].op, FieldEditDesc::Op::Move);
    EXPECT_EQ(d.field.edits[1].a, 2);
    EXPECT_EQ(d.field.edits[1].p, Vec3(0, 0, 1));
    EXPECT_EQ(d.field.edits[2].op, FieldEditDesc::Op::CancelNear);
    EXPECT_EQ(d.field.edits[2].q, Vec3(1, 1, 1));
}

TEST(ParseSceneField, DefaultsWithoutBlock) {
    SceneDesc d = parseScene("mesh: thing.off\n", scenePath());
    EXPECT_FALSE(d.field.given);
    EXPECT_EQ(d.field.spec.nSym, 4);
    EXPECT_EQ(d.field.spec.source, rosy::field::FieldSource::Curvature);
    EXPECT_DOUBLE_EQ(d.field.spec.smoothingLength, 0.08);
    EXPECT_TRUE(d.field.edits.empty());
}

TEST(ParseSceneField, ErrorsCarryFileLineColumn) {
    const std::string p = scenePath();
    std::string unknown = errorOf("mesh: thing.off\nfield:\n  symetry: 4\n");
    EXPECT_TRUE(startsWith(unknown, p + ":3:3: error: unknown key 'symetry' in field")) << unknown;
    EXPECT_TRUE(contains(unknown, "did you mean 'symmetry'?")) << unknown;
    std::string source = errorOf("mesh: thing.off\nfield: {source: curvatur}\n");
    EXPECT_TRUE(startsWith(source, p + ":2:17: error: unknown field source 'curvatur'")) << source;
    EXPECT_TRUE(contains(source, "did you mean 'curvature'?")) << source;
    std::string sym = errorOf("mesh: thing.off\nfield: {symmetry: 13}\n");
    EXPECT_TRUE(startsWith(sym, p + ":2:19: error: field.symmetry must be in [1, 12], got 13")) << sym;
    std::string order = errorOf("mesh: thing.off\nfield:\n  elements:\n    - {position: [0, 0, 0], order: 2}\n");
    EXPECT_TRUE(startsWith(order, p + ":4:36: error: field.elements[0].order must be in [-1, 1], got 2")) << order;
    std::string phase = errorOf("mesh: thing.off\nfield:\n  elements:\n    - {position: [0, 0, 0], phase: 30}\n");
    EXPECT_TRUE(startsWith(phase, p + ":4:36: error: field.elements[0].phase only applies")) << phase;
    std::string design = errorOf("mesh: thing.off\nfield: {source: design}\n");
    EXPECT_TRUE(startsWith(design, p + ":2:17: error: a designed field needs at least one element")) << design;
}

TEST(ParseSceneField, BadEditShapes) {
    const std::string p = scenePath();
    const std::string head = "mesh: thing.off\nfield:\n  edits:\n";
    std::string one = errorOf(head + "    - {cancel: [1]}\n");
    EXPECT_TRUE(startsWith(one, p + ":4:16: error: field.edits[0].cancel must be a list of two singularity ids"))
        << one;
    std::string two = errorOf(head + "    - {cancel: [1, 2], move: {singularity: 0, to: [0, 0, 0]}}\n");
    EXPECT_TRUE(startsWith(two, p + ":4:7: error: field.edits[0] must hold exactly one operation")) << two;
    std::string half = errorOf(head + "    - {move: {singularity: 1}}\n");
    EXPECT_TRUE(startsWith(half, p + ":4:14: error: field.edits[0].move needs both singularity and to")) << half;
    std::string op = errorOf(head + "    - {cancle: [0, 1]}\n");
    EXPECT_TRUE(startsWith(op, p + ":4:8: error: unknown key 'cancle' in field.edits[0]")) << op;
    EXPECT_TRUE(contains(op, "did you mean 'cancel'?")) << op;
    std::string neg = errorOf(head + "    - {cancel: [-1, 2]}\n");
    EXPECT_TRUE(startsWith(neg, p + ":4:17: error: field.edits[0].cancel[0] must be in")) << neg;
    std::string list = errorOf(head + "    cancel: [0, 1]\n");
    EXPECT_TRUE(startsWith(list, p + ":4:5: error: field.edits must be a list")) << list;
}

TEST(ApplyFieldEdits, RenumbersBetweenEditsAndNamesTheFailingEntry) {
    // A designed ±1 pair on a disk: cancelling it leaves no singularity, so a
    // second edit naming id 0 must fail at its own location.
    const rosy::field::Mesh mesh = rosy::field::makeDisk(12);
    const rosy::field::TangentFrames frames(mesh);
    rosy::field::FieldSpec spec;
    spec.source = rosy::field::FieldSource::Design;
    rosy::field::DesignElement plus, minus;
    plus.position = Vec3(-0.3, 0.05, 0);
    plus.order = 1;
    minus.position = Vec3(0.3, -0.05, 0);
    minus.order = -1;
    spec.elements = {plus, minus};
    spec.weights = rosy::field::LaplaceWeights::Cotan;
    rosy::field::RosyField field = rosy::field::buildField(frames, spec).field;
    FieldEditDesc near;
    near.op = FieldEditDesc::Op::CancelNear;
    near.p = plus.position;
    near.q = minus.position;
    near.loc = rosy::FileLoc{"s.yaml", 5, 7};
    std::vector<AppliedEdit> done = applyFieldEdits(frames, field, {near});
    ASSERT_EQ(done.size(), 1u);
    EXPECT_EQ(done[0].before.size(), 2u);
    EXPECT_TRUE(done[0].after.empty());
    FieldEditDesc again;
    again.a = 0;
    again.b = 1;
    again.loc = rosy::FileLoc{"s.yaml", 6, 7};
    try {
        applyFieldEdits(frames, field, {again});
        ADD_FAILURE() << "no error for a cancel on a field without singularities";
    } catch (const rosy::InputError &e) {
        EXPECT_TRUE(startsWith(e.what(), "s.yaml:6:7: error: singularity #0 does not exist")) << e.what();
    }
}

// ---- style: presets and inline overrides ---------------------------------------

namespace {

/// Writes a preset file into the scene folder (so a path preset resolves).
fs::path writePreset(const std::string &name, const std::string &text) {
    fs::path p = sceneDir() / name;
    std::ofstream(p) << text;
    return p;
}

} // namespace

TEST(StylePresets, EachShippedPresetParsesWithADescription) {
    std::vector<StylePreset> presets = listStylePresets();
    std::vector<std::string> names;
    for (const StylePreset &p : presets) {
        names.push_back(p.name);
        EXPECT_FALSE(p.description.empty()) << p.name;
        EXPECT_NO_THROW(loadStylePreset(p.path)) << p.name;
    }
    for (const char *want : {"engraving", "fine-pen", "sketch"})
        EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
}

TEST(StylePresets, FinePenIsTheBuiltInDefault) {
    // The brief defines fine-pen as the Style defaults written out.
    for (const StylePreset &p : listStylePresets()) {
        if (p.name != "fine-pen") continue;
        rosy::styles::Style s = loadStylePreset(p.path), d;
        EXPECT_EQ(s.hatch.strokeWidthPx, d.hatch.strokeWidthPx);
        EXPECT_EQ(s.hatch.crossDensity, d.hatch.crossDensity);
        EXPECT_EQ(s.contour.widthPx, d.contour.widthPx);
        EXPECT_EQ(s.ambient, d.ambient);
        return;
    }
    FAIL() << "fine-pen preset not found";
}

TEST(ParseScene, StylePresetValuesReachTheScene) {
    SceneDesc d = parseScene("mesh: thing.off\nstyle: {preset: engraving}\n", scenePath());
    ASSERT_TRUE(d.style.preset.has_value());
    EXPECT_EQ(d.style.preset->value, "engraving");
    EXPECT_EQ(fs::path(d.style.presetPath).filename(), "engraving.yaml");
    // Values written in styles/presets/engraving.yaml.
    EXPECT_EQ(d.style.style.hatch.strokeWidthPx, 2.4);
    EXPECT_EQ(d.style.style.hatch.crossDensity, 0.78);
    EXPECT_EQ(d.style.style.hatch.minLengthPx, 40.0);
    EXPECT_EQ(d.style.setAt.at("hatch.stroke_width_px").path, d.style.presetPath);
}

TEST(ParseScene, InlineStyleOverridesWinOverThePreset) {
    // The override comes before the preset in the file: order must not matter.
    SceneDesc d = parseScene("mesh: thing.off\n"
                             "style:\n"
                             "  hatch: {stroke_width_px: 0.7, jitter_px: 2}\n"
                             "  preset: engraving\n"
                             "  seed: 42\n"
                             "  contour: {hidden: true}\n",
                             scenePath());
    EXPECT_EQ(d.style.style.hatch.strokeWidthPx, 0.7);
    EXPECT_EQ(d.style.style.hatch.jitterPx, 2.0);
    EXPECT_EQ(d.style.style.hatch.crossDensity, 0.78); // still the preset's
    EXPECT_EQ(d.style.style.seed, 42u);
    EXPECT_TRUE(d.style.style.contour.hidden);
    rosy::FileLoc w = d.style.setAt.at("hatch.stroke_width_px");
    EXPECT_EQ(w.path, scenePath());
    EXPECT_EQ(w.line, 3);
    EXPECT_EQ(w.col, 28);
}

TEST(ParseScene, StylePresetByPathResolvesAgainstTheSceneFolder) {
    writePreset("mine.yaml", "description: test preset\nhatch: {taper: 0.4}\n");
    SceneDesc d = parseScene("mesh: thing.off\nstyle: {preset: mine.yaml, ambient: 0.5}\n", scenePath());
    EXPECT_EQ(d.style.style.hatch.taper, 0.4);
    EXPECT_EQ(d.style.style.ambient, 0.5);
}

TEST(ParseScene, UnknownStylePresetListsThePresets) {
    std::string e = errorOf("mesh: thing.off\nstyle: {preset: engravng}\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:17: error: unknown style preset 'engravng'")) << e;
    EXPECT_TRUE(contains(e, "did you mean 'engraving'?")) << e;
    EXPECT_TRUE(contains(e, "sketch")) << e;
    std::string far = errorOf("mesh: thing.off\nstyle: {preset: watercolour}\n");
    EXPECT_TRUE(contains(far, "fine-pen")) << far;
}

TEST(ParseScene, UnknownStyleKeySuggestsTheNearestOne) {
    std::string e = errorOf("mesh: thing.off\nstyle:\n  hatch:\n    stroke_widht_px: 2\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":4:5: error: unknown key 'stroke_widht_px' in style.hatch")) << e;
    EXPECT_TRUE(contains(e, "did you mean 'stroke_width_px'?")) << e;
    std::string top = errorOf("mesh: thing.off\nstyle: {presett: sketch}\n");
    EXPECT_TRUE(startsWith(top, scenePath() + ":2:9: error: unknown key 'presett' in style")) << top;
    EXPECT_TRUE(contains(top, "did you mean 'preset'?")) << top;
}

TEST(ParseScene, OutOfRangeStyleValuesPointAtTheValue) {
    std::string w = errorOf("mesh: thing.off\nstyle: {hatch: {stroke_width_px: -1}}\n");
    EXPECT_TRUE(startsWith(w, scenePath() + ":2:34: error: style.hatch.stroke_width_px must be in")) << w;
    std::string dens = errorOf("mesh: thing.off\nstyle:\n  hatch:\n    cross_density: 1.5\n");
    EXPECT_TRUE(startsWith(dens, scenePath() + ":4:20: error: style.hatch.cross_density must be in [0, 1]")) << dens;
    std::string seed = errorOf("mesh: thing.off\nstyle: {seed: -3}\n");
    EXPECT_TRUE(startsWith(seed, scenePath() + ":2:15: error: style.seed must be a whole number")) << seed;
    std::string group = errorOf("mesh: thing.off\nstyle: {contour: 3}\n");
    EXPECT_TRUE(startsWith(group, scenePath() + ":2:18: error: style.contour must be a map")) << group;
}

TEST(ParseScene, InconsistentSpacingsAreAnError) {
    std::string e = errorOf("mesh: thing.off\nstyle: {hatch: {min_spacing_px: 8, max_spacing_px: 4}}\n");
    EXPECT_TRUE(contains(e, "hatch.max_spacing_px (4) is below hatch.min_spacing_px (8)")) << e;
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:")) << e;
}

TEST(ParseScene, BadPresetFileErrorsPointIntoThePresetFile) {
    fs::path bad = writePreset("bad-preset.yaml", "description: broken\nhatch:\n  taper: 0.9\n");
    std::string e = errorOf("mesh: thing.off\nstyle: {preset: bad-preset.yaml}\n");
    EXPECT_TRUE(startsWith(e, bad.lexically_normal().string() + ":3:10: error: hatch.taper must be in [0, 0.5]"))
        << e;
    writePreset("nodesc.yaml", "ambient: 0.2\n");
    std::string nd = errorOf("mesh: thing.off\nstyle: {preset: nodesc.yaml}\n");
    EXPECT_TRUE(contains(nd, "has no description")) << nd;
    std::string missing = errorOf("mesh: thing.off\nstyle: {preset: ./nope.yaml}\n");
    EXPECT_TRUE(startsWith(missing, scenePath() + ":2:17: error: style preset file")) << missing;
}

TEST(StyleKeys, CoverEveryDocumentedGroup) {
    std::vector<std::string> keys = styleKeys();
    // Style has 5 top-level values, HatchStyle 14 settable fields (the lines they follow,
    // the quad edge and 12 of the drawing), ContourStyle 6, PageStyle 8 (style.h: size,
    // margin, pen width and the print mode's px_mm and three lengths in mm).
    EXPECT_EQ(keys.size(), 5u + 14u + 6u + 8u);
    std::string readme;
    {
        std::ifstream in(std::string(ROSY_SOURCE_DIR) + "/scenes/README.md");
        readme.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (const std::string &k : keys) EXPECT_TRUE(contains(readme, "`" + k + "`")) << k << " not documented";
}

// Every example scene the project ships must load as it is: a renamed key or a
// moved mesh would otherwise only show when a user tries it.
TEST(ExampleScenes, EveryShippedSceneParsesAndBuilds) {
    const fs::path dir = fs::path(ROSY_SOURCE_DIR) / "scenes";
    std::vector<fs::path> scenes;
    for (const auto &entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".yaml") scenes.push_back(entry.path());
    std::sort(scenes.begin(), scenes.end());
    ASSERT_GE(scenes.size(), 5u);
    for (const fs::path &p : scenes) {
        SCOPED_TRACE(p.string());
        SceneDesc desc = parseSceneFile(p.string());
        Scene scene = buildScene(desc);
        EXPECT_GT(scene.mesh.nFaces(), 0);
        EXPECT_FALSE(scene.output.empty());
    }
}

// --- --set overrides ----------------------------------------------------------

namespace {

/// The message of the InputError parseScene throws for `text` with `overrides`.
std::string overrideErrorOf(const std::string &text, const std::vector<std::string> &overrides) {
    try {
        parseScene(text, scenePath(), overrides);
    } catch (const rosy::InputError &e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return {};
}

const char *kPlainScene = "mesh: {primitive: icosphere}\n"
                          "camera: {resolution: [64, 48]}\n"
                          "lights: [{type: directional, direction: [1, 1, 1]}, {type: point, position: [0, 3, 0]}]\n";

} // namespace

TEST(SceneOverrides, ReplaceValuesAndAreLocatedAtTheOverride) {
    SceneDesc d = parseScene(kPlainScene, scenePath(),
                             {"field.symmetry=2", "camera.resolution=[512, 256]", "lights.1.intensity=0.25"});
    EXPECT_EQ(d.field.spec.nSym, 2);
    EXPECT_TRUE(d.field.given); // the override created the field block
    EXPECT_EQ(d.field.symmetryLoc.path, "--set field.symmetry=2");
    EXPECT_EQ(d.field.symmetryLoc.line, 0);
    EXPECT_EQ(d.camera.resolution.value[0], 512);
    EXPECT_EQ(d.camera.resolution.value[1], 256);
    EXPECT_EQ(d.camera.resolution.loc.path, "--set camera.resolution=[512, 256]");
    ASSERT_EQ(d.lights.size(), 2u);
    EXPECT_EQ(d.lights[1].light.intensity, 0.25);
    EXPECT_EQ(d.lights[0].light.intensity, 1.0); // the other light keeps its default
}

TEST(SceneOverrides, ApplyInOrderSoTheLastWins) {
    SceneDesc d = parseScene(kPlainScene, scenePath(), {"field.symmetry=3", "field.symmetry=6"});
    EXPECT_EQ(d.field.spec.nSym, 6);
}

TEST(SceneOverrides, MapValuesAndPresetsWork) {
    SceneDesc d = parseScene(kPlainScene, scenePath(), {"style={preset: engraving}", "mesh.subdivisions=1"});
    ASSERT_TRUE(d.style.preset.has_value());
    EXPECT_EQ(d.style.preset->value, "engraving");
    EXPECT_EQ(d.mesh.params.at("subdivisions").value, 1.0);
    EXPECT_EQ(d.mesh.params.at("subdivisions").loc.path, "--set mesh.subdivisions=1");
}

TEST(SceneOverrides, ValidationErrorsNameTheOverride) {
    // Each class of error, raised by a value the override brought.
    const std::string range = overrideErrorOf(kPlainScene, {"field.symmetry=0"});
    EXPECT_TRUE(startsWith(range, "--set field.symmetry=0: error: field.symmetry must be in [1, 12]")) << range;
    const std::string res = overrideErrorOf(kPlainScene, {"camera.resolution=[0, 64]"});
    EXPECT_TRUE(startsWith(res, "--set camera.resolution=[0, 64]: error: camera.resolution width must be in [1, 16384]"))
        << res;
    const std::string type = overrideErrorOf(kPlainScene, {"camera.fov=wide"});
    EXPECT_TRUE(startsWith(type, "--set camera.fov=wide: error: camera.fov (degrees) must be a number")) << type;
    const std::string key = overrideErrorOf(kPlainScene, {"feild.symmetry=2"});
    EXPECT_TRUE(startsWith(key, "--set feild.symmetry=2: error: unknown key 'feild' in the scene")) << key;
    EXPECT_TRUE(contains(key, "did you mean 'field'?")) << key;
    const std::string nested = overrideErrorOf(kPlainScene, {"camera.fvo=30"});
    EXPECT_TRUE(startsWith(nested, "--set camera.fvo=30: error: unknown key 'fvo' in camera")) << nested;
    const std::string prob = overrideErrorOf(kPlainScene, {"style.hatch.cross_density=1.5"});
    EXPECT_TRUE(startsWith(prob, "--set style.hatch.cross_density=1.5: error: style.hatch.cross_density must be in [0, 1]"))
        << prob;
}

TEST(SceneOverrides, MalformedOverridesAreInputErrors) {
    const std::string noEq = overrideErrorOf(kPlainScene, {"field.symmetry"});
    EXPECT_TRUE(startsWith(noEq, "--set field.symmetry: error: an override needs KEY=VALUE")) << noEq;
    const std::string empty = overrideErrorOf(kPlainScene, {"field..symmetry=2"});
    EXPECT_TRUE(startsWith(empty, "--set field..symmetry=2: error: 'field..symmetry' has an empty key")) << empty;
    const std::string yaml = overrideErrorOf(kPlainScene, {"camera.resolution=[1, "});
    EXPECT_TRUE(startsWith(yaml, "--set camera.resolution=[1, : error: the value is not valid YAML")) << yaml;
    const std::string none = overrideErrorOf(kPlainScene, {"field.symmetry="});
    EXPECT_TRUE(startsWith(none, "--set field.symmetry=: error: the value of 'field.symmetry' is empty")) << none;
    const std::string scalar = overrideErrorOf("mesh: thing.off\n", {"mesh.primitive=torus"});
    EXPECT_TRUE(startsWith(scalar, "--set mesh.primitive=torus: error: 'mesh' is 'thing.off', not a map")) << scalar;
    const std::string index = overrideErrorOf(kPlainScene, {"lights.2.intensity=1"});
    EXPECT_TRUE(startsWith(index, "--set lights.2.intensity=1: error: 'lights' is a list of 2 entries")) << index;
}

TEST(SceneOverrides, FileErrorsKeepTheirFileLocation) {
    // An override elsewhere does not move the location of an error in the file.
    const std::string msg = overrideErrorOf("mesh: thing.off\ncamera: {fov: 500}\n", {"field.symmetry=2"});
    EXPECT_TRUE(startsWith(msg, scenePath() + ":2:15: error: camera.fov")) << msg;
}

// --- picture, field weights and global smoothing -----------------------------

TEST(ParseScene, PictureBlock) {
    SceneDesc d = parseScene("mesh: thing.off\npicture: {kind: field, separatrices: true}\n", scenePath());
    EXPECT_EQ(d.picture.kind.value, PictureDesc::Kind::Field);
    EXPECT_TRUE(d.picture.separatrices.value);
    SceneDesc plain = parseScene("mesh: thing.off\n", scenePath());
    EXPECT_EQ(plain.picture.kind.value, PictureDesc::Kind::Hatching);
    const std::string kind = errorOf("mesh: thing.off\npicture: {kind: feild}\n");
    EXPECT_TRUE(startsWith(kind, scenePath() + ":2:17: error: unknown picture kind 'feild'")) << kind;
    EXPECT_TRUE(contains(kind, "did you mean 'field'?")) << kind;
    const std::string seps = errorOf("mesh: thing.off\npicture: {separatrices: true}\n");
    EXPECT_TRUE(startsWith(seps, scenePath() + ":2:25: error: picture.separatrices needs picture.kind: field")) << seps;
}

TEST(ParseSceneField, WeightsAndGlobalSmoothing) {
    SceneDesc d = parseScene("mesh: thing.off\nfield:\n  weights: cotan\n  global_smoothing: {iterations: 30, "
                             "strength: 0.25}\n",
                             scenePath());
    EXPECT_EQ(d.field.spec.weights, rosy::field::LaplaceWeights::Cotan);
    EXPECT_EQ(d.field.spec.globalSmoothingIterations, 30);
    EXPECT_EQ(d.field.spec.globalSmoothingStrength, 0.25);
    const std::string w = errorOf("mesh: thing.off\nfield: {weights: cotangent}\n");
    EXPECT_TRUE(startsWith(w, scenePath() + ":2:18: error: unknown weights 'cotangent'")) << w;
    const std::string s = errorOf("mesh: thing.off\nfield: {global_smoothing: {strength: 2}}\n");
    EXPECT_TRUE(startsWith(s, scenePath() + ":2:38: error: field.global_smoothing.strength must be in")) << s;
}

// --- mesh.transform, output lists, threads, seed ----------------------------------

namespace {

/// Axis-aligned bounding box of the built scene's mesh.
std::pair<Vec3, Vec3> builtBounds(const std::string &text) {
    Scene scene = buildScene(parseScene(text, scenePath()));
    Vec3 lo, hi;
    scene.mesh.bounds(lo, hi);
    return {lo, hi};
}

void expectNear(const Vec3 &a, const Vec3 &b, double tol, const char *what) {
    EXPECT_LT((a - b).norm(), tol) << what << ": [" << a.transpose() << "] vs [" << b.transpose() << "]";
}

} // namespace

TEST(MeshTransform, ParsesEveryFormAndDefaultsToIdentity) {
    SceneDesc plain = parseScene("mesh: {primitive: icosphere}\n", scenePath());
    EXPECT_FALSE(plain.mesh.transform.given);
    EXPECT_TRUE(plain.mesh.transform.linear().isIdentity());

    SceneDesc d = parseScene("mesh: {file: thing.off, transform: {translate: [1, 2, 3], scale: 2}}\n", scenePath());
    ASSERT_TRUE(d.mesh.file);
    EXPECT_EQ(fs::path(d.mesh.file->value).filename(), "thing.off");
    EXPECT_TRUE(d.mesh.transform.given);
    // p' = 2 p + [1, 2, 3]
    expectNear(d.mesh.transform.apply(Vec3(1, 0, -1)), Vec3(3, 2, 1), 1e-12, "uniform scale + translate");

    SceneDesc e = parseScene("mesh:\n"
                             "  primitive: grid\n"
                             "  transform: {scale: [1, 2, 3], rotate: [0, 0, 90]}\n",
                             scenePath());
    // scale first: (1, 1, 1) -> (1, 2, 3); then 90 deg about Z (counter-clockwise): (x, y) -> (-y, x).
    expectNear(e.mesh.transform.apply(Vec3(1, 1, 1)), Vec3(-2, 1, 3), 1e-12, "scale then rotate");
    EXPECT_EQ(e.mesh.transform.scale.loc.line, 3);
}

// A grid ([-1, 1]^2 in z = 0) scaled by [1, 2, 1] spans x in [-1, 1], y in [-2, 2].
// Rotating X by 90 deg maps (x, y, 0) to (x, 0, y); then Y by 90 deg maps (x, 0, z) to
// (z, 0, -x): x in [-2, 2], y = 0, z in [-1, 1]; translating by [1, 2, 3] gives the box
// below. The opposite order (Y then X) would give x = 0, y in [-1, 1], z in [-2, 2].
TEST(MeshTransform, RotatedGridBoundingBoxMatchesTheHandComputedOne) {
    const auto [lo, hi] = builtBounds(
        "mesh: {primitive: grid, n: 2, transform: {scale: [1, 2, 1], rotate: [90, 90, 0], translate: [1, 2, 3]}}\n");
    expectNear(lo, Vec3(-1, 2, 2), 1e-9, "lo");
    expectNear(hi, Vec3(3, 2, 4), 1e-9, "hi");
}

// The cube [-1, 1]^3 turned 45 deg about Z: its corners reach sqrt(2) along x and y.
TEST(MeshTransform, CubeTurnedAboutZReachesTheDiagonal) {
    const auto [lo, hi] = builtBounds("mesh: {primitive: cube, n: 2, transform: {rotate: [0, 0, 45]}}\n");
    const double r = std::sqrt(2.0);
    expectNear(lo, Vec3(-r, -r, -1), 1e-9, "lo");
    expectNear(hi, Vec3(r, r, 1), 1e-9, "hi");
}

// Automatic framing sees the transformed mesh: a uniformly scaled and translated
// sphere lands on exactly the same pixels as the original (the camera moves with it).
TEST(MeshTransform, AutoFramingFollowsAScaledTranslatedMesh) {
    const std::string base = "mesh: {primitive: icosphere, subdivisions: 2";
    const std::string cam = "camera: {resolution: [200, 120], direction: [1, 0.5, 2]}\n";
    Scene a = buildScene(parseScene(base + "}\n" + cam, scenePath()));
    Scene b = buildScene(
        parseScene(base + ", transform: {scale: 2.5, translate: [30, -10, 20]}}\n" + cam, scenePath()));
    ASSERT_EQ(a.mesh.nVertices(), b.mesh.nVertices());
    expectNear(b.mesh.position(7), 2.5 * a.mesh.position(7) + Vec3(30, -10, 20), 1e-9, "vertex 7");
    double worst = 0;
    for (int v = 0; v < a.mesh.nVertices(); ++v)
        worst = std::max(worst, (a.camera.project(a.mesh.position(v)) - b.camera.project(b.mesh.position(v))).norm());
    EXPECT_LT(worst, 1e-6) << "pixels";
    // And a camera that ignored the transform would not see the moved sphere centred.
    const Eigen::Vector2d centre = a.camera.project(Vec3(30, -10, 20));
    EXPECT_GT((centre - Eigen::Vector2d(100, 60)).norm(), 50.0);
}

TEST(MeshTransform, BadValuesNameTheirPlace) {
    const std::string head = "mesh:\n  primitive: grid\n  transform:\n";
    std::string e = errorOf(head + "    scale: 0\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":4:12: error: mesh.transform.scale must be positive, got 0")) << e;
    e = errorOf(head + "    scale: [1, -2, 1]\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":4:16: error: mesh.transform.scale[1] must be positive, got -2")) << e;
    e = errorOf(head + "    rotate: [0, 90]\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":4:13: error: mesh.transform.rotate")) << e;
    e = errorOf(head + "    scael: 2\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":4:5: error: unknown key 'scael'")) << e;
    EXPECT_TRUE(contains(e, "did you mean 'scale'?")) << e;
    e = errorOf("mesh: {file: thing.off, primitive: grid}\n");
    EXPECT_TRUE(contains(e, "both 'file' and 'primitive'")) << e;
}

TEST(SceneOutputs, OnePathOrAList) {
    SceneDesc one = parseScene("mesh: thing.off\noutput: a.tif\n", scenePath());
    ASSERT_EQ(one.outputs.size(), 1u);
    EXPECT_EQ(one.output.value, "a.tif");
    SceneDesc many = parseScene("mesh: thing.off\noutput: [a.png, b.svg, c.exr, d.jpg]\n", scenePath());
    ASSERT_EQ(many.outputs.size(), 4u);
    EXPECT_EQ(many.outputs[1].value, "b.svg");
    EXPECT_EQ(many.outputs[3].loc.line, 2);
    EXPECT_EQ(many.outputs[3].loc.col, 31); // "output: [a.png, b.svg, c.exr, " is 30 characters
    EXPECT_EQ(many.output.value, "a.png");
    SceneDesc none = parseScene("mesh: thing.off\n", scenePath());
    ASSERT_EQ(none.outputs.size(), 1u);
    EXPECT_EQ(none.outputs[0].value, "s.png");
}

TEST(SceneOutputs, BadListsNameTheEntry) {
    std::string e = errorOf("mesh: thing.off\noutput: [a.png, a.png]\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:17: error: output 'a.png' is listed twice")) << e;
    e = errorOf("mesh: thing.off\noutput: [a.png, b.gif]\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:17: error: output 'b.gif' has an unsupported extension")) << e;
    e = errorOf("mesh: thing.off\noutput: []\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:9: error: output must list 1 to 16 paths")) << e;
    e = errorOf("mesh: thing.off\noutput: {a: b.png}\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:9: error: output must be a path or a list")) << e;
}

TEST(SceneThreadsAndSeed, ParseWithRanges) {
    SceneDesc d = parseScene("mesh: thing.off\nthreads: 3\nseed: 4294967295\n", scenePath());
    EXPECT_EQ(d.threads.value, 3);
    ASSERT_TRUE(d.seed);
    EXPECT_EQ(d.style.style.seed, 4294967295u);
    SceneDesc none = parseScene("mesh: thing.off\n", scenePath());
    EXPECT_EQ(none.threads.value, 0);
    EXPECT_FALSE(none.seed);
    EXPECT_EQ(none.style.style.seed, 1u);

    std::string e = errorOf("mesh: thing.off\nthreads: -1\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:10: error: threads must be in [0, 4096], got -1")) << e;
    e = errorOf("mesh: thing.off\nthreads: 5000\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:10: error: threads must be in [0, 4096]")) << e;
    e = errorOf("mesh: thing.off\nseed: -3\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:7: error: seed must be in [0, 4294967295], got -3")) << e;
    e = errorOf("mesh: thing.off\nseed: 4294967296\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:7: error: seed must be in [0, 4294967295]")) << e;
    e = errorOf("mesh: thing.off\nseed: 1.5\n");
    EXPECT_TRUE(startsWith(e, scenePath() + ":2:7: error: seed must be a whole number")) << e;
}

// Precedence: the scene's own style.seed > top-level seed > a preset's seed > default 1.
TEST(SceneThreadsAndSeed, TopLevelSeedSetsTheStyleSeedUnlessTheStyleGivesOne) {
    writePreset("seeded.yaml", "description: a preset with its own seed\nseed: 9\n");
    auto seedOf = [](const std::string &text, const std::vector<std::string> &overrides = {}) {
        return parseScene(text, scenePath(), overrides).style.style.seed;
    };
    EXPECT_EQ(seedOf("mesh: thing.off\nseed: 42\n"), 42u);
    EXPECT_EQ(seedOf("mesh: thing.off\nseed: 42\nstyle: {seed: 5}\n"), 5u);
    EXPECT_EQ(seedOf("mesh: thing.off\nstyle: {seed: 5}\nseed: 42\n"), 5u); // order does not matter
    EXPECT_EQ(seedOf("mesh: thing.off\nstyle: {preset: seeded.yaml}\n"), 9u);
    EXPECT_EQ(seedOf("mesh: thing.off\nseed: 42\nstyle: {preset: seeded.yaml}\n"), 42u);
    EXPECT_EQ(seedOf("mesh: thing.off\nseed: 42\n", {"seed=7"}), 7u);
    EXPECT_EQ(seedOf("mesh: thing.off\nseed: 42\n", {"style.seed=8"}), 8u);
    SceneDesc d = parseScene("mesh: thing.off\n\nseed: 42\n", scenePath());
    EXPECT_EQ(d.style.setAt.at("seed").line, 3);
}

TEST(ParseScene, AmbientOcclusionIsOffByDefaultAndItsRadiusFollowsTheMeshSize) {
    const Scene plain = buildScene(parseScene("mesh: {primitive: icosphere}\n", scenePath()));
    EXPECT_EQ(plain.shading.aoSamples, 0);

    const Scene defaults =
        buildScene(parseScene("mesh: {primitive: icosphere}\nambient_occlusion: true\nseed: 9\n", scenePath()));
    rosy::field::Vec3 lo, hi;
    defaults.mesh.bounds(lo, hi);
    EXPECT_EQ(defaults.shading.aoSamples, 16);
    EXPECT_NEAR(defaults.shading.aoRadius, 0.1 * (hi - lo).norm(), 1e-12);
    EXPECT_EQ(defaults.shading.aoSeed, 9u);

    // The same scene scaled by 1000 gets a 1000 times longer radius: the drawing
    // does not depend on the units.
    const std::string text = "mesh: {primitive: icosphere, transform: {scale: SCALE}}\n"
                             "ambient_occlusion: {samples: 8, radius: 0.5}\n";
    auto with = [&](const std::string &scale) {
        std::string t = text;
        t.replace(t.find("SCALE"), 5, scale);
        return buildScene(parseScene(t, scenePath()));
    };
    const Scene small = with("1"), large = with("1000");
    EXPECT_EQ(small.shading.aoSamples, 8);
    small.mesh.bounds(lo, hi);
    EXPECT_NEAR(small.shading.aoRadius, 0.5 * (hi - lo).norm(), 1e-12);
    EXPECT_NEAR(large.shading.aoRadius / small.shading.aoRadius, 1000.0, 1e-9);
    EXPECT_FALSE(parseScene("mesh: {primitive: icosphere}\nambient_occlusion: false\n", scenePath())
                     .ambientOcclusion.enabled);
}

// The memory check's estimate (README, "Limits") holds what whole renders at 1024² of
// large meshes were measured to peak at (`/usr/bin/time -v rosyhatch render`, maximum
// resident set size, 2026-12-05): a 270k-face scan 302 MB, the CGAL elephant
// subdivided to 5,691,392 faces 4.89 GB, and to 7,963,762 faces with noise and needles
// 6.50 GB. At 600 bytes a face (until then) the two large ones were estimated at 3.7
// and 5.0 GB, and a machine with 6 GB left would have started the second and run out.
TEST(RenderMemory, EstimateHoldsTheMeasuredPeaksOfLargeMeshes) {
    const double pixels = 1024.0 * 1024.0, spacing = 3.2; // PNG renders with the default style
    EXPECT_GE(rosy::scenes::renderMemoryEstimate(pixels, 270464, spacing, false), 302264ull * 1024);
    EXPECT_GE(rosy::scenes::renderMemoryEstimate(pixels, 5691392, spacing, false), 4887588ull * 1024);
    EXPECT_GE(rosy::scenes::renderMemoryEstimate(pixels, 7963762, spacing, false), 6496920ull * 1024);
    // scans judged noisy (field/scan_noise.h: a second field on a smoothed copy), scan-like
    // elephants from tools/make_scan_mesh.py at noise 0.3, slivers 0.3 (docs/hatching.md)
    EXPECT_GE(rosy::scenes::renderMemoryEstimate(pixels, 2276370, spacing, false), 2796688ull * 1024);
    EXPECT_GE(rosy::scenes::renderMemoryEstimate(pixels, 9105818, spacing, false), 10327848ull * 1024);
    // and does not refuse what fits twice over
    EXPECT_LE(rosy::scenes::renderMemoryEstimate(pixels, 7963762, spacing, false), 2 * 6496920ull * 1024);
}
