/// \file cmd_diff.cpp
/// `rosyhatch diff A B`: compares two renderings the way our golden tests do
/// (renderer/image_diff.h) and exits with idiff's codes, so users can keep
/// image regression tests of their own scenes.
///
/// Exit codes (idiff's for the comparison, the README table for errors):
///   0 PASS     every channel within the thresholds
///   1 WARNING  within the fail thresholds, but more than --warnpercent of the
///              pixels over --warn
///   2 FAILURE  a channel failed, or the images differ in size (idiff says 3
///              there; our 3 means I/O, so a size mismatch is a plain failure)
///   2          also a rejected input (usage, bad threshold, not an image)
///   3          a file that cannot be read, or an unwritable -o (idiff: 4)
/// The verdict word (PASS / WARNING / FAILURE) is always the last line on
/// stdout; errors print nothing there, so a script can tell exit 2 apart.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "renderer/image.h"
#include "renderer/image_diff.h"

#include <iostream>
#include <memory>

namespace rosy::cli {

namespace {

struct DiffCliOptions {
    std::string pathA, pathB;
    std::string diffPath; ///< -o: amplified difference image
    bool coverageOnly = false;
    bool quiet = false;
    renderer::DiffOptions diff;
};

void runDiff(const DiffCliOptions &opt) {
    if (!opt.diffPath.empty()) {
        if (!renderer::isSupportedImagePath(opt.diffPath))
            throw InputError(FileLoc{opt.diffPath}, "-o: unsupported image extension",
                             std::string("use one of ") + renderer::supportedImageExtensions());
        checkWritable(opt.diffPath);
        checkNotAnInput(opt.diffPath, opt.pathA, "reference image");
        checkNotAnInput(opt.diffPath, opt.pathB, "image");
    }
    renderer::DiffOptions options = opt.diff;
    options.exrChannels = !opt.coverageOnly;
    const renderer::DiffResult result = renderer::compareImageFiles(opt.pathA, opt.pathB, options);
    if (!opt.diffPath.empty() && result.diffImage.width > 0) renderer::writeImage(result.diffImage, opt.diffPath);
    if (opt.quiet)
        std::cout << renderer::toString(result.verdict) << "\n";
    else
        std::cout << renderer::diffReportText(result, options);
    std::cout.flush();
    if (result.verdict != renderer::DiffVerdict::Pass) throw ExitWith{int(result.verdict)};
}

} // namespace

void addDiffCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<DiffCliOptions>();
    CLI::App *sub = app.add_subcommand(
        "diff", "compare two renderings on blurred ink coverage (and EXR channels) with idiff-style thresholds; "
                "exit 0 pass, 1 warning, 2 failure");
    sub->add_option("reference", opt->pathA, "reference image (A), e.g. a golden .png or .exr")->required();
    sub->add_option("image", opt->pathB, "new image (B) to check against A")->required();
    sub->add_option("--fail", opt->diff.fail, "per-pixel failure threshold on coverage in 0..1 (default 0.02)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--failpercent", opt->diff.failPercent,
                    "percent of pixels allowed over --fail (default 0.1)")
        ->check(CLI::Range(0.0, 100.0));
    sub->add_option("--hardfail", opt->diff.hardFail, "fail if any pixel differs by more (default 0.1)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--warn", opt->diff.warn, "per-pixel warning threshold (default 0.01)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--warnpercent", opt->diff.warnPercent, "percent of pixels allowed over --warn (default 0.1)")
        ->check(CLI::Range(0.0, 100.0));
    sub->add_option("--blur", opt->diff.blurPx,
                    "Gaussian sigma in pixels applied before comparing (default: half the hatch spacing "
                    "stored in A's EXR, else 2.5)")
        ->check(CLI::Range(0.0, 1000.0));
    sub->add_option("--shift", opt->diff.shiftPx, "displacement in pixels tolerated between A and B (default 1)")
        ->check(CLI::Range(0.0, 1000.0));
    sub->add_flag("--coverage-only", opt->coverageOnly, "compare only the ink coverage, not the EXR channels");
    sub->add_option("-o,--output", opt->diffPath,
                    "write the amplified difference: red where B has more ink, blue where less");
    sub->add_flag("-q,--quiet", opt->quiet, "print only the verdict");
    sub->callback([opt, &action] { action = [opt] { runDiff(*opt); }; });
}

} // namespace rosy::cli
