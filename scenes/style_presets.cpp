#include "scenes/style_presets.h"

#include "renderer/output/svg.h"
#include "scenes/scene.h"
#include "scenes/style_block.h"
#include "scenes/yaml_reader.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <tuple>

namespace rosy::scenes {
namespace fs = std::filesystem;
using namespace detail;

namespace {

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
        StyleKey{"hatch.lines", SK::Text, 0, 0, nullptr, nullptr, nullptr, nullptr},
        ROSY_NUM("hatch.quad_edge_px", 2.0, 512.0, hatch.quadEdgePx),
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
        ROSY_NUM("contour.feature_scale_px", 0.0, 256.0, contour.featureScalePx),
        ROSY_BOOL("contour.borders", contour.borders),
        ROSY_BOOL("contour.hidden", contour.hidden),
        StyleKey{"page.size", SK::Text, 0, 0, nullptr, nullptr, nullptr, nullptr},
        ROSY_NUM("page.margin_mm", 0.0, 1000.0, page.marginMm),
        StyleKey{"page.orientation", SK::Text, 0, 0, nullptr, nullptr, nullptr, nullptr},
        ROSY_NUM("page.pen_width_mm", 0.0, 10.0, page.penWidthMm),
        ROSY_NUM("page.px_mm", 0.01, 10.0, page.pxMm),
        ROSY_NUM("page.min_spacing_mm", 0.0, 100.0, page.minSpacingMm),
        ROSY_NUM("page.max_spacing_mm", 0.0, 1000.0, page.maxSpacingMm),
        ROSY_NUM("page.min_length_mm", 0.0, 1000.0, page.minLengthMm),
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
    if (dotted == "hatch.lines") {
        using L = styles::HatchStyle::Lines;
        if (text == "field") style.hatch.lines = L::Field;
        else if (text == "quad_mesh") style.hatch.lines = L::QuadMesh;
        else p.fail(value, what + " must be field or quad_mesh, got '" + text + "'",
                    "field: streamlines of the field (the default); quad_mesh: the edges of the field's quad remesh");
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
    if (style.page.minSpacingMm > 0 && style.page.maxSpacingMm > 0 && style.page.maxSpacingMm < style.page.minSpacingMm)
        throw InputError(where("page.max_spacing_mm", "page.min_spacing_mm"),
                         "page.max_spacing_mm (" + Parser::fmt(style.page.maxSpacingMm) +
                             ") is below page.min_spacing_mm (" + Parser::fmt(style.page.minSpacingMm) + ")",
                         "the sparsest spacing must be at least the densest");
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

} // namespace

namespace detail {

void parseStyle(const Parser &p, const YAML::Node &node, StyleDesc &sd) {
    sd.loc = p.loc(node);
    if (!node.IsMap()) p.fail(node, "style must be a map (key: value lines), got " + Parser::kindOf(node));
    // The preset goes first wherever it is written, so the block's own keys win.
    if (const YAML::Node presetNode = node["preset"]) {
        const std::string value = p.text(presetNode, "style.preset");
        sd.preset = Located<std::string>{value, p.loc(presetNode)};
        if (looksLikePath(value)) {
            sd.presetPath = p.existingFile(presetNode, value, "style preset",
                                           "give a preset name or a path relative to the scene file",
                                           "give a preset name or the path of a preset .yaml file")
                                .string();
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

} // namespace detail

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

} // namespace rosy::scenes
