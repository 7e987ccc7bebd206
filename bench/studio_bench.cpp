// rosyhatch studio's speed (issue 19), each figure a median and a ratio against a
// yardstick measured in the same run:
//   - an edit request (cancel the closest opposite pair) through HTTP until the new
//     field and singularities are received, against the library's own edit
//     (field::applyFieldEdits + findSingularities on the same field);
//   - an element added (the whole field rebuilt) through HTTP, against
//     scenes::buildSceneField() of the scene (the field pipeline alone), and in
//     process with its steps (Studio::lastEditTimings(): parse, field,
//     singularities, directions, response; the mesh-only parts are kept in the
//     studio's field::FieldCache);
//   - a first load (Studio built, then state, mesh and field fetched), against
//     scenes::buildSceneField() of the scene;
//   - a 512² preview PNG, against scenes::renderScene() at 512² (no file written).
// The page's own drawing time is measured in the browser (docs/studio.md).
//
//   studio_bench [SCENE.yaml] [REPEATS]     (defaults: scenes/bunny.yaml, 15)
//   studio_bench --large [REPEATS]          (default 5) the 270k-face stress mesh:
//       armadillo (52,000 faces) midpoint-subdivided once, 15 % of the faces split
//       into slivers, vertices moved by noise (tools/make_scan_mesh.py, written to a
//       temporary folder with a copy of scenes/armadillo.yaml): 270,464 faces, shown
//       on the page as a display mesh (docs/studio.md).
// The measurements of each group are taken in turn, round after round (after one
// untimed round), so that a yardstick and what it measures see the same machine.

#include "field/edits.h"
#include "field/singularities.h"
#include "scenes/pipeline.h"
#include "studio/display_mesh.h"
#include "studio/server.h"
#include "studio/studio.h"

#include <httplib.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <functional>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// Medians of several measurements taken in turn, round after round, so that every
/// one sees the same machine (this one is shared: its load changes within seconds).
/// Each entry: the timed work and untimed work after it. One untimed warm-up round.
std::vector<double> interleaved(int repeats,
                                const std::vector<std::pair<std::function<void()>, std::function<void()>>> &work) {
    std::vector<std::vector<double>> t(work.size());
    for (int round = -1; round < repeats; ++round)
        for (size_t k = 0; k < work.size(); ++k) {
            const auto a = Clock::now();
            work[k].first();
            if (round >= 0) t[k].push_back(ms(a, Clock::now()));
            if (work[k].second) work[k].second();
        }
    std::vector<double> out;
    for (auto &v : t) out.push_back(median(v));
    return out;
}

std::pair<int, int> closestPair(const std::vector<rosy::field::Singularity> &s) {
    std::pair<int, int> best{-1, -1};
    double bestD = 1e300;
    for (size_t i = 0; i < s.size(); ++i)
        for (size_t j = 0; j < s.size(); ++j)
            if (s[i].indexNumerator == 1 && s[j].indexNumerator == -1) {
                const double d = (s[i].position - s[j].position).norm();
                if (d < bestD) bestD = d, best = {int(i), int(j)};
            }
    return best;
}

void require(bool ok, const char *what) {
    if (!ok) {
        std::fprintf(stderr, "studio_bench: %s failed\n", what);
        std::exit(1);
    }
}

} // namespace

/// The --large scene: its folder (removed at exit by the caller) and path.
std::string makeLargeScene(const std::filesystem::path &dir) {
    namespace fs = std::filesystem;
    const std::string src = ROSY_SOURCE_DIR;
    fs::create_directories(dir);
    const std::string mesh = (dir / "armadillo-270k.off").string();
    const std::string cmd = "python3 '" + src + "/tools/make_scan_mesh.py' '" + src +
                            "/data/meshes/armadillo.off' '" + mesh +
                            "' --faces 200000 --slivers 0.15 --noise 0.1 --thin 0 --seed 1 > /dev/null";
    require(std::system(cmd.c_str()) == 0, "making the 270k-face mesh (tools/make_scan_mesh.py)");
    std::ifstream in(src + "/scenes/armadillo.yaml");
    std::string text((std::istreambuf_iterator<char>(in)), {}), line, out;
    std::istringstream lines(text);
    while (std::getline(lines, line))
        out += (line.rfind("mesh:", 0) == 0 ? "mesh: " + mesh : line) + "\n";
    const std::string scene = (dir / "armadillo-270k.yaml").string();
    std::ofstream(scene) << out;
    return scene;
}

