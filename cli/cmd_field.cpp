/// \file cmd_field.cpp
/// `rosyhatch field SCENE_OR_MESH`: builds an N-RoSy field on a mesh, finds its
/// singularities, prints a summary and optionally writes the JSON report and a
/// PLY export of the member directions, the repaired mesh through OpenMesh's
/// writers (--export-mesh), and pictures of the field (--image, --image-before).
/// The work is the field pipeline, scenes::buildSceneField() (a bare mesh becomes a
/// scene of that mesh alone); this file parses flags, calls it, prints and writes.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "field/field_builder.h"
#include "field/field_io.h"
#include "field/mesh/mesh_io.h"
#include "field/mesh/mesh_stats.h"
#include "field/mesh/poly_mesh.h"
#include "field/separatrices.h"
#include "field/singularities.h"
#include "field/smoothing.h"
#include "renderer/output/image_io.h"
#include "renderer/field_picture.h"
#include "renderer/output/image.h"
#include "renderer/output/svg.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

namespace rosy::cli {
namespace {

struct FieldOptions {
    std::string input;
    int symmetry = 4;
    std::string source = "curvature";
    double smoothingLength = 0.08; // field::FieldSpec's default
    std::string weights = "meanvalue";
    std::vector<std::string> elements;
    std::string globalSmoothing; ///< "ITER[:STRENGTH]"
    std::vector<std::string> cancels, moves, cancelNears; ///< "I,J", "I:x,y,z", "x,y,z:x,y,z"
    /// The edit flags in the order they were given on the command line.
    std::vector<std::pair<std::string, std::string>> editOrder;
    bool separatrices = false;
    std::string jsonPath, plyPath;
    std::string exportMeshPath;    ///< --export-mesh: the repaired mesh through OpenMesh's writers
    bool exportMeshDirections = false;
    std::string imagePath, imageBeforePath; ///< field pictures after / before the edits
    std::vector<std::string> overrides;     ///< --set KEY=VALUE (scenes only)
    CommonOptions common;
    /// Options a scene's field block provides too: the flag wins only when given.
    std::vector<std::string> explicitFlags;
    bool given(const std::string &flag) const {
        return std::find(explicitFlags.begin(), explicitFlags.end(), flag) != explicitFlags.end();
    }
};


// "L,x,y,z[,phase_deg]" or "0,x,y,z,dx,dy,dz".
field::DesignElement parseElement(const std::string &text, int k) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    const FileLoc loc{"--element #" + std::to_string(k + 1)};
    while (std::getline(ss, item, ',')) {
        try {
            size_t used = 0;
            v.push_back(std::stod(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception &) {
            throw InputError(loc, "'" + item + "' is not a number", "write L,x,y,z[,phase_deg] or 0,x,y,z,dx,dy,dz");
        }
    }
    if (v.size() < 4 || v.size() > 7 || (v[0] != 0 && v.size() > 5) || (v[0] == 0 && v.size() != 4 && v.size() != 7))
        throw InputError(loc, "'" + text + "' has the wrong number of values",
                         "write L,x,y,z[,phase_deg] for L = -1 or 1, or 0,x,y,z,dx,dy,dz");
    field::DesignElement el;
    el.order = int(v[0]);
    if (double(el.order) != v[0]) throw InputError(loc, "the order must be -1, 0 or 1");
    el.position = field::Vec3(v[1], v[2], v[3]);
    if (el.order != 0 && v.size() == 5) el.phaseRad = v[4] * M_PI / 180.0;
    if (el.order == 0 && v.size() == 7) el.direction = field::Vec3(v[4], v[5], v[6]);
    el.label = loc.path;
    return el;
}

std::vector<double> parseNumbers(const std::string &text, const FileLoc &loc, const std::string &shape) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            size_t used = 0;
            v.push_back(std::stod(item, &used));
            if (used != item.size() || !std::isfinite(v.back())) throw std::invalid_argument(item);
        } catch (const std::exception &) {
            throw InputError(loc, "'" + item + "' is not a number", "write " + shape);
        }
    }
    return v;
}

