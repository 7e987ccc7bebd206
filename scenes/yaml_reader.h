#pragma once
/// \file yaml_reader.h
/// Internal to scenes/: reading YAML with source locations. A Parser carries the
/// file's path and turns yaml-cpp's 0-based marks (and the nodes a --set override
/// put in the tree) into `FILE:LINE:COL` for every InputError; its typed reads
/// (number, whole number, boolean, text, vec3, colour) check type and range and
/// name the key in the message. loadYaml() reads one document within limits that
/// keep a hostile file from exhausting stack or memory. Only scenes/ includes this
/// header (it brings yaml-cpp).

#include "core/error.h"
#include "scenes/suggest.h"
#include "styles/style.h"

#include <Eigen/Core>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace rosy::scenes::detail {

using Vec3 = Eigen::Vector3d;

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

    /// A scalar quoted for a message: whole when short, else its first line cut at
    /// kQuoteMax characters with its length (a mesh file given where a scene belongs is
    /// one scalar of megabytes).
    static std::string quoteScalar(const std::string &text) {
        constexpr size_t kQuoteMax = 60;
        const size_t eol = text.find('\n');
        if (text.size() <= kQuoteMax && eol == std::string::npos) {
            std::string quoted = "'";
            quoted += text;
            quoted += '\'';
            return quoted;
        }
        size_t cut = std::min({text.size(), kQuoteMax, eol});
        while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut; // not inside a UTF-8 character
        std::string quoted = "'";
        quoted.append(text, 0, cut);
        quoted += "...' (";
        quoted += std::to_string(text.size());
        quoted += " characters)";
        return quoted;
    }

    static std::string kindOf(const YAML::Node &node) {
        switch (node.Type()) {
        case YAML::NodeType::Map: return "a map";
        case YAML::NodeType::Sequence: return "a list";
        case YAML::NodeType::Scalar: return quoteScalar(node.Scalar());
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

    /// A number for messages: six significant digits (printf's %g), so 1e-9 reads
    /// 1e-09 rather than std::to_string's 0.000000.
    static std::string fmt(double v) { return ::fmt::format("{:g}", v); }

    /// The file named by `value` (written at `node`), resolved against this file's
    /// folder and normalised. Fails at `node` with "WHAT file '...' does not exist"
    /// (hint `missingHint`) or "WHAT '...' is a folder, not a file" (`folderHint`).
    std::filesystem::path existingFile(const YAML::Node &node, const std::string &value, const std::string &what,
                                       const std::string &missingHint, const std::string &folderHint = {}) const {
        std::filesystem::path file(value);
        if (file.is_relative()) file = std::filesystem::path(m_path).parent_path() / file;
        file = file.lexically_normal();
        std::error_code ec;
        if (!std::filesystem::exists(file, ec))
            fail(node, what + " file '" + file.string() + "' does not exist", missingHint);
        if (std::filesystem::is_directory(file, ec))
            fail(node, what + " '" + file.string() + "' is a folder, not a file", folderHint);
        return file;
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

/// A linear RGB colour written as [r, g, b], each in [0, 1].
styles::Rgb colour(const Parser &p, const YAML::Node &node, const std::string &what);

/// Scene and preset files are small (a few KB); this bound stops an endless
/// stream (a link to /dev/zero, `yes | rosyhatch render /dev/stdin`) early.
constexpr size_t kMaxSceneBytes = 4u << 20;

/// The text of a scene or preset file (at most kMaxSceneBytes, a regular file).
/// \throws IoError naming `what` ("scene file", "style preset") and the path.
std::string readText(const std::string &path, const char *what);

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
                    const FileLoc *at = nullptr, long maxValues = kMaxYamlValues);

/// Flow brackets ([ and {) nested deeper than kMaxYamlDepth, found in the text
/// before yaml-cpp recurses into them, so the error names the exact column.
/// Brackets inside quoted scalars and comments do not count. `at` locates the
/// error when the text is a --set value.
void checkFlowDepth(const Parser &p, const std::string &text, const FileLoc *at = nullptr);

/// Parses one YAML document and checks its shape: one document, nesting and
/// alias expansion within the limits above.
YAML::Node loadYaml(const Parser &p, const std::string &text);

} // namespace rosy::scenes::detail
