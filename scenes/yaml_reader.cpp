#include "scenes/yaml_reader.h"

#include "core/input_file.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>

#include <sstream>

namespace rosy::scenes::detail {

styles::Rgb colour(const Parser &p, const YAML::Node &node, const std::string &what) {
    Vec3 c = p.vec3(node, what + " (linear RGB)", 0.0, 1.0);
    return {c.x(), c.y(), c.z()};
}

std::string readText(const std::string &path, const char *what) {
    return readInputFile(path, InputFileRules{what, kMaxSceneBytes, true});
}

void checkYamlShape(const Parser &p, const YAML::Node &node, std::vector<YAML::Node> &stack, long &visited,
                    const FileLoc *at, long maxValues) {
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

void checkFlowDepth(const Parser &p, const std::string &text, const FileLoc *at) {
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

namespace {

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

} // namespace

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

} // namespace rosy::scenes::detail
