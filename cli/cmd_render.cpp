/// \file cmd_render.cpp
/// `rosyhatch render SCENE.yaml`: the Lambert preview of a scene.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "renderer/embree_scene.h"
#include "renderer/gbuffer.h"
#include "renderer/image.h"
#include "renderer/shading.h"
#include "scenes/scene.h"
#include "core/diagnostics.h"
#include "core/json.h"
#include "field/field_builder.h"
#include "field/singularities.h"
#include "renderer/illustration.h"
#include "renderer/svg.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <fstream>

#include <tbb/global_control.h>

#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace rosy::cli {

namespace {

struct RenderOptions {
    std::string reportPath; ///< --report: stroke-list statistics as JSON
    std::string scenePath;
    std::string outputPath; ///< -o; overrides the scene's output
    std::string paper = "a4"; ///< --paper: SVG page size (a4, a3, letter or WxH in mm)
    double marginMm = 10;     ///< --margin-mm: SVG page margin
    bool noPlotter = false;   ///< --no-plotter: keep strokes as traced (no merge, simplify, sort)
    CommonOptions common;
};

bool hasExtension(const std::string &path, const char *dotExt) {
    const std::string want(dotExt);
    std::string ext = path.size() >= want.size() ? path.substr(path.size() - want.size()) : "";
    for (char &ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext == want;
}

bool isExrPath(const std::string &path) { return hasExtension(path, ".exr"); }
bool isSvgPath(const std::string &path) { return hasExtension(path, ".svg"); }

void runRender(const RenderOptions &opt) {
    const auto start = std::chrono::steady_clock::now();
    std::optional<tbb::global_control> threadLimit;
    if (opt.common.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, size_t(opt.common.threads));
    setProgressEnabled(!opt.common.quiet);

    Timings timings;
    scenes::SceneDesc desc = timings.time("parse", [&] { return scenes::parseSceneFile(opt.scenePath); });
    std::string output = desc.output.value;
    if (!opt.outputPath.empty()) {
        if (!renderer::isSupportedImagePath(opt.outputPath) && !isSvgPath(opt.outputPath))
            throw InputError(FileLoc{opt.outputPath}, "-o: unsupported image extension",
                             std::string("use one of ") + renderer::supportedImageExtensions() + " .svg");
        output = opt.outputPath;
    }
    renderer::SvgOptions svgOptions;
    if (isSvgPath(output)) {
        const auto paper = renderer::parsePaperSize(opt.paper);
        if (!paper)
            throw InputError(FileLoc{"--paper"}, "unknown paper size '" + opt.paper + "'",
                             "use a4, a3, letter or WIDTHxHEIGHT in mm such as 300x200");
        if (!(opt.marginMm >= 0) || 2 * opt.marginMm >= std::min(paper->first, paper->second))
            throw InputError(FileLoc{"--margin-mm"}, "margin " + (std::ostringstream() << opt.marginMm).str() +
                                                          " mm leaves no room on the page",
                             "use a margin of at least 0 and less than half the paper's shorter side");
        svgOptions.pageWidthMm = paper->first;
        svgOptions.pageHeightMm = paper->second;
        svgOptions.marginMm = opt.marginMm;
        svgOptions.plotterPass = !opt.noPlotter;
    }
    // Fail on an unwritable destination before spending time on the render.
    checkWritable(output);
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);
    if (!opt.reportPath.empty()) checkWritable(opt.reportPath);

    scenes::Scene scene = timings.time("load", [&] { return scenes::buildScene(desc); });
    const field::TangentFrames frames = timings.time("frames", [&] { return field::TangentFrames(scene.mesh); });
    field::FieldResult fieldResult = timings.time("field", [&] {
        field::FieldResult r = field::buildField(frames, desc.field.spec);
        scenes::applyFieldEdits(frames, r.field, desc.field.edits);
        return r;
    });
    const field::SingularityReport singularities =
        timings.time("singularities", [&] { return field::findSingularities(frames, fieldResult.field); });
    auto rayScene = timings.time("bvh", [&] { return std::make_unique<renderer::RayScene>(scene.mesh); });

    renderer::IllustrationInput input;
    input.mesh = &scene.mesh;
    input.frames = &frames;
    input.field = &fieldResult.field;
    input.singularities = &singularities;
    input.scene = rayScene.get();
    input.camera = &scene.camera;
    input.lights = scene.lights;
    input.shading = scene.shading;
    input.style = scene.style;
    const renderer::Illustration il = renderer::renderIllustration(input);
    for (const auto &[stage, ms] : il.timingsMs) timings.add(stage, ms);

    std::optional<renderer::SvgReport> svgReport;
    timings.time("write", [&] {
        if (isSvgPath(output)) {
            svgReport.emplace();
            renderer::writeSvg(il.strokes, svgOptions, output, &*svgReport);
        } else if (isExrPath(output))
            renderer::writeImage(renderer::illustrationExr(il), output,
                                 renderer::inkExrWriteOptions(renderer::nominalHatchSpacingPx(scene.style.hatch)));
        else
            renderer::writeImage(il.composite, output);
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
        json.field("ink_length_px", il.hatch.inkLengthPx);
        json.field("min_spacing_violations", il.hatch.minSpacingViolations);
        json.field("strokes_near_singularities", il.hatch.strokesNearSingularities);
        json.field("singularities", int(singularities.singularities.size()));
        json.field("symmetry", fieldResult.field.nSym);
        if (svgReport) {
            json.field("penup_mm", svgReport->penUpMm);
            json.field("pendown_mm", svgReport->penDownMm);
            json.field("penup_ratio_vs_unsorted", svgReport->penUpRatioVsUnsorted);
            json.field("paths", svgReport->paths);
        }
        json.key("warnings").beginObject();
        for (const auto &[kind, count] : warningCounts()) json.field(kind, count);
        json.endObject();
        json.endObject();
        writeTextAtomically(opt.reportPath, json.str());
    }
    if (!opt.common.timingsPath.empty()) timings.write(opt.common.timingsPath, totalMs);
    std::cout << output << "\n"; // the written path, also with --quiet (scripts read it)
}

} // namespace

void addRenderCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<RenderOptions>();
    CLI::App *sub = app.add_subcommand("render", "render a scene as a pen-and-ink illustration (PNG/TIFF/JPEG, or EXR with channels)");
    sub->add_option("scene", opt->scenePath, "scene file (YAML, see scenes/README.md)")->required();
    sub->add_option("-o,--output", opt->outputPath,
                    "output image (.png .exr .tif .tiff .jpg .jpeg) or layered vector drawing (.svg); "
                    "overrides the scene's output");
    sub->add_option("--paper", opt->paper, "SVG page size: a4 (default), a3, letter, or WIDTHxHEIGHT in mm");
    sub->add_option("--margin-mm", opt->marginMm, "SVG page margin in mm (default 10); the picture is fitted inside");
    sub->add_flag("--no-plotter", opt->noPlotter,
                  "SVG: skip the plotter pass (merging strokes whose ends meet within 0.5 px, "
                  "simplifying within 0.25 px, ordering to cut pen-up travel)");
    sub->add_option("--report", opt->reportPath,
                    "write stroke statistics (strokes, ink length, spacing violations, strokes near singularities; "
                    "with an SVG output also penup_mm, pendown_mm, penup_ratio_vs_unsorted, paths) as JSON");
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, &action] { action = [opt] { runRender(*opt); }; });
}

} // namespace rosy::cli
