// Print mode's line density on paper (issue 18): the hatch ink per mm² of the
// picture of one scene traced at several pixel pitches and page sizes.
//
//   build/bench/print_density [SCENE.yaml] [PAGE SIDE keep|svg [PX_MM]]...
//
// Each run goes through scenes::renderScene() with PipelineOptions::print, as
// `rosyhatch render` does for an SVG: `keep` traces at the camera's SIDE² px (a
// raster output kept the resolution), `svg` lets print mode choose it from PX_MM
// (default: the style's page.px_mm, 0.17 mm). PAGE is a square page's side in mm
// (5 mm margins) or a paper name (a4, a3, ...; the scene's margin). Ink per mm² is
// the hatch polylines' length on paper over the picture's area.
//
// Without SCENE.yaml: the torus scene of svg_render_test (PrintMode tests).
// Environment: PRINT_KEYS (the page keys after size and margin, default the test's
// pen 0.3 mm, spacing 0.8–2.4 mm, min length 1 mm; "" for the scene's own),
// PRINT_STYLE (one more line in the torus's style block, e.g. "seed: 2"),
// PRINT_DIRECTION (the torus camera's direction); for a scene file, PRINT_SET
// (more --set overrides, separated by ';', e.g. "style.seed=2"); PRINT_BINS=1 adds
// the fill by tone band, PRINT_MEASURE=1 measureHatches() (squeezed ink, stubs).
// "fill" is the drawn hatch ink over the ink the tone asks for (1 / d_sep of each
// family that hatches, per px²), computed here with the scene's own spacings.
#include "renderer/illustration.h"
#include "renderer/strokes/hatching.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace rosy;

namespace {

const char *envOr(const char *name, const char *fallback) {
    const char *v = std::getenv(name);
    return v ? v : fallback;
}

bool isNumber(const std::string &s) { return !s.empty() && s.find_first_not_of("0123456789.") == std::string::npos; }

/// "pen_width_mm: 0.3, min_spacing_mm: 0.8" -> style.page.pen_width_mm=0.3, ...
std::vector<std::string> keyOverrides(const std::string &keys) {
    std::vector<std::string> out;
    std::istringstream in(keys);
    std::string item;
    while (std::getline(in, item, ',')) {
        const size_t colon = item.find(':');
        if (colon == std::string::npos) continue;
        auto trim = [](std::string s) {
            s.erase(0, s.find_first_not_of(' '));
            s.erase(s.find_last_not_of(' ') + 1);
            return s;
        };
        out.push_back("style.page." + trim(item.substr(0, colon)) + "=" + trim(item.substr(colon + 1)));
    }
    return out;
}

} // namespace

