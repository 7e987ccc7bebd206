// Issue 15's quality thresholds, on every shipped example scene that draws hatching
// (scenes/*.yaml; the field pictures of the paper's figures have no strokes): each
// is rendered at its own 1024² exactly as `rosyhatch render` does (scenes::renderScene,
// the scene's field edits included), its EXR written and measured by inspect from
// the file's channels alone, and its stroke list by the report's measures.
// The thresholds are the issue's, not numbers read off a render:
//   seam_fraction <= 0.002, stub_fraction <= 0.05, alignment median < 5° and
//   p90 < 15°, tone error < 0.12, no spacing violation, no ink outside the
//   silhouette, no stroke near a singularity.
// One CTest test per scene (Quality/ExampleScene.MeetsTheThresholds/<name>); every
// scene is held to every threshold (docs/hatching.md has the history of the last
// scenes that were not, armadillo and three-peaks, until the hole pass reached
// depth edges).

#include "renderer/illustration.h"
#include "renderer/evaluation/inspect.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace rosy;
namespace fs = std::filesystem;

namespace {

const fs::path kScenes = fs::path(ROSY_SOURCE_DIR) / "scenes";

std::vector<std::string> exampleScenes() {
    std::vector<std::string> names;
    for (const auto &entry : fs::directory_iterator(kScenes))
        if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

struct Measured {
    renderer::InspectResult inspect;
    renderer::HatchReport hatch;
    int width = 0, height = 0;
};

/// Renders a scene exactly as `rosyhatch render` does (N replaced when nSym > 0),
/// writes its EXR and measures it from the file.
Measured renderAndMeasure(const std::string &name, int nSym = 0) {
    const scenes::SceneDesc desc = scenes::parseSceneFile((kScenes / (name + ".yaml")).string());
    scenes::PipelineOptions pipeline;
    pipeline.nSym = nSym;
    // The scene's edits name singularities of the scene's own field by id; a field
    // rebuilt with another N has other singularities, so it is drawn unedited.
    pipeline.applyEdits = nSym == 0;
    const scenes::RenderResult result = scenes::renderScene(desc, pipeline);
    const renderer::Illustration &il = *result.illustration;
    const scenes::Scene &scene = *result.loaded.scene;

    const std::string exr = testing::TempDir() + "/quality_" + name + ".exr";
    renderer::writeImage(renderer::illustrationExr(il), exr,
                         renderer::inkExrWriteOptions(renderer::nominalHatchSpacingPx(scene.style.hatch),
                                                      scene.style.hatch.crossDensity));
    const renderer::InkMaps maps = renderer::readInkMaps(exr);
    fs::remove(exr);
    renderer::InspectOptions options;
    options.keepSeamMask = true;
    Measured m{renderer::inspectInk(maps, options), il.hatch, il.gbuffer.width, il.gbuffer.height};
    // ROSY_QUALITY_DIR=FOLDER keeps each scene's picture and its seam map there.
    if (const char *dir = std::getenv("ROSY_QUALITY_DIR")) {
        // Appended, not "-" + std::to_string(): GCC 12's -Wrestrict false positive (PR 105651).
        std::string stem = name;
        if (nSym > 0) {
            stem += '-';
            stem += std::to_string(nSym);
            stem += "rosy";
        }
        renderer::writeImage(il.composite, (fs::path(dir) / (stem + ".png")).string());
        renderer::writeImage(renderer::seamPicture(maps, m.inspect), (fs::path(dir) / (stem + ".seams.png")).string());
    }
    return m;
}

bool skipUnlessHatching(const std::string &name, std::string &why) {
    const scenes::SceneDesc desc = scenes::parseSceneFile((kScenes / (name + ".yaml")).string());
    if (desc.picture.kind.value == scenes::PictureDesc::Kind::Field) {
        why = name + " draws the field itself: no strokes to measure";
        return true;
    }
    if (desc.mesh.file && !fs::exists(desc.mesh.file->value)) {
        why = desc.mesh.file->value + " missing (tools/setup.sh extracts it)";
        return true;
    }
    return false;
}

class ExampleScene : public testing::TestWithParam<std::string> {};

TEST_P(ExampleScene, MeetsTheThresholds) {
    std::string why;
    if (skipUnlessHatching(GetParam(), why)) GTEST_SKIP() << why;
#ifdef ROSY_SANITIZED
    // Thresholds are about the picture, not memory: the sanitized suite keeps one
    // scene (about 10x slower there) to run the whole path under ASan + UBSan.
    if (GetParam() != "bunny") GTEST_SKIP() << "quality thresholds run in the Release suite";
#endif
    const Measured m = renderAndMeasure(GetParam());
    const renderer::InspectResult &r = m.inspect;
    ASSERT_EQ(m.width, 1024);
    ASSERT_EQ(m.height, 1024);

    EXPECT_GT(r.alignmentSamples, 10000); // enough ink to measure at all
    EXPECT_GT(m.hatch.strokes, 100);
    EXPECT_LE(r.seamFraction, 0.002) << "cross pixels " << r.crossPixels << ", seam pixels " << r.seamPixels;
    EXPECT_LE(m.hatch.stubFraction, 0.05) << m.hatch.stubs << " stubs of " << m.hatch.strokes;
    EXPECT_LT(r.alignmentMedianDeg, 5.0);
    EXPECT_LT(r.alignmentP90Deg, 15.0);
    EXPECT_LT(r.toneMae, 0.12);
    EXPECT_EQ(r.inkOutsideSilhouettePx, 0);
    EXPECT_EQ(m.hatch.minSpacingViolations, 0);
    EXPECT_EQ(m.hatch.strokesNearSingularities, 0);
    std::printf("%s: seam %.4f stub %.4f align %.2f/%.2f tone %.4f overdense %.4f squeezed %.4f incoherent %.4f "
                "strokes %d\n",
                GetParam().c_str(), r.seamFraction, m.hatch.stubFraction, r.alignmentMedianDeg, r.alignmentP90Deg,
                r.toneMae, m.hatch.crossOverdenseFraction, m.hatch.squeezedFraction, m.hatch.incoherentFraction,
                m.hatch.strokes);
}

// The paper's claim behind Figure 1 (a)-(b), on the figures: hatching along the
// 4-RoSy field has no more cracks than along the 2-RoSy field of the same tensor
// (`rosyhatch compare --symmetry 2,4` prints both panels' seam_fraction).
TEST(Quality, Fig1FourRosyPanelHasNoMoreSeamsThanTwoRosy) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "quality figures run in the Release suite";
#endif
    for (const std::string name : {"fig1-symmetry", "fig1-editing"}) {
        std::string why;
        if (skipUnlessHatching(name, why)) GTEST_SKIP() << why;
        const Measured two = renderAndMeasure(name, 2), four = renderAndMeasure(name, 4);
        EXPECT_LE(four.inspect.seamFraction, two.inspect.seamFraction) << name;
        EXPECT_EQ(four.hatch.strokesNearSingularities, 0) << name;
        std::printf("%s: seam_fraction 2-RoSy %.4f, 4-RoSy %.4f\n", name.c_str(), two.inspect.seamFraction,
                    four.inspect.seamFraction);
    }
}

INSTANTIATE_TEST_SUITE_P(Quality, ExampleScene, testing::ValuesIn(exampleScenes()),
                         [](const testing::TestParamInfo<std::string> &info) {
                             std::string name = info.param;
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

} // namespace
