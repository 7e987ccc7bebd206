/// \file cmd_inspect.cpp
/// `rosyhatch inspect RENDER.exr [--json OUT]`: quality measures of a rendering
/// from its EXR channels alone (see renderer/evaluation/inspect.h).

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "renderer/output/image.h"
#include "renderer/evaluation/inspect.h"

#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

namespace rosy::cli {
namespace {

struct InspectCliOptions {
    std::string input;
    std::string jsonPath;
    std::string seamsPath; ///< --seams: picture of the seams over the ink
    int threads = 0;
};

std::string fixed(double v, const char *format) {
    if (!std::isfinite(v)) return "n/a";
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

void runInspect(const InspectCliOptions &opt) {
    std::optional<tbb::global_control> threadLimit;
    if (opt.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, size_t(opt.threads));
    if (!opt.jsonPath.empty()) {
        checkWritable(opt.jsonPath);
        checkNotAnInput(opt.jsonPath, opt.input, "rendering");
    }

    if (!opt.seamsPath.empty()) {
        if (!renderer::isSupportedImagePath(opt.seamsPath))
            throw InputError(FileLoc{"--seams"}, "cannot write an image named '" + opt.seamsPath + "'",
                             std::string("use one of the extensions ") + renderer::supportedImageExtensions());
        checkWritable(opt.seamsPath);
        checkNotAnInput(opt.seamsPath, opt.input, "rendering");
        if (!opt.jsonPath.empty()) checkNotAnInput(opt.seamsPath, opt.jsonPath, "--json output");
    }
    // Both outputs are published together, or neither (core/atomic_file.h).
    OutputBatch batch;

    renderer::InkMaps maps = renderer::readInkMaps(opt.input);
    renderer::InspectOptions options;
    options.keepSeamMask = !opt.seamsPath.empty();
    renderer::InspectResult r = renderer::inspectInk(maps, options);

    std::cout << "alignment_median_deg: " << fixed(r.alignmentMedianDeg, "%.3f") << "\n"
              << "alignment_p90_deg: " << fixed(r.alignmentP90Deg, "%.3f") << "\n"
              << "tone_mae: " << fixed(r.toneMae, "%.4f") << "\n"
              << "spacing_cv: " << fixed(r.spacingCv, "%.4f") << "\n"
              << "ink_outside_silhouette_px: " << r.inkOutsideSilhouettePx << "\n"
              << "seam_fraction: " << fixed(r.seamFraction, "%.4f") << " (" << r.seamPixels << " of "
              << r.crossPixels << " cross-hatched px, cross density " << fixed(r.crossDensity, "%.2f")
              << (std::isfinite(maps.crossDensity) ? " from the file" : " by default") << ")\n"
              << "(alignment samples " << r.alignmentSamples << ", spacing samples " << r.spacingSamples
              << ", hatch spacing " << fixed(r.hatchSpacingPx, "%.2f") << " px"
              << (maps.hatchSpacingPx > 0 ? " from the file" : " measured") << ")\n";

    if (!opt.jsonPath.empty()) writeTextAtomically(opt.jsonPath, renderer::inspectJson(r));
    if (!opt.seamsPath.empty()) renderer::writeImage(renderer::seamPicture(maps, r), opt.seamsPath);
    batch.commit();
}

} // namespace

void addInspectCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<InspectCliOptions>();
    CLI::App *sub = app.add_subcommand(
        "inspect", "measure hatch alignment, tone error, spacing spread, stray ink and seams of a rendered .exr");
    sub->add_option("render", opt->input, "multi-channel .exr written by rosyhatch render")->required();
    sub->add_option("--json", opt->jsonPath, "also write the measures as JSON to FILE");
    sub->add_option("--seams", opt->seamsPath,
                    "also draw the ink in grey with the seam pixels counted by seam_fraction in red to an image");
    sub->add_option("--threads", opt->threads, "worker threads (0 = all cores); results do not depend on it")
        ->check(CLI::Range(0, 4096));
    sub->callback([opt, &action] { action = [opt] { runInspect(*opt); }; });
}

} // namespace rosy::cli
