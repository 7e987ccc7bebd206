#include "scenes/scene.h"

#include "core/input_file.h"
#include "field/mesh_io.h"
#include "field/primitives.h"
#include "field/winding_number.h"
#include "field/smoothing.h"
#include "renderer/image.h"
#include "renderer/svg.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

namespace rosy::scenes {
namespace fs = std::filesystem;

int editDistance(const std::string &a, const std::string &b) {
    std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = int(j);
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = int(i);
        for (size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

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

std::string joinNames(const std::vector<std::string> &names) {
    std::string s;
    for (size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
    return s;
}

/// "did you mean 'x'?" for the closest candidate within a small edit distance,
/// else the list of allowed names.
std::string suggest(const std::string &word, const std::vector<std::string> &candidates) {
    std::string best;
    int bestDist = 1 << 30;
    for (const std::string &c : candidates) {
        int d = editDistance(word, c);
        if (d < bestDist) {
            bestDist = d;
            best = c;
        }
    }
    int limit = std::max(2, int(word.size()) / 3);
    if (!best.empty() && bestDist <= limit) return "did you mean '" + best + "'?";
    return "expected one of: " + joinNames(candidates);
}

/// Reads one scene file; carries the path for every location.
class Parser {
public:
    explicit Parser(std::string path) : m_path(std::move(path)) {}

    FileLoc loc(const YAML::Node &node) const {
        // A node a --set override put in the tree is located at that override.
        for (const auto &[origin, where] : m_origins)
            if (origin.is(node)) return m_originLocs[where];
        YAML::Mark m = node.Mark();
        // yaml-cpp marks are 0-based; a null mark (-1) means "unknown".
        return FileLoc{m_path, m.line >= 0 ? m.line + 1 : 0, m.column >= 0 ? m.column + 1 : 0};
    }
    FileLoc loc(const YAML::Mark &m) const {
        return FileLoc{m_path, m.line >= 0 ? m.line + 1 : 0, m.column >= 0 ? m.column + 1 : 0};
    }

    static std::string kindOf(const YAML::Node &node) {
        switch (node.Type()) {
        case YAML::NodeType::Map: return "a map";
        case YAML::NodeType::Sequence: return "a list";
        case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
        default: return "nothing";
        }
    }

    [[noreturn]] void fail(const YAML::Node &node, const std::string &what,
                           const std::string &hint = {}) const {
        throw InputError(loc(node), what, hint);
    }

    /// The entries of a map node in file order, after rejecting duplicate and
    /// unknown keys. yaml-cpp keeps duplicate keys in the node but lookups see only
    /// one of them, so duplicates are found by walking the entries ourselves.
    std::vector<std::pair<YAML::Node, YAML::Node>>
    entries(const YAML::Node &map, const std::string &context,
            const std::vector<std::string> &allowed) const {
        if (!map.IsMap()) fail(map, context + " must be a map (key: value lines), got " + kindOf(map));
        std::vector<std::pair<YAML::Node, YAML::Node>> out;
        for (auto it = map.begin(); it != map.end(); ++it) {
            YAML::Node key = it->first, value = it->second;
            if (!key.IsScalar()) fail(key, "keys in " + context + " must be plain names");
            const std::string &name = key.Scalar();
            for (const auto &seen : out)
                if (seen.first.Scalar() == name) {
                    FileLoc first = loc(seen.first);
                    fail(key, "duplicate key '" + name + "' in " + context + " (first set at line " +
                                  std::to_string(first.line) + ")",
                         "keep only one of them");
                }
            if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
                fail(key, "unknown key '" + name + "' in " + context, suggest(name, allowed));
            out.emplace_back(key, value);
        }
        return out;
    }

    double number(const YAML::Node &node, const std::string &what, double lo, double hi) const {
        if (!node.IsScalar()) fail(node, what + " must be a number, got " + kindOf(node));
        double v;
        try {
            v = node.as<double>();
        } catch (const YAML::Exception &) {
            fail(node, what + " must be a number, got " + kindOf(node));
        }
        if (!std::isfinite(v)) fail(node, what + " must be a finite number, got " + kindOf(node));
        if (v < lo || v > hi) fail(node, what + " must be in [" + fmt(lo) + ", " + fmt(hi) + "], got " + fmt(v));
        return v;
    }

    int integer(const YAML::Node &node, const std::string &what, int lo, int hi) const {
        if (!node.IsScalar()) fail(node, what + " must be a whole number, got " + kindOf(node));
        long long v = wholeNumber(node, what, lo, hi);
        if (v < lo || v > hi)
            fail(node, what + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                           "], got " + std::to_string(v));
        return int(v);
    }

    /// A scalar that is a whole number, also when written as 128.0 or 1e3; a
    /// fractional or non-numeric value fails naming it. Values beyond [lo, hi] are
    /// returned clamped just outside it (the caller reports the range).
    long long wholeNumber(const YAML::Node &node, const std::string &what, long long lo, long long hi) const {
        try {
            return node.as<long long>();
        } catch (const YAML::Exception &) {
        }
        double d = 0;
        try {
            d = node.as<double>();
        } catch (const YAML::Exception &) {
            fail(node, what + " must be a whole number, got " + kindOf(node));
        }
        if (!std::isfinite(d)) fail(node, what + " must be a finite whole number, got " + kindOf(node));
        if (d != std::floor(d)) fail(node, what + " must be a whole number, got " + fmt(d));
        if (d < double(lo) || d > double(hi))
            fail(node, what + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + fmt(d));
        return (long long)d;
    }

    bool boolean(const YAML::Node &node, const std::string &what) const {
        if (!node.IsScalar()) fail(node, what + " must be true or false, got " + kindOf(node));
        try {
            return node.as<bool>();
        } catch (const YAML::Exception &) {
            fail(node, what + " must be true or false, got " + kindOf(node));
        }
    }

    std::string text(const YAML::Node &node, const std::string &what) const {
        if (!node.IsScalar() || node.Scalar().empty())
            fail(node, what + " must be text, got " + kindOf(node));
        return node.Scalar();
    }

    Vec3 vec3(const YAML::Node &node, const std::string &what, double lo = -1e12,
              double hi = 1e12) const {
        if (!node.IsSequence() || node.size() != 3)
            fail(node, what + " must be a list of 3 numbers like [0, 1, 0], got " + kindOf(node));
        return Vec3(number(node[0], what + "[0]", lo, hi), number(node[1], what + "[1]", lo, hi),
                    number(node[2], what + "[2]", lo, hi));
    }

    static std::string fmt(double v) {
        std::ostringstream os;
        os << v;
        return os.str();
    }

    const std::string &path() const { return m_path; }
    /// Nodes located at --set overrides so far.
    size_t originCount() const { return m_origins.size(); }

    /// Locates `node` and everything below it at `where` (a --set override).
    void addOrigin(const YAML::Node &node, const FileLoc &where) {
        // One copy of the location per override (it holds the whole override text),
        // an index per node.
        if (m_originLocs.empty() || m_originLocs.back().path != where.path) m_originLocs.push_back(where);
        addOrigin(node, m_originLocs.size() - 1);
    }

private:
    std::string m_path;
    void addOrigin(const YAML::Node &node, size_t where) {
        m_origins.emplace_back(node, where);
        if (node.IsMap())
            for (auto it = node.begin(); it != node.end(); ++it) {
                addOrigin(it->first, where);
                addOrigin(it->second, where);
            }
        else if (node.IsSequence())
            for (auto it = node.begin(); it != node.end(); ++it) addOrigin(*it, where);
    }

    std::vector<std::pair<YAML::Node, size_t>> m_origins; ///< node, index into m_originLocs
    std::vector<FileLoc> m_originLocs;
};

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
        std::string value = p.text(node, "mesh");
        fs::path file(value);
        if (file.is_relative()) file = fs::path(p.path()).parent_path() / file;
        file = file.lexically_normal();
        std::error_code ec;
        if (!fs::exists(file, ec))
            p.fail(node, "mesh file '" + file.string() + "' does not exist",
                   "paths are relative to the scene file's folder");
        if (fs::is_directory(file, ec))
            p.fail(node, "mesh '" + file.string() + "' is a folder, not a file");
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

styles::Rgb colour(const Parser &p, const YAML::Node &node, const std::string &what) {
    Vec3 c = p.vec3(node, what + " (linear RGB)", 0.0, 1.0);
    return {c.x(), c.y(), c.z()};
}

/// One settable Style field: its dotted key, range and where it lives in a Style.
/// Ranges keep values the renderer can honour (a width must be positive, a
/// density is a coverage fraction, a taper over half a stroke would overlap).
struct StyleKey {
    enum class Kind { Number, Integer, Boolean, Colour, Text };
    const char *key;
    Kind kind;
    double lo, hi;
    double *(*number)(styles::Style &);
    bool *(*boolean)(styles::Style &);
    styles::Rgb *(*colour)(styles::Style &);
    uint32_t *(*integer)(styles::Style &);
};

using SK = StyleKey::Kind;
#define ROSY_NUM(k, lo, hi, member) \
    StyleKey{k, SK::Number, lo, hi, [](styles::Style &s) { return &s.member; }, nullptr, nullptr, nullptr}
#define ROSY_BOOL(k, member) \
    StyleKey{k, SK::Boolean, 0, 1, nullptr, [](styles::Style &s) { return &s.member; }, nullptr, nullptr}
#define ROSY_RGB(k, member) \
    StyleKey{k, SK::Colour, 0, 1, nullptr, nullptr, [](styles::Style &s) { return &s.member; }, nullptr}

const std::vector<StyleKey> &styleKeyTable() {
    static const std::vector<StyleKey> table = {
        ROSY_RGB("paper", paper),
        ROSY_RGB("ink", ink),
        ROSY_NUM("ambient", 0.0, 1.0, ambient),
        ROSY_NUM("paper_grain", 0.0, 1.0, paperGrain),
        StyleKey{"seed", SK::Integer, 0, 4294967295.0, nullptr, nullptr, nullptr,
                 [](styles::Style &s) { return &s.seed; }},
        ROSY_NUM("hatch.stroke_width_px", 0.05, 64.0, hatch.strokeWidthPx),
        ROSY_NUM("hatch.min_spacing_px", 0.5, 512.0, hatch.minSpacingPx),
        ROSY_NUM("hatch.max_spacing_px", 0.5, 4096.0, hatch.maxSpacingPx),
        ROSY_NUM("hatch.highlight_density", 0.0, 1.0, hatch.highlightDensity),
        ROSY_NUM("hatch.cross_density", 0.0, 1.0, hatch.crossDensity),
        ROSY_NUM("hatch.tone_gamma", 0.1, 10.0, hatch.toneGamma),
        ROSY_NUM("hatch.taper", 0.0, 0.5, hatch.taper),
        ROSY_NUM("hatch.pressure_variation", 0.0, 0.95, hatch.pressureVariation),
        ROSY_NUM("hatch.jitter_px", 0.0, 64.0, hatch.jitterPx),
        ROSY_NUM("hatch.angle_offset_deg", -360.0, 360.0, hatch.angleOffsetDeg),
        ROSY_NUM("hatch.spacing_jitter", 0.0, 0.9, hatch.spacingJitter),
        ROSY_NUM("hatch.min_length_px", 0.0, 4096.0, hatch.minLengthPx),
        ROSY_NUM("contour.width_px", 0.0, 64.0, contour.widthPx),
        ROSY_NUM("contour.crease_width_px", 0.0, 64.0, contour.creaseWidthPx),
        ROSY_NUM("contour.crease_angle_deg", 0.0, 180.0, contour.creaseAngleDeg),
        ROSY_BOOL("contour.borders", contour.borders),
        ROSY_BOOL("contour.hidden", contour.hidden),
        StyleKey{"page.size", SK::Text, 0, 0, nullptr, nullptr, nullptr, nullptr},
        ROSY_NUM("page.margin_mm", 0.0, 1000.0, page.marginMm),
        StyleKey{"page.orientation", SK::Text, 0, 0, nullptr, nullptr, nullptr, nullptr},
        ROSY_NUM("page.pen_width_mm", 0.0, 10.0, page.penWidthMm),
    };
    return table;
}
#undef ROSY_NUM
#undef ROSY_BOOL
#undef ROSY_RGB

/// The keys of the map at `prefix` ("" for the top, "hatch." / "contour." below):
/// leaf names plus the names of nested groups.
std::vector<std::string> styleKeysUnder(const std::string &prefix) {
    std::vector<std::string> names;
    for (const StyleKey &k : styleKeyTable()) {
        std::string key = k.key;
        if (key.rfind(prefix, 0) != 0) continue;
        std::string rest = key.substr(prefix.size());
        std::string name = rest.substr(0, rest.find('.'));
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
    return names;
}

/// The text-valued style keys (the SVG page's size and orientation).
void applyStyleText(const Parser &p, const YAML::Node &value, const std::string &dotted, const std::string &what,
                    styles::Style &style) {
    const std::string text = p.text(value, what);
    if (dotted == "page.size") {
        try {
            std::tie(style.page.widthMm, style.page.heightMm) = renderer::paperSize(text, p.loc(value));
        } catch (const InputError &e) {
            // A value from a flag (--paper) is located at the flag, which already
            // names the setting; a file's or --set's value names its key.
            const std::string origin = p.loc(value).path;
            const bool fromFlag = origin.rfind("--", 0) == 0 && origin.rfind("--set ", 0) != 0;
            p.fail(value, (fromFlag ? "" : what + ": ") + e.message(),
                   "use a4, a3, letter or WIDTHxHEIGHT in mm such as 300x200");
        }
        return;
    }
    using O = styles::PageStyle::Orientation;
    if (text == "auto") style.page.orientation = O::Auto;
    else if (text == "portrait") style.page.orientation = O::Portrait;
    else if (text == "landscape") style.page.orientation = O::Landscape;
    else p.fail(value, what + " must be auto, portrait or landscape, got '" + text + "'");
}

/// Sets the style values of one (possibly nested) map of a `style:` block or
/// preset file. `context` names the map in messages ("style", "style.hatch").
/// `extra` are further keys the caller handles itself (preset, description).
void applyStyleMap(const Parser &p, const YAML::Node &node, const std::string &prefix,
                   const std::string &context, const std::vector<std::string> &extra, styles::Style &style,
                   std::map<std::string, FileLoc> &setAt) {
    std::vector<std::string> allowed = styleKeysUnder(prefix);
    allowed.insert(allowed.end(), extra.begin(), extra.end());
    for (const auto &[key, value] : p.entries(node, context, allowed)) {
        const std::string name = key.Scalar();
        if (std::find(extra.begin(), extra.end(), name) != extra.end()) continue;
        const std::string dotted = prefix + name;
        // In a scene the keys live under `style:`; in a preset file at the top.
        const std::string what = (context.rfind("style", 0) == 0 ? "style." : "") + dotted;
        auto it = std::find_if(styleKeyTable().begin(), styleKeyTable().end(),
                               [&](const StyleKey &k) { return dotted == k.key; });
        if (it == styleKeyTable().end()) {
            // A group such as `hatch:`; its own keys are checked one level down.
            applyStyleMap(p, value, dotted + ".", what, {}, style, setAt);
            continue;
        }
        switch (it->kind) {
        case SK::Number: *it->number(style) = p.number(value, what, it->lo, it->hi); break;
        case SK::Boolean: *it->boolean(style) = p.boolean(value, what); break;
        case SK::Colour: *it->colour(style) = colour(p, value, what); break;
        case SK::Text: applyStyleText(p, value, dotted, what, style); break;
        case SK::Integer: {
            if (!value.IsScalar()) p.fail(value, what + " must be a whole number, got " + Parser::kindOf(value));
            const long long v = p.wholeNumber(value, what, 0, 4294967295LL);
            if (v < 0 || v > 4294967295LL)
                p.fail(value, what + " must be a whole number in [0, 4294967295], got " + std::to_string(v));
            *it->integer(style) = uint32_t(v);
            break;
        }
        }
        setAt[dotted] = p.loc(value);
    }
}

/// Checks that hold between style values, reported at the value the user set last
/// (the scene's override before the preset's value).
void checkStyle(const styles::Style &style, const std::map<std::string, FileLoc> &setAt, const FileLoc &fallback) {
    auto where = [&](const char *a, const char *b) {
        auto ia = setAt.find(a), ib = setAt.find(b);
        if (ia != setAt.end() && (ib == setAt.end() || ia->second.path == fallback.path)) return ia->second;
        if (ib != setAt.end()) return ib->second;
        return fallback;
    };
    if (style.hatch.maxSpacingPx < style.hatch.minSpacingPx)
        throw InputError(where("hatch.max_spacing_px", "hatch.min_spacing_px"),
                         "hatch.max_spacing_px (" + Parser::fmt(style.hatch.maxSpacingPx) +
                             ") is below hatch.min_spacing_px (" + Parser::fmt(style.hatch.minSpacingPx) + ")",
                         "the sparsest spacing must be at least the densest");
    if (style.hatch.crossDensity < style.hatch.highlightDensity)
        throw InputError(where("hatch.cross_density", "hatch.highlight_density"),
                         "hatch.cross_density (" + Parser::fmt(style.hatch.crossDensity) +
                             ") is below hatch.highlight_density (" + Parser::fmt(style.hatch.highlightDensity) + ")",
                         "cross-hatching starts at a darker tone than the first hatches");
    if (2 * style.page.marginMm >= std::min(style.page.widthMm, style.page.heightMm))
        throw InputError(where("page.margin_mm", "page.size"),
                         "page.margin_mm (" + Parser::fmt(style.page.marginMm) + ") leaves no room on a " +
                             Parser::fmt(style.page.widthMm) + "x" + Parser::fmt(style.page.heightMm) + " mm page",
                         "use a margin below half the paper's shorter side, or a larger page.size");
}

/// The build-time preset folder and the installed one next to the executable.
std::vector<fs::path> candidateStyleDirs() {
    std::vector<fs::path> dirs;
    if (const char *env = std::getenv("ROSY_STYLES_PATH")) {
        std::string list = env;
        size_t start = 0;
        while (start <= list.size()) {
            size_t end = list.find(':', start);
            if (end == std::string::npos) end = list.size();
            if (end > start) dirs.emplace_back(list.substr(start, end - start));
            start = end + 1;
        }
    }
#ifdef ROSY_STYLES_DIR
    dirs.emplace_back(ROSY_STYLES_DIR);
#endif
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(exe.parent_path() / ".." / "share" / "rosyhatch" / "styles");
    return dirs;
}

/// True when `value` names a file rather than a preset.
bool looksLikePath(const std::string &value) {
    const std::string ext = fs::path(value).extension().string();
    return value.find('/') != std::string::npos || ext == ".yaml" || ext == ".yml";
}

/// Scene and preset files are small (a few KB); this bound stops an endless
/// stream (a link to /dev/zero, `yes | rosyhatch render /dev/stdin`) early.
constexpr size_t kMaxSceneBytes = 4u << 20;

std::string readText(const std::string &path, const char *what) {
    return readInputFile(path, InputFileRules{what, kMaxSceneBytes, true});
}

/// Limits that keep a hostile file from exhausting the stack or memory (yaml-cpp
/// itself stops nesting only at depth 2000 and shares aliased nodes, so
/// `&a [*a]` is a cycle and nested aliases expand exponentially when walked).
constexpr int kMaxYamlDepth = 32;
constexpr long kMaxYamlValues = 100000;
/// A --set value is one setting, not a scene: every node it brings is located at
/// the override (a linear list, Parser::loc()), so it is kept much smaller.
constexpr long kMaxOverrideValues = 10000;

/// Walks the tree once, stopping at the limits above. `at` locates every error
/// when the tree came from somewhere else than the file (a --set value).
void checkYamlShape(const Parser &p, const YAML::Node &node, std::vector<YAML::Node> &stack, long &visited,
                    const FileLoc *at = nullptr, long maxValues = kMaxYamlValues) {
    auto fail = [&](const std::string &what, const std::string &hint) {
        if (at) throw InputError(*at, what, hint);
        p.fail(node, what, hint);
    };
    const std::string source = at ? "the value" : "the file";
    if (++visited > maxValues)
        fail(source + " expands to more than " + std::to_string(maxValues) + " values (aliases of aliases?)",
             "write the values out instead of nesting aliases");
    if (!node.IsMap() && !node.IsSequence()) return;
    for (const YAML::Node &ancestor : stack)
        if (ancestor.is(node)) fail("an alias refers to a node that contains it (a cycle)", "remove that alias");
    if (int(stack.size()) >= kMaxYamlDepth)
        fail("nesting deeper than " + std::to_string(kMaxYamlDepth) + " levels",
             "scene files need only a few levels of maps and lists");
    stack.push_back(node);
    for (auto it = node.begin(); it != node.end(); ++it) {
        if (node.IsMap()) {
            checkYamlShape(p, it->first, stack, visited, at, maxValues);
            checkYamlShape(p, it->second, stack, visited, at, maxValues);
        } else {
            checkYamlShape(p, *it, stack, visited, at, maxValues);
        }
    }
    stack.pop_back();
}

/// Flow brackets ([ and {) nested deeper than kMaxYamlDepth, found in the text
/// before yaml-cpp recurses into them, so the error names the exact column.
/// Brackets inside quoted scalars and comments do not count. `at` locates the
/// error when the text is a --set value.
void checkFlowDepth(const Parser &p, const std::string &text, const FileLoc *at = nullptr) {
    int depth = 0, line = 1, col = 0;
    char quote = 0;
    bool comment = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        ++col;
        if (c == '\n') {
            ++line;
            col = 0;
            comment = false;
            continue;
        }
        if (comment) continue;
        if (quote) {
            if (c == '\\' && quote == '"') ++i, ++col;
            else if (c == quote) quote = 0;
            continue;
        }
        const char before = i == 0 ? ' ' : text[i - 1];
        const bool tokenStart = std::isspace(static_cast<unsigned char>(before)) || before == '[' ||
                                before == '{' || before == ',' || before == ':';
        if (c == '#' && std::isspace(static_cast<unsigned char>(before))) comment = true;
        else if ((c == '"' || c == '\'') && tokenStart) quote = c;
        else if (c == '[' || c == '{') {
            if (++depth > kMaxYamlDepth)
                throw InputError(at ? *at : FileLoc{p.path(), line, col},
                                 "nesting deeper than " + std::to_string(kMaxYamlDepth) + " levels",
                                 "scene files need only a few levels of maps and lists");
        } else if (c == ']' || c == '}') {
            depth = std::max(0, depth - 1);
        }
    }
}

/// Walks the token stream once, document by document, before anything is built:
/// records where the second document with content starts, and stops a stream the
/// parser cannot advance. yaml-cpp 0.7's LoadAll loops forever on a stray ',' at
/// the top level (each call yields an empty document at the same mark without
/// consuming the token: jbeder/yaml-cpp#1040, fixed after 0.7); the fuzzer found it
/// (tests/fuzz/scene/crashers/comma_loadall_hang.yaml).
class DocumentCounter final : public YAML::EventHandler {
public:
    bool content = false;        ///< the current document holds a non-null node
    YAML::Mark contentMark;      ///< where that content starts
    YAML::Mark start;            ///< the current document's start
    void OnDocumentStart(const YAML::Mark &mark) override {
        start = mark;
        content = false;
    }
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark &, YAML::anchor_t) override {}
    void OnAlias(const YAML::Mark &mark, YAML::anchor_t) override { see(mark); }
    void OnScalar(const YAML::Mark &mark, const std::string &, YAML::anchor_t, const std::string &) override {
        see(mark);
    }
    void OnSequenceStart(const YAML::Mark &mark, const std::string &, YAML::anchor_t,
                         YAML::EmitterStyle::value) override {
        see(mark);
    }
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark &mark, const std::string &, YAML::anchor_t, YAML::EmitterStyle::value) override {
        see(mark);
    }
    void OnMapEnd() override {}

private:
    void see(const YAML::Mark &mark) {
        if (!content) contentMark = mark;
        content = true;
    }
};

YAML::Mark markAt(const std::string &text, size_t pos) {
    YAML::Mark m;
    m.pos = int(pos);
    m.line = int(std::count(text.begin(), text.begin() + std::min(pos, text.size()), '\n'));
    const size_t nl = text.rfind('\n', pos == 0 ? std::string::npos : pos - 1);
    m.column = int(nl == std::string::npos || pos == 0 ? pos : pos - nl - 1);
    return m;
}

void checkSingleDocument(const Parser &p, const std::string &text) {
    std::istringstream in(text);
    YAML::Parser parser(in);
    DocumentCounter counter;
    int withContent = 0;
    int previousStart = -1;
    while (parser.HandleNextDocument(counter)) {
        if (counter.start.pos == previousStart && !counter.content) {
            // No progress: the parser is stuck on a token it cannot use.
            size_t at = size_t(std::max(0, counter.start.pos));
            while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
            const std::string what = at < text.size() ? std::string("'") + text[at] + "'" : "end of file";
            throw InputError(p.loc(markAt(text, at)), "YAML syntax error: unexpected " + what,
                             "a ',' separates items only inside [lists] and {maps}; quote the text if it is a value");
        }
        previousStart = counter.start.pos;
        if (counter.content && ++withContent > 1)
            throw InputError(p.loc(counter.contentMark), "the file holds several YAML documents (separated by '---')",
                             "keep one scene per file");
    }
}

/// Parses one YAML document and checks its shape: one document, nesting and
/// alias expansion within the limits above.
YAML::Node loadYaml(const Parser &p, const std::string &text) {
    checkFlowDepth(p, text);
    YAML::Node root;
    try {
        checkSingleDocument(p, text);
        root = YAML::Load(text); // the first document (the only one with content)
    } catch (const YAML::DeepRecursion &e) {
        throw InputError(p.loc(e.mark), "nesting deeper than " + std::to_string(kMaxYamlDepth) + " levels",
                         "scene files need only a few levels of maps and lists");
    } catch (const YAML::ParserException &e) {
        throw InputError(p.loc(e.mark), "YAML syntax error: " + e.msg, "check indentation, colons and brackets");
    }
    if (!root) return YAML::Node();
    std::vector<YAML::Node> stack;
    long visited = 0;
    checkYamlShape(p, root, stack, visited);
    return root;
}

void parseStyle(const Parser &p, const YAML::Node &node, StyleDesc &sd) {
    sd.loc = p.loc(node);
    if (!node.IsMap()) p.fail(node, "style must be a map (key: value lines), got " + Parser::kindOf(node));
    // The preset goes first wherever it is written, so the block's own keys win.
    if (const YAML::Node presetNode = node["preset"]) {
        const std::string value = p.text(presetNode, "style.preset");
        sd.preset = Located<std::string>{value, p.loc(presetNode)};
        if (looksLikePath(value)) {
            fs::path file(value);
            if (file.is_relative()) file = fs::path(p.path()).parent_path() / file;
            file = file.lexically_normal();
            std::error_code ec;
            if (!fs::exists(file, ec))
                p.fail(presetNode, "style preset file '" + file.string() + "' does not exist",
                       "give a preset name or a path relative to the scene file");
            if (fs::is_directory(file, ec))
                p.fail(presetNode, "style preset '" + file.string() + "' is a folder, not a file",
                       "give a preset name or the path of a preset .yaml file");
            sd.presetPath = file.string();
        } else {
            std::vector<std::string> names;
            for (const StylePreset &preset : listStylePresets()) {
                names.push_back(preset.name);
                if (preset.name == value && sd.presetPath.empty()) sd.presetPath = preset.path;
            }
            if (sd.presetPath.empty()) {
                std::string hint = names.empty() ? std::string("no presets were found; set ROSY_STYLES_PATH")
                                                 : suggest(value, names);
                if (!names.empty() && hint.rfind("expected", 0) != 0) hint += " (presets: " + joinNames(names) + ")";
                p.fail(presetNode, "unknown style preset '" + value + "'", hint);
            }
        }
        sd.style = loadStylePreset(sd.presetPath, nullptr, &sd.setAt);
    }
    applyStyleMap(p, node, "", "style", {"preset"}, sd.style, sd.setAt);
    checkStyle(sd.style, sd.setAt, sd.loc);
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
                   {"symmetry", "source", "smoothing_length", "weights", "global_smoothing", "elements", "edits"})) {
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

/// Applies one `--set dotted.path=VALUE` to the scene's YAML tree, before any
/// validation: VALUE is parsed as YAML, maps on the way are created, and every node
/// the override brings (value, new keys, new maps) is located at the override, so
/// a bad value is reported as `--set KEY=VALUE: error: ...`. A list element is
/// addressed by its 0-based position (`lights.0.intensity=0.5`).
void applyOverride(Parser &p, YAML::Node &root, const std::string &text, const FileLoc &where) {
    const std::string shape = "write --set KEY=VALUE with a dotted key, e.g. --set field.symmetry=2 or "
                              "--set 'camera.resolution=[512, 512]'";
    const size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError(where, "an override needs KEY=VALUE", shape);
    const std::string keyPath = text.substr(0, eq), valueText = text.substr(eq + 1);
    std::vector<std::string> segments;
    for (size_t start = 0;;) {
        const size_t dot = keyPath.find('.', start);
        segments.push_back(keyPath.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
        if (segments.back().empty()) throw InputError(where, "'" + keyPath + "' has an empty key", shape);
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    // The value is YAML text like a scene file, so it meets the same limits (nesting,
    // alias expansion, cycles) before anything walks it.
    checkFlowDepth(p, valueText, &where);
    YAML::Node value;
    try {
        value = YAML::Load(valueText);
    } catch (const YAML::DeepRecursion &) {
        throw InputError(where, "nesting deeper than " + std::to_string(kMaxYamlDepth) + " levels",
                         "scene values need only a few levels of maps and lists");
    } catch (const YAML::ParserException &e) {
        throw InputError(where, "the value is not valid YAML: " + e.msg,
                         "quote lists and maps for the shell, e.g. --set 'camera.resolution=[512, 512]'");
    }
    if (!value || value.IsNull()) {
        if (valueText.find_first_not_of(" \t\r\n") == std::string::npos)
            throw InputError(where, "the value of '" + keyPath + "' is empty", "write a value after '='");
        // `~`, `null` or a lone `,`: YAML reads these as no value at all.
        throw InputError(where, "'" + valueText + "' is no value in YAML (null)",
                         "write a number, text, [list] or {map}; quote text such as ',' for the shell and YAML");
    }
    {
        std::vector<YAML::Node> stack;
        long visited = 0;
        checkYamlShape(p, value, stack, visited, &where, kMaxOverrideValues);
    }
    p.addOrigin(value, where);
    if (long(p.originCount()) > kMaxOverrideValues)
        throw InputError(where, "the --set values hold more than " + std::to_string(kMaxOverrideValues) +
                                    " values together",
                         "put large settings in the scene file");
    YAML::Node node = root;
    std::string walked;
    for (size_t i = 0; i < segments.size(); ++i) {
        const std::string &seg = segments[i];
        const bool last = i + 1 == segments.size();
        if (node.IsSequence()) {
            size_t used = 0;
            unsigned long index = 0;
            try {
                index = std::stoul(seg, &used);
            } catch (const std::exception &) {
                used = 0;
            }
            if (used != seg.size() || index >= node.size())
                throw InputError(where, "'" + walked + "' is a list of " + std::to_string(node.size()) +
                                            " entries; '" + seg + "' is not a position in it",
                                 "address entries by 0-based position, e.g. lights.0.intensity");
            if (last) {
                node[index] = value;
                return;
            }
            node.reset(node[index]);
        } else {
            if (!node.IsMap())
                throw InputError(where, "'" + walked + "' is " + Parser::kindOf(node) + ", not a map, so it has no key '" +
                                            seg + "'",
                                 "override '" + walked + "' as a whole instead");
            const bool existed = bool(static_cast<const YAML::Node &>(node)[seg]);
            if (last) {
                node[seg] = value;
            } else if (!existed) {
                YAML::Node fresh(YAML::NodeType::Map);
                p.addOrigin(fresh, where);
                node[seg] = fresh;
            }
            if (!existed)
                for (auto it = node.begin(); it != node.end(); ++it)
                    if (it->first.IsScalar() && it->first.Scalar() == seg) p.addOrigin(it->first, where);
            if (last) return;
            YAML::Node child = node[seg];
            node.reset(child);
        }
        walked += (walked.empty() ? "" : ".") + seg;
    }
}

} // namespace

std::vector<std::string> primitiveNames() {
    std::vector<std::string> names;
    for (const auto &s : primitiveSpecs()) names.push_back(s.name);
    return names;
}

std::vector<std::string> styleKeys() {
    std::vector<std::string> keys;
    for (const StyleKey &k : styleKeyTable()) keys.push_back(k.key);
    return keys;
}

std::vector<std::string> styleSearchDirs() {
    std::vector<std::string> dirs;
    for (const fs::path &d : candidateStyleDirs()) {
        std::error_code ec;
        if (!fs::is_directory(d, ec)) continue;
        std::string dir = fs::weakly_canonical(d, ec).string();
        if (ec) dir = d.lexically_normal().string();
        if (std::find(dirs.begin(), dirs.end(), dir) == dirs.end()) dirs.push_back(dir);
    }
    return dirs;
}

std::vector<StylePreset> listStylePresets() {
    std::vector<StylePreset> presets;
    for (const std::string &dir : styleSearchDirs()) {
        std::vector<fs::path> files;
        std::error_code ec;
        for (const fs::directory_entry &e : fs::directory_iterator(dir, ec))
            if (e.path().extension() == ".yaml") files.push_back(e.path());
        // Directory order differs between file systems; names decide.
        std::sort(files.begin(), files.end());
        for (const fs::path &f : files) {
            const std::string name = f.stem().string();
            bool seen = std::any_of(presets.begin(), presets.end(), [&](const StylePreset &x) { return x.name == name; });
            if (seen) continue;
            StylePreset preset{name, {}, f.string()};
            loadStylePreset(preset.path, &preset.description);
            presets.push_back(preset);
        }
    }
    std::sort(presets.begin(), presets.end(),
              [](const StylePreset &a, const StylePreset &b) { return a.name < b.name; });
    return presets;
}

styles::Style loadStylePreset(const std::string &path, std::string *description,
                              std::map<std::string, FileLoc> *setAt) {
    Parser p(path);
    YAML::Node root = loadYaml(p, readText(path, "style preset file"));
    if (!root || root.IsNull())
        throw InputError(FileLoc{path, 1, 1}, "the style preset file is empty",
                         "it needs at least a description: line");
    styles::Style style;
    std::map<std::string, FileLoc> locs;
    applyStyleMap(p, root, "", "the style preset", {"description"}, style, locs);
    const YAML::Node desc = root["description"];
    if (!desc) p.fail(root, "the style preset has no description", "add description: followed by one line");
    std::string text = p.text(desc, "description");
    if (text.find('\n') != std::string::npos)
        p.fail(desc, "the description must be one line", "shorten it; details belong in comments");
    checkStyle(style, locs, p.loc(root));
    if (description) *description = text;
    if (setAt) *setAt = locs;
    return style;
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

namespace {

field::Mesh makePrimitive(const MeshDesc &m) {
    const std::string &name = m.primitive->value;
    auto P = [&](const char *k) { return m.params.at(k).value; };
    auto I = [&](const char *k) { return int(std::lround(m.params.at(k).value)); };
    if (name == "icosphere") return field::makeIcosphere(I("subdivisions"), P("radius"));
    if (name == "ellipsoid") return field::makeEllipsoid(I("subdivisions"), P("a"), P("b"), P("c"));
    if (name == "torus") return field::makeTorus(P("major_radius"), P("minor_radius"), I("nu"), I("nv"));
    if (name == "genus2") return field::makeGenus2(I("resolution"));
    if (name == "cube") return field::makeCube(I("n"));
    if (name == "tetrahedron") return field::makePlatonic(field::Platonic::Tetrahedron, I("subdivisions"));
    if (name == "octahedron") return field::makePlatonic(field::Platonic::Octahedron, I("subdivisions"));
    if (name == "dodecahedron") return field::makePlatonic(field::Platonic::Dodecahedron, I("subdivisions"));
    if (name == "icosahedron") return field::makePlatonic(field::Platonic::Icosahedron, I("subdivisions"));
    if (name == "disk") return field::makeDisk(I("rings"));
    if (name == "grid") return field::makeGrid(I("n"));
    if (name == "cylinder")
        return field::makeCylinder(P("radius"), P("height"), I("n_around"), I("n_along"));
    ROSY_CHECK(!"primitive table and makePrimitive() disagree");
    return {};
}

/// Triangles of a Platonic solid before subdivision (pentagons as 5-fans).
long long platonicFaces(const std::string &name) {
    if (name == "tetrahedron") return 4;
    if (name == "octahedron") return 8;
    if (name == "dodecahedron") return 60;
    return 20; // icosahedron
}

/// The face limit of meshes (--max-faces) applies to primitives too: checked from
/// the parameters, before anything is allocated.
void checkPrimitiveFaces(const MeshDesc &m, const field::LoadOptions &options) {
    const long long faces = primitiveFaceCount(m);
    if (faces > options.maxFaces)
        throw InputError(m.primitive->loc,
                         "the " + m.primitive->value + " primitive would have " + std::to_string(faces) +
                             " faces, more than the limit of " + std::to_string(options.maxFaces),
                         "lower its resolution parameters, or raise the limit with --max-faces");
}

/// A manual camera must see some of the mesh and must not stand inside it. The
/// visibility test is conservative (the bounding sphere against the view
/// frustum), so it never rejects a camera that sees something.
void checkManualCamera(const renderer::Camera &cam, const field::Mesh &mesh, const CameraDesc &c) {
    Vec3 centre;
    double radius;
    renderer::boundingSphere(mesh, centre, radius);
    const Vec3 d = centre - cam.position();
    const double x = d.dot(cam.right()), y = d.dot(cam.up()), z = d.dot(cam.forward());
    const double aspect = double(cam.width()) / cam.height();
    bool outside;
    if (cam.projection() == renderer::Projection::Perspective) {
        const double ty = std::tan(0.5 * cam.fovYDeg() * M_PI / 180), tx = ty * aspect;
        // Signed distances of the centre outside each side plane through the eye.
        outside = z < -radius || (std::abs(x) - z * tx) / std::sqrt(1 + tx * tx) > radius ||
                  (std::abs(y) - z * ty) / std::sqrt(1 + ty * ty) > radius;
    } else {
        const double hy = 0.5 * cam.viewHeight(), hx = hy * aspect;
        outside = z < -radius || std::abs(x) > hx + radius || std::abs(y) > hy + radius;
    }
    const FileLoc &where = c.lookAt.loc.line ? c.lookAt.loc : c.loc;
    if (outside)
        throw InputError(where, "the camera sees none of the mesh (its bounding sphere, centre [" +
                                    Parser::fmt(centre.x()) + ", " + Parser::fmt(centre.y()) + ", " +
                                    Parser::fmt(centre.z()) + "], radius " + Parser::fmt(radius) +
                                    ", lies outside the view)",
                         "point look_at at the mesh, or use auto: true");
    if (std::abs(field::windingNumber(mesh, cam.position())) > 0.5)
        throw InputError(c.position.loc.line ? c.position.loc : c.loc,
                         "camera.position is inside the mesh, which hides its outside",
                         "move the camera outside the surface, or use auto: true");
}

} // namespace

Eigen::Matrix3d TransformDesc::linear() const {
    const Vec3 r = rotateDeg.value * (M_PI / 180.0);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
                               Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
                                  .toRotationMatrix();
    return R * scale.value.asDiagonal();
}

field::Mesh transformMesh(const field::Mesh &mesh, const TransformDesc &transform) {
    const Eigen::Matrix3d L = transform.linear();
    std::vector<Vec3> positions(mesh.positions());
    for (Vec3 &q : positions) q = L * q + transform.translate.value;
    return field::Mesh::fromTriangles(std::move(positions), mesh.faces(), mesh.name());
}

long long primitiveFaceCount(const MeshDesc &m) {
    ROSY_CHECK(m.primitive.has_value());
    const std::string &name = m.primitive->value;
    auto I = [&](const char *k) { return (long long)std::llround(m.params.at(k).value); };
    auto pow4 = [](long long s) { return 1LL << (2 * s); };
    if (name == "icosphere" || name == "ellipsoid") return 20 * pow4(I("subdivisions"));
    if (name == "torus") return 2 * I("nu") * I("nv");
    if (name == "genus2") return field::genus2FaceCount(int(I("resolution")));
    if (name == "cube") return 12 * I("n") * I("n");
    if (name == "tetrahedron" || name == "octahedron" || name == "dodecahedron" || name == "icosahedron")
        return platonicFaces(name) * pow4(I("subdivisions"));
    if (name == "disk") return 6 * I("rings") * I("rings");
    if (name == "grid") return 2 * I("n") * I("n");
    if (name == "cylinder") return 2 * I("n_around") * I("n_along");
    ROSY_CHECK(!"primitive table and primitiveFaceCount() disagree");
    return 0;
}

uint64_t renderMemoryEstimate(const Scene &scene, bool exrOutput) {
    const double pixels = double(scene.camera.width()) * double(scene.camera.height());
    const double spacing = std::max(scene.style.hatch.minSpacingPx, 0.5);
    const double perPixel = 130.0 + std::max(160.0 / spacing, exrOutput ? 100.0 : 0.0);
    const double perFace = 600.0;
    return uint64_t(pixels * perPixel + double(scene.mesh.nFaces()) * perFace);
}

Scene buildScene(const SceneDesc &desc, const field::LoadOptions &meshOptions) {
    Scene scene;
    if (!desc.mesh.file) checkPrimitiveFaces(desc.mesh, meshOptions);
    scene.mesh = desc.mesh.file ? field::loadMesh(desc.mesh.file->value, meshOptions) : makePrimitive(desc.mesh);
    if (scene.mesh.nFaces() == 0)
        throw InputError(desc.mesh.loc, "the mesh has no faces");
    // Before framing, so the automatic camera sees the transformed mesh.
    if (desc.mesh.transform.given) scene.mesh = transformMesh(scene.mesh, desc.mesh.transform);

    const CameraDesc &c = desc.camera;
    int w = c.resolution.value[0], h = c.resolution.value[1];
    if (c.automatic) {
        renderer::FramingOptions fo;
        fo.direction = c.direction.value;
        fo.up = c.up.value;
        fo.fovYDeg = c.fov.value;
        fo.margin = c.margin.value;
        fo.projection = c.projection.value;
        scene.camera = renderer::frameMesh(scene.mesh, w, h, fo);
    } else if (c.projection.value == renderer::Projection::Perspective) {
        scene.camera = renderer::Camera::perspective(c.position.value, c.lookAt.value, c.up.value,
                                                     c.fov.value, w, h);
    } else {
        scene.camera = renderer::Camera::orthographic(c.position.value, c.lookAt.value, c.up.value,
                                                      c.height.value, w, h);
    }
    if (!c.automatic) checkManualCamera(scene.camera, scene.mesh, c);

    if (desc.lightsGiven) {
        for (const LightDesc &l : desc.lights) scene.lights.push_back(l.light);
    } else {
        // A key light over the viewer's left shoulder: the classic illustration setup,
        // so form reads without the user placing a light.
        renderer::Light key;
        key.direction = (-0.6 * scene.camera.right() + 0.8 * scene.camera.up() -
                         0.7 * scene.camera.forward()).normalized();
        key.intensity = 1.0;
        scene.lights.push_back(key);
    }
    scene.shading.shadows = desc.shadows.value;
    scene.style = desc.style.style;
    scene.shading.ambient = scene.style.ambient;
    if (desc.ambientOcclusion.enabled && scene.mesh.nVertices() > 0) {
        Vec3 lo, hi;
        scene.mesh.bounds(lo, hi);
        // Relative to the mesh's size, so the drawing is the same at any scale.
        const double radius = desc.ambientOcclusion.radius * (hi - lo).norm();
        if (radius > 0.0) {
            scene.shading.aoSamples = desc.ambientOcclusion.samples;
            scene.shading.aoRadius = radius;
            scene.shading.aoSeed = scene.style.seed;
        }
    }
    scene.output = desc.output.value;
    return scene;
}

} // namespace rosy::scenes
