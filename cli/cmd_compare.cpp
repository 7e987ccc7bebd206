/// \file cmd_compare.cpp
/// `rosyhatch compare SCENE.yaml`: parses the panel flags (--symmetry or
/// --variants, --smoothing, --cancel-pairs, --field-pictures), runs
/// scenes::compareScene() (Palacios & Zhang 2007, Figure 1), lays the panels out
/// with renderer::panelSheet() and writes the image, the per-panel figures on
/// stderr and the --report / --timings JSON.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "core/progress.h"
#include "field/field_builder.h"
#include "renderer/output/image.h"
#include "renderer/output/image_io.h"
#include "renderer/output/panel_sheet.h"
#include "scenes/compare.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>

namespace rosy::cli {
namespace {

struct CompareOptions {
    std::string scenePath, outputPath;
    std::string symmetries;      ///< "2,4"
    std::string variants;        ///< "edited,smoothed"
    std::string smoothing = "60:0.5"; ///< ITERATIONS[:STRENGTH] of the smoothed variant
    std::string reportPath;      ///< --report: per panel figures as JSON
    int cancelPairs = -1;        ///< edited variant without scene edits: pairs to cancel (-1: automatic)
    bool fieldPictures = false;  ///< panels are field pictures instead of hatching
    bool separatrices = false;   ///< field pictures: draw separatrices
    std::vector<std::string> overrides;
    CommonOptions common;
    bool threadsGiven = false; ///< --threads was given: it beats the scene's `threads`
};

std::vector<std::string> splitList(const std::string &text) {
    std::vector<std::string> items;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) items.push_back(item);
    return items;
}

void runCompare(const CompareOptions &opt) {
    const auto start = std::chrono::steady_clock::now();
    // --threads beats the scene's `threads` (0 = all cores); the limit is set once
    // the scene is read, and until then only --threads applies.
    const std::optional<int> threads = opt.threadsGiven ? std::optional<int>(opt.common.threads) : std::nullopt;
    std::optional<tbb::global_control> flagLimit;
    if (threads && *threads > 0) flagLimit.emplace(tbb::global_control::max_allowed_parallelism, size_t(*threads));
    setProgressEnabled(!opt.common.quiet);
    Timings timings;

    if (!opt.symmetries.empty() && !opt.variants.empty())
        throw InputError(FileLoc{"--variants"}, "--symmetry and --variants cannot be combined",
                         "compare symmetries (--symmetry 2,4) or variants of the scene's field (--variants edited,smoothed)");
    if (!renderer::isSupportedImagePath(opt.outputPath))
        throw InputError(FileLoc{"-o"}, "cannot write an image named '" + opt.outputPath + "'",
                         std::string("use one of the extensions ") + renderer::supportedImageExtensions());

    // What the panels are, checked before any work.
    scenes::CompareSpec spec;
    spec.symmetries.clear();
    if (!opt.variants.empty()) {
        const std::vector<std::string> variants = splitList(opt.variants);
        if (variants.empty() || variants.size() > 8)
            throw InputError(FileLoc{"--variants"}, "'" + opt.variants + "' is not a list of 1 to 8 variants",
                             "e.g. --variants edited,smoothed");
        using V = scenes::CompareSpec::Variant;
        for (const std::string &v : variants) {
            if (v == "original") spec.variants.push_back(V::Original);
            else if (v == "edited") spec.variants.push_back(V::Edited);
            else if (v == "smoothed") spec.variants.push_back(V::Smoothed);
            else
                throw InputError(FileLoc{"--variants"}, "unknown variant '" + v + "'",
                                 "use original, edited or smoothed");
        }
    } else {
        const std::string list = opt.symmetries.empty() ? "2,4" : opt.symmetries;
        for (const std::string &item : splitList(list)) {
            int n = 0;
            size_t used = 0;
            try {
                n = std::stoi(item, &used);
            } catch (const std::exception &) {
                used = 0;
            }
            if (used != item.size())
                throw InputError(FileLoc{"--symmetry"}, "'" + item + "' is not a whole number", "e.g. --symmetry 2,4");
            field::checkSymmetry(n, "--symmetry");
            spec.symmetries.push_back(n);
        }
        if (spec.symmetries.empty() || spec.symmetries.size() > 8)
            throw InputError(FileLoc{"--symmetry"}, "'" + list + "' is not a list of 1 to 8 symmetries",
                             "e.g. --symmetry 2,4");
    }
    {
        int smoothIterations = 0;
        double smoothStrength = 0.5;
        char extra = 0;
        const int n = std::sscanf(opt.smoothing.c_str(), "%d:%lf%c", &smoothIterations, &smoothStrength, &extra);
        if (n < 1 || n > 2 || smoothIterations < 1 || smoothIterations > 100000 ||
            !(smoothStrength > 0 && smoothStrength <= 1))
            throw InputError(FileLoc{"--smoothing"}, "'" + opt.smoothing + "' is not ITERATIONS[:STRENGTH]",
                             "e.g. 60:0.5 (at least one iteration, strength in (0, 1])");
        spec.smoothIterations = smoothIterations;
        spec.smoothStrength = smoothStrength;
    }
    spec.cancelPairs = opt.cancelPairs;
    spec.fieldPictures = opt.fieldPictures;
    spec.separatrices = opt.separatrices;

    scenes::SceneDesc desc =
        timings.time("parse", [&] { return scenes::parseSceneOrMesh(opt.scenePath, opt.overrides); });
    const scenes::ThreadLimit threadLimit(desc, threads);
    checkWritable(opt.outputPath);
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);
    if (!opt.reportPath.empty()) {
        checkWritable(opt.reportPath);
        checkNotAnInput(opt.reportPath, opt.scenePath, "scene");
    }
    // OpenImageIO maps while the fields are built (renderer/output/image_io.h); PNG needs no module.
    if (renderer::writeNeedsImageIoModule(opt.outputPath)) renderer::preloadImageIo();

