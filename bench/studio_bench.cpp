// rosyhatch studio's speed (issue 19), each figure a median and a ratio against a
// yardstick measured in the same run:
//   - an edit request (cancel the closest opposite pair) through HTTP until the new
//     field and singularities are received, against the library's own edit
//     (field::applyFieldEdits + findSingularities on the same field);
//   - an element added (the whole field rebuilt) through HTTP, against
//     scenes::buildSceneField() of the scene (the field pipeline alone);
//   - a first load (Studio built, then state, mesh and field fetched), against
//     scenes::buildSceneField() of the scene;
//   - a 512² preview PNG, against scenes::renderScene() at 512² (no file written).
// The page's own drawing time is measured in the browser (docs/studio.md).
//
//   studio_bench [SCENE.yaml] [REPEATS]     (defaults: scenes/bunny.yaml, 15)

#include "field/edits.h"
#include "field/singularities.h"
#include "scenes/pipeline.h"
#include "studio/server.h"
#include "studio/studio.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
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

/// Median of `repeats` timings of `timed` (each preceded by `setup`, untimed).
double measure(int repeats, const std::function<void()> &timed, const std::function<void()> &after = {}) {
    std::vector<double> t;
    for (int i = 0; i < repeats; ++i) {
        const auto a = Clock::now();
        timed();
        t.push_back(ms(a, Clock::now()));
        if (after) after();
    }
    return median(t);
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

int main(int argc, char **argv) {
    const std::string scenePath = argc > 1 ? argv[1] : std::string(ROSY_SOURCE_DIR) + "/scenes/bunny.yaml";
    const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 15;
    const rosy::scenes::SceneDesc desc = rosy::scenes::parseSceneFile(scenePath);

    // Yardsticks: the library alone.
    rosy::scenes::SceneField sf = rosy::scenes::buildSceneField(desc);
    const auto &frames = *sf.loaded.frames;
    const auto pair = closestPair(sf.field.singularities.singularities);
    require(pair.first >= 0, "finding an opposite pair");
    const double libraryEdit = measure(repeats, [&] {
        rosy::field::RosyField f = sf.field.field.field;
        rosy::field::FieldEdit e;
        e.op = rosy::field::FieldEdit::Op::Cancel;
        e.a = pair.first;
        e.b = pair.second;
        rosy::field::applyFieldEdits(frames, f, {e});
        rosy::field::findSingularities(frames, f);
    });
    const double fieldPipeline = measure(std::max(3, repeats / 3), [&] { rosy::scenes::buildSceneField(desc); });
    rosy::scenes::SceneDesc small = rosy::scenes::parseSceneFile(scenePath, {"camera.resolution=[512,512]"});
    rosy::scenes::PipelineOptions noMeasure;
    noMeasure.measureHatching = false;
    const double render512 = measure(std::max(3, repeats / 3), [&] { rosy::scenes::renderScene(small, noMeasure); });

    // The studio through HTTP.
    double firstLoad = 0;
    {
        std::vector<double> t;
        for (int i = 0; i < std::max(3, repeats / 3); ++i) {
            const auto a = Clock::now();
            rosy::studio::Studio st(scenePath);
            rosy::studio::StudioServer srv(st, {});
            const int port = srv.bind();
            srv.start();
            httplib::Client c("127.0.0.1", port);
            c.set_default_headers({{"X-Rosy-Token", srv.token()}});
            auto s = c.Get("/api/state");
            auto m = c.Get("/api/mesh");
            auto f = c.Get("/api/field");
            require(s && m && f && s->status == 200 && m->status == 200 && f->status == 200, "first load");
            t.push_back(ms(a, Clock::now()));
            srv.stop();
        }
        firstLoad = median(t);
    }
    rosy::studio::Studio st(scenePath);
    rosy::studio::StudioServer srv(st, {});
    const int port = srv.bind();
    srv.start();
    httplib::Client c("127.0.0.1", port);
    c.set_default_headers({{"X-Rosy-Token", srv.token()}});
    const std::string cancel =
        nlohmann::json{{"op", "cancel"}, {"a", pair.first}, {"b", pair.second}}.dump();
    size_t responseBytes = 0;
    const double editRequest = measure(
        repeats,
        [&] {
            auto r = c.Post("/api/edit", cancel, "application/json");
            require(r && r->status == 200, "the cancel request");
            responseBytes = r->body.size();
        },
        [&] { require(c.Post("/api/undo", "", "text/plain")->status == 200, "undo"); });
    const double fieldInProcess = measure(repeats, [&] { st.fieldBinary(); });
    const double stateInProcess = measure(repeats, [&] { st.stateJson(); });
    const double editInProcess = measure(
        repeats, [&] { st.edit(cancel); }, [&] { st.undo(); });
    const auto p = sf.field.singularities.singularities[pair.first].position;
    const std::string add = nlohmann::json{{"op", "add_element"},
                                           {"position", {p.x(), p.y(), p.z()}},
                                           {"order", 1},
                                           {"phase", 0}}
                                .dump();
    const double elementRequest = measure(
        std::max(3, repeats / 3),
        [&] { require(c.Post("/api/edit", add, "application/json")->status == 200, "the element request"); },
        [&] { require(c.Post("/api/undo", "", "text/plain")->status == 200, "undo"); });
    const auto firstPreviewStart = Clock::now();
    require(c.Post("/api/preview?size=512", "", "text/plain")->status == 200, "the first preview");
    const double firstPreview = ms(firstPreviewStart, Clock::now());
    const double preview = measure(std::max(3, repeats / 3), [&] {
        require(c.Post("/api/preview?size=512", "", "text/plain")->status == 200, "the preview");
    });
    srv.stop();

    std::printf("studio_bench %s (%d vertices, %d faces), medians of %d (%d for the slow ones)\n", scenePath.c_str(),
                sf.loaded.scene->mesh.nVertices(), sf.loaded.scene->mesh.nFaces(), repeats, std::max(3, repeats / 3));
    std::printf("%-44s %9s %26s %9s %7s\n", "what", "median", "yardstick", "median", "ratio");
    auto row = [](const char *what, double t, const char *yard, double y) {
        std::printf("%-44s %7.1f ms %26s %7.1f ms %6.2fx\n", what, t, yard, y, t / y);
    };
    row("edit request: cancel -> field + singularities", editRequest, "library cancel + find", libraryEdit);
    row("Studio::edit() cancel, in process (no HTTP)", editInProcess, "library cancel + find", libraryEdit);
    row("  of which Studio::fieldBinary()", fieldInProcess, "library cancel + find", libraryEdit);
    row("  of which Studio::stateJson()", stateInProcess, "library cancel + find", libraryEdit);
    row("edit request: +1 element (field rebuilt)", elementRequest, "buildSceneField()", fieldPipeline);
    row("first load: studio + state + mesh + field", firstLoad, "buildSceneField()", fieldPipeline);
    row("preview 512^2 PNG (scene at 512 cached)", preview, "renderScene() at 512^2", render512);
    row("first preview 512^2 (loads the scene at 512)", firstPreview, "renderScene() at 512^2", render512);
    std::printf("edit response: %zu bytes (state JSON + 24 bytes per vertex)\n", responseBytes);
    return 0;
}
