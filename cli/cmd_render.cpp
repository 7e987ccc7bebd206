/// \file cmd_render.cpp
/// `rosyhatch render SCENE.yaml`: parses the flags, runs the scene through
/// scenes::renderScene() (the pen-and-ink hatching, or a picture of the field for
/// `picture.kind: field`) and writes PNG/TIFF/JPEG, the EXR with its channels, the
/// layered SVG, the stroke report and the timings, all published together.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/diagnostics.h"
#include "core/error.h"
#include "core/json.h"
#include "core/memory.h"
#include "core/progress.h"
#include "renderer/field_picture.h"
#include "renderer/illustration.h"
#include "renderer/output/image.h"
#include "renderer/output/image_io.h"
#include "renderer/output/svg.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

namespace rosy::cli {

namespace {

struct RenderOptions {
    std::string reportPath; ///< --report: stroke-list statistics as JSON
    std::string scenePath;
    std::vector<std::string> outputPaths; ///< -o (repeatable); overrides the scene's output list
    bool threadsGiven = false; ///< --threads was on the command line (it beats the scene's `threads`)
    std::string svgPath;      ///< --svg: the layered SVG as well, from the same render
    // SVG page overrides, shorthand for --set style.page.*; unset: the style's
    // `page` (scenes/README.md).
    std::string paper;              ///< --paper: a4, a3, letter or WxH in mm
    std::optional<std::string> marginMm; ///< --margin-mm (YAML text, checked as style.page.margin_mm)
    std::string orientation;             ///< --orientation: auto, portrait or landscape
    std::optional<std::string> penMm;    ///< --pen-mm: every path this wide
    bool noPlotter = false;   ///< --no-plotter: keep strokes as traced (no merge, simplify, sort)
    std::vector<std::string> overrides; ///< --set KEY=VALUE, applied to the scene before validation
    CommonOptions common;
};

bool isExrPath(const std::string &path) { return hasExtension(path, ".exr"); }

/// Throws IoError (exit 3) when the render's estimated memory exceeds what this
/// process can still allocate; ROSY_MEMORY_CHECK=off skips the check.
void checkRenderFits(const std::string &scenePath, const scenes::Scene &scene, bool exr) {
    if (const char *env = std::getenv("ROSY_MEMORY_CHECK"); env && std::string(env) == "off") return;
    const uint64_t need = scenes::renderMemoryEstimate(scene, exr);
    const std::optional<MemoryBudget> budget = availableMemory();
    if (!budget || need <= budget->bytes) return;
    std::ostringstream os;
    os << "the render needs about " << formatBytes(need) << " (" << scene.camera.width() << " x "
       << scene.camera.height() << " pixels, hatch.min_spacing_px " << scene.style.hatch.minSpacingPx << ", "
       << scene.mesh.nFaces() << " faces) but " << budget->source << " leaves " << formatBytes(budget->bytes);
    throw IoError(scenePath, os.str() + "; lower camera.resolution or raise hatch.min_spacing_px "
                                        "(ROSY_MEMORY_CHECK=off tries anyway)");
}

void runRender(const RenderOptions &opt) {
    const auto start = std::chrono::steady_clock::now();
    setProgressEnabled(!opt.common.quiet);

    Timings timings;
    // The page flags are shorthand for style.page keys, checked by the scene parser.
    std::vector<scenes::FlagOverride> pageFlags;
    if (!opt.paper.empty()) pageFlags.push_back({"--paper", "style.page.size", opt.paper});
    if (opt.marginMm) pageFlags.push_back({"--margin-mm", "style.page.margin_mm", *opt.marginMm});
    if (!opt.orientation.empty()) pageFlags.push_back({"--orientation", "style.page.orientation", opt.orientation});
    if (opt.penMm) pageFlags.push_back({"--pen-mm", "style.page.pen_width_mm", *opt.penMm});
    scenes::SceneDesc desc =
        timings.time("parse", [&] { return scenes::parseSceneOrMesh(opt.scenePath, opt.overrides, pageFlags); });
    // --threads beats the scene's `threads`; 0 = all cores. Held over the writes too.
    const std::optional<int> threads = opt.threadsGiven ? std::optional<int>(opt.common.threads) : std::nullopt;
    const scenes::ThreadLimit threadLimit(desc, threads);
    // Every file this render writes: the scene's `output` list, or every -o, plus --svg.
    std::vector<std::string> outputs;
    for (const auto &o : desc.outputs) outputs.push_back(o.value);
    if (!opt.outputPaths.empty()) {
        outputs.clear();
        for (const std::string &o : opt.outputPaths) {
            if (!renderer::isSupportedImagePath(o) && !isSvgPath(o))
                throw InputError(FileLoc{o}, "-o: unsupported image extension",
                                 std::string("use one of ") + renderer::supportedImageExtensions() + " .svg");
            if (std::find(outputs.begin(), outputs.end(), o) != outputs.end())
                throw InputError(FileLoc{o}, "-o: the same output is given twice", "give each file once");
            outputs.push_back(o);
        }
    }
    if (!opt.svgPath.empty() && !isSvgPath(opt.svgPath))
        throw InputError(FileLoc{opt.svgPath}, "--svg: the file name must end in .svg", "name it like out/bunny.svg");
    if (!opt.svgPath.empty() && std::find(outputs.begin(), outputs.end(), opt.svgPath) == outputs.end())
        outputs.push_back(opt.svgPath);
    const std::string output = outputs.front(); // named in the report
    std::vector<std::string> svgPaths, rasterPaths;
    for (const std::string &o : outputs) (isSvgPath(o) ? svgPaths : rasterPaths).push_back(o);
    // The SVG (if any): an .svg output or --svg. Page from the style's `page`, then
    // the command-line overrides.
    const std::string svgPath = svgPaths.empty() ? std::string() : svgPaths.front();
    renderer::SvgOptions svgOptions = renderer::svgOptionsFor(desc.style.style.page);
    svgOptions.plotterPass = !opt.noPlotter;
    if (desc.picture.kind.value == scenes::PictureDesc::Kind::Field && !opt.reportPath.empty())
        throw InputError(FileLoc{"--report"}, "the report measures strokes; a field picture has none",
                         "drop --report, or set picture.kind: hatching");
    // Fail on any unwritable destination before spending time on the render: then
    // nothing at all is written.
    for (const std::string &o : outputs) checkWritable(o);
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);
    if (!opt.reportPath.empty()) checkWritable(opt.reportPath);
    std::vector<std::string> written = outputs;
    written.push_back(opt.reportPath);
    written.push_back(opt.common.timingsPath);
    for (const std::string &out : written) {
        checkNotAnInput(out, opt.scenePath, "scene file");
        if (desc.mesh.file) checkNotAnInput(out, desc.mesh.file->value, "input mesh");
        if (!desc.style.presetPath.empty()) checkNotAnInput(out, desc.style.presetPath, "style preset");
    }

