/// \file cmd_remesh.cpp
/// `rosyhatch remesh SCENE_OR_MESH -o OUT`: a quad-dominant (4-RoSy) or
/// triangle-dominant (6-RoSy) mesh along the scene's field (or the default
/// curvature field of a bare mesh), written through OpenMesh's writers, with the
/// quality report of remesh/quality.h (docs/remeshing.md).

#include "cli/commands.h"

#include "core/atomic_file.h"
#include "core/diagnostics.h"
#include "core/error.h"
#include "core/json.h"
#include "field/mesh/poly_mesh.h"
#include "field/primitives.h"
#include "remesh/input_refinement.h"
#include "remesh/quality.h"
#include "remesh/remesh.h"
#include "remesh/streamline_network.h"
#include "renderer/mesh_picture.h"
#include "renderer/output/image_io.h"
#include "renderer/output/svg.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"

#include <fmt/format.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>

namespace rosy::cli {
namespace {

struct RemeshCliOptions {
    std::string input, output, reportPath;
    std::string imagePath; ///< --image: a picture of the remeshed surface (raster or .svg)
    std::string edge = "1%"; ///< world units, or a percentage of the bounding-box diagonal
    std::string separatrices = "off";
    std::string method = "position"; ///< --method position|streamlines
    std::vector<std::string> positionOnlyGiven; ///< position-field options given on the command line
    /// --separatrix-length: multiples of L (the network's own; "inf": full length)
    std::string separatrixLength = fmt::format("{}", remesh::StreamlineNetworkOptions{}.separatrixLength);
    bool separatrixLengthGiven = false;
    std::string thinParts = "on";
    std::string refineInput = "on"; ///< --refine-input: remesh::refineCoarseInput() before the field
    std::string dislocations = "move"; ///< --dislocations keep|move|remove (RemeshOptions::dislocationReach)
    bool dislocationsGiven = false;
    double dislocationReach = 0; ///< --dislocation-reach: lattice spacings (0: the mode's own)
    bool dislocationReachGiven = false;
    double adaptiveScale = 0;
    double anisotropicScale = remesh::RemeshOptions{}.anisotropicScale;
    double featureAngle = 50; ///< --feature-angle: degrees, 0 = off (field constraint and snapping)
    bool featureAngleGiven = false;
    int symmetry = 4;
    bool symmetryGiven = false;
    std::vector<std::string> overrides;
    CommonOptions common;
};

/// "--edge": a length in world units ("0.02") or a percentage of the diagonal ("1%").
struct EdgeSpec {
    double value = 1;
    bool relative = true;
    double resolve(double diagonal) const { return relative ? value / 100.0 * diagonal : value; }
};

EdgeSpec parseEdge(const std::string &text) {
    EdgeSpec e;
    std::string t = text;
    e.relative = !t.empty() && t.back() == '%';
    if (e.relative) t.pop_back();
    try {
        size_t used = 0;
        e.value = std::stod(t, &used);
        if (used != t.size()) throw std::invalid_argument(t);
    } catch (const std::exception &) {
        throw InputError(FileLoc{"--edge"}, "'" + text + "' is not a length",
                         "give a length in the mesh's units (0.02) or a percentage of its bounding-box diagonal (1%)");
    }
    if (!(e.value > 0) || !std::isfinite(e.value) || (e.relative && (e.value < 0.1 || e.value > 50)))
        throw InputError(FileLoc{"--edge"}, "'" + text + "' is out of range",
                         "a positive length, or a percentage of the diagonal in [0.1%, 50%]");
    return e;
}

/// The remesh does not keep the input's topology or misses a part of it
/// (remesh::QualityReport::topologyLost, partsMissing): say what, where first, and
/// what to try. The mesh is still written (exit 0).
void warnThinParts(const std::string &output, const remesh::QualityReport &q) {
    std::string what;
    auto add = [&](const std::string &s) { what += (what.empty() ? "" : "; ") + s; };
    char buf[160];
    if (q.inputBoundaryEdges == 0 && !q.closed) {
        std::snprintf(buf, sizeof buf, "open: %d boundary edges, the input has none", q.boundaryEdges);
        add(buf);
    }
    if (q.eulerCharacteristic != q.inputEulerCharacteristic) {
        std::snprintf(buf, sizeof buf, "chi %d, the input's %d", q.eulerCharacteristic, q.inputEulerCharacteristic);
        add(buf);
    }
    if (q.components != q.inputComponents) {
        std::snprintf(buf, sizeof buf, "%d pieces, the input's %d", q.components, q.inputComponents);
        add(buf);
    }
    if (q.genus != q.inputGenus) {
        std::snprintf(buf, sizeof buf, "genus %d, the input's %d", q.genus, q.inputGenus);
        add(buf);
    }
    if (!q.manifold) {
        std::snprintf(buf, sizeof buf, "not manifold: %d edges, %d vertices", q.nonManifoldEdges,
                      q.nonManifoldVertices);
        add(buf);
    }
    if (!q.oriented) add(std::to_string(q.inconsistentEdges) + " edges not consistently oriented");
    if (q.flippedFaces > 0) add(std::to_string(q.flippedFaces) + (q.flippedFaces == 1 ? " flipped face" : " flipped faces"));
    const double L = q.edgeLength;
    if (q.partsMissing()) {
        std::snprintf(buf, sizeof buf, "a part of the input is missing: (%.4g, %.4g, %.4g) is %.1f L from the output",
                      q.farthestInputPoint.x(), q.farthestInputPoint.y(), q.farthestInputPoint.z(),
                      q.distanceInToOutPct * q.diagonal / 100 / L);
        add(buf);
    }
    std::string where;
    if (!q.problems.empty()) {
        std::snprintf(buf, sizeof buf, ", first near (%.4g, %.4g, %.4g)", q.problems[0].x(), q.problems[0].y(),
                      q.problems[0].z());
        where = buf;
    }
    const double shorter = q.diagonal > 0 ? 50 * q.edgeLength / q.diagonal : 0;
    std::snprintf(buf, sizeof buf, "%.2g%%", shorter);
    warn(output, "remesh-thin-parts",
         std::string(q.topologyLost() ? "the remesh does not keep the input's topology (" : "the remesh is not whole (") +
             what + ")" + where +
             ": the lattice cannot follow a part, or a gap between two parts, about as narrow as the edge length "
             "or narrower (a tail, a finger, a rim, a tail lying on the body); an edge well below that width keeps "
             "it (half the length now: --edge " + buf +
             "; docs/remeshing.md, \"When the topology is not kept\")" +
             (q.problems.empty() ? "" : ". The report's quality.topology.problems_at lists such places"));
}

void runRemesh(const RemeshCliOptions &opt) {
    using Clock = std::chrono::steady_clock;
    const auto tStart = Clock::now();
    const bool isScene = hasExtension(opt.input, ".yaml") || hasExtension(opt.input, ".yml");
    // A bare mesh with --set is the scene `mesh: FILE` (scenes::parseSceneOrMesh);
    // without, the mesh alone as before.
    const bool meshWithOverrides = !isScene && !opt.overrides.empty() && scenes::isMeshPath(opt.input);
    if (!isScene && !meshWithOverrides && !opt.overrides.empty())
        throw InputError(FileLoc{"--set " + opt.overrides.front()}, "--set overrides keys of a scene file",
                         "give a scene (.yaml) or a mesh (.obj .ply .off .stl)");
    if (!hasExtension(opt.output, ".obj") && !hasExtension(opt.output, ".off") && !hasExtension(opt.output, ".ply"))
        throw InputError(FileLoc{"-o"}, "cannot write a polygon mesh named '" + opt.output + "'",
                         "use .obj, .off or .ply (STL has triangles only)");
    if (opt.separatrices != "on" && opt.separatrices != "off")
        throw InputError(FileLoc{"--separatrices"}, "'" + opt.separatrices + "' is not on or off", "use on or off");
    if (opt.method != "position" && opt.method != "streamlines")
        throw InputError(FileLoc{"--method"}, "'" + opt.method + "' is not position or streamlines",
                         "use position (the default) or streamlines");
    if (opt.method == "streamlines" && !opt.positionOnlyGiven.empty())
        throw InputError(FileLoc{opt.positionOnlyGiven.front()},
                         opt.positionOnlyGiven.front() + " is an option of the position field, which --method streamlines does not use",
                         "leave it out, or use --method position");
    if (opt.separatrixLengthGiven && opt.method != "streamlines")
        throw InputError(FileLoc{"--separatrix-length"},
                         "--separatrix-length is an option of the streamline network; the position field pins the "
                         "lattice at each singularity instead of tracing separatrices",
                         "leave it out, or use --method streamlines");
    if (opt.separatrixLengthGiven && opt.separatrices != "on")
        throw InputError(FileLoc{"--separatrix-length"}, "--separatrix-length needs --separatrices on",
                         "add --separatrices on, or leave it out");
    double separatrixLength = std::numeric_limits<double>::infinity();
    if (opt.separatrixLength != "inf") {
        char *end = nullptr;
        separatrixLength = std::strtod(opt.separatrixLength.c_str(), &end);
        if (opt.separatrixLength.empty() || *end != '\0' || !(separatrixLength > 0) || !std::isfinite(separatrixLength))
            throw InputError(FileLoc{"--separatrix-length"},
                             "'" + opt.separatrixLength + "' is not a positive number of edge lengths or inf",
                             "use e.g. --separatrix-length 6, or inf for full separatrices");
    }
    if (opt.thinParts != "on" && opt.thinParts != "off")
        throw InputError(FileLoc{"--thin-parts"}, "'" + opt.thinParts + "' is not on or off", "use on or off");
    if (opt.refineInput != "on" && opt.refineInput != "off")
        throw InputError(FileLoc{"--refine-input"}, "'" + opt.refineInput + "' is not on or off", "use on or off");
    if (opt.dislocations != "keep" && opt.dislocations != "move" && opt.dislocations != "remove")
        throw InputError(FileLoc{"--dislocations"}, "'" + opt.dislocations + "' is not keep, move or remove",
                         "use keep, move or remove");
    if (opt.symmetry != 4 && opt.symmetry != 6)
        throw InputError(FileLoc{"--symmetry"}, "remeshing needs N = 4 (quads) or 6 (triangles), got " +
                                                    std::to_string(opt.symmetry),
                         "use --symmetry 4 or 6");
    const EdgeSpec edge = parseEdge(opt.edge);
    const bool imageSvg = hasExtension(opt.imagePath, ".svg");
    if (!opt.imagePath.empty() && !imageSvg && !renderer::isSupportedImagePath(opt.imagePath))
        throw InputError(FileLoc{"--image"}, "cannot write an image named '" + opt.imagePath + "'",
                         std::string("use one of the extensions ") + renderer::supportedImageExtensions() +
                             ", or .svg for the edges as pen layers");

    scenes::SceneDesc desc;
    if (isScene || meshWithOverrides) {
        desc = scenes::parseSceneOrMesh(opt.input, opt.overrides);
    } else {
        desc.path = opt.input;
        desc.mesh.file = scenes::Located<std::string>{opt.input, FileLoc{opt.input}};
        desc.mesh.loc = FileLoc{opt.input};
    }
    checkWritable(opt.output);
    if (!opt.reportPath.empty()) checkWritable(opt.reportPath);
    if (!opt.common.timingsPath.empty()) checkWritable(opt.common.timingsPath);
    if (!opt.imagePath.empty()) checkWritable(opt.imagePath);
    for (const std::string &out : {opt.output, opt.reportPath, opt.common.timingsPath, opt.imagePath}) {
        checkNotAnInput(out, opt.input, isScene ? "scene file" : "input mesh");
        if (desc.mesh.file) checkNotAnInput(out, desc.mesh.file->value, "input mesh");
    }
    // The scene's own symmetry when it is 4 or 6 and --symmetry was not given.
    int nSym = opt.symmetry;
    const int sceneSym = desc.field.given ? desc.field.spec.nSym : 4;
    if (!opt.symmetryGiven && (sceneSym == 4 || sceneSym == 6)) nSym = sceneSym;
    // Sharp features and boundaries: the field is aligned to the feature curves
    // (field.features.angle, replaced by --feature-angle) and the remesher keeps them.
    // N = 6 defaults to the boundary only (179°: no crease is that sharp): a triangle
    // lattice cannot have rows along two creases at 90° (docs/remeshing.md).
    const double featureAngle = opt.featureAngleGiven || nSym == 4 ? opt.featureAngle : 179.0;
    if (opt.dislocationReachGiven && opt.dislocations == "keep")
        throw InputError(FileLoc{"--dislocation-reach"}, "--dislocations keep moves nothing, so it has no reach",
                         "use --dislocations move or remove with --dislocation-reach, or leave it out");
    if (nSym != 4 && opt.dislocationReachGiven)
        throw InputError(FileLoc{"--dislocation-reach"}, "dislocations are moved in square lattices only (N = 4), not N = " +
                                                             std::to_string(nSym),
                         "leave --dislocation-reach out with -n 6");
    if (nSym != 4 && opt.dislocationsGiven && opt.dislocations != "keep")
        throw InputError(FileLoc{"--dislocations"}, "dislocations are moved in square lattices only (N = 4), not N = " +
                                                        std::to_string(nSym),
                         "leave --dislocations out with -n 6");
    desc.field.spec.featureAngleDeg = featureAngle;

    // OpenImageIO maps while the field is built (renderer/output/image_io.h).
    if (!opt.imagePath.empty() && !imageSvg) renderer::preloadImageIo();
    OutputBatch outputs;
    scenes::PipelineOptions popt;
    popt.load = field::LoadOptions{opt.common.maxFaces};
    if (opt.common.threads > 0) popt.threads = opt.common.threads;
    popt.nSym = nSym;
    // Edits name singularities of the scene's own field: only with its own N.
    popt.applyEdits = nSym == sceneSym;
    double edgeLength = 0;
    // A coarse mesh (a CAD part's few large triangles) gets vertices at about the
    // lattice's spacing before its field is built: the field lives on the vertices,
    // and interpolated across faces many cells wide it swirls (docs/remeshing.md,
    // "Coarse meshes refined"). Not where the scene's edits name singularities by id:
    // those are ids of the field on the mesh as given.
    bool idEdits = false;
    if (popt.applyEdits)
        for (const scenes::FieldEditDesc &e : desc.field.edits)
            idEdits = idEdits || e.op != field::FieldEdit::Op::CancelNear;
    std::optional<remesh::InputRefinement> refinement;
    popt.afterLoad = [&](scenes::Scene &scene) {
        field::Vec3 lo, hi;
        scene.mesh.bounds(lo, hi);
        edgeLength = edge.resolve((hi - lo).norm());
        // The field ignores the creases shorter than 2 L, as the remesher does
        // (RemeshOptions::featureAngleDeg); read by the field stage, which follows.
        desc.field.spec.featureMinLength = 2 * edgeLength / std::max(1e-300, (hi - lo).norm());
        if (opt.refineInput != "on" || !(edgeLength > 0) || !std::isfinite(edgeLength)) return;
        if (idEdits) {
            warn(scene.mesh.name(), "remesh-refine-input",
                 "the mesh is not refined before its field is built (--refine-input): the scene's edits name "
                 "singularities by id, which are ids of the field on the mesh as given; name them by position "
                 "(cancel_near) to have it refined");
            return;
        }
        refinement.emplace();
        scene.mesh = remesh::refineCoarseInput(scene.mesh, edgeLength, opt.common.maxFaces, &*refinement);
    };
    if (!opt.common.quiet) popt.onStage = [](const std::string &stage, double ms) {
        std::fprintf(stderr, "  %s %.0f ms\n", stage.c_str(), ms);
    };
    scenes::SceneField sf = scenes::buildSceneField(desc, popt);
    const field::TangentFrames &frames = *sf.loaded.frames;
    const field::RosyField &rosyField = sf.field.field.field;

    remesh::RemeshOptions ropt;
    ropt.edgeLength = edgeLength;
    ropt.separatrices = opt.separatrices == "on";
    ropt.thinParts = opt.thinParts == "on";
    ropt.scaleStrength = opt.adaptiveScale;
    ropt.anisotropicScale = opt.anisotropicScale;
    ropt.featureAngleDeg = featureAngle;
    ropt.maxVertices = opt.common.maxFaces;
    remesh::setDislocationMode(ropt, nSym != 4 || opt.dislocations == "keep" ? remesh::DislocationMode::Keep
                                     : opt.dislocations == "move"            ? remesh::DislocationMode::Move
                                                                             : remesh::DislocationMode::Remove);
    // (--dislocation-reach with keep or N = 6 was refused above.)
    if (opt.dislocationReachGiven) ropt.dislocationReach = opt.dislocationReach;
    auto t0 = Clock::now();
    remesh::RemeshResult result;
    if (opt.method == "streamlines") {
        remesh::StreamlineNetworkOptions sopt;
        sopt.edgeLength = edgeLength;
        sopt.separatrices = ropt.separatrices;
        sopt.separatrixLength = separatrixLength;
        sopt.maxVertices = opt.common.maxFaces;
        result = remesh::remeshStreamlines(frames, rosyField, sf.field.singularities, sopt);
    } else {
        result = remesh::remesh(frames, rosyField, sf.field.singularities, ropt);
    }
    if (result.polygons.empty() && frames.mesh().nFaces() > 0) {
        char length[64];
        std::snprintf(length, sizeof length, "%.4g", edgeLength);
        throw InputError(FileLoc{"--edge"},
                         std::string("at edge length ") + length + " (" + opt.edge +
                             ") the remesh has no face: the surface is thinner than the edge length everywhere",
                         "use a shorter --edge (nothing was written)");
    }
    const double remeshMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    t0 = Clock::now();
    const remesh::QualityReport quality = remesh::measureQuality(result.positions, result.polygons, frames, rosyField,
                                                                 sf.field.singularities, edgeLength);
    const double qualityMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();

    field::writePolyMesh(opt.output, result.poly);
    double imageMs = -1;
    if (!opt.imagePath.empty()) {
        // The remeshed surface through the scene's camera (a bare mesh's automatic
        // one), with the field's singularities as rings (renderer/mesh_picture.h).
        t0 = Clock::now();
        // Singularities of index ±1/N that did not end up as one irregular vertex or
        // face get a second ring (the report's singularities_as_one_irregular).
        renderer::MeshPictureOptions mpo;
        mpo.regularSides = nSym == 6 ? 3 : 4;
        std::vector<field::Vec3> singular;
        const std::vector<field::Singularity> &all = sf.field.singularities.singularities;
        for (size_t i = 0; i < all.size(); ++i)
            if (all[i].indexNumerator != 0) {
                singular.push_back(all[i].position);
                mpo.singularityAsOne.push_back(quality.singularityAsOneIrregular[i]);
            }
        const renderer::FieldDrawing drawing =
            renderer::drawMeshPicture(result.positions, result.polygons, singular, sf.loaded.scene->camera, mpo);
        if (imageSvg) {
            renderer::SvgOptions svg = renderer::svgOptionsFor(desc.style.style.page);
            svg.layerLabels = renderer::kMeshPictureLayerLabels;
            renderer::writeSvg(renderer::fieldPictureStrokes(drawing), svg, opt.imagePath);
        }
        else renderer::writeImage(renderer::rasterizeFieldDrawing(drawing), opt.imagePath);
        imageMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }
    if (quality.topologyLost() || quality.partsMissing()) warnThinParts(opt.output, quality);
    std::vector<std::pair<std::string, double>> ms = sf.timingsMs;
    // thin_parts is part of the hierarchy, distance_repair of the extraction
    for (const char *stage : {"hierarchy", "thin_parts", "position", "dislocations", "extraction", "distance_repair",
                              "streamlines", "arrangement"})
        if (result.timingsMs.count(stage)) ms.emplace_back(stage, result.timingsMs.at(stage));
    ms.emplace_back("remesh", remeshMs);
    ms.emplace_back("quality", qualityMs);
    if (imageMs >= 0) ms.emplace_back("image", imageMs);
    ms.emplace_back("total", std::chrono::duration<double, std::milli>(Clock::now() - tStart).count());
    if (!opt.common.quiet) {
        std::printf("%s: %d vertices, %d faces (%.1f %% %s), %d irregular vertices (%d of %d singularities as one), "
                    "angle deviation p90 %.1f deg, "
                    "edge CV %.3f, distance %.2f %% / %.2f %% of the diagonal; %s, %s, chi %d (input %d)\n",
                    opt.output.c_str(), quality.vertices, quality.faces, 100 * quality.regularFaceFraction,
                    nSym == 6 ? "triangles" : "quads", quality.irregularVertices, quality.singularitiesAsOneIrregular,
                    quality.singularities, quality.angleDevP90Deg,
                    quality.edgeLengthCv, quality.distanceOutToInPct, quality.distanceInToOutPct,
                    quality.closed ? "closed" : "open", quality.manifold && quality.oriented ? "manifold, oriented"
                                                                                              : "NOT manifold/oriented",
                    quality.eulerCharacteristic, quality.inputEulerCharacteristic);
    }
    if (!opt.reportPath.empty()) {
        JsonWriter json;
        // A reach or length that may be infinite: the number, or "unbounded".
        auto valueOrUnbounded = [&](double v) {
            if (std::isfinite(v)) json.value(v);
            else json.value("unbounded");
        };
        json.beginObject();
        json.field("input", opt.input).field("output", opt.output);
        json.field("method", opt.method == "streamlines" ? "streamline-network" : "position-field");
        json.key("options").beginObject();
        json.field("symmetry", nSym).field("edge_length", edgeLength).field("edge", opt.edge);
        if (opt.method == "streamlines") {
            // The network's own options; the position field's do not apply.
            const remesh::StreamlineNetworkOptions sopt;
            json.field("separatrices", ropt.separatrices).field("feature_angle", ropt.featureAngleDeg);
            json.field("stop_distance", sopt.stopDistance).field("seed_distance", sopt.seedDistance);
            json.key("separatrix_length"); // multiples of the edge length; null without separatrices
            if (!ropt.separatrices) json.null();
            else valueOrUnbounded(separatrixLength);
        } else {
            json.field("separatrices", ropt.separatrices).field("thin_parts", ropt.thinParts);
            json.field("adaptive_scale", ropt.scaleStrength);
            json.field("anisotropic_scale", ropt.anisotropicScale).field("feature_angle", ropt.featureAngleDeg);
            json.field("dislocations", ropt.dislocationReach > 0 ? opt.dislocations : std::string("keep"));
            json.key("dislocation_reach");
            valueOrUnbounded(ropt.dislocationReach);
            // The cone settings count only where cones may take lone units (`remove`),
            // the pull wherever units move.
            const bool moves = ropt.dislocationReach > 0;
            const bool cones = moves && std::isfinite(ropt.dislocationConePenalty);
            json.key("dislocation_cone_penalty");
            cones ? json.value(ropt.dislocationConePenalty) : json.null();
            json.key("dislocation_cone_reach");
            cones ? json.value(ropt.dislocationConeReach) : json.null();
            json.key("dislocation_anchor");
            moves ? json.value(ropt.dislocationAnchor) : json.null();
        }
        json.endObject();
        if (refinement) {
            const remesh::InputRefinement &ri = *refinement;
            json.key("input_refinement").beginObject();
            json.field("max_edge", ri.maxEdge).field("long_edge_area_fraction", ri.longEdgeAreaFraction);
            json.field("applied", ri.applied).field("longest_edge_before", ri.refinement.maxEdgeBefore);
            json.field("edges_bisected", ri.refinement.bisections).field("delaunay_flips", ri.delaunayFlips);
            json.field("vertices_before", ri.verticesBefore);
            json.field("vertices_after", ri.verticesAfter).endObject();
        }
        json.key("field").beginObject().field("source", field::toString(sf.field.spec.source));
        json.field("singularities", int(sf.field.singularities.singularities.size())).endObject();
        json.key("repairs").beginObject();
        for (const auto &[k, n] : result.repairs) json.field(k, n);
        json.endObject();
        json.key("quality");
        remesh::writeQualityJson(json, quality);
        json.key("timings_ms").beginObject();
        for (const auto &[stage, t] : ms) json.field(stage, t);
        json.endObject().endObject();
        writeTextAtomically(opt.reportPath, json.str());
    }
    if (!opt.common.timingsPath.empty()) {
        JsonWriter json;
        json.beginObject();
        for (const auto &[stage, t] : ms) json.field(stage, t);
        json.endObject();
        writeTextAtomically(opt.common.timingsPath, json.str());
    }
    outputs.commit();
}

} // namespace

void addRemeshCommand(CLI::App &app, Action &action) {
    auto opt = std::make_shared<RemeshCliOptions>();
    CLI::App *sub = app.add_subcommand("remesh", "Quad-dominant (or triangle) remeshing along the N-RoSy field");
    sub->add_option("input", opt->input, "Scene (.yaml) or mesh (.obj .ply .off .stl)")->required();
    sub->add_option("-o,--output", opt->output, "Output polygon mesh (.obj, .off, .ply)")->required();
    sub->add_option("--edge", opt->edge, "Target edge length: world units, or N% of the bounding-box diagonal")
        ->capture_default_str();
    sub->add_option("--separatrices", opt->separatrices,
                    "on: pin the lattice at each singularity (separatrices become lattice lines), or with --method "
                    "streamlines trace each singularity's separatrices before any other line; off (default, measured "
                    "better): neither")
        ->capture_default_str();
    sub->add_option("--method", opt->method,
                    "position (default): a field-aligned position field (Jakob et al. 2015); streamlines: the "
                    "paper's streamline network (both directions at spacing L, separatrices first with "
                    "--separatrices on, intersected on the surface), closed surfaces and N = 4 only, kept to "
                    "compare (docs/remeshing.md, The streamline network, measured)")
        ->capture_default_str();
    sub->add_option("--separatrix-length", opt->separatrixLength,
                    "K > 0 (default 6), with --method streamlines --separatrices on: each separatrix is traced "
                    "K edge lengths from its singularity before any other line, as the paper does (\"for a "
                    "certain distance\"), so the singular points get rings of quads, and runs on from there as an "
                    "ordinary line; inf: all of each first, beside the separatrices of nearby singularities "
                    "(docs/remeshing.md, Separatrices in the network)")
        ->capture_default_str();
    sub->add_option("--refine-input", opt->refineInput,
                    "on (default): when faces with an edge longer than 2 L cover 5 % or more of the input's area, "
                    "its long edges are bisected (the surface unchanged) before the field is built, so the field "
                    "has vertices at about the lattice's spacing, which a CAD mesh of a few large triangles lacks; "
                    "off: the field on the mesh as given (docs/remeshing.md, Coarse meshes refined)")
        ->capture_default_str();
    sub->add_option("--thin-parts", opt->thinParts,
                    "on (default): a finer lattice where the surface is thinner than the edge length or faces "
                    "another part across a narrower gap (a tail, a finger, a tail on the body), down to a quarter "
                    "of it, so such parts are not cut off; off: one edge length everywhere (docs/remeshing.md, When the topology is not kept, step 6)")
        ->capture_default_str();
    sub->add_option("--adaptive-scale", opt->adaptiveScale,
                    "0 (default): edges of length L everywhere; x in (0, 2]: spacing L exp(x phi), phi absorbing the "
                    "field's curl: fewer irregular vertices, more spread in edge length (docs/remeshing.md)")
        ->check(CLI::Range(0.0, 2.0))
        ->capture_default_str();
    sub->add_option("--anisotropic-scale", opt->anisotropicScale,
                    "mu in [0, 2]: the spacings along the two field directions scaled apart, each by the scale that "
                    "closes its lattice lines (fewer irregular vertices, more spread in edge length); 0: L along "
                    "both; N = 4 only (docs/remeshing.md, Anisotropic scale)")
        ->check(CLI::Range(0.0, 2.0))
        ->capture_default_str();
    sub->add_option("--feature-angle", opt->featureAngle,
                    "D in degrees: creases whose faces' normals differ by more than D, and the boundary, are "
                    "feature curves; the field is aligned to them and the mesh keeps them (vertices on the curves "
                    "and corners, openings left open); 0: off; default 50 for -n 4, 179 (the boundary only) for -n 6 "
                    "(docs/remeshing.md, Sharp features and boundaries)")
        ->check(CLI::Range(0.0, 179.0))
        ->capture_default_str();
    sub->add_option("--dislocations", opt->dislocations,
                    "move (default): the lattice's dislocations (a triangle with a valence-5 corner where a row "
                    "is gained) moved into a partner or a singularity where that costs little (about half the "
                    "irregular vertices, a little more spread in edge length); keep: as the position field leaves "
                    "them; remove: every one with a partner or a singularity within 80 lattice spacings, one that "
                    "finds no partner ending beside a singularity, the strain spread wider (irregular vertices "
                    "mostly at the singularities, edge lengths and corner angles a little more spread); N = 4 only "
                    "(docs/remeshing.md, Dislocations moved)")
        ->capture_default_str();
    sub->add_option("--dislocation-reach", opt->dislocationReach,
                    "R > 0: how far a dislocation may be moved, in lattice spacings of clear path, instead of the "
                    "mode's own (move: 20, remove: 80); larger: fewer irregular vertices, more strain "
                    "(docs/remeshing.md, Dislocations moved)")
        ->check(CLI::PositiveNumber);
    sub->add_option("-n,--symmetry", opt->symmetry, "4 (quads) or 6 (triangles); default the scene's if 4 or 6")
        ->capture_default_str();
    sub->add_option("--report", opt->reportPath, "Write the quality report (JSON) here");
    sub->add_option("--image", opt->imagePath,
                    "Write a picture of the remeshed surface through the scene's camera: edges, faces that are not "
                    "quads (triangles for -n 6) tinted orange, irregular vertices (blue below the regular valence, "
                    "red above), the field's singularities as black rings; an image, or .svg for pen layers "
                    "(1 edges, 2 rings, 3 dots)");
    addSetOption(*sub, opt->overrides);
    addCommonOptions(*sub, opt->common);
    sub->callback([opt, sub, &action] {
        opt->symmetryGiven = sub->get_option("--symmetry")->count() > 0;
        opt->featureAngleGiven = sub->get_option("--feature-angle")->count() > 0;
        opt->dislocationsGiven = sub->get_option("--dislocations")->count() > 0;
        opt->dislocationReachGiven = sub->get_option("--dislocation-reach")->count() > 0;
        opt->separatrixLengthGiven = sub->get_option("--separatrix-length")->count() > 0;
        opt->positionOnlyGiven.clear();
        for (const char *name : {"--thin-parts", "--adaptive-scale", "--anisotropic-scale", "--dislocations",
                                 "--dislocation-reach"})
            if (sub->get_option(name)->count() > 0) opt->positionOnlyGiven.push_back(name);
        action = [opt] { runRemesh(*opt); };
    });
}

} // namespace rosy::cli