field::Vec3 parsePoint(const std::string &text, const FileLoc &loc, const std::string &shape) {
    std::vector<double> v = parseNumbers(text, loc, shape);
    if (v.size() != 3) throw InputError(loc, "'" + text + "' is not a point x,y,z", "write " + shape);
    return {v[0], v[1], v[2]};
}

int parseId(const std::string &text, const FileLoc &loc, const std::string &shape) {
    try {
        size_t used = 0;
        long long id = std::stoll(text, &used);
        if (used == text.size() && id >= 0 && id < (1 << 30)) return int(id);
    } catch (const std::exception &) {
    }
    throw InputError(loc, "'" + text + "' is not a singularity id (a whole number >= 0)", "write " + shape);
}

// One edit flag, e.g. ("--cancel", "3,7") as the k-th edit flag on the command line.
scenes::FieldEditDesc parseEdit(const std::string &flag, const std::string &text, int k) {
    scenes::FieldEditDesc e;
    e.loc = FileLoc{flag + " #" + std::to_string(k + 1)};
    if (flag == "--cancel") {
        const std::string shape = "--cancel I,J (two ids from the singularity list)";
        const size_t comma = text.find(',');
        if (comma == std::string::npos) throw InputError(e.loc, "'" + text + "' is not two ids", "write " + shape);
        e.op = scenes::FieldEditDesc::Op::Cancel;
        e.a = parseId(text.substr(0, comma), e.loc, shape);
        e.b = parseId(text.substr(comma + 1), e.loc, shape);
    } else if (flag == "--move") {
        const std::string shape = "--move I:x,y,z";
        const size_t colon = text.find(':');
        if (colon == std::string::npos) throw InputError(e.loc, "'" + text + "' has no ':'", "write " + shape);
        e.op = scenes::FieldEditDesc::Op::Move;
        e.a = parseId(text.substr(0, colon), e.loc, shape);
        e.p = parsePoint(text.substr(colon + 1), e.loc, shape);
    } else {
        const std::string shape = "--cancel-near x,y,z:x,y,z";
        const size_t colon = text.find(':');
        if (colon == std::string::npos) throw InputError(e.loc, "'" + text + "' has no ':'", "write " + shape);
        e.op = scenes::FieldEditDesc::Op::CancelNear;
        e.p = parsePoint(text.substr(0, colon), e.loc, shape);
        e.q = parsePoint(text.substr(colon + 1), e.loc, shape);
    }
    return e;
}

void writeSingularityList(JsonWriter &json, const std::vector<field::Singularity> &list) {
    json.beginArray();
    for (size_t i = 0; i < list.size(); ++i) {
        const field::Singularity &s = list[i];
        json.beginObject().field("id", int(i)).field("face", s.face);
        json.key("position").beginArray().value(s.position.x()).value(s.position.y()).value(s.position.z()).endArray();
        json.field("index", s.index()).field("index_numerator", s.indexNumerator).endObject();
    }
    json.endArray();
}

/// {"method": ..., "iterations": N, "lobpcg_iterations": N, "fallback": null | "reason"}.
void writeEigenSolveJson(JsonWriter &json, const field::EigenSolveReport &solve) {
    json.beginObject().field("method", solve.method).field("iterations", solve.iterations);
    json.field("lobpcg_iterations", solve.lobpcgIterations).key("fallback");
    if (solve.fallbackReason.empty()) json.null();
    else json.value(solve.fallbackReason);
    json.endObject();
}

