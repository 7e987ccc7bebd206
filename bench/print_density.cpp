// Print mode's line density on paper (issue 18): the hatch ink per mm² of the
// picture of one scene traced at several pixel pitches.
//
//   build/bench/print_density [PAGE_MM SIDE keep|svg [PX_MM]]...
//
// Environment: PRINT_KEYS (the page keys after size and margin), PRINT_STYLE (one
// more line in the style block, e.g. "seed: 2"), PRINT_DIRECTION (camera direction).
//
// Each run: the torus scene of svg_render_test on a square page of PAGE_MM (5 mm
// margins), camera SIDE² px; `keep` traces at SIDE² (a raster output kept the
// resolution), `svg` lets print mode choose it from PX_MM (default 0.17).
#include "renderer/illustration.h"
#include "renderer/output/svg.h"
#include "scenes/pipeline.h"
#include "scenes/print_units.h"
#include "scenes/scene.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace rosy;

int main(int argc, char **argv) {
    const char *env = std::getenv("PRINT_KEYS");
    const std::string keys = env ? env : "pen_width_mm: 0.3, min_spacing_mm: 0.8, max_spacing_mm: 2.4, min_length_mm: 1";
    const char *envStyle = std::getenv("PRINT_STYLE");
    const std::string style = envStyle ? std::string("  ") + envStyle + "\n" : "";
    const char *envDirection = std::getenv("PRINT_DIRECTION");
    const std::string direction = envDirection ? envDirection : "0.2, 1.0, 0.9";
    for (int a = 1; a + 2 < argc; a += 3) {
        const double pageMm = std::atof(argv[a]);
        const int side = std::atoi(argv[a + 1]);
        const bool keep = std::string(argv[a + 2]) == "keep";
        std::string pxMm;
        if (!keep && a + 3 < argc && std::string(argv[a + 3]).find('.') != std::string::npos) pxMm = argv[++a + 2];
        const std::string page = std::to_string(int(pageMm));
        const std::string text =
            "mesh: {primitive: torus}\ncamera:\n  auto: true\n  direction: [" + direction + "]\n"
            "  fov: 30\n  resolution: [" + std::to_string(side) + ", " + std::to_string(side) +
            "]\nlights:\n  - {type: directional, direction: [-0.6, 1.0, 0.7], intensity: 0.9}\n"
            "style:\n  page: {size: " + page + "x" + page + ", margin_mm: 5, " + keys + (pxMm.empty() ? "" : ", px_mm: " + pxMm) + "}\n" + style;
        scenes::SceneDesc desc = scenes::parseScene(text, std::string(ROSY_SOURCE_DIR) + "/scenes/print_density.yaml");
        const scenes::PrintSetup setup = scenes::applyPrintUnits(desc, keep);
        scenes::PipelineOptions options;
        options.raster = false;
        const auto t0 = std::chrono::steady_clock::now();
        const renderer::Illustration il = std::move(*scenes::renderScene(desc, options).illustration);
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        double ink[2] = {0, 0};
        int n[2] = {0, 0};
        for (const renderer::Stroke &s : il.strokes.strokes) {
            if (s.kind != renderer::StrokeKind::Hatch) continue;
            const int f = s.family != 0;
            ++n[f];
            for (size_t i = 1; i < s.points.size(); ++i) ink[f] += (s.points[i] - s.points[i - 1]).norm();
        }
        const double pic = (pageMm - 10) * (pageMm - 10), mm = setup.mmPerPx;
        std::printf("page %3.0f mm  %5d² px  %.4f mm/px  ink/mm² %.4f (f0 %.4f f1 %.4f)  strokes %d+%d  mean %.2f mm  %.1f s\n",
                    pageMm, setup.resolution[0], mm, (ink[0] + ink[1]) * mm / pic, ink[0] * mm / pic,
                    ink[1] * mm / pic, n[0], n[1], (ink[0] + ink[1]) * mm / std::max(1, n[0] + n[1]), sec);
    }
}
