// The golden suite: every example scene and every style preset rendered at
// 256², compared with its committed golden (tests/golden/<name>.png) through
// renderer/evaluation/image_diff.h, and gated on the structure of the drawing (the render
// report and `rosyhatch inspect` against <name>.report.json / .inspect.json).
//
// Regenerate every golden (then LOOK at each PNG before committing):
//     ROSY_UPDATE_GOLDENS=1 ctest --test-dir build -R golden
// On failure the test leaves new.png, golden.png, diff.png and index.html (all
// three side by side) in build/test-output/golden/<name>/ and prints the paths.

#include "golden_util.h"

#include "renderer/output/image.h"
#include "renderer/evaluation/image_diff.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

namespace {

using namespace golden;
namespace r = rosy::renderer;

bool updating() {
    const char *v = std::getenv("ROSY_UPDATE_GOLDENS");
    return v && std::string(v) == "1";
}

/// The golden report of a field picture: the figures of `rosyhatch field --json`
/// that the picture shows (N, the singularities and their index sum, the surface's
/// Euler characteristic), flat so the same gates read them.
std::string fieldPictureReport(const std::string &fieldJson) {
    const nlohmann::json field = nlohmann::json::parse(fieldJson);
    nlohmann::ordered_json report;
    report["symmetry"] = field.at("field").at("symmetry");
    report["singularities"] = field.at("singularities").size();
    report["index_sum"] = field.at("index_sum");
    report["euler_characteristic"] = field.at("mesh").at("euler_characteristic");
    return report.dump(2) + "\n";
}

struct Rendered {
    fs::path exr, png, report, inspect;
    double hatchSpacingPx = 0.0;
};

/// Renders a case as EXR (the channels, for inspect) and PNG (the picture: the
/// EXR's RGBA is the ink alone, premultiplied) from one render, with its report.
Rendered renderCase(const std::string &scene, const Overrides &overrides, const fs::path &dir) {
    Rendered out{dir / "new.exr", dir / "new.png", dir / "new.report.json", dir / "new.inspect.json"};
    for (const fs::path &p : {out.exr, out.png, out.report, out.inspect}) fs::remove(p);
    std::ostringstream args;
    args << "render " << sceneArgs(kScenesDir / scene, overrides, dir) << " -o '" << out.exr.string() << "' -o '"
         << out.png.string() << "' --report '" << out.report.string() << "' --quiet";
    const RunResult render = runRosy(args.str(), dir, "render");
    if (render.exitCode == 2 && render.err.find("field picture") != std::string::npos) {
        // A field picture (the paper's figures) has no strokes to report or ink
        // channels to inspect: the golden is its picture and what the picture shows,
        // the field's topology as `rosyhatch field` reports it for the same scene.
        std::ostringstream png;
        png << "render " << sceneArgs(kScenesDir / scene, overrides, dir) << " -o '" << out.png.string()
            << "' --quiet";
        const RunResult picture = runRosy(png.str(), dir, "render-picture");
        EXPECT_EQ(picture.exitCode, 0) << picture.err;
        const fs::path fieldJson = dir / "new.field.json";
        fs::remove(fieldJson);
        const RunResult field = runRosy("field " + sceneArgs(kScenesDir / scene, overrides, dir) + " --json '" +
                                            fieldJson.string() + "' --quiet",
                                        dir, "field");
        EXPECT_EQ(field.exitCode, 0) << field.err;
        put(out.report, fieldPictureReport(slurp(fieldJson)));
        put(out.inspect, "{}\n");
        return out;
    }
    EXPECT_EQ(render.exitCode, 0) << render.err;
    const RunResult inspect = runRosy("inspect '" + out.exr.string() + "' --json '" + out.inspect.string() + "'", dir,
                                "inspect");
    // A hatching render always has ink channels to inspect (field pictures returned
    // above), so any failure is reported with its stderr: a subprocess that died at
    // exit (LeakSanitizer's tracer, see tools/ci-extra.sh) must show its message in
    // the log instead of passing as a render without quality figures.
    if (inspect.exitCode != 0) put(out.inspect, "{}\n");
    EXPECT_EQ(inspect.exitCode, 0) << inspect.err;
    if (render.exitCode != 0) return out;
    out.hatchSpacingPx = r::readDiffInput(out.exr.string()).hatchSpacingPx;
    return out;
}

/// The report with machine-specific paths replaced, fit to commit.
std::string portableReport(const std::string &report, const Case &c) {
    std::string text = std::regex_replace(report, std::regex(R"("scene": "[^"]*")"),
                                          "\"scene\": \"scenes/" + c.scene + "\"");
    return std::regex_replace(text, std::regex(R"("output": "[^"]*")"), "\"output\": \"" + c.name + ".png\"");
}

/// One structural gate: a figure of the new render against the golden's.
struct Gate {
    std::string key;
    double golden, now, tolerance;
    bool ok;
};

/// Relative gates (1 %) on the amount of drawing, absolute ones on the quality
/// figures, exact equality on the topology of the field.
std::vector<Gate> checkGates(const std::map<std::string, double> &goldReport,
                             const std::map<std::string, double> &newReport,
                             const std::map<std::string, double> &goldInspect,
                             const std::map<std::string, double> &newInspect, std::string &problems) {
    std::vector<Gate> gates;
    auto gate = [&](const std::map<std::string, double> &g, const std::map<std::string, double> &n,
                    const std::string &key, double tolerance, bool relative) {
        const bool inG = g.count(key) > 0, inN = n.count(key) > 0;
        if (!inG && !inN) return; // unmeasurable (null) in both
        if (inG != inN) {
            gates.push_back({key, inG ? g.at(key) : NAN, inN ? n.at(key) : NAN, tolerance, false});
            problems += key + " is measured in only one of golden and new render\n";
            return;
        }
        const double a = g.at(key), b = n.at(key);
        const double tol = relative ? tolerance * std::abs(a) : tolerance;
        const bool ok = std::abs(a - b) <= tol;
        gates.push_back({key, a, b, tol, ok});
        if (!ok) {
            std::ostringstream os;
            os << key << ": golden " << a << ", now " << b << " (allowed +-" << tol << ")\n";
            problems += os.str();
        }
    };
    gate(goldReport, newReport, "strokes", 0.01, true);
    gate(goldReport, newReport, "ink_length_px", 0.01, true);
    gate(goldReport, newReport, "symmetry", 0, false);
    gate(goldReport, newReport, "singularities", 0, false);
    gate(goldReport, newReport, "index_sum", 1e-9, false);            // field pictures
    gate(goldReport, newReport, "euler_characteristic", 0, false);    // field pictures
    // Every golden gates the field at least: a report without these compares nothing.
    for (const char *key : {"symmetry", "singularities"})
        if (!goldReport.count(key)) problems += std::string("the golden report has no ") + key + ": nothing is gated\n";
    const double strokes = goldReport.count("strokes") ? goldReport.at("strokes") : 0.0;
    gate(goldReport, newReport, "min_spacing_violations", std::max(2.0, 0.01 * strokes), false);
    gate(goldReport, newReport, "strokes_near_singularities", std::max(2.0, 0.01 * strokes), false);
    gate(goldInspect, newInspect, "alignment_median_deg", 0.5, false);
    gate(goldInspect, newInspect, "alignment_p90_deg", 1.0, false);
    gate(goldInspect, newInspect, "tone_mae", 0.005, false);
    gate(goldInspect, newInspect, "spacing_cv", 0.02, false);
    gate(goldInspect, newInspect, "ink_outside_silhouette_px", 10, false);
    return gates;
}

std::string htmlEscape(const std::string &s) {
    std::string out;
    for (char c : s) out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
    return out;
}

void writeHtml(const fs::path &dir, const Case &c, const std::string &diffText, const std::vector<Gate> &gates) {
    std::ostringstream html;
    html << "<!doctype html><meta charset=\"utf-8\"><title>golden " << c.name << "</title>\n"
         << "<style>body{font-family:sans-serif} img{width:512px;image-rendering:pixelated;border:1px solid #999}"
            " td{vertical-align:top;padding:4px} .bad{color:#c00;font-weight:bold}</style>\n"
         << "<h1>golden " << c.name << " (scenes/" << c.scene << ")</h1>\n"
         << "<table><tr><th>golden</th><th>new render</th><th>amplified diff (red: more ink, blue: less)</th></tr>\n"
         << "<tr><td><img src=\"golden.png\"></td><td><img src=\"new.png\"></td><td><img src=\"diff.png\"></td></tr>"
            "</table>\n<h2>image comparison</h2><pre>"
         << htmlEscape(diffText) << "</pre>\n<h2>structure</h2><table><tr><th>figure</th><th>golden</th><th>now</th>"
         << "<th>allowed</th></tr>\n";
    for (const Gate &g : gates)
        html << "<tr" << (g.ok ? "" : " class=\"bad\"") << "><td>" << g.key << "</td><td>" << g.golden << "</td><td>"
             << g.now << "</td><td>&plusmn;" << g.tolerance << "</td></tr>\n";
    html << "</table>\n<p>If the change is intended: <code>ROSY_UPDATE_GOLDENS=1 ctest --test-dir build -R golden</code>,"
            " then look at every PNG in tests/golden/ before committing.</p>\n";
    put(dir / "index.html", html.str());
}

class GoldenScene : public ::testing::TestWithParam<Case> {};

TEST_P(GoldenScene, MatchesGolden) {
    const Case &c = GetParam();
    const fs::path dir = workDir(c.name);
    fs::remove(dir / "index.html");
    const Rendered now = renderCase(c.scene, c.overrides, dir);
    ASSERT_TRUE(fs::exists(now.png)) << "render failed, see " << dir;

    const fs::path goldPng = kGoldenDir / (c.name + ".png");
    const fs::path goldReport = kGoldenDir / (c.name + ".report.json");
    const fs::path goldInspect = kGoldenDir / (c.name + ".inspect.json");
    if (updating()) {
        fs::copy_file(now.png, goldPng, fs::copy_options::overwrite_existing);
        put(goldReport, portableReport(slurp(now.report), c));
        fs::copy_file(now.inspect, goldInspect, fs::copy_options::overwrite_existing);
        std::cout << "updated " << goldPng.string() << " (look at it before committing)\n";
        return;
    }
    ASSERT_TRUE(fs::exists(goldPng) && fs::exists(goldReport) && fs::exists(goldInspect))
        << "no golden for " << c.name << " in " << kGoldenDir << "; create it with "
        << "ROSY_UPDATE_GOLDENS=1 ctest --test-dir <build> -R golden";

    const r::DiffOptions options; // the documented defaults, blur from the style's hatch spacing
    const r::DiffInput gold = r::readDiffInput(goldPng.string());
    const r::DiffInput fresh = r::readDiffInput(now.png.string());
    const r::DiffResult diff = r::compareImages(gold.image, fresh.image, options, now.hatchSpacingPx);
    const std::string diffText = r::diffReportText(diff, options);

    std::string problems;
    const std::vector<Gate> gates = checkGates(numbersOf(slurp(goldReport)), numbersOf(slurp(now.report)),
                                               numbersOf(slurp(goldInspect)), numbersOf(slurp(now.inspect)),
                                               problems);
    const bool imageOk = diff.verdict != r::DiffVerdict::Fail;
    if (!imageOk || !problems.empty()) {
        fs::copy_file(goldPng, dir / "golden.png", fs::copy_options::overwrite_existing);
        if (diff.diffImage.width > 0) r::writeImage(diff.diffImage, (dir / "diff.png").string());
        writeHtml(dir, c, diffText, gates);
        ADD_FAILURE() << c.name << " differs from its golden\n"
                      << diffText << problems << "  new render: " << now.png.string() << "\n"
                      << "  golden:     " << (dir / "golden.png").string() << "\n"
                      << "  diff:       " << (dir / "diff.png").string() << "\n"
                      << "  side by side: " << (dir / "index.html").string() << "\n"
                      << "  intended? ROSY_UPDATE_GOLDENS=1 ctest --test-dir <build> -R golden";
    }
}

INSTANTIATE_TEST_SUITE_P(golden, GoldenScene, ::testing::ValuesIn(allCases()),
                         [](const ::testing::TestParamInfo<Case> &info) { return info.param.name; });

TEST(GoldenSuite, EveryGoldenFileBelongsToACase) {
    // A golden whose scene or preset was removed would never be checked again.
    std::set<std::string> names;
    for (const Case &c : allCases()) names.insert(c.name);
    EXPECT_GE(names.size(), 8u); // five scenes and three presets at least
    for (const auto &entry : fs::directory_iterator(kGoldenDir)) {
        const std::string file = entry.path().filename().string();
        const size_t dot = file.find('.');
        const std::string ext = dot == std::string::npos ? "" : file.substr(dot);
        if (ext != ".png" && ext != ".report.json" && ext != ".inspect.json") continue;
        EXPECT_TRUE(names.count(file.substr(0, dot))) << file << " belongs to no scene or preset: delete it";
    }
}

TEST(GoldenSuite, GoldensStaySmall) {
    uintmax_t total = 0;
    for (const auto &entry : fs::directory_iterator(kGoldenDir))
        if (entry.is_regular_file()) total += entry.file_size();
    EXPECT_LT(total, 2u * 1024u * 1024u) << "tests/golden/ holds " << total << " bytes";
}

} // namespace
