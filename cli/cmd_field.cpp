/// \file cmd_field.cpp
/// `rosyhatch field SCENE_OR_MESH`: builds an N-RoSy field on a mesh, finds its
/// singularities, prints a summary and optionally writes the JSON report and a
/// PLY export of the member directions.

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json.h"
#include "field/field_builder.h"
#include "field/field_io.h"
#include "field/mesh_io.h"
#include "field/mesh_stats.h"
#include "field/singularities.h"
#include "scenes/scene.h"

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

namespace rosy::cli {
namespace {

struct FieldOptions {
    std::string input;
    int symmetry = 4;
    std::string source = "curvature";
    double smoothingLength = 0.04;
    std::string weights = "meanvalue";
    std::vector<std::string> elements;
    std::string globalSmoothing; ///< "ITER[:STRENGTH]"
    std::string jsonPath, plyPath;
    CommonOptions common;
};

bool endsWith(const std::string &s, const std::string &suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

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

void runField(const FieldOptions &opt) {
    using Clock = std::chrono::steady_clock;
    std::optional<tbb::global_control> threadLimit;
    if (opt.common.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, size_t(opt.common.threads));
    field::checkSymmetry(opt.symmetry, "--symmetry");
    field::FieldSpec spec;
    spec.nSym = opt.symmetry;
    if (opt.source == "curvature") spec.source = field::FieldSource::Curvature;
    else if (opt.source == "smoothest") spec.source = field::FieldSource::Smoothest;
    else if (opt.source == "design") spec.source = field::FieldSource::Design;
    else throw InputError(FileLoc{"--source"}, "unknown field source '" + opt.source + "'",
                          "use curvature, smoothest or design");
    if (!(opt.smoothingLength >= 0) || opt.smoothingLength > 10)
        throw InputError(FileLoc{"--smoothing-length"}, "must be in [0, 10]");
    spec.smoothingLength = opt.smoothingLength;
    if (opt.weights == "meanvalue") spec.weights = field::LaplaceWeights::MeanValue;
    else if (opt.weights == "cotan") spec.weights = field::LaplaceWeights::Cotan;
    else throw InputError(FileLoc{"--weights"}, "unknown weights '" + opt.weights + "'", "use meanvalue or cotan");
    for (size_t k = 0; k < opt.elements.size(); ++k) spec.elements.push_back(parseElement(opt.elements[k], int(k)));
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
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);

    std::vector<std::pair<std::string, double>> ms;
    auto t0 = Clock::now(), tStart = t0;
    auto lap = [&](const std::string &stage) {
        auto t = Clock::now();
        ms.emplace_back(stage, std::chrono::duration<double, std::milli>(t - t0).count());
        t0 = t;
    };
    field::Mesh mesh;
    if (endsWith(opt.input, ".yaml") || endsWith(opt.input, ".yml"))
        mesh = scenes::buildScene(scenes::parseSceneFile(opt.input)).mesh;
    else
        mesh = field::loadMesh(opt.input);
    lap("load");
    const field::MeshStats stats = field::computeStats(mesh);
    field::TangentFrames frames(mesh);
    lap("frames");
    field::FieldResult result = field::buildField(frames, spec);
    for (const auto &[stage, t] : result.timingsMs) ms.emplace_back(stage, t);
    t0 = Clock::now();
    const field::SingularityReport report = field::findSingularities(frames, result.field);
    lap("singularities");
    ms.emplace_back("total", std::chrono::duration<double, std::milli>(Clock::now() - tStart).count());

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
        std::printf("timings:");
        for (const auto &[stage, t] : ms) std::printf(" %s %.1f ms", stage.c_str(), t);
        std::printf("\n");
    }
    if (!opt.jsonPath.empty()) {
        JsonWriter json;
        json.beginObject();
        json.field("input", opt.input);
        field::writeAnalysisJson(json, stats, report, spec.nSym);
        json.key("field").beginObject().field("symmetry", spec.nSym).field("source", field::toString(spec.source));
        json.field("smoothing_length", spec.smoothingLength).endObject();
        json.key("timings_ms").beginObject();
        for (const auto &[stage, t] : ms) json.field(stage, t);
        json.endObject().endObject();
        const std::string text = json.str();
        writeAtomically(opt.jsonPath, [&](const std::string &tmp) {
            std::ofstream os(tmp, std::ios::binary);
            os << text;
            if (!os.flush()) throw IoError(opt.jsonPath, "write failed");
        });
    }
    if (!opt.plyPath.empty()) field::writeFieldPly(opt.plyPath, frames, result.field);
    if (!holds) throw std::logic_error("Poincare-Hopf check failed");
}

} // namespace

void addFieldCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<FieldOptions>();
    CLI::App *sub = app.add_subcommand("field", "Build an N-RoSy field, find its singularities, report and export it");
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
    sub->add_option("--json", opt->jsonPath, "Write the JSON report here");
    sub->add_option("--export", opt->plyPath, "Write the field as PLY with per-vertex member directions");
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, &action] { action = [opt] { runField(*opt); }; });
}

} // namespace rosy::cli
