/// \file cmd_diff.cpp
/// `rosyhatch diff A B`: compares two renderings the way our golden tests do
/// (renderer/evaluation/image_diff.h) and exits with idiff's codes, so users can keep
/// image regression tests of their own scenes, and scripts written for
/// OpenImageIO's idiff keep working.
///
/// Exit codes, idiff's (Debian's idiff 2.4.7, checked: README "Exit codes"):
///   0 PASS     every channel within the thresholds
///   1 WARNING  within the fail thresholds, but more than --warnpercent of the
///              pixels over --warn
///   2 FAILURE  a channel failed, or the images differ in size (idiff 2.4 also
///              says FAILURE, exit 2, there)
///   4          a file error: an input that is missing, unreadable, no image or
///              over the read budget, or an -o that cannot be written
///   2          also a rejected command line (unknown option, bad threshold, an -o
///              with an unknown extension or naming an input), as for every command
/// The verdict word (PASS / WARNING / FAILURE) is the last line on stdout;
/// errors print nothing there, so a script can tell exit 2 apart. With -q, as
/// idiff: nothing at all on a pass, the verdict word on stderr otherwise.
/// idiff's single-dash spellings (`-fail 0.01`, `-failpercent`, `-hardfail`,
/// `-warn`, `-warnpercent`) are accepted beside ours (acceptIdiffSpellings()).

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "renderer/output/image.h"
#include "renderer/evaluation/image_diff.h"

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

/// idiff's exit code for a file it cannot read or write.
constexpr int kFileError = 4;

/// Runs `work`; a file that cannot be read or written (IoError, or an input that
/// is no image or too large: InputError naming the file) ends the command with
/// idiff's file-error code 4, the message on stderr.
template <typename F>
auto asFileError(F &&work) {
    try {
        return work();
    } catch (const IoError &e) {
        std::cerr << e.what() << "\n";
        throw ExitWith{kFileError};
    } catch (const InputError &e) {
        std::cerr << e.what() << "\n";
        throw ExitWith{kFileError};
    }
}

void runDiff(const DiffCliOptions &opt) {
    if (!opt.diffPath.empty()) {
        if (!renderer::isSupportedImagePath(opt.diffPath))
            throw InputError(FileLoc{opt.diffPath}, "-o: unsupported image extension",
                             std::string("use one of ") + renderer::supportedImageExtensions());
        checkNotAnInput(opt.diffPath, opt.pathA, "reference image");
        checkNotAnInput(opt.diffPath, opt.pathB, "image");
        asFileError([&] { checkWritable(opt.diffPath); });
    }
    renderer::DiffOptions options = opt.diff;
    options.exrChannels = !opt.coverageOnly;
    const renderer::DiffInput a = asFileError([&] { return renderer::readDiffInput(opt.pathA); });
    const renderer::DiffInput b = asFileError([&] { return renderer::readDiffInput(opt.pathB); });
    const renderer::DiffResult result = renderer::compareImages(a.image, b.image, options, a.hatchSpacingPx);
    if (!opt.diffPath.empty() && result.diffImage.width > 0)
        asFileError([&] { renderer::writeImage(result.diffImage, opt.diffPath); });
    if (!opt.quiet) {
        std::cout << renderer::diffReportText(result, options);
        std::cout.flush();
    } else if (result.verdict != renderer::DiffVerdict::Pass) {
        std::cerr << renderer::toString(result.verdict) << "\n";
    }
    if (result.verdict != renderer::DiffVerdict::Pass) throw ExitWith{int(result.verdict)};
}

} // namespace

void acceptIdiffSpellings(std::vector<std::string> &args) {
    if (args.size() < 2 || args[1] != "diff") return;
    for (size_t i = 2; i < args.size(); ++i) {
        std::string &a = args[i];
        if (a == "--") break; // the rest are file names
        for (const char *name : {"fail", "failpercent", "hardfail", "warn", "warnpercent"})
            if (a == std::string("-") + name) a = std::string("--") + name;
    }
}

void addDiffCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<DiffCliOptions>();
    CLI::App *sub = app.add_subcommand(
        "diff", "compare two renderings on blurred ink coverage (and EXR channels) with idiff's thresholds, "
                "spellings (-fail 0.02 or --fail 0.02) and exit codes: 0 pass, 1 warning, 2 failure, "
                "4 file error (2 also for a rejected command line)");
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
    sub->add_flag("-q,--quiet", opt->quiet,
                  "as idiff: print nothing on a pass, only the verdict word (on stderr) otherwise");
    sub->callback([opt, &action] { action = [opt] { runDiff(*opt); }; });
}

} // namespace rosy::cli
