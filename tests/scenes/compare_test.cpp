// scenes::compareScene() (`rosyhatch compare`'s panels) and renderer::panelSheet()
// (their layout). Expected values come from the request (panel count, order,
// labels), Poincaré–Hopf and the layout rule written in panel_sheet.h.

#include "renderer/output/bitmap_font.h"
#include "renderer/output/panel_sheet.h"
#include "scenes/compare.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"
#include "core/parallel.h"
#include "field/scan_noise.h"
#include "../field/scan_like.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

using namespace rosy;

namespace {

const std::string kCompareScenePath = std::string(ROSY_SOURCE_DIR) + "/scenes/compare_test.yaml";

const char *kSmallTorus = R"(
mesh: {primitive: torus, nu: 48, nv: 24}
camera: {auto: true, resolution: [80, 60]}
)";

} // namespace

TEST(CompareScene, OnePanelPerSymmetryInOrderWithLabelsAndPictures) {
    const scenes::SceneDesc desc = scenes::parseScene(kSmallTorus, kCompareScenePath);
    scenes::CompareSpec spec;
    spec.symmetries = {2, 4, 6};
    const scenes::Comparison c = scenes::compareScene(desc, spec);
    ASSERT_EQ(c.panels.size(), 3u);
    const char *prefixes[] = {"(a) 2-RoSy: ", "(b) 4-RoSy: ", "(c) 6-RoSy: "};
    for (size_t k = 0; k < 3; ++k) {
        const scenes::ComparePanel &p = c.panels[k];
        EXPECT_TRUE(test::startsWith(p.label, prefixes[k])) << p.label;
        EXPECT_EQ(p.field.nSym, spec.symmetries[k]);
        EXPECT_EQ(p.singularities.indexNumeratorSum, 0); // Poincaré–Hopf, torus: χ = 0
        EXPECT_EQ(p.picture.width, 80);
        EXPECT_EQ(p.picture.height, 60);
        EXPECT_GE(p.seamFraction, 0.0); // measured: hatching panels
    }
    std::vector<std::string> stages;
    for (const auto &[stage, ms] : c.timingsMs) stages.push_back(stage);
    EXPECT_EQ(stages, (std::vector<std::string>{"load", "frames", "fields", "bvh", "panels"}));
}

TEST(CompareScene, EachPanelIsTheRenderOfItsSymmetry) {
    // compareScene() shares the G-buffer, tone and contours between panels and draws
    // the fields and panels side by side; each panel must still be exactly the
    // composite renderScene() draws for that N, on one thread and on several.
    const scenes::SceneDesc desc = scenes::parseScene(kSmallTorus, kCompareScenePath);
    for (int threads : {1, 2}) {
        scenes::PipelineOptions options;
        options.threads = threads;
        scenes::CompareSpec spec;
        spec.symmetries = {2, 4};
        const scenes::ThreadLimit limit(desc, threads);
        const scenes::Comparison c = scenes::compareScene(desc, spec, options);
        ASSERT_EQ(c.panels.size(), 2u);
        for (size_t k = 0; k < 2; ++k) {
            scenes::PipelineOptions one = options;
            one.nSym = spec.symmetries[k];
            const scenes::RenderResult r = scenes::renderScene(desc, one);
            ASSERT_TRUE(r.illustration.has_value());
            EXPECT_EQ(c.panels[k].picture.data, r.illustration->composite.data) << "N " << spec.symmetries[k];
            EXPECT_EQ(c.panels[k].stubFraction, r.illustration->hatch.stubFraction);
            EXPECT_EQ(c.panels[k].singularities.singularities.size(), r.field.singularities.singularities.size());
        }
    }
}

TEST(CompareScene, VariantsKeepTheirOrderAndFieldPicturesHaveNoInkFigures) {
    const scenes::SceneDesc desc = scenes::parseScene(kSmallTorus, kCompareScenePath);
    scenes::CompareSpec spec;
    using V = scenes::CompareSpec::Variant;
    spec.variants = {V::Smoothed, V::Original};
    spec.smoothIterations = 3;
    spec.fieldPictures = true;
    const scenes::Comparison c = scenes::compareScene(desc, spec);
    ASSERT_EQ(c.panels.size(), 2u);
    EXPECT_TRUE(test::startsWith(c.panels[0].label, "(a) 4-RoSy, smoothed 3x: ")) << c.panels[0].label;
    EXPECT_TRUE(test::startsWith(c.panels[1].label, "(b) 4-RoSy: ")) << c.panels[1].label;
    for (const scenes::ComparePanel &p : c.panels) {
        EXPECT_NE(p.seamFraction, p.seamFraction); // NaN: a field picture has no ink to measure
        EXPECT_EQ(p.picture.width, 80);
    }
}