void writeEditsJson(JsonWriter &json, const std::vector<scenes::AppliedEdit> &edits) {
    json.key("edits").beginArray();
    for (const scenes::AppliedEdit &e : edits) {
        json.beginObject();
        const bool move = e.edit.op == scenes::FieldEditDesc::Op::Move;
        json.field("op", move ? "move" : "cancel");
        json.key("args").beginObject();
        if (move) {
            json.field("singularity", e.a);
            json.key("to").beginArray().value(e.edit.p.x()).value(e.edit.p.y()).value(e.edit.p.z()).endArray();
        } else {
            json.key("singularities").beginArray().value(e.a).value(e.b).endArray();
            if (e.edit.op == scenes::FieldEditDesc::Op::CancelNear) {
                json.key("near").beginArray();
                for (const field::Vec3 &p : {e.edit.p, e.edit.q})
                    json.beginArray().value(p.x()).value(p.y()).value(p.z()).endArray();
                json.endArray();
            }
        }
        json.endObject();
        json.field("region_faces", int(e.result.regionFaces.size()));
        json.field("free_vertices", e.result.freeVertices).field("rounds", e.result.rounds);
        json.key("singularities_before");
        writeSingularityList(json, e.before);
        json.key("singularities_after");
        writeSingularityList(json, e.after);
        json.endObject();
    }
    json.endArray();
}

