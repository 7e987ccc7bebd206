#include "scenes/scene.h"

#include "core/input_file.h"
#include "scenes/overrides.h"
#include "scenes/style_block.h"
#include "scenes/style_presets.h"
#include "scenes/yaml_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace rosy::scenes {
namespace fs = std::filesystem;
using namespace detail;

namespace {

/// One parameter of a procedural primitive.
struct ParamSpec {
    const char *name;
    double defaultValue;
    double lo, hi;
    bool integer;
};

struct PrimitiveSpec {
    const char *name;
    std::vector<ParamSpec> params;
};

// Upper limits keep a typo from asking for hundreds of millions of triangles.
const std::vector<PrimitiveSpec> &primitiveSpecs() {
    static const std::vector<PrimitiveSpec> specs = {
        {"icosphere", {{"subdivisions", 3, 0, 8, true}, {"radius", 1, 1e-6, 1e6, false}}},
        {"ellipsoid",
         {{"subdivisions", 3, 0, 8, true},
          {"a", 1.5, 1e-6, 1e6, false},
          {"b", 1.0, 1e-6, 1e6, false},
          {"c", 0.75, 1e-6, 1e6, false}}},
        {"torus",
         {{"major_radius", 1.0, 1e-6, 1e6, false},
          {"minor_radius", 0.35, 1e-6, 1e6, false},
          {"nu", 64, 3, 4096, true},
          {"nv", 32, 3, 4096, true}}},
        {"genus2", {{"resolution", 48, 16, 512, true}}},
        {"cube", {{"n", 8, 1, 1024, true}}},
        {"rounded_cube_pair", {{"n", 32, 2, 1024, true}}},
        {"tetrahedron", {{"subdivisions", 0, 0, 8, true}}},
        {"octahedron", {{"subdivisions", 0, 0, 8, true}}},
        {"dodecahedron", {{"subdivisions", 0, 0, 8, true}}},
        {"icosahedron", {{"subdivisions", 0, 0, 8, true}}},
        {"disk", {{"rings", 16, 1, 2048, true}}},
        {"grid", {{"n", 16, 1, 4096, true}}},
        {"cylinder",
         {{"radius", 1.0, 1e-6, 1e6, false},
          {"height", 2.0, 1e-6, 1e6, false},
          {"n_around", 48, 3, 4096, true},
          {"n_along", 16, 1, 4096, true}}},
    };
    return specs;
}

/// `mesh.transform: {translate: [x, y, z], rotate: [rx, ry, rz], scale: s | [sx, sy, sz]}`.
void parseTransform(const Parser &p, const YAML::Node &node, TransformDesc &t) {
    t.given = true;
    t.loc = p.loc(node);
    for (const auto &[key, value] : p.entries(node, "mesh.transform", {"translate", "rotate", "scale"})) {
        const std::string &k = key.Scalar();
        const FileLoc l = p.loc(value);
        if (k == "translate") {
            t.translate = {p.vec3(value, "mesh.transform.translate"), l};
        } else if (k == "rotate") {
            t.rotateDeg = {p.vec3(value, "mesh.transform.rotate (degrees)", -3600.0, 3600.0), l};
        } else {
            const std::string hint = "scale must be positive: a number like 2 or a list [sx, sy, sz] (mirroring "
                                     "and flattening are not supported)";
            auto one = [&](const YAML::Node &n, const std::string &what) {
                const double v = p.number(n, what, -1e12, 1e12);
                if (!(v > 0)) p.fail(n, what + " must be positive, got " + Parser::fmt(v), hint);
                if (v < 1e-6 || v > 1e6) p.fail(n, what + " must be in [1e-06, 1e+06], got " + Parser::fmt(v), hint);
                return v;
            };
            if (value.IsSequence()) {
                if (value.size() != 3)
                    p.fail(value, "mesh.transform.scale must be a number or a list of 3 numbers, got a list of " +
                                      std::to_string(value.size()), hint);
                t.scale = {Vec3(one(value[0], "mesh.transform.scale[0]"), one(value[1], "mesh.transform.scale[1]"),
                                one(value[2], "mesh.transform.scale[2]")),
                           l};
            } else {
                t.scale = {Vec3::Constant(one(value, "mesh.transform.scale")), l};
            }
        }
    }
}

void parseMeshFile(const Parser &p, const YAML::Node &node, MeshDesc &mesh) {
    {
        const fs::path file =
            p.existingFile(node, p.text(node, "mesh"), "mesh", "paths are relative to the scene file's folder");
        std::error_code ec;
        // Links are followed; what they reach must be a file on disk (the readers check
        // header counts against its size, and a device such as /dev/zero never ends).
        if (!fs::is_regular_file(file, ec))
            p.fail(node, "mesh '" + file.string() + "' is not a regular file (a device, pipe or socket)",
                   "give a mesh file on disk");
        mesh.file = Located<std::string>{file.string(), p.loc(node)};
    }
}

void parseMesh(const Parser &p, const YAML::Node &node, MeshDesc &mesh) {
    mesh.loc = p.loc(node);
    if (node.IsScalar()) {
        parseMeshFile(p, node, mesh);
        return;
    }
    if (!node.IsMap())
        p.fail(node, "mesh must be a file path or a map like {primitive: icosphere}, got " +
                         Parser::kindOf(node));
    // Find the primitive first: which parameters are allowed depends on it.
    // A default-constructed YAML::Node converts to true, so presence is tracked apart.
    YAML::Node nameNode, fileNode;
    bool hasName = false, hasFile = false;
    for (auto it = node.begin(); it != node.end(); ++it) {
        if (it->first.IsScalar() && it->first.Scalar() == "primitive") nameNode = it->second, hasName = true;
        if (it->first.IsScalar() && it->first.Scalar() == "file") fileNode = it->second, hasFile = true;
    }
    if (hasName && hasFile)
        p.fail(fileNode, "mesh has both 'file' and 'primitive'", "keep one of them");
    if (hasFile) {
        for (const auto &[key, value] : p.entries(node, "mesh (file)", {"file", "transform"})) {
            if (key.Scalar() == "file") parseMeshFile(p, value, mesh);
            else parseTransform(p, value, mesh.transform);
        }
        return;
    }
    if (!hasName)
        p.fail(node, "mesh map needs a 'primitive' or a 'file' key",
               "e.g. mesh: {primitive: icosphere} or mesh: {file: bunny.off, transform: {scale: 2}}");
    std::string name = p.text(nameNode, "mesh.primitive");
    const PrimitiveSpec *spec = nullptr;
    for (const auto &s : primitiveSpecs())
        if (name == s.name) spec = &s;
    if (!spec)
        p.fail(nameNode, "unknown primitive '" + name + "'", suggest(name, primitiveNames()));
    mesh.primitive = Located<std::string>{name, p.loc(nameNode)};
    std::vector<std::string> allowed{"primitive", "transform"};
    for (const auto &ps : spec->params) {
        allowed.push_back(ps.name);
        mesh.params[ps.name] = Located<double>{ps.defaultValue, {}};
    }
    for (const auto &[key, value] : p.entries(node, "mesh (" + name + ")", allowed)) {
        const std::string &k = key.Scalar();
        if (k == "primitive") continue;
        if (k == "transform") {
            parseTransform(p, value, mesh.transform);
            continue;
        }
        for (const auto &ps : spec->params) {
            if (k != ps.name) continue;
            std::string what = "mesh." + k;
            double v = ps.integer ? double(p.integer(value, what, int(ps.lo), int(ps.hi)))
                                  : p.number(value, what, ps.lo, ps.hi);
            mesh.params[k] = Located<double>{v, p.loc(value)};
        }
    }
}

/// Largest camera.resolution width x height (documented in scenes/README.md).
constexpr long long kMaxPixels = 4096LL * 4096LL;

void parseCamera(const Parser &p, const YAML::Node &node, CameraDesc &cam) {
    cam.loc = p.loc(node);
    std::optional<Located<bool>> autoFlag;
    bool hasPosition = false, hasLookAt = false;
    const auto entries =
        p.entries(node, "camera",
                  {"auto", "projection", "position", "look_at", "up", "fov", "height", "direction",
                   "margin", "resolution"});
    for (const auto &[key, value] : entries) {
        const std::string &k = key.Scalar();
        FileLoc l = p.loc(value);
        if (k == "auto") {
            autoFlag = Located<bool>{p.boolean(value, "camera.auto"), l};
        } else if (k == "projection") {
            std::string s = p.text(value, "camera.projection");
            if (s == "perspective")
                cam.projection = {renderer::Projection::Perspective, l};
            else if (s == "orthographic")
                cam.projection = {renderer::Projection::Orthographic, l};
            else
                p.fail(value, "unknown projection '" + s + "'", suggest(s, {"perspective", "orthographic"}));
        } else if (k == "position") {
            cam.position = {p.vec3(value, "camera.position"), l};
            hasPosition = true;
        } else if (k == "look_at") {
            cam.lookAt = {p.vec3(value, "camera.look_at"), l};
            hasLookAt = true;
        } else if (k == "up") {
            cam.up = {p.vec3(value, "camera.up"), l};
            if (cam.up.value.norm() == 0.0) p.fail(value, "camera.up must not be [0, 0, 0]");
        } else if (k == "fov") {
            cam.fov = {p.number(value, "camera.fov (degrees)", 1.0, 179.0), l};
        } else if (k == "height") {
            cam.height = {p.number(value, "camera.height", 1e-9, 1e12), l};
        } else if (k == "direction") {
            cam.direction = {p.vec3(value, "camera.direction"), l};
            if (cam.direction.value.norm() == 0.0) p.fail(value, "camera.direction must not be [0, 0, 0]");
        } else if (k == "margin") {
            cam.margin = {p.number(value, "camera.margin", 0.0, 10.0), l};
        } else if (k == "resolution") {
            if (!value.IsSequence() || value.size() != 2)
                p.fail(value, "camera.resolution must be a list [width, height], got " + Parser::kindOf(value));
            cam.resolution = {{p.integer(value[0], "camera.resolution width", 1, 16384),
                               p.integer(value[1], "camera.resolution height", 1, 16384)},
                              l};
            // Rejected before anything is allocated: the render keeps 112 to 430 bytes
            // per pixel (G-buffer, screen field, layers, strokes; renderMemoryEstimate()),
            // 1.9 to 7.2 GB at the limit. What fits in the memory left is checked
            // after the mesh is loaded (cli/cmd_render.cpp).
            const long long pixels = 1LL * cam.resolution.value[0] * cam.resolution.value[1];
            if (pixels > kMaxPixels)
                p.fail(value, "camera.resolution " + std::to_string(cam.resolution.value[0]) + " x " +
                                  std::to_string(cam.resolution.value[1]) + " is " + std::to_string(pixels) +
                                  " pixels, more than the limit of " + std::to_string(kMaxPixels) +
                                  " (4096 x 4096; a render keeps 112 to 430 bytes per pixel)",
                       "render at most 16.7 million pixels, or use an SVG output for print sizes");
        }
    }
    cam.automatic = autoFlag ? autoFlag->value : !hasPosition;
    if (cam.automatic) {
        if (hasPosition || hasLookAt) {
            const YAML::Node &bad = hasPosition ? node["position"] : node["look_at"];
            p.fail(bad, "an automatic camera takes no position or look_at",
                   "remove them, or set auto: false");
        }
        Vec3 r = cam.direction.value.normalized().cross(cam.up.value.normalized());
        if (r.norm() < 1e-6)
            throw InputError(cam.direction.loc.line ? cam.direction.loc : cam.loc,
                             "camera.direction is parallel to camera.up", "tilt one of them");
        return;
    }
    if (!hasPosition) p.fail(node, "a camera with auto: false needs a position");
    if (!hasLookAt) p.fail(node, "a manual camera needs look_at", "e.g. look_at: [0, 0, 0]");
    if (cam.position.value == cam.lookAt.value)
        throw InputError(cam.lookAt.loc, "camera.look_at equals camera.position",
                         "look at a point away from the camera");
    Vec3 f = (cam.lookAt.value - cam.position.value).normalized();
    if (f.cross(cam.up.value.normalized()).norm() < 1e-6)
        throw InputError(cam.up.loc.line ? cam.up.loc : cam.lookAt.loc,
                         "camera.up is parallel to the viewing direction", "choose another up vector");
    if (cam.projection.value == renderer::Projection::Orthographic && cam.height.loc.line == 0)
        p.fail(node, "a manual orthographic camera needs height (world units the image spans vertically)");
}

void parseAmbientOcclusion(const Parser &p, const YAML::Node &node, AmbientOcclusionDesc &ao) {
    ao.loc = p.loc(node);
    if (node.IsScalar()) {
        ao.enabled = p.boolean(node, "ambient_occlusion");
        return;
    }
    if (!node.IsMap())
        p.fail(node, "ambient_occlusion must be true, false or a map like {samples: 16, radius: 0.1}, got " +
                         Parser::kindOf(node));
    ao.enabled = true;
    for (const auto &[key, value] : p.entries(node, "ambient_occlusion", {"samples", "radius"})) {
        const std::string &k = key.Scalar();
        if (k == "samples") {
            ao.samples = p.integer(value, "ambient_occlusion.samples", 1, 1024);
        } else if (k == "radius") {
            ao.radius = p.number(value, "ambient_occlusion.radius", 0.0, 10.0);
            if (!(ao.radius > 0.0))
                p.fail(value, "ambient_occlusion.radius must be greater than 0",
                       "a fraction of the mesh's bounding-box diagonal, e.g. 0.1");
        }
    }
}

void parseLights(const Parser &p, const YAML::Node &node, std::vector<LightDesc> &lights) {
    if (!node.IsSequence())
        p.fail(node, "lights must be a list like [{type: directional, direction: [1, 1, 1]}], got " +
                         Parser::kindOf(node));
    for (size_t i = 0; i < node.size(); ++i) {
        YAML::Node ln = node[i];
        std::string ctx = "lights[" + std::to_string(i) + "]";
        LightDesc d;
        d.loc = p.loc(ln);
        bool hasDirection = false, hasPosition = false;
        YAML::Node typeNode;
        for (const auto &[key, value] :
             p.entries(ln, ctx, {"type", "direction", "position", "intensity"})) {
            const std::string &k = key.Scalar();
            if (k == "type") {
                typeNode = value;
                std::string s = p.text(value, ctx + ".type");
                if (s == "directional")
                    d.light.type = renderer::Light::Type::Directional;
                else if (s == "point")
                    d.light.type = renderer::Light::Type::Point;
                else
                    p.fail(value, "unknown light type '" + s + "'", suggest(s, {"directional", "point"}));
            } else if (k == "direction") {
                d.light.direction = p.vec3(value, ctx + ".direction");
                if (d.light.direction.norm() == 0.0) p.fail(value, ctx + ".direction must not be [0, 0, 0]");
                hasDirection = true;
            } else if (k == "position") {
                d.light.position = p.vec3(value, ctx + ".position");
                hasPosition = true;
            } else if (k == "intensity") {
                d.light.intensity = p.number(value, ctx + ".intensity", 0.0, 1e6);
            }
        }
        if (!typeNode) p.fail(ln, ctx + " needs a type", "type: directional or type: point");
        if (d.light.type == renderer::Light::Type::Directional) {
            if (!hasDirection) p.fail(ln, "a directional light needs direction (toward the light)");
            if (hasPosition) p.fail(ln["position"], "a directional light has no position", "use direction");
        } else {
            if (!hasPosition) p.fail(ln, "a point light needs position");
            if (hasDirection) p.fail(ln["direction"], "a point light has no direction", "use position");
        }
        lights.push_back(d);
    }
}

field::DesignElement parseElement(const Parser &p, const YAML::Node &node, const std::string &ctx) {
    field::DesignElement el;
    bool hasPosition = false;
    std::optional<FileLoc> phaseLoc, directionLoc;
    for (const auto &[key, value] :
         p.entries(node, ctx, {"position", "order", "direction", "phase", "strength"})) {
        const std::string &k = key.Scalar();
        if (k == "position") {
            el.position = p.vec3(value, ctx + ".position");
            hasPosition = true;
        } else if (k == "order") {
            el.order = p.integer(value, ctx + ".order", -1, 1);
        } else if (k == "direction") {
            el.direction = p.vec3(value, ctx + ".direction");
            if (el.direction.norm() == 0.0) p.fail(value, ctx + ".direction must not be [0, 0, 0]");
            directionLoc = p.loc(value);
        } else if (k == "phase") {
            el.phaseRad = p.number(value, ctx + ".phase (degrees)", -3600.0, 3600.0) * M_PI / 180.0;
            phaseLoc = p.loc(value);
        } else if (k == "strength") {
            el.strength = p.number(value, ctx + ".strength", 1e-9, 1e9);
        }
    }
    if (!hasPosition) p.fail(node, ctx + " needs a position", "e.g. position: [0, 1, 0]");
    // An ignored key would silently do nothing: say so instead.
    if (el.order == 0 && phaseLoc)
        throw InputError(*phaseLoc, ctx + ".phase only applies to singular elements (order -1 or 1)",
               "use direction for order 0");
    if (el.order != 0 && directionLoc)
        throw InputError(*directionLoc, ctx + ".direction only applies to order 0", "use phase (degrees) for order -1 or 1");
    el.label = p.loc(node).str();
    return el;
}

void parseEdits(const Parser &p, const YAML::Node &node, std::vector<FieldEditDesc> &edits) {
    const std::string shape = "each edit is {cancel: [i, j]}, {move: {singularity: i, to: [x, y, z]}} "
                              "or {cancel_near: [[x, y, z], [x, y, z]]}";
    if (!node.IsSequence()) p.fail(node, "field.edits must be a list, got " + Parser::kindOf(node), shape);
    for (size_t i = 0; i < node.size(); ++i) {
        const YAML::Node en = node[i];
        const std::string ctx = "field.edits[" + std::to_string(i) + "]";
        const auto entries = p.entries(en, ctx, {"cancel", "move", "cancel_near"});
        if (entries.size() != 1) p.fail(en, ctx + " must hold exactly one operation", shape);
        const auto &[key, value] = entries.front();
        FieldEditDesc e;
        e.loc = p.loc(en);
        const std::string &k = key.Scalar();
        if (k == "cancel") {
            if (!value.IsSequence() || value.size() != 2)
                p.fail(value, ctx + ".cancel must be a list of two singularity ids, got " + Parser::kindOf(value),
                       "e.g. cancel: [3, 7]");
            e.op = FieldEditDesc::Op::Cancel;
            e.a = p.integer(value[0], ctx + ".cancel[0]", 0, 1 << 30);
            e.b = p.integer(value[1], ctx + ".cancel[1]", 0, 1 << 30);
        } else if (k == "move") {
            e.op = FieldEditDesc::Op::Move;
            bool hasId = false, hasTo = false;
            for (const auto &[mk, mv] : p.entries(value, ctx + ".move", {"singularity", "to"})) {
                if (mk.Scalar() == "singularity") {
                    e.a = p.integer(mv, ctx + ".move.singularity", 0, 1 << 30);
                    hasId = true;
                } else {
                    e.p = p.vec3(mv, ctx + ".move.to");
                    hasTo = true;
                }
            }
            if (!hasId || !hasTo)
                p.fail(value, ctx + ".move needs both singularity and to", "e.g. move: {singularity: 2, to: [0, 1, 0]}");
        } else {
            if (!value.IsSequence() || value.size() != 2)
                p.fail(value, ctx + ".cancel_near must be a list of two points, got " + Parser::kindOf(value),
                       "e.g. cancel_near: [[0, 1, 0], [0.1, 1, 0]]");
            e.op = FieldEditDesc::Op::CancelNear;
            e.p = p.vec3(value[0], ctx + ".cancel_near[0]");
            e.q = p.vec3(value[1], ctx + ".cancel_near[1]");
        }
        edits.push_back(e);
    }
}

void parseField(const Parser &p, const YAML::Node &node, FieldDesc &fd) {
    fd.given = true;
    fd.loc = p.loc(node);
    YAML::Node sourceNode;
    for (const auto &[key, value] :
         p.entries(node, "field",
                   {"symmetry", "source", "smoothing_length", "weights", "global_smoothing", "elements", "edits",
                    "features"})) {
        const std::string &k = key.Scalar();
        if (k == "symmetry") {
            fd.spec.nSym = p.integer(value, "field.symmetry", 1, field::kMaxSymmetry);
            fd.symmetryLoc = p.loc(value);
        } else if (k == "source") {
            const std::string s = p.text(value, "field.source");
            if (s == "curvature") fd.spec.source = field::FieldSource::Curvature;
            else if (s == "smoothest") fd.spec.source = field::FieldSource::Smoothest;
            else if (s == "design") fd.spec.source = field::FieldSource::Design;
            else p.fail(value, "unknown field source '" + s + "'", suggest(s, {"curvature", "smoothest", "design"}));
            fd.sourceLoc = p.loc(value);
            sourceNode = value;
        } else if (k == "smoothing_length") {
            fd.spec.smoothingLength = p.number(value, "field.smoothing_length", 0.0, field::kMaxSmoothingLength);
            if (fd.spec.smoothingLength != 0 && fd.spec.smoothingLength < field::kMinSmoothingLength)
                p.fail(value, "field.smoothing_length must be 0 (raw curvature directions) or in [" +
                                  Parser::fmt(field::kMinSmoothingLength) + ", " +
                                  Parser::fmt(field::kMaxSmoothingLength) + "], got " +
                                  Parser::fmt(fd.spec.smoothingLength),
                       "a fraction of the bounding-box diagonal such as 0.08");
            fd.smoothingLengthLoc = p.loc(value);
        } else if (k == "weights") {
            const std::string s = p.text(value, "field.weights");
            if (s == "meanvalue") fd.spec.weights = field::LaplaceWeights::MeanValue;
            else if (s == "cotan") fd.spec.weights = field::LaplaceWeights::Cotan;
            else p.fail(value, "unknown weights '" + s + "'", suggest(s, {"meanvalue", "cotan"}));
        } else if (k == "global_smoothing") {
            for (const auto &[gk, gv] : p.entries(value, "field.global_smoothing", {"iterations", "strength"})) {
                if (gk.Scalar() == "iterations")
                    fd.spec.globalSmoothingIterations = p.integer(gv, "field.global_smoothing.iterations", 0, 100000);
                else
                    fd.spec.globalSmoothingStrength = p.number(gv, "field.global_smoothing.strength", 1e-6, 1.0);
            }
        } else if (k == "features") {
            // field/features.h: the field follows the creases sharper than `angle` and the boundary
            for (const auto &[fk, fv] : p.entries(value, "field.features", {"angle", "min_length"})) {
                if (fk.Scalar() == "angle")
                    fd.spec.featureAngleDeg = p.number(fv, "field.features.angle (degrees, 0: off)", 0.0, 179.0);
                else
                    fd.spec.featureMinLength =
                        p.number(fv, "field.features.min_length (relative to the diagonal)", 0.0, 10.0);
            }
        } else if (k == "elements") {
            if (!value.IsSequence())
                p.fail(value, "field.elements must be a list of maps, got " + Parser::kindOf(value),
                       "e.g. elements: [{position: [0, 1, 0], order: 1}]");
            for (size_t i = 0; i < value.size(); ++i)
                fd.spec.elements.push_back(parseElement(p, value[i], "field.elements[" + std::to_string(i) + "]"));
        } else if (k == "edits") {
            parseEdits(p, value, fd.edits);
        }
    }
    if (fd.spec.source == field::FieldSource::Design && fd.spec.elements.empty())
        p.fail(sourceNode, "a designed field needs at least one element", "add field.elements");
}

void parsePicture(const Parser &p, const YAML::Node &node, PictureDesc &pd) {
    pd.loc = p.loc(node);
    for (const auto &[key, value] : p.entries(node, "picture", {"kind", "separatrices"})) {
        if (key.Scalar() == "kind") {
            const std::string s = p.text(value, "picture.kind");
            if (s == "hatching") pd.kind = {PictureDesc::Kind::Hatching, p.loc(value)};
            else if (s == "field") pd.kind = {PictureDesc::Kind::Field, p.loc(value)};
            else p.fail(value, "unknown picture kind '" + s + "'", suggest(s, {"hatching", "field"}));
        } else {
            pd.separatrices = {p.boolean(value, "picture.separatrices"), p.loc(value)};
        }
    }
    if (pd.separatrices.value && pd.kind.value != PictureDesc::Kind::Field)
        throw InputError(pd.separatrices.loc, "picture.separatrices needs picture.kind: field",
                         "separatrices are drawn on field pictures only");
}

} // namespace