TEST(PanelSheet, LaysPanelsOutWithGapsAndInksTheLabelsUnderneath) {
    // Two 40 x 20 panels, red and blue: gap = max(4, 20 / 32) = 4, font scale
    // max(1, round(20 * 0.025 / 7)) = 1, one label line of (9 + 2) px, band 11 + 4.
    renderer::Image red(40, 20, {"R", "G", "B"}), blue(40, 20, {"R", "G", "B"});
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 40; ++x) {
            red.at(x, y, 0) = 1.0f;
            blue.at(x, y, 2) = 1.0f;
        }
    const std::array<float, 3> paper{1, 1, 1}, ink{0, 0, 0};
    const renderer::Image sheet = renderer::panelSheet({red, blue}, {"ab", "c"}, paper, ink);
    EXPECT_EQ(sheet.width, 2 * 40 + 3 * 4);
    EXPECT_EQ(sheet.height, 20 + 2 * 4 + 11 + 4);
    EXPECT_EQ(sheet.at(2, 10, 0), 1.0f); // left gap: paper
    EXPECT_EQ(sheet.at(2, 10, 2), 1.0f);
    EXPECT_EQ(sheet.at(4 + 20, 4 + 10, 0), 1.0f); // inside panel a: red
    EXPECT_EQ(sheet.at(4 + 20, 4 + 10, 2), 0.0f);
    EXPECT_EQ(sheet.at(8 + 40 + 20, 4 + 10, 0), 0.0f); // inside panel b: blue
    EXPECT_EQ(sheet.at(8 + 40 + 20, 4 + 10, 2), 1.0f);
    // Ink under each panel, within its columns only.
    auto inkIn = [&](int x0, int x1) {
        int n = 0;
        for (int y = 4 + 20; y < sheet.height; ++y)
            for (int x = x0; x < x1; ++x) n += sheet.at(x, y, 0) == 0.0f;
        return n;
    };
    EXPECT_GT(inkIn(4, 44), 0);
    EXPECT_GT(inkIn(48, 88), 0);
    EXPECT_EQ(inkIn(44, 48), 0);
    EXPECT_EQ(renderer::textWidthPx("ab", 1), 11); // 2 glyphs at a 6 px advance, no trailing gap
    EXPECT_EQ(renderer::textWidthPx("", 3), 0);
}

TEST(LoadedScene, SmoothedCopyIsBuiltOnceForConcurrentCallers) {
    const char *kEllipsoid = "mesh: {primitive: ellipsoid, subdivisions: 4, a: 1.0, b: 0.7, c: 0.5}\n"
                             "camera: {auto: true, resolution: [32, 32]}\n";
    const scenes::LoadedScene loaded = scenes::loadScene(scenes::parseScene(kEllipsoid, kCompareScenePath));
    std::vector<const field::SmoothedSurface *> seen(8, nullptr);
    parallelFor(0, int64_t(seen.size()), [&](int64_t k) { seen[size_t(k)] = loaded.smoothedCopy().get(); }, 1);
    for (const field::SmoothedSurface *s : seen) EXPECT_EQ(s, seen[0]);
    ASSERT_NE(seen[0], nullptr);
    // The copy field::smoothAtScale() makes of the scene's mesh, bit for bit.
    const field::SmoothedSurface direct = field::smoothAtScale(loaded.scene->mesh);
    EXPECT_EQ(seen[0]->mesh->positions(), direct.mesh->positions());
    EXPECT_EQ(seen[0]->radius, direct.radius);
    EXPECT_EQ(&seen[0]->frames->mesh(), seen[0]->mesh.get());
}

TEST(CompareScene, PanelsOfANoisyScanShareOneSmoothedCopy) {
#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "two fields on a scan-like mesh (~20 s under the sanitizers); the shared copy's "
                    "concurrent build is LoadedScene.SmoothedCopyIsBuiltOnceForConcurrentCallers";
#endif
    const std::string ellipsoid = "mesh: {primitive: ellipsoid, subdivisions: " +
                                  std::to_string(test::kScanEllipsoidLevel) + ", a: 1.0, b: 0.7, c: 0.5}\n" +
                                  "camera: {auto: true, resolution: [64, 48]}\n";
    const scenes::SceneDesc desc = scenes::parseScene(ellipsoid, kCompareScenePath);
    scenes::PipelineOptions options;
    options.afterLoad = [](scenes::Scene &scene) {
        scene.mesh = test::makeScanLike(scene.mesh, test::kScanEllipsoidNoise);
    };
    scenes::CompareSpec spec;
    spec.symmetries = {2, 4};
    const scenes::Comparison c = scenes::compareScene(desc, spec, options);
    ASSERT_EQ(c.panels.size(), 2u);
    ASSERT_TRUE(c.panels[0].scanCopy && c.panels[1].scanCopy);
    EXPECT_EQ(c.panels[0].scanCopy.get(), c.panels[1].scanCopy.get());
    EXPECT_EQ(c.panels[0].scanCopy.get(), c.loaded.smoothedCopy().get());
    // Each panel's field is the one its own N gets on that copy: Poincaré–Hopf, N χ.
    EXPECT_EQ(c.panels[0].singularities.indexNumeratorSum, 2 * 2);
    EXPECT_EQ(c.panels[1].singularities.indexNumeratorSum, 4 * 2);
}