void runField(const FieldOptions &opt) {
    using Clock = std::chrono::steady_clock;
    std::optional<tbb::global_control> threadLimit;
    if (opt.common.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, size_t(opt.common.threads));
    const bool isScene = hasExtension(opt.input, ".yaml") || hasExtension(opt.input, ".yml");
    std::optional<scenes::SceneDesc> scene;
    // A bare mesh with --set is the scene `mesh: FILE` (scenes::parseSceneOrMesh);
    // without, the mesh alone as before.
    const bool meshWithOverrides = !isScene && !opt.overrides.empty() && scenes::isMeshPath(opt.input);
    if (!isScene && !meshWithOverrides && !opt.overrides.empty())
        throw InputError(FileLoc{"--set " + opt.overrides.front()}, "--set overrides keys of a scene file",
                         "give a scene (.yaml) or a mesh (.obj .ply .off .stl), or use the field flags");
    if (isScene || meshWithOverrides) scene = scenes::parseSceneOrMesh(opt.input, opt.overrides);
    const bool fromScene = scene && scene->field.given;
    // A scene's field block is the base; each flag given explicitly overrides its part.
    field::FieldSpec spec = fromScene ? scene->field.spec : field::FieldSpec{};
    if (!fromScene || opt.given("--symmetry")) {
        field::checkSymmetry(opt.symmetry, "--symmetry");
        spec.nSym = opt.symmetry;
    }
    if (fromScene && !opt.given("--source")) {
        // keep the scene's source
    } else if (opt.source == "curvature") spec.source = field::FieldSource::Curvature;
    else if (opt.source == "smoothest") spec.source = field::FieldSource::Smoothest;
    else if (opt.source == "design") spec.source = field::FieldSource::Design;
    else throw InputError(FileLoc{"--source"}, "unknown field source '" + opt.source + "'",
                          "use curvature, smoothest or design");
    if (!(opt.smoothingLength == 0 || (opt.smoothingLength >= field::kMinSmoothingLength &&
                                       opt.smoothingLength <= field::kMaxSmoothingLength))) {
        std::ostringstream os;
        os << "--smoothing-length must be 0 (raw curvature directions) or in [" << field::kMinSmoothingLength
           << ", " << field::kMaxSmoothingLength << "], got " << opt.smoothingLength;
        throw InputError(FileLoc{"--smoothing-length"}, os.str(),
                         "a fraction of the bounding-box diagonal such as 0.08");
    }
    if (!fromScene || opt.given("--smoothing-length")) spec.smoothingLength = opt.smoothingLength;
    if (opt.weights == "meanvalue") spec.weights = field::LaplaceWeights::MeanValue;
    else if (opt.weights == "cotan") spec.weights = field::LaplaceWeights::Cotan;
    else throw InputError(FileLoc{"--weights"}, "unknown weights '" + opt.weights + "'", "use meanvalue or cotan");
    if (!opt.elements.empty()) spec.elements.clear();
    for (size_t k = 0; k < opt.elements.size(); ++k) spec.elements.push_back(parseElement(opt.elements[k], int(k)));
    // Edit flags replace the scene's edits: the scene's ids were chosen for its own field.
    std::vector<scenes::FieldEditDesc> edits;
    if (fromScene && opt.editOrder.empty()) edits = scene->field.edits;
    for (size_t k = 0; k < opt.editOrder.size(); ++k)
        edits.push_back(parseEdit(opt.editOrder[k].first, opt.editOrder[k].second, int(k)));
    if (!opt.globalSmoothing.empty()) {
        int iters = 0;
        double strength = 0.5;
        char extra = 0;
        int n = std::sscanf(opt.globalSmoothing.c_str(), "%d:%lf%c", &iters, &strength, &extra);
        if (n < 1 || n > 2 || iters < 0 || iters > 100000 || !(strength > 0 && strength <= 1))
            throw InputError(FileLoc{"--global-smoothing"}, "'" + opt.globalSmoothing + "' is not ITERATIONS[:STRENGTH]",
                             "e.g. 20:0.5 (strength in (0, 1])");
        spec.globalSmoothingIterations = iters;
        spec.globalSmoothingStrength = strength;
    }
    if (!opt.jsonPath.empty()) checkWritable(opt.jsonPath);
    if (!opt.plyPath.empty()) checkWritable(opt.plyPath);
    if (!opt.exportMeshPath.empty()) {
        if (!field::isMeshExportPath(opt.exportMeshPath))
            throw InputError(FileLoc{"--export-mesh"}, "cannot write a mesh named '" + opt.exportMeshPath + "'",
                             std::string("use one of the extensions ") + field::meshExportExtensions());
        checkWritable(opt.exportMeshPath);
    }
    if (opt.exportMeshDirections) {
        if (opt.exportMeshPath.empty())
            throw InputError(FileLoc{"--export-mesh-directions"}, "there is no --export-mesh to add directions to",
                             "give --export-mesh OUT.ply (or .obj, .off)");
        std::string ext = opt.exportMeshPath.substr(opt.exportMeshPath.size() - 4);
        for (char &c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ext == ".stl")
            throw InputError(FileLoc{"--export-mesh-directions"}, "STL files have no per-vertex data",
                             "export to .ply, .obj or .off to keep the directions");
    }
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);
    for (const auto &[flag, path] : {std::pair<std::string, std::string>{"--image", opt.imagePath},
                                     std::pair<std::string, std::string>{"--image-before", opt.imageBeforePath}}) {
        if (path.empty()) continue;
        if (!isSvgPath(path) && !renderer::isSupportedImagePath(path))
            throw InputError(FileLoc{flag}, "cannot write an image named '" + path + "'",
                             std::string("use one of the extensions ") + renderer::supportedImageExtensions() +
                                 " .svg");
        checkWritable(path);
    }
    for (const std::string &out : {opt.jsonPath, opt.plyPath, opt.exportMeshPath, opt.common.timingsPath,
                                   opt.imagePath, opt.imageBeforePath}) {
        checkNotAnInput(out, opt.input, isScene ? "scene file" : "input mesh");
        if (scene && scene->mesh.file) checkNotAnInput(out, scene->mesh.file->value, "input mesh");
    }
    if (!opt.imageBeforePath.empty() && edits.empty())
        throw InputError(FileLoc{"--image-before"}, "there are no edits to show the field before",
                         "give --cancel, --move or --cancel-near (or a scene with field edits), or use --image only");
    // Every output is published at the end, together, or none is (core/atomic_file.h).
    OutputBatch outputs;
    // OpenImageIO maps while the field is built (renderer/output/image_io.h).
    if ((!opt.imagePath.empty() && !isSvgPath(opt.imagePath)) ||
        (!opt.imageBeforePath.empty() && !isSvgPath(opt.imageBeforePath)))
        renderer::preloadImageIo();

    // The field pipeline (scenes/pipeline.h) on the scene, or on a bare mesh as a
    // scene of that mesh alone (automatic 1024² camera, default key light).
    scenes::SceneDesc desc;
    if (scene) {
        desc = std::move(*scene);
    } else {
        desc.path = opt.input;
        desc.mesh.file = scenes::Located<std::string>{opt.input, FileLoc{opt.input}};
    }
    desc.field.spec = spec;
    desc.field.edits = edits;
    scenes::PipelineOptions pipeline;
    pipeline.load = field::LoadOptions{opt.common.maxFaces};
    if (opt.common.threads > 0) pipeline.threads = opt.common.threads;
    pipeline.separatrices = opt.separatrices;
    pipeline.keepUnedited = !opt.imageBeforePath.empty();
    const auto tStart = Clock::now();
    const scenes::SceneField built = scenes::buildSceneField(desc, pipeline);
    const field::Mesh &mesh = built.loaded.scene->mesh;
    const field::TangentFrames &frames = *built.loaded.frames;
    const field::FieldResult &result = built.field.field;
    const field::SingularityReport &report = built.field.singularities;
    const std::vector<field::Separatrix> &separatrices = built.field.separatrices;
    const std::vector<scenes::AppliedEdit> &applied = built.field.edits;
    // Stage milliseconds: the pipeline's, with the field builder's own parts after the
    // stage that built the field kept: "field", or on a noisy scan "scan_field" (then
    // with the copy's smoothing first).
    std::vector<std::pair<std::string, double>> ms;
    const bool onCopy = built.field.smoothedSurface != nullptr;
    for (const auto &[stage, t] : built.timingsMs) {
        ms.emplace_back(stage, t);
        if (onCopy && stage == "scan_field") ms.emplace_back("scan_smoothing", built.field.smoothingMs);
        if (stage == (onCopy ? "scan_field" : "field"))
            for (const auto &[part, tp] : result.timingsMs) ms.emplace_back(part, tp);
    }
    // Pictures through the scene's camera.
    auto writePicture = [&](const std::string &path, const field::RosyField &rosyField,
                            const field::SingularityReport &rep, const std::vector<field::Separatrix> &seps,
                            const std::string &stage) {
        const auto t0 = Clock::now();
        const renderer::FieldDrawing drawing =
            renderer::drawFieldPicture(mesh, frames, rosyField, rep, seps, built.loaded.scene->camera);
        // SVG: the strokes through the SVG writer on its pen layers, on the scene's page
        // (A4 for a bare mesh); otherwise the raster picture.
        if (isSvgPath(path)) {
            renderer::SvgOptions svg = renderer::svgOptionsFor(desc.style.style.page);
            svg.layerLabels = renderer::kFieldPictureLayerLabels;
            renderer::writeSvg(renderer::fieldPictureStrokes(drawing), svg, path);
        }
        else renderer::writeImage(renderer::rasterizeFieldDrawing(drawing), path);
        ms.emplace_back(stage, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    };
    if (built.field.unedited)
        writePicture(opt.imageBeforePath, built.field.unedited->field, built.field.unedited->singularities,
                     built.field.unedited->separatrices, "image-before");
    if (!opt.imagePath.empty()) writePicture(opt.imagePath, result.field, report, separatrices, "image");
    ms.emplace_back("total", std::chrono::duration<double, std::milli>(Clock::now() - tStart).count());
    const field::MeshStats stats = field::computeStats(mesh);

    int nPos = 0, nNeg = 0;
    for (const auto &s : report.singularities) (s.indexNumerator > 0 ? nPos : nNeg)++;
    const double total = report.totalIndex(spec.nSym);
    const bool holds = std::abs(total - stats.eulerCharacteristic) < 1e-6;
    if (!opt.common.quiet) {
        std::printf("%s: %d vertices, %d faces, chi = %d, %d component(s), %d boundary loop(s), genus %d\n",
                    opt.input.c_str(), stats.vertices, stats.faces, stats.eulerCharacteristic, stats.components,
                    stats.boundaryLoops, stats.genus);
        std::printf("field: %d-RoSy from %s\n", spec.nSym, field::toString(spec.source));
        std::printf("singularities: %zu (%d positive, %d negative); index sum %.6g%s = chi %s\n",
                    report.singularities.size(), nPos, nNeg, double(report.indexNumeratorSum) / spec.nSym,
                    stats.boundaryLoops ? (" + boundary " + std::to_string(report.boundaryIndex)).c_str() : "",
                    holds ? "(Poincare-Hopf holds)" : "(MISMATCH: please report)");
        for (const scenes::AppliedEdit &e : applied) {
            if (e.edit.op == scenes::FieldEditDesc::Op::Move)
                std::printf("edit: moved singularity %d into face %d", e.a, e.result.targetFace);
            else
                std::printf("edit: cancelled singularities %d and %d", e.a, e.b);
            std::printf(" (region %zu faces, %d vertices relaxed, %d solve(s)); %zu -> %zu singularities\n",
                        e.result.regionFaces.size(), e.result.freeVertices, e.result.rounds, e.before.size(),
                        e.after.size());
        }
        if (opt.separatrices) std::printf("separatrices: %zu\n", separatrices.size());
        std::printf("timings:");
        for (const auto &[stage, t] : ms) std::printf(" %s %.1f ms", stage.c_str(), t);
        std::printf("\n");
        if (result.eigenSolve)
            std::printf("eigen-solve: %s, %d iterations%s\n", result.eigenSolve->method.c_str(),
                        result.eigenSolve->iterations,
                        result.eigenSolve->fallbackReason.empty()
                            ? ""
                            : (" (LOBPCG gave up after " + std::to_string(result.eigenSolve->lobpcgIterations) +
                               ": " + result.eigenSolve->fallbackReason + ")")
                                  .c_str());
    }
    if (!opt.jsonPath.empty()) {
        JsonWriter json;
        json.beginObject();
        json.field("input", opt.input);
        field::writeAnalysisJson(json, stats, report, spec.nSym);
        json.key("field").beginObject().field("symmetry", spec.nSym).field("source", field::toString(spec.source));
        json.field("smoothing_length", spec.smoothingLength).endObject();
        if (built.field.smoothedSurface) {
            // field/scan_noise.h: the field on the surface itself was its noise.
            json.key("scan_noise").beginObject();
            json.field("singularities_on_surface", double(built.field.noisySingularities));
            json.field("density", built.field.noisyDensity);
            json.field("smoothing_radius", built.field.smoothedSurface->radius).endObject();
        }
        writeEditsJson(json, applied);
        if (opt.separatrices) field::writeSeparatricesJson(json, separatrices);
        if (result.eigenSolve) {
            json.key("eigen_solve");
            writeEigenSolveJson(json, *result.eigenSolve);
        }
        json.key("timings_ms").beginObject();
        for (const auto &[stage, t] : ms) json.field(stage, t);
        json.endObject().endObject();
        writeTextAtomically(opt.jsonPath, json.str());
    }
    if (!opt.plyPath.empty()) field::writeFieldPly(opt.plyPath, frames, result.field);
    if (!opt.exportMeshPath.empty()) {
        field::MeshExportOptions exportOptions;
        if (opt.exportMeshDirections)
            for (int v = 0; v < mesh.nVertices(); ++v)
                exportOptions.vertexDirections.push_back(field::memberDirections(frames, result.field, v)[0]);
        field::writePolyMesh(opt.exportMeshPath, field::toPolyMesh(mesh), exportOptions);
    }
    if (!opt.common.timingsPath.empty()) {
        // Stage milliseconds, and the smoothest field's eigen-solve when there was one.
        JsonWriter json;
        json.beginObject();
        for (const auto &[stage, t] : ms) json.field(stage, t);
        if (result.eigenSolve) {
            json.key("eigen_solve");
            writeEigenSolveJson(json, *result.eigenSolve);
        }
        json.endObject();
        writeTextAtomically(opt.common.timingsPath, json.str());
    }
    if (!holds) throw std::logic_error("Poincare-Hopf check failed");
    outputs.commit();
}

} // namespace

void addFieldCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<FieldOptions>();
    CLI::App *sub = app.add_subcommand("field", "build an N-RoSy field, find its singularities, report and export it");
    sub->add_option("input", opt->input, "Scene (.yaml) or mesh (.obj .ply .off .stl)")->required();
    sub->add_option("-n,--symmetry", opt->symmetry, "Symmetry order N (1..12)")->capture_default_str();
    sub->add_option("--source", opt->source, "curvature | smoothest | design")->capture_default_str();
    sub->add_option("--smoothing-length", opt->smoothingLength,
                    "Curvature source: smoothing length relative to the bounding-box diagonal (0 = raw directions)")
        ->capture_default_str();
    sub->add_option("--weights", opt->weights, "Relaxation weights: meanvalue (the paper's) | cotan")->capture_default_str();
    sub->add_option("--element", opt->elements,
                    "Design element L,x,y,z[,phase_deg] (L = -1 or 1) or 0,x,y,z,dx,dy,dz; repeatable");
    sub->add_option("--global-smoothing", opt->globalSmoothing,
                    "The paper's global smoothing afterwards: ITERATIONS[:STRENGTH]");
    const std::vector<std::string> editFlags{"--cancel", "--move", "--cancel-near"};
    sub->add_option("--cancel", opt->cancels,
                    "Cancel singularities I,J (ids from the report, +1/N with -1/N); repeatable, "
                    "edits run in command-line order and ids are re-numbered after each")
        ->allow_extra_args(false);
    sub->add_option("--move", opt->moves, "Move singularity I to the surface point x,y,z: I:x,y,z; repeatable")
        ->allow_extra_args(false);
    sub->add_option("--cancel-near", opt->cancelNears,
                    "Cancel the opposite-sign pair nearest to two points: x,y,z:x,y,z; repeatable")
        ->allow_extra_args(false);
    sub->add_flag("--separatrices", opt->separatrices, "Trace separatrices and add them to the JSON report");
    sub->add_option("--json", opt->jsonPath, "Write the JSON report here");
    sub->add_option("--export", opt->plyPath, "Write the field as PLY with per-vertex member directions");
    sub->add_option("--export-mesh", opt->exportMeshPath,
                    "Write the repaired mesh through OpenMesh's writers (.obj, .off, .ply binary, .stl binary)");
    sub->add_flag("--export-mesh-directions", opt->exportMeshDirections,
                  "With --export-mesh: each vertex's first field direction (unit, world) in the format's "
                  "vertex-normal slot (OBJ vn, NOFF, PLY nx ny nz; not STL)");
    sub->add_option("--image", opt->imagePath,
                    "Write a picture of the field (after any edits): shaded mesh, streamlines, singularities "
                    "(red +, blue -, darker/larger for higher order), separatrices with --separatrices "
                    "(green outgoing, orange incoming); format from the extension: an image, or .svg for the "
                    "strokes as pen layers (1 streamlines, 2 separatrices, 3 singularities; no colours or shading)");
    sub->add_option("--image-before", opt->imageBeforePath,
                    "Write the same picture of the field before the edits, to compare with --image");
    addSetOption(*sub, opt->overrides);
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, sub, editFlags, &action] {
        // The edit flags are separate options, so their relative order comes from
        // the parse order: the k-th occurrence of a flag takes its k-th value.
        std::map<std::string, size_t> used;
        for (const CLI::Option *o : sub->parse_order()) {
            const std::string flag = "--" + o->get_single_name();
            if (std::find(editFlags.begin(), editFlags.end(), flag) == editFlags.end()) continue;
            const std::vector<std::string> &values = flag == "--cancel" ? opt->cancels
                                                     : flag == "--move" ? opt->moves
                                                                        : opt->cancelNears;
            size_t &k = used[flag];
            if (k < values.size()) opt->editOrder.emplace_back(flag, values[k++]);
        }
        for (const char *flag : {"--symmetry", "--source", "--smoothing-length"})
            if (sub->get_option(flag)->count() > 0) opt->explicitFlags.push_back(flag);
        action = [opt] { runField(*opt); };
    });
}

} // namespace rosy::cli
