#include "scenes/overrides.h"

#include <yaml-cpp/depthguard.h>

#include <string>
#include <vector>

namespace rosy::scenes::detail {

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

} // namespace rosy::scenes::detail