int main(int argc, char **argv) {
    const std::string keys =
        envOr("PRINT_KEYS", "pen_width_mm: 0.3, min_spacing_mm: 0.8, max_spacing_mm: 2.4, min_length_mm: 1");
    const std::string styleLine = std::getenv("PRINT_STYLE") ? std::string("  ") + std::getenv("PRINT_STYLE") + "\n" : "";
    const std::string direction = envOr("PRINT_DIRECTION", "0.2, 1.0, 0.9");
    int a = 1;
    std::string scenePath;
    if (argc > 1 && std::string(argv[1]).size() > 5 && std::string(argv[1]).rfind(".yaml") == std::string(argv[1]).size() - 5)
        scenePath = argv[a++];
    for (; a + 2 < argc; a += 3) {
        const std::string page = argv[a];
        const int side = std::atoi(argv[a + 1]);
        const bool keep = std::string(argv[a + 2]) == "keep";
        std::string pxMm;
        if (!keep && a + 3 < argc && std::string(argv[a + 3]).find('.') != std::string::npos) pxMm = argv[++a + 2];
        scenes::SceneDesc desc;
        if (scenePath.empty()) {
            const std::string square = std::to_string(int(std::atof(page.c_str())));
            const std::string text =
                "mesh: {primitive: torus}\ncamera:\n  auto: true\n  direction: [" + direction + "]\n"
                "  fov: 30\n  resolution: [" + std::to_string(side) + ", " + std::to_string(side) +
                "]\nlights:\n  - {type: directional, direction: [-0.6, 1.0, 0.7], intensity: 0.9}\n"
                "style:\n  page: {size: " + square + "x" + square + ", margin_mm: 5" + (keys.empty() ? "" : ", " + keys) +
                (pxMm.empty() ? "" : ", px_mm: " + pxMm) + "}\n" + styleLine;
            desc = scenes::parseScene(text, std::string(ROSY_SOURCE_DIR) + "/scenes/print_density.yaml");
        } else {
            std::vector<std::string> overrides = keyOverrides(keys);
            overrides.push_back("camera.resolution=[" + std::to_string(side) + ", " + std::to_string(side) + "]");
            overrides.push_back("style.page.size=" + (isNumber(page) ? page + "x" + page : page));
            if (!pxMm.empty()) overrides.push_back("style.page.px_mm=" + pxMm);
            std::istringstream set(envOr("PRINT_SET", ""));
            for (std::string item; std::getline(set, item, ';');)
                if (!item.empty()) overrides.push_back(item);
            desc = scenes::parseSceneFile(scenePath, overrides);
        }
        scenes::PipelineOptions options;
        options.raster = false;
        options.measureHatching = false;
        options.print = true;
        options.printKeepsResolution = keep;
        const auto t0 = std::chrono::steady_clock::now();
        scenes::RenderResult result = scenes::renderScene(desc, options);
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const scenes::PrintSetup &setup = *result.print;
        const renderer::Illustration &il = *result.illustration;
        // What the tone asks for: 1 / d_sep of each family that hatches, per pixel
        // (lines per px across); the drawn ink over it is the fill.
        const styles::HatchStyle &hs = result.loaded.scene->style.hatch;
        double asked = 0, askedBin[10] = {}, inkBin[10] = {};
        auto binOf = [&](size_t i) { return std::min(9, int(il.targetDensity[i] * 10)); };
        for (size_t i = 0; i < il.targetDensity.size(); ++i) {
            const double rho = il.targetDensity[i];
            if (renderer::hatchFamilies(rho, hs) == 0) continue;
            const double w = il.screen.valid(i) ? renderer::crossWeight(il.screen, i) : 0.0;
            const std::array<double, 2> c = renderer::familyCoverage(rho, hs, w);
            for (int f = 0; f < 2; ++f)
                if (c[size_t(f)] > 0) {
                    asked += 1.0 / renderer::familySpacingPx(rho, f, hs, w);
                    askedBin[binOf(i)] += 1.0 / renderer::familySpacingPx(rho, f, hs, w);
                }
        }
        double ink[2] = {0, 0};
        int n[2] = {0, 0};
        for (const renderer::Stroke &s : il.strokes.strokes) {
            if (s.kind != renderer::StrokeKind::Hatch) continue;
            const int f = s.family != 0;
            ++n[f];
            for (size_t i = 1; i < s.points.size(); ++i) {
                ink[f] += (s.points[i] - s.points[i - 1]).norm();
                const auto m = 0.5 * (s.points[i] + s.points[i - 1]);
                const int x = std::clamp(int(m.x()), 0, il.screen.width - 1), y = std::clamp(int(m.y()), 0, il.screen.height - 1);
                inkBin[binOf(size_t(il.screen.index(x, y)))] += (s.points[i] - s.points[i - 1]).norm();
            }
        }
        const double mm = setup.mmPerPx;
        const double pic = setup.resolution[0] * mm * setup.resolution[1] * mm;
        std::printf("page %-5s %5d x %-5d px  %.4f mm/px  ink/mm² %.4f (f0 %.4f f1 %.4f)  fill %.3f  strokes %d+%d  mean %.2f mm  %.1f s\n",
                    page.c_str(), setup.resolution[0], setup.resolution[1], mm, (ink[0] + ink[1]) * mm / pic,
                    ink[0] * mm / pic, ink[1] * mm / pic, (ink[0] + ink[1]) / std::max(asked, 1e-9), n[0], n[1], (ink[0] + ink[1]) * mm / std::max(1, n[0] + n[1]),
                    sec);
        if (std::getenv("PRINT_MEASURE")) {
            const renderer::HatchReport r = renderer::measureHatches(il.strokes, il.screen, il.targetDensity, hs);
            std::printf("   squeezed %.3f  stubs %.3f  cross-overdense %.3f  near-singularities %d  violations %d\n",
                        r.squeezedFraction, r.stubFraction, r.crossOverdenseFraction, r.strokesNearSingularities,
                        r.minSpacingViolations);
        }
        if (std::getenv("PRINT_BINS")) {
            std::printf("   fill by target density (tenths), share of asked:");
            for (int b = 0; b < 10; ++b)
                if (askedBin[b] > 0) std::printf(" %d:%.2f/%.2f", b, inkBin[b] / askedBin[b], askedBin[b] / asked);
            std::printf("\n");
        }
        std::fflush(stdout);
    }
}