    scenes::PipelineOptions pipeline;
    pipeline.load = field::LoadOptions{opt.common.maxFaces};
    pipeline.threads = threads;
    scenes::Comparison comparison = scenes::compareScene(desc, spec, pipeline);
    for (const auto &[stage, ms] : comparison.timingsMs) timings.add(stage, ms);
    const std::vector<scenes::ComparePanel> &panels = comparison.panels;

    // Side by side on paper, labels underneath in ink (field pictures: black on white).
    const styles::Style &style = comparison.loaded.scene->style;
    auto toFloat = [](const styles::Rgb &c) { return std::array<float, 3>{float(c[0]), float(c[1]), float(c[2])}; };
    const std::array<float, 3> paper = opt.fieldPictures ? std::array<float, 3>{1, 1, 1} : toFloat(style.paper);
    const std::array<float, 3> ink = opt.fieldPictures ? std::array<float, 3>{0, 0, 0} : toFloat(style.ink);
    std::vector<renderer::Image> pictures;
    std::vector<std::string> labels;
    for (scenes::ComparePanel &p : comparison.panels) {
        pictures.push_back(std::move(p.picture)); // only the sheet needs them
        labels.push_back(p.label);
    }
    const renderer::Image sheet = renderer::panelSheet(pictures, labels, paper, ink);
    timings.time("write", [&] { renderer::writeImage(sheet, opt.outputPath); });

    auto figures = [&](const scenes::ComparePanel &p) {
        if (opt.fieldPictures) return std::string();
        char buf[160];
        std::snprintf(buf, sizeof buf, "; seam_fraction %.4f, strokes_near_singularities %d", p.seamFraction,
                      p.strokesNearSingularities);
        return std::string(buf);
    };
    if (!opt.common.quiet)
        for (const scenes::ComparePanel &p : panels) std::cerr << p.label << figures(p) << "\n";
    if (!opt.reportPath.empty()) {
        JsonWriter json;
        json.beginObject();
        json.field("scene", opt.scenePath).field("output", opt.outputPath);
        json.key("panels").beginArray();
        for (const scenes::ComparePanel &p : panels) {
            json.beginObject();
            json.field("label", p.label).field("symmetry", p.field.nSym);
            json.field("singularities", int(p.singularities.singularities.size()));
            if (!opt.fieldPictures) {
                json.field("seam_fraction", p.seamFraction);
                json.field("strokes_near_singularities", p.strokesNearSingularities);
                json.field("stub_fraction", p.stubFraction);
            }
            json.endObject();
        }
        json.endArray();
        json.endObject();
        writeTextAtomically(opt.reportPath, json.str());
    }
    const double totalMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!opt.common.timingsPath.empty()) timings.write(opt.common.timingsPath, totalMs);
    std::cout << opt.outputPath << "\n";
}

} // namespace

void addCompareCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<CompareOptions>();
    CLI::App *sub = app.add_subcommand(
        "compare", "draw a scene along several fields side by side, each panel labeled with its field and "
                   "singularity count (P&Z 2007 Fig. 1)");
    sub->add_option("scene", opt->scenePath, "scene file (YAML, see scenes/README.md), or a mesh (.obj .ply .off .stl) with the default scene around it")->required();
    sub->add_option("-o,--output", opt->outputPath, "the side-by-side image (.png .exr .tif .tiff .jpg .jpeg)")
        ->required();
    sub->add_option("--symmetry", opt->symmetries,
                    "one panel per symmetry order, e.g. 2,4 (the default): the scene's field source built as an "
                    "N-RoSy for each N; the scene's edits apply only to its own N");
    sub->add_option("--variants", opt->variants,
                    "one panel per variant of the scene's field, e.g. edited,smoothed: original; edited (the scene's "
                    "field edits, or without any the closest opposite pairs cancelled until as few singularities "
                    "remain as smoothing leaves); smoothed (the paper's global smoothing, see --smoothing)");
    sub->add_option("--smoothing", opt->smoothing,
                    "global smoothing of the smoothed variant: ITERATIONS[:STRENGTH]")
        ->capture_default_str();
    sub->add_option("--cancel-pairs", opt->cancelPairs,
                    "edited variant of a scene without edits: cancel exactly this many closest pairs")
        ->check(CLI::Range(0, 100000));
    sub->add_flag("--field-pictures", opt->fieldPictures,
                  "panels show the field (streamlines, singularity dots) instead of the hatching");
    sub->add_flag("--separatrices", opt->separatrices, "with --field-pictures: draw each singularity's separatrices");
    sub->add_option("--report", opt->reportPath,
                    "also write per panel its label, singularity count, seam_fraction, strokes_near_singularities "
                    "and stub_fraction as JSON to FILE");
    addSetOption(*sub, opt->overrides);
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, sub, &action] {
        opt->threadsGiven = sub->get_option("--threads")->count() > 0;
        action = [opt] { runCompare(*opt); };
    });
}

} // namespace rosy::cli