int main(int argc, char **argv) {
    const bool large = argc > 1 && std::string(argv[1]) == "--large";
    const std::filesystem::path largeDir =
        std::filesystem::temp_directory_path() / ("rosy-studio-bench-" + std::to_string(::getpid()));
    const std::string scenePath = large      ? makeLargeScene(largeDir)
                                  : argc > 1 ? argv[1]
                                             : std::string(ROSY_SOURCE_DIR) + "/scenes/bunny.yaml";
    const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : large ? 5 : 15;
    const int slow = std::max(3, repeats / 3);
    const rosy::scenes::SceneDesc desc = rosy::scenes::parseSceneFile(scenePath);
    const rosy::scenes::SceneDesc small = rosy::scenes::parseSceneFile(scenePath, {"camera.resolution=[512,512]"});
    rosy::scenes::PipelineOptions noMeasure;
    noMeasure.measureHatching = false;

    // The library alone (yardsticks) and the studio, in process and through HTTP.
    rosy::scenes::SceneField sf = rosy::scenes::buildSceneField(desc);
    // On a noisy scan the field is designed on the smoothed copy (field/scan_noise.h):
    // the yardstick edits it there, as the studio does.
    const auto &frames = sf.field.fieldFrames(*sf.loaded.frames);
    const auto pair = closestPair(sf.field.singularities.singularities);
    require(pair.first >= 0, "finding an opposite pair");
    rosy::studio::Studio st(scenePath);
    rosy::studio::StudioServer srv(st, {});
    const int port = srv.bind();
    srv.start();
    httplib::Client c("127.0.0.1", port);
    c.set_default_headers({{"X-Rosy-Token", srv.token()}});
    c.set_read_timeout(300); // a field rebuild of a large mesh takes longer than httplib's 5 s
    const std::string cancel = nlohmann::json{{"op", "cancel"}, {"a", pair.first}, {"b", pair.second}}.dump();
    const auto p = sf.field.singularities.singularities[pair.first].position;
    const std::string add =
        nlohmann::json{{"op", "add_element"}, {"position", {p.x(), p.y(), p.z()}}, {"order", 1}, {"phase", 0}}.dump();
    auto ok = [](const httplib::Result &r) { return r && r->status == 200; };
    auto undo = [&] { require(ok(c.Post("/api/undo", "", "text/plain")), "undo"); };
    size_t responseBytes = 0;

    const std::vector<double> edits = interleaved(
        repeats, {{[&] {
                       rosy::field::RosyField f = sf.field.fieldOnFieldFrames();
                       rosy::field::FieldEdit e;
                       e.op = rosy::field::FieldEdit::Op::CancelNear; // as the studio saves it
                       e.p = sf.field.singularities.singularities[pair.first].position;
                       e.q = sf.field.singularities.singularities[pair.second].position;
                       rosy::field::applyFieldEdits(frames, f, {e});
                       rosy::field::findSingularities(frames, f);
                   },
                   {}},
                  {[&] { st.edit(cancel); }, [&] { st.undo(); }},
                  {[&] {
                       auto r = c.Post("/api/edit", cancel, "application/json");
                       require(r && r->status == 200, "the cancel request");
                       responseBytes = r->body.size();
                   },
                   undo},
                  {[&] { st.fieldBinary(); }, {}},
                  {[&] { st.stateJson(); }, {}}});
    std::vector<rosy::scenes::StageTimings> addStages; // Studio::lastEditTimings() of each +1 element in process
    const std::vector<double> rebuilds = interleaved(
        slow, {{[&] { rosy::scenes::buildSceneField(desc); }, {}},
               {[&] { require(ok(c.Post("/api/edit", add, "application/json")), "the element request"); },
                undo},
               {[&] {
                    st.edit(add);
                    addStages.push_back(st.lastEditTimings());
                },
                [&] { st.undo(); }},
               {[&] {
                    rosy::studio::Studio fresh(scenePath);
                    rosy::studio::StudioServer s2(fresh, {});
                    const int port2 = s2.bind();
                    s2.start();
                    httplib::Client c2("127.0.0.1", port2);
                    c2.set_default_headers({{"X-Rosy-Token", s2.token()}});
                    c2.set_read_timeout(300);
                    auto a = c2.Get("/api/state");
                    auto m = c2.Get("/api/mesh");
                    auto f = c2.Get("/api/field");
                    require(a && m && f && a->status == 200 && m->status == 200 && f->status == 200, "first load");
                    s2.stop();
                },
                {}}});
    // The display mesh (made once at load above StudioOptions::displayAbove faces).
    const rosy::studio::StudioOptions defaults;
    std::vector<double> displayMs;
    for (int k = 0; k < 3; ++k) {
        const auto t0 = Clock::now();
        rosy::studio::makeDisplayMesh(sf.loaded.scene->mesh, defaults.displayFaces);
        displayMs.push_back(ms(t0, Clock::now()));
    }
    const auto firstPreviewStart = Clock::now();
    require(ok(c.Post("/api/preview?size=512", "", "text/plain")), "the first preview");
    const double firstPreview = ms(firstPreviewStart, Clock::now());
    const std::vector<double> previews = interleaved(
        slow, {{[&] { rosy::scenes::renderScene(small, noMeasure); }, {}},
               {[&] { require(ok(c.Post("/api/preview?size=512", "", "text/plain")), "the preview"); }, {}}});
    srv.stop();

    std::printf("studio_bench %s (%d vertices, %d faces), medians of %d (%d for the slow ones), interleaved\n",
                scenePath.c_str(), sf.loaded.scene->mesh.nVertices(), sf.loaded.scene->mesh.nFaces(), repeats, slow);
    std::printf("%-46s %9s %26s %9s %7s\n", "what", "median", "yardstick", "median", "ratio");
    auto row = [](const char *what, double t, const char *yard, double y) {
        std::printf("%-46s %7.1f ms %26s %7.1f ms %6.2fx\n", what, t, yard, y, t / y);
    };
    row("edit request: cancel -> field + singularities", edits[2], "library cancel_near + find", edits[0]);
    row("Studio::edit() cancel, in process (no HTTP)", edits[1], "library cancel_near + find", edits[0]);
    row("  Studio::fieldBinary()", edits[3], "library cancel_near + find", edits[0]);
    row("  Studio::stateJson()", edits[4], "library cancel_near + find", edits[0]);
    row("edit request: +1 element (field rebuilt)", rebuilds[1], "buildSceneField()", rebuilds[0]);
    row("Studio::edit() +1 element, in process", rebuilds[2], "buildSceneField()", rebuilds[0]);
    for (size_t k = 0; !addStages.empty() && k < addStages.back().size(); ++k) {
        std::vector<double> t;
        for (const auto &stages : addStages)
            if (k < stages.size()) t.push_back(stages[k].second);
        const std::string what = "  step: " + addStages.back()[k].first;
        row(what.c_str(), median(t), "buildSceneField()", rebuilds[0]);
    }
    row("first load: studio + state + mesh + field", rebuilds[3], "buildSceneField()", rebuilds[0]);
    row("makeDisplayMesh() (at most 50,000 faces)", median(displayMs), "buildSceneField()", rebuilds[0]);
    row("preview 512^2 PNG (scene at 512 cached)", previews[1], "renderScene() at 512^2", previews[0]);
    row("first preview 512^2 (loads the scene at 512)", firstPreview, "renderScene() at 512^2", previews[0]);
    std::printf("edit response: %zu bytes (state JSON + 24 bytes per display vertex)\n", responseBytes);
    std::printf("display mesh: %d vertices, %d faces (%s); mesh response %zu bytes\n",
                int(st.displayMesh().fullVertex.size()), int(st.displayMesh().faces.size()),
                st.decimated() ? "decimated" : "the mesh itself", st.meshBinary().size());
    if (large) std::filesystem::remove_all(largeDir);
    return 0;
}
