/// \file scene_writer.cpp
/// The `field:` block written back into a scene's text (scene_writer.h).

#include "scenes/scene_writer.h"

#include "core/error.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace rosy::scenes {
namespace {

/// Shortest text that reads back to exactly `x` (fmt's default for doubles).
std::string num(double x) { return fmt::format("{}", x); }

std::string vec(const field::Vec3 &v) { return fmt::format("[{}, {}, {}]", v.x(), v.y(), v.z()); }

std::vector<std::string> splitLines(const std::string &text) {
    std::vector<std::string> lines;
    std::string::size_type start = 0;
    while (start < text.size()) {
        const auto end = text.find('\n', start);
        if (end == std::string::npos) {
            lines.push_back(text.substr(start));
            break;
        }
        lines.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return lines;
}

bool blankOrComment(const std::string &line) {
    const auto first = line.find_first_not_of(" \t\r");
    return first == std::string::npos || line[first] == '#';
}

} // namespace

FieldBlock fieldBlockOf(const field::FieldSpec &spec, const std::vector<field::FieldEdit> &edits) {
    FieldBlock b;
    b.symmetry = spec.nSym;
    b.source = spec.source;
    b.smoothingLength = spec.smoothingLength;
    b.weights = spec.weights;
    b.globalSmoothingIterations = spec.globalSmoothingIterations;
    b.globalSmoothingStrength = spec.globalSmoothingStrength;
    b.featureAngleDeg = spec.featureAngleDeg;
    b.featureMinLength = spec.featureMinLength;
    for (const field::DesignElement &e : spec.elements)
        b.elements.push_back({e.position, e.order, e.direction, e.phaseRad * 180.0 / M_PI, e.strength});
    b.edits = edits;
    return b;
}

std::string fieldBlockYaml(const FieldBlock &b) {
    std::string s = "field:\n";
    s += "  symmetry: " + std::to_string(b.symmetry) + "\n";
    s += std::string("  source: ") + field::toString(b.source) + "\n";
    s += "  smoothing_length: " + num(b.smoothingLength) + "\n";
    s += std::string("  weights: ") + (b.weights == field::LaplaceWeights::Cotan ? "cotan" : "meanvalue") + "\n";
    if (b.globalSmoothingIterations > 0)
        s += "  global_smoothing: {iterations: " + std::to_string(b.globalSmoothingIterations) +
             ", strength: " + num(b.globalSmoothingStrength) + "}\n";
    if (b.featureAngleDeg > 0)
        s += "  features: {angle: " + num(b.featureAngleDeg) +
             (b.featureMinLength > 0 ? ", min_length: " + num(b.featureMinLength) : std::string()) + "}\n";
    if (!b.elements.empty()) {
        s += "  elements:\n";
        for (const FieldBlock::Element &e : b.elements) {
            s += "    - {position: " + vec(e.position) + ", order: " + std::to_string(e.order);
            if (e.order == 0) s += ", direction: " + vec(e.direction);
            else s += ", phase: " + num(e.phaseDeg);
            if (e.strength != 1) s += ", strength: " + num(e.strength);
            s += "}\n";
        }
    }
    if (!b.edits.empty()) {
        s += "  edits:\n";
        for (const field::FieldEdit &e : b.edits) {
            switch (e.op) {
            case field::FieldEdit::Op::Cancel:
                s += "    - {cancel: [" + std::to_string(e.a) + ", " + std::to_string(e.b) + "]}\n";
                break;
            case field::FieldEdit::Op::Move:
                s += "    - {move: {singularity: " + std::to_string(e.a) + ", to: " + vec(e.p) + "}}\n";
                break;
            case field::FieldEdit::Op::CancelNear:
                s += "    - {cancel_near: [" + vec(e.p) + ", " + vec(e.q) + "]}\n";
                break;
            }
        }
    }
    return s;
}

std::string replaceFieldBlock(const std::string &sceneText, const std::string &path, const FieldBlock &block) {
    YAML::Node root;
    try {
        root = YAML::Load(sceneText);
    } catch (const YAML::Exception &e) {
        throw InputError(FileLoc{path, e.mark.line + 1, e.mark.column + 1}, "YAML syntax error: " + e.msg,
                         "fix the scene file before saving into it");
    }
    const std::string fieldText = fieldBlockYaml(block);
    if (root.IsNull()) return sceneText + (sceneText.empty() || sceneText.back() == '\n' ? "" : "\n") + fieldText;
    if (!root.IsMap())
        throw InputError(FileLoc{path}, "the scene is not a YAML map", "write the scene as `key: value` lines");
    if (root.Style() == YAML::EmitterStyle::Flow)
        throw InputError(FileLoc{path}, "the scene's top level is written in flow style ({...}), where the field block "
                                        "cannot be replaced",
                         "write the top-level keys one per line, or save as a new file");
    int fieldLine = -1, endLine = std::numeric_limits<int>::max();
    std::vector<int> keyLines;
    for (auto it = root.begin(); it != root.end(); ++it) {
        const int line = it->first.Mark().line;
        if (it->first.IsScalar() && it->first.Scalar() == "field") fieldLine = line;
        keyLines.push_back(line);
    }
    std::vector<std::string> lines = splitLines(sceneText);
    if (fieldLine < 0) {
        std::string out = sceneText;
        if (!out.empty() && out.back() != '\n') out += '\n';
        return out + fieldText;
    }
    for (int line : keyLines) {
        if (line == fieldLine) continue;
        if (line > fieldLine) endLine = std::min(endLine, line);
    }
    int count = 0;
    for (int line : keyLines) count += line == fieldLine;
    if (count > 1)
        throw InputError(FileLoc{path, fieldLine + 1, 1}, "another top-level key shares the line of `field:`",
                         "write the top-level keys one per line, or save as a new file");
    endLine = std::min<int>(endLine, int(lines.size()));
    // Comments and blank lines right before the next key belong to it: keep them.
    while (endLine - 1 > fieldLine && blankOrComment(lines[endLine - 1])) --endLine;
    std::string out;
    for (int i = 0; i < fieldLine; ++i) out += lines[i] + "\n";
    out += fieldText;
    for (int i = endLine; i < int(lines.size()); ++i) out += lines[i] + "\n";
    return out;
}

} // namespace rosy::scenes