    // Every file is published at the end, together, or none is (core/atomic_file.h).
    OutputBatch batch;
    scenes::PipelineOptions pipeline;
    pipeline.load = field::LoadOptions{opt.common.maxFaces};
    pipeline.threads = threads;
    pipeline.measureHatching = !opt.reportPath.empty(); // only the report reads it
    pipeline.raster = !rasterPaths.empty();            // an SVG alone is written from the strokes
    // Print mode (an SVG, or --paper): lengths in mm on the page, traced at the
    // resolution that serves them; the scene's own when a raster is written too.
    pipeline.print = !svgPaths.empty() || !opt.paper.empty();
    pipeline.afterLoad = [&](scenes::Scene &scene) {
        // Refuse, before the work, a render that cannot fit in the memory left
        // (scenes::renderMemoryEstimate(); README, "Limits").
        checkRenderFits(opt.scenePath, scene, std::any_of(rasterPaths.begin(), rasterPaths.end(), isExrPath));
        // Image files other than PNG go out through OpenImageIO, a module of ~260 shared
        // libraries: map it on a background thread while the field is solved
        // (renderer/output/image_io.h). Not before the mesh load: the mapping slowed the
        // loader's page faults from 50 to 100 ms, more than the load could hide. PNG
        // (libpng directly) and SVG do not need it.
        if (std::any_of(rasterPaths.begin(), rasterPaths.end(), renderer::writeNeedsImageIoModule))
            renderer::preloadImageIo();
    };
    // The stages before the drawing's own display (renderer/illustration.cpp): pipeline
    // stage names and display names, weighted by their times on the bunny at 4096²
    // (load 0.18 s, frames 0.20, field 0.71, singularities 0.04, BVH 0.10).
    std::vector<std::pair<std::string, ProgressStage>> before = {
        {"load", {"load", 18}}, {"frames", {"frames", 20}}, {"field", {"field", 71}},
        {"singularities", {"singularities", 4}}};
    if (desc.picture.kind.value == scenes::PictureDesc::Kind::Field) {
        if (desc.picture.separatrices.value) before.push_back({"separatrices", {"separatrices", 10}});
        before.push_back({"field_picture", {"field picture", 60}});
    } else {
        before.push_back({"bvh", {"bvh", 10}});
    }
    std::vector<ProgressStage> beforeStages;
    for (const auto &b : before) beforeStages.push_back(b.second);
    std::optional<Progress> preparing;
    preparing.emplace("preparing", std::move(beforeStages));
    // A stage is shown as it starts (one that only some scenes have, scan_field, is put
    // in then); the last one's end hands over to the drawing's own display.
    auto indexOf = [&](const std::string &stage) {
        for (size_t i = 0; i < before.size(); ++i)
            if (before[i].first == stage) return i;
        return before.size();
    };
    pipeline.onStageStart = [&](const std::string &stage) {
        if (!preparing) return;
        size_t i = indexOf(stage);
        if (stage == "scan_field" && i == before.size()) {
            // A noisy scan: its field again on the smoothed copy (seconds to minutes on
            // millions of faces), after the singularities of the field on the scan itself.
            i = std::min(indexOf("singularities") + 1, before.size());
            const ProgressStage shown{"scan field", 150};
            before.insert(before.begin() + std::ptrdiff_t(i), {stage, shown});
            preparing->insertStage(i, shown);
        }
        if (i < before.size()) preparing->beginStage(i);
    };
    pipeline.onStage = [&](const std::string &stage, double) {
        if (preparing && indexOf(stage) + 1 == before.size()) preparing.reset();
    };
    const scenes::RenderResult result = scenes::renderScene(desc, pipeline);
    preparing.reset();
    for (const auto &[stage, ms] : result.timingsMs) timings.add(stage, ms);
    if (result.fieldPicture) {
        timings.time("write", [&] {
            // SVG: the picture's streamlines, separatrices and dots on pen layers
            // (renderer/field_picture.h), as `rosyhatch field --image x.svg` writes them.
            renderer::SvgOptions fieldSvg = svgOptions;
            fieldSvg.layerLabels = renderer::kFieldPictureLayerLabels;
            for (const std::string &o : svgPaths)
                renderer::writeSvg(renderer::fieldPictureStrokes(*result.fieldDrawing), fieldSvg, o);
            for (const std::string &o : rasterPaths) renderer::writeImage(*result.fieldPicture, o);
        });
        if (!opt.common.timingsPath.empty())
            timings.write(opt.common.timingsPath,
                          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        batch.commit();
        for (const std::string &o : outputs) std::cout << o << "\n";
        return;
    }
    const std::optional<scenes::PrintSetup> &print = result.print;
    if (print) {
        svgOptions.penWidthMm = print->lengths.penWidthMm; // one pen: every path this wide
        svgOptions.plotter = print->plotter;
    }
    const renderer::Illustration &il = *result.illustration;
    const scenes::Scene &scene = *result.loaded.scene;

    std::optional<renderer::SvgReport> svgReport;
    timings.time("write", [&] {
        for (const std::string &path : svgPaths) {
            // The report describes the first SVG; the others are the same drawing.
            renderer::SvgReport report;
            renderer::writeSvg(il.strokes, svgOptions, path, &report);
            if (!svgReport) svgReport = report;
        }
        for (const std::string &path : rasterPaths) {
            if (isExrPath(path)) {
                // Gathering the channels takes a while at 4096² too; writeImage() shows the file.
                std::optional<Progress> gather;
                gather.emplace("writing", std::vector<ProgressStage>{
                                              {std::filesystem::path(path).filename().string() + " (channels)", 1}});
                renderer::Image exr = renderer::illustrationExr(il);
                gather.reset();
                renderer::writeImage(exr, path,
                                     renderer::inkExrWriteOptions(renderer::nominalHatchSpacingPx(scene.style.hatch),
                                                                 scene.style.hatch.crossDensity));
            } else {
                renderer::writeImage(il.composite, path);
            }
        }
    });
    const double totalMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!opt.reportPath.empty()) {
        JsonWriter json;
        json.beginObject();
        json.field("scene", opt.scenePath).field("output", output);
        json.field("width", il.gbuffer.width).field("height", il.gbuffer.height);
        json.field("strokes", int(il.strokes.strokes.size()));
        json.field("hatch_strokes", il.hatch.strokes);
        json.field("contour_strokes", int(il.strokes.strokes.size()) - il.hatch.strokes);
        json.field("contour_creases_below_scale", il.contours.nCreasesBelowScale);
        json.field("contour_scan_noise", il.contours.judgedAtPictureScale);
        json.field("ink_length_px", il.hatch.inkLengthPx);
        json.field("min_spacing_violations", il.hatch.minSpacingViolations);
        json.field("strokes_near_singularities", il.hatch.strokesNearSingularities);
        json.field("singularity_holes", il.hatch.singularityHoles);
        json.field("stubs", il.hatch.stubs);
        json.field("stub_fraction", il.hatch.stubFraction);
        json.field("cross_overdense_fraction", il.hatch.crossOverdenseFraction);
        json.field("squeezed_fraction", il.hatch.squeezedFraction);
        json.field("incoherent_fraction", il.hatch.incoherentFraction);
        json.field("singularities", int(result.field.singularities.singularities.size()));
        json.field("symmetry", result.field.field.field.nSym);
        if (svgReport) {
            json.field("penup_mm", svgReport->penUpMm);
            json.field("pendown_mm", svgReport->penDownMm);
            json.field("penup_ratio_vs_unsorted", svgReport->penUpRatioVsUnsorted);
            json.field("paths", svgReport->paths);
            json.field("overlap_removed_mm", svgReport->overlapRemovedMm);
            json.field("page_mm", (std::ostringstream() << svgReport->pageWidthMm << "x" << svgReport->pageHeightMm).str());
        }
        if (print) {
            json.field("pen_width_mm", print->lengths.penWidthMm);
            json.field("min_spacing_mm", print->lengths.minSpacingMm);
            json.field("mm_per_px", print->mmPerPx);
            json.field("spacing_gain", il.spacingGain);
            json.field("ink_fill", il.inkFill);
            json.field("ink_at_min_spacing", il.inkAtMinSpacing);
        }
        json.key("warnings").beginObject();
        for (const auto &[kind, count] : warningCounts()) json.field(kind, count);
        json.endObject();
        json.endObject();
        const Progress writing("writing", {{std::filesystem::path(opt.reportPath).filename().string(), 1}});
        writeTextAtomically(opt.reportPath, json.str());
    }
    if (!opt.common.timingsPath.empty()) timings.write(opt.common.timingsPath, totalMs);
    batch.commit();
    // The written paths, one a line, also with --quiet (scripts read them).
    for (const std::string &o : outputs) std::cout << o << "\n";
}

} // namespace

void addRenderCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<RenderOptions>();
    CLI::App *sub = app.add_subcommand("render", "render a scene as a pen-and-ink illustration (PNG/TIFF/JPEG, or EXR with channels)");
    sub->add_option("scene", opt->scenePath, "scene file (YAML, see scenes/README.md), or a mesh (.obj .ply .off .stl) with the default scene around it")->required();
    sub->add_option("-o,--output", opt->outputPaths,
                    "output image (.png .exr .tif .tiff .jpg .jpeg) or layered vector drawing (.svg); "
                    "repeatable, all from one render; overrides the scene's output list")
        ->allow_extra_args(false);
    sub->add_option("--svg", opt->svgPath, "also write the layered SVG of the same render (next to a raster -o)");
    sub->add_option("--paper", opt->paper,
                    "page size: a4, a3, letter, or WIDTHxHEIGHT in mm (default: the style's page.size, a4); "
                    "also turns on print mode (lengths in mm on the page) for raster outputs");
    sub->add_option("--margin-mm", opt->marginMm,
                    "SVG page margin in mm (default: the style's page.margin_mm, 10); the picture is fitted inside");
    sub->add_option("--orientation", opt->orientation,
                    "SVG page orientation: auto (turn the page if the picture gets larger), portrait, landscape "
                    "(default: the style's page.orientation, auto)");
    sub->add_option("--pen-mm", opt->penMm,
                    "print: the pen width in mm, every path this wide (default: the style's page.pen_width_mm; "
                    "0 = hatch.stroke_width_px x page.px_mm)");
    sub->add_flag("--no-plotter", opt->noPlotter,
                  "SVG: skip the plotter pass (merging strokes whose ends meet within 0.5 px, "
                  "simplifying within 0.25 px, ordering to cut pen-up travel)");
    sub->add_option("--report", opt->reportPath,
                    "write stroke statistics (strokes, ink length, spacing violations, strokes near singularities; "
                    "with an SVG output also penup_mm, pendown_mm, penup_ratio_vs_unsorted, paths) as JSON");
    addSetOption(*sub, opt->overrides);
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, sub, &action] {
        opt->threadsGiven = sub->get_option("--threads")->count() > 0;
        action = [opt] { runRender(*opt); };
    });
}

} // namespace rosy::cli