std::vector<std::string> primitiveNames() {
    std::vector<std::string> names;
    for (const auto &s : primitiveSpecs()) names.push_back(s.name);
    return names;
}

namespace {

bool isSvgOutput(const std::string &path) {
    std::string ext = fs::path(path).extension().string();
    for (char &c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".svg";
}

/// `output: PATH` or `output: [PATH, ...]`.
void parseOutputs(const Parser &p, const YAML::Node &value, std::vector<Located<std::string>> &outputs) {
    outputs.clear();
    auto one = [&](const YAML::Node &n) {
        std::string out = p.text(n, "output");
        if (!renderer::isSupportedImagePath(out) && !isSvgOutput(out))
            p.fail(n, "output '" + out + "' has an unsupported extension",
                   std::string("use one of ") + renderer::supportedImageExtensions() + " .svg");
        for (const auto &o : outputs)
            if (fs::path(o.value).lexically_normal() == fs::path(out).lexically_normal())
                p.fail(n, "output '" + out + "' is listed twice (first at line " + std::to_string(o.loc.line) + ")",
                       "list each file once");
        outputs.push_back({out, p.loc(n)});
    };
    if (value.IsSequence()) {
        if (value.size() == 0 || value.size() > 16)
            p.fail(value, "output must list 1 to 16 paths, got " + std::to_string(value.size()),
                   "e.g. output: [out/bunny.png, out/bunny.svg]");
        for (size_t i = 0; i < value.size(); ++i) one(value[i]);
    } else {
        if (!value.IsScalar())
            p.fail(value, "output must be a path or a list of paths, got " + Parser::kindOf(value),
                   "e.g. output: out/bunny.png or output: [out/bunny.png, out/bunny.exr]");
        one(value);
    }
}

} // namespace

SceneDesc parseScene(const std::string &text, const std::string &path, const std::vector<std::string> &overrides,
                     const std::vector<FlagOverride> &flags) {
    Parser p(path);
    YAML::Node root = loadYaml(p, text);
    const bool overridden = !overrides.empty() || !flags.empty();
    if (overridden && (!root || root.IsNull())) root = YAML::Node(YAML::NodeType::Map);
    if (root.IsMap() && overridden) {
        // The --set list first, then the flags that stand for keys: a flag wins.
        for (const std::string &o : overrides) applyOverride(p, root, o, FileLoc{"--set " + o});
        for (const FlagOverride &f : flags) applyOverride(p, root, f.key + "=" + f.value, FileLoc{f.flag});
        // The file and every value together stay within the value budget.
        std::vector<YAML::Node> stack;
        long visited = 0;
        const FileLoc where = flags.empty() ? FileLoc{"--set " + overrides.back()} : FileLoc{flags.back().flag};
        checkYamlShape(p, root, stack, visited, &where);
    }
    SceneDesc desc;
    desc.path = path;
    if (!root || root.IsNull())
        throw InputError(FileLoc{path, 1, 1}, "the scene file is empty", "it needs at least a mesh: key");
    const auto entries = p.entries(root, "the scene", {"mesh", "camera", "lights", "output", "shadows", "ambient_occlusion", "style", "field",
                                                       "picture", "threads", "seed"});
    bool hasMesh = false;
    for (const auto &[key, value] : entries) {
        const std::string &k = key.Scalar();
        if (k == "mesh") {
            parseMesh(p, value, desc.mesh);
            hasMesh = true;
        } else if (k == "camera") {
            parseCamera(p, value, desc.camera);
        } else if (k == "lights") {
            desc.lightsGiven = true;
            parseLights(p, value, desc.lights);
        } else if (k == "output") {
            parseOutputs(p, value, desc.outputs);
            desc.output = desc.outputs.front();
        } else if (k == "threads") {
            desc.threads = {p.integer(value, "threads", 0, 4096), p.loc(value)};
        } else if (k == "seed") {
            if (!value.IsScalar()) p.fail(value, "seed must be a whole number, got " + Parser::kindOf(value));
            const long long v = p.wholeNumber(value, "seed", 0, 4294967295LL);
            if (v < 0 || v > 4294967295LL)
                p.fail(value, "seed must be in [0, 4294967295], got " + std::to_string(v),
                       "any whole number in that range; the same seed gives the same drawing");
            desc.seed = Located<long long>{v, p.loc(value)};
        } else if (k == "field") {
            parseField(p, value, desc.field);
        } else if (k == "shadows") {
            desc.shadows = {p.boolean(value, "shadows"), p.loc(value)};
        } else if (k == "ambient_occlusion") {
            parseAmbientOcclusion(p, value, desc.ambientOcclusion);
        } else if (k == "style") {
            parseStyle(p, value, desc.style);
        } else if (k == "picture") {
            parsePicture(p, value, desc.picture);
        }
    }
    if (!hasMesh)
        throw InputError(FileLoc{path, 1, 1}, "the scene has no mesh",
                         "add e.g. mesh: bunny.off or mesh: {primitive: icosphere}");
    if (desc.outputs.empty()) {
        desc.output.value = fs::path(path).stem().string() + ".png";
        desc.outputs.push_back(desc.output);
    }
    // Top-level seed: sets the style's seed unless the scene's own style block (or a
    // --set style.seed) gave one; a preset's seed is overridden.
    if (desc.seed) {
        const auto at = desc.style.setAt.find("seed");
        const bool explicitInScene = at != desc.style.setAt.end() &&
                                     (desc.style.presetPath.empty() || at->second.path != desc.style.presetPath);
        if (!explicitInScene) {
            desc.style.style.seed = uint32_t(desc.seed->value);
            desc.style.setAt["seed"] = desc.seed->loc;
        }
    }
    return desc;
}

SceneDesc parseSceneFile(const std::string &path, const std::vector<std::string> &overrides,
                         const std::vector<FlagOverride> &flags) {
    return parseScene(readText(path, "scene file"), path, overrides, flags);
}

bool isMeshPath(const std::string &path) {
    std::string ext = fs::path(path).extension().string();
    for (char &c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

SceneDesc parseSceneOrMesh(const std::string &path, const std::vector<std::string> &overrides,
                           const std::vector<FlagOverride> &flags) {
    if (!isMeshPath(path)) return parseSceneFile(path, overrides, flags);
    // A missing, folder or device input is an I/O error (exit 3), as for a scene file
    // or `rosyhatch field MESH`; the mesh reader checks the rest when the scene is built.
    checkInputPath(path, InputFileRules{"mesh file", 0, false});
    // The file's name as a double-quoted YAML string (resolved against its own folder).
    std::string quoted = "\"";
    for (const char c : fs::path(path).filename().string()) {
        if (c == '"' || c == '\\') quoted += '\\';
        if (static_cast<unsigned char>(c) < 0x20) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(static_cast<unsigned char>(c)));
            quoted += hex;
        } else quoted += c;
    }
    quoted += '"';
    return parseScene("mesh: " + quoted + "\n", path, overrides, flags);
}

} // namespace rosy::scenes
