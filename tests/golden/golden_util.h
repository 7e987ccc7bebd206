#pragma once
// Helpers of the golden suite: running rosyhatch, reading the flat numbers of
// its JSON reports, the scene overrides of each golden.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/wait.h>
#include <utility>
#include <vector>

#include "tests/test_output.h"

namespace golden {

namespace fs = std::filesystem;

inline const std::string kBinary = std::string(ROSY_BINARY_DIR) + "/cli/rosyhatch";
inline const fs::path kGoldenDir = fs::path(ROSY_SOURCE_DIR) / "tests" / "golden";
inline const fs::path kScenesDir = fs::path(ROSY_SOURCE_DIR) / "scenes";

/// Golden renders are this many pixels square.
inline constexpr int kGoldenSize = 256;

/// How a render gets its scene overrides: `rosyhatch render --set key=value`
/// (true) or a temporary copy of the scene with the keys edited in the text
/// (false, for a rosyhatch without --set). Switching is this one line.
inline constexpr bool kRenderHasSetOption = true;

/// The YAML value of camera.resolution for the golden size, "[256, 256]".
inline std::string goldenResolution() {
    std::ostringstream os;
    os << "[" << kGoldenSize << ", " << kGoldenSize << "]";
    return os.str();
}

inline fs::path workDir(const std::string &name) {
    return rosy::test::testOutputDir("golden/" + name);
}

using rosy::test::put;
using rosy::test::slurp;

struct RunResult {
    int exitCode;
    std::string out, err;
};

/// Runs rosyhatch with already shell-quoted `args`, output captured in `dir`.
inline RunResult runRosy(const std::string &args, const fs::path &dir, const std::string &tag) {
    const fs::path out = dir / (tag + ".stdout"), err = dir / (tag + ".stderr");
    // A stream, not operator+ chains: GCC 12 reports a false -Wrestrict on those.
    std::ostringstream cmd;
    cmd << "cd '" << dir.string() << "' && '" << kBinary << "' " << args << " >'" << out.string() << "' 2>'"
        << err.string() << "'";
    const int status = std::system(cmd.str().c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

using Overrides = std::vector<std::pair<std::string, std::string>>;

/// Without --set: a copy of `scene` in `dir` with the overrides written into
/// the text (camera.resolution, style.preset and lights.0.direction, the keys
/// the golden suite uses) and the relative mesh path made absolute.
inline fs::path editedSceneCopy(const fs::path &scene, const Overrides &overrides, const fs::path &dir) {
    std::string text = slurp(scene);
    text = std::regex_replace(text, std::regex(R"((^|\n)mesh: (\.\./\S+))"),
                              "$1mesh: " + (scene.parent_path().string() + "/") + "$2");
    for (const auto &[key, value] : overrides) {
        if (key == "camera.resolution") {
            text = std::regex_replace(text, std::regex(R"(resolution: \[[^\]]*\])"), "resolution: " + value);
        } else if (key == "style.preset") {
            if (text.find("\nstyle:\n") != std::string::npos)
                text = std::regex_replace(text, std::regex("\nstyle:\n"), "\nstyle:\n  preset: " + value + "\n");
            else
                text += "style: {preset: " + value + "}\n";
        } else if (key == "lights.0.direction") {
            text = std::regex_replace(text, std::regex(R"((type: directional, direction: )\[[^\]]*\])"),
                                      "$1" + value, std::regex_constants::format_first_only);
        } else {
            ADD_FAILURE() << "editedSceneCopy cannot apply " << key << "; use --set (kRenderHasSetOption)";
        }
    }
    const fs::path copy = dir / ("scene-" + scene.filename().string());
    put(copy, text);
    return copy;
}

/// The scene argument of `rosyhatch render` with the overrides applied either way.
inline std::string sceneArgs(const fs::path &scene, const Overrides &overrides, const fs::path &dir) {
    std::ostringstream args;
    if (!kRenderHasSetOption) {
        args << "'" << editedSceneCopy(scene, overrides, dir).string() << "'";
        return args.str();
    }
    args << "'" << scene.string() << "'";
    for (const auto &[key, value] : overrides) args << " --set '" << key << "=" << value << "'";
    return args.str();
}

/// Every top-level `"key": number` of a JSON object (null and non-numbers are left
/// out), read by a real parser. \throws nlohmann::json::exception when `json` is
/// not a JSON object, so a truncated or garbled report fails the test.
inline std::map<std::string, double> numbersOf(const std::string &json) {
    const nlohmann::json doc = nlohmann::json::parse(json);
    if (!doc.is_object()) throw std::invalid_argument("a report must be a JSON object, got: " + json);
    std::map<std::string, double> out;
    for (const auto &[key, value] : doc.items())
        if (value.is_number()) out.emplace(key, value.get<double>());
    return out;
}

/// One golden: a scene and the overrides that make it (256² always added).
struct Case {
    std::string name;  ///< file stem in tests/golden/ and the CTest name suffix
    std::string scene; ///< file in scenes/
    Overrides overrides;
};

/// Test names and failure messages show the case's name, not its bytes.
inline void PrintTo(const Case &c, std::ostream *os) { *os << c.name; }

/// Every example scene (scenes/*.yaml, sorted) and the bunny in every style
/// preset (styles/presets/*.yaml), found when the test program starts, so a new
/// scene or preset gets a test (failing until its golden exists).
inline std::vector<Case> allCases() {
    const std::string res = goldenResolution();
    auto identifier = [](std::string name) {
        for (char &c : name)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return name;
    };
    auto yamlStems = [](const fs::path &dir) {
        std::vector<std::string> stems;
        std::error_code ec;
        for (const auto &entry : fs::directory_iterator(dir, ec))
            if (entry.path().extension() == ".yaml") stems.push_back(entry.path().stem().string());
        std::sort(stems.begin(), stems.end());
        return stems;
    };
    std::vector<Case> cases;
    for (const std::string &scene : yamlStems(kScenesDir))
        cases.push_back({identifier(scene), scene + ".yaml", {{"camera.resolution", res}}});
    for (const std::string &preset : yamlStems(fs::path(ROSY_SOURCE_DIR) / "styles" / "presets"))
        cases.push_back({identifier("bunny_" + preset), "bunny.yaml", {{"camera.resolution", res}, {"style.preset", preset}}});
    return cases;
}

} // namespace golden
