/// \file cmd_compare.cpp
/// `rosyhatch compare SCENE.yaml`: the same scene drawn along several fields,
/// side by side, each panel labeled with its field and singularity count, as in
/// Palacios & Zhang 2007, Figure 1: 2-RoSy against 4-RoSy (a–b, `--symmetry 2,4`),
/// a topologically edited field against a globally smoothed one (c–d,
/// `--variants edited,smoothed`). Labels are drawn with a small built-in bitmap
/// font, so the picture needs no font installed.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "core/progress.h"
#include "field/edits.h"
#include "field/field_builder.h"
#include "field/separatrices.h"
#include "field/singularities.h"
#include "field/smoothing.h"
#include "renderer/bitmap_font.h"
#include "renderer/image_io.h"
#include "renderer/embree_scene.h"
#include "renderer/field_picture.h"
#include "renderer/illustration.h"
#include "renderer/image.h"
#include "renderer/inspect.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

namespace rosy::cli {
namespace {

// --- options and panels -------------------------------------------------------

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

struct Panel {
    std::string label;
    field::RosyField field;
    field::SingularityReport singularities;
    /// Hatching panels: what inspect and the stroke list say of its ink.
    double seamFraction = std::numeric_limits<double>::quiet_NaN();
    int strokesNearSingularities = 0;
    double stubFraction = std::numeric_limits<double>::quiet_NaN();
};

std::vector<std::string> splitList(const std::string &text) {
    std::vector<std::string> items;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty()) items.push_back(item);
    return items;
}

std::string countText(size_t n) { return std::to_string(n) + (n == 1 ? " singularity" : " singularities"); }

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
    std::vector<int> symmetries;
    std::vector<std::string> variants;
    if (!opt.variants.empty()) {
        variants = splitList(opt.variants);
        if (variants.empty() || variants.size() > 8)
            throw InputError(FileLoc{"--variants"}, "'" + opt.variants + "' is not a list of 1 to 8 variants",
                             "e.g. --variants edited,smoothed");
        for (const std::string &v : variants)
            if (v != "original" && v != "edited" && v != "smoothed")
                throw InputError(FileLoc{"--variants"}, "unknown variant '" + v + "'",
                                 "use original, edited or smoothed");
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
            symmetries.push_back(n);
        }
        if (symmetries.empty() || symmetries.size() > 8)
            throw InputError(FileLoc{"--symmetry"}, "'" + list + "' is not a list of 1 to 8 symmetries",
                             "e.g. --symmetry 2,4");
    }
    int smoothIterations = 0;
    double smoothStrength = 0.5;
    {
        char extra = 0;
        const int n = std::sscanf(opt.smoothing.c_str(), "%d:%lf%c", &smoothIterations, &smoothStrength, &extra);
        if (n < 1 || n > 2 || smoothIterations < 1 || smoothIterations > 100000 ||
            !(smoothStrength > 0 && smoothStrength <= 1))
            throw InputError(FileLoc{"--smoothing"}, "'" + opt.smoothing + "' is not ITERATIONS[:STRENGTH]",
                             "e.g. 60:0.5 (at least one iteration, strength in (0, 1])");
    }

    scenes::SceneDesc desc =
        timings.time("parse", [&] { return scenes::parseSceneFile(opt.scenePath, opt.overrides); });
    const scenes::ThreadLimit threadLimit(desc, threads);
    checkWritable(opt.outputPath);
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);
    if (!opt.reportPath.empty()) {
        checkWritable(opt.reportPath);
        checkNotAnInput(opt.reportPath, opt.scenePath, "scene");
    }
    renderer::preloadImageIo(); // OpenImageIO maps while the fields are built (renderer/image_io.h)

    scenes::PipelineOptions pipeline;
    pipeline.load = field::LoadOptions{opt.common.maxFaces};
    pipeline.threads = threads;
    scenes::StageTimings loadTimings;
    const scenes::LoadedScene loaded = scenes::loadScene(desc, pipeline, &loadTimings);
    for (const auto &[stage, ms] : loadTimings) timings.add(stage, ms);
    const scenes::Scene &scene = *loaded.scene;
    const field::TangentFrames &frames = *loaded.frames;
    const field::FieldSpec &spec = desc.field.spec;
    const char letters[] = "abcdefgh";

    std::vector<Panel> panels;
    timings.time("fields", [&] {
        if (!symmetries.empty()) {
            for (size_t k = 0; k < symmetries.size(); ++k) {
                scenes::PipelineOptions panelOptions = pipeline;
                panelOptions.nSym = symmetries[k];
                // The scene's edits name singularities of its own field: only that N gets them.
                panelOptions.applyEdits = symmetries[k] == spec.nSym;
                scenes::SceneFieldResult built = scenes::buildSceneField(loaded, desc.field, panelOptions);
                Panel panel;
                panel.field = std::move(built.field.field);
                panel.singularities = std::move(built.singularities);
                const std::string edited = built.edits.empty() ? "" : ", edited";
                panel.label = std::string("(") + letters[k] + ") " + std::to_string(symmetries[k]) + "-RoSy" + edited + ": " +
                              countText(panel.singularities.singularities.size());
                panels.push_back(std::move(panel));
            }
            return;
        }
        // The scene's field as built; each variant starts from a copy of it.
        scenes::PipelineOptions baseOptions = pipeline;
        baseOptions.applyEdits = false;
        const scenes::SceneFieldResult built = scenes::buildSceneField(loaded, desc.field, baseOptions);
        const field::RosyField &base = built.field.field;
        const std::string name = std::to_string(spec.nSym) + "-RoSy";
        const size_t baseCount = built.singularities.singularities.size();
        // The smoothed field first: an automatic edit aims at its singularity count.
        std::optional<Panel> smoothed;
        if (std::find(variants.begin(), variants.end(), "smoothed") != variants.end()) {
            smoothed.emplace();
            smoothed->field = base;
            field::relaxationSmooth(frames, smoothed->field, smoothIterations, smoothStrength, {}, spec.weights);
            smoothed->singularities = field::findSingularities(frames, smoothed->field);
        }
        for (size_t k = 0; k < variants.size(); ++k) {
            const std::string prefix = std::string("(") + letters[k] + ") " + name;
            Panel panel;
            std::string what;
            if (variants[k] == "original") {
                panel.field = base;
                panel.singularities = built.singularities;
                what = "";
            } else if (variants[k] == "smoothed") {
                panel = *smoothed;
                what = ", smoothed " + std::to_string(smoothIterations) + "x";
            } else {
                panel.field = base;
                if (!desc.field.edits.empty()) {
                    field::applyFieldEdits(frames, panel.field, desc.field.edits);
                    what = ", " + std::to_string(desc.field.edits.size()) + " edits";
                } else {
                    // No edits in the scene: cancel the closest pairs, as many as smoothing
                    // removed (or --cancel-pairs), so the two remedies are compared fairly.
                    size_t target = 0;
                    int maxPairs = opt.cancelPairs;
                    if (maxPairs < 0) {
                        const size_t goal = smoothed ? smoothed->singularities.singularities.size()
                                                     : (baseCount > 20 ? baseCount - 20 : 0);
                        target = std::min(goal, baseCount);
                        maxPairs = int(baseCount);
                    }
                    const int pairs = field::cancelClosestPairs(frames, panel.field, target, maxPairs);
                    what = ", " + std::to_string(pairs) + (pairs == 1 ? " pair" : " pairs") + " cancelled";
                }
                panel.singularities = field::findSingularities(frames, panel.field);
            }
            panel.label = prefix + what + ": " + countText(panel.singularities.singularities.size());
            panels.push_back(std::move(panel));
        }
    });

    // One picture per panel, all through the scene's camera.
    std::vector<renderer::Image> pictures;
    std::unique_ptr<renderer::RayScene> rayScene;
    if (!opt.fieldPictures)
        rayScene = timings.time("bvh", [&] { return std::make_unique<renderer::RayScene>(scene.mesh); });
    timings.time("panels", [&] {
        for (Panel &panel : panels) {
            if (opt.fieldPictures) {
                std::vector<field::Separatrix> seps;
                if (opt.separatrices)
                    seps = field::traceSeparatrices(frames, panel.field, panel.singularities.singularities);
                renderer::FieldPictureOptions fo;
                fo.lights = scene.lights;
                pictures.push_back(renderer::renderFieldPicture(scene.mesh, frames, panel.field, panel.singularities,
                                                                seps, scene.camera, fo));
                continue;
            }
            renderer::Illustration il = scenes::drawHatching(loaded, panel.field, panel.singularities, *rayScene);
            // The paper's claim (4-RoSy hatching has fewer artifacts than 2-RoSy) in
            // figures: cracks in the cross-hatching and strokes crossing singularities.
            panel.seamFraction = renderer::inspectInk(renderer::illustrationInkMaps(il, scene.style.hatch)).seamFraction;
            panel.strokesNearSingularities = il.hatch.strokesNearSingularities;
            panel.stubFraction = il.hatch.stubFraction;
            pictures.push_back(std::move(il.composite));
        }
    });

    // Side by side on paper, labels underneath in ink.
    const int w = scene.camera.width(), h = scene.camera.height();
    const int n = int(pictures.size());
    const int gap = std::max(4, std::min(w, h) / 32);
    size_t longest = 0;
    for (const Panel &p : panels) longest = std::max(longest, p.label.size());
    // Labels about 2.5% of the panel height tall, shrunk to fit the panel width;
    // a label still too wide breaks after its ':' (field, then count), and a line
    // still too wide is clipped at the panel's edges.
    int scale = std::max(1, int(std::lround(std::min(w, h) * 0.025 / 7.0)));
    while (scale > 1 && renderer::textWidthPx(std::string(longest, 'x'), scale) > w) --scale;
    std::vector<std::vector<std::string>> labelLines;
    size_t maxLines = 1;
    for (const Panel &p : panels) {
        std::vector<std::string> lines{p.label};
        const size_t colon = p.label.rfind(": ");
        if (renderer::textWidthPx(p.label, scale) > w && colon != std::string::npos)
            lines = {p.label.substr(0, colon + 1), p.label.substr(colon + 2)};
        maxLines = std::max(maxLines, lines.size());
        labelLines.push_back(lines);
    }
    const int lineHeight = (renderer::kFontGlyphRows + 2) * scale;
    const int band = int(maxLines) * lineHeight + gap;
    auto toFloat = [](const styles::Rgb &c) { return std::array<float, 3>{float(c[0]), float(c[1]), float(c[2])}; };
    const std::array<float, 3> paper = opt.fieldPictures ? std::array<float, 3>{1, 1, 1} : toFloat(scene.style.paper);
    const std::array<float, 3> ink = opt.fieldPictures ? std::array<float, 3>{0, 0, 0} : toFloat(scene.style.ink);
    renderer::Image sheet(n * w + (n + 1) * gap, h + 2 * gap + band, {"R", "G", "B"});
    for (int y = 0; y < sheet.height; ++y)
        for (int x = 0; x < sheet.width; ++x)
            for (int c = 0; c < 3; ++c) sheet.at(x, y, c) = paper[size_t(c)];
    for (int k = 0; k < n; ++k) {
        const renderer::Image &pic = pictures[size_t(k)];
        const int x0 = gap + k * (w + gap), y0 = gap;
        const bool hasAlpha = pic.nChannels >= 4;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float a = hasAlpha ? pic.at(x, y, 3) : 1.0f;
                for (int c = 0; c < 3; ++c)
                    sheet.at(x0 + x, y0 + y, c) = pic.at(x, y, c) * a + paper[size_t(c)] * (1 - a);
            }
        const std::vector<std::string> &lines = labelLines[size_t(k)];
        for (size_t i = 0; i < lines.size(); ++i)
            renderer::drawText(sheet, lines[i], x0 + std::max(0, (w - renderer::textWidthPx(lines[i], scale)) / 2),
                     y0 + h + gap / 2 + int(i) * lineHeight, scale, ink, x0, x0 + w);
    }
    timings.time("write", [&] { renderer::writeImage(sheet, opt.outputPath); });

    auto figures = [&](const Panel &p) {
        if (opt.fieldPictures) return std::string();
        char buf[160];
        std::snprintf(buf, sizeof buf, "; seam_fraction %.4f, strokes_near_singularities %d", p.seamFraction,
                      p.strokesNearSingularities);
        return std::string(buf);
    };
    if (!opt.common.quiet)
        for (const Panel &p : panels) std::cerr << p.label << figures(p) << "\n";
    if (!opt.reportPath.empty()) {
        JsonWriter json;
        json.beginObject();
        json.field("scene", opt.scenePath).field("output", opt.outputPath);
        json.key("panels").beginArray();
        for (const Panel &p : panels) {
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
    sub->add_option("scene", opt->scenePath, "scene file (YAML, see scenes/README.md)")->required();
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
