// Renderer-stage benchmarks on bunny00 at 1024², and the yardstick the issue
// asks for: the G-buffer stage against a bare Embree primary-ray loop over the
// same scene (single rays, same camera, same parallel rows), so the overhead of
// our G-buffer (barycentrics, positions, interpolated normals, depth) is visible.
#include "core/parallel.h"
#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "renderer/illustration.h"
#include "renderer/view/shading.h"
#include "renderer/strokes/screen_field.h"
#include "renderer/output/raster.h"
#include "renderer/output/image.h"
#include "renderer/strokes/hatching.h"
#include "renderer/strokes/contours.h"
#include "scenes/pipeline.h"
#include "scenes/scene.h"
#include "renderer/view/camera.h"
#include "renderer/view/embree_scene.h"
#include "renderer/view/gbuffer.h"

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

using namespace rosy;

namespace {
constexpr int kSize = 1024;

struct Setup {
    field::Mesh mesh;
    std::unique_ptr<renderer::RayScene> scene;
    std::unique_ptr<renderer::Camera> camera;
    // A bare Embree scene of the same triangles, built the plain way.
    RTCDevice device = nullptr;
    RTCScene bare = nullptr;
};

Setup &setup() {
    static Setup *s = [] {
        auto *x = new Setup;
        x->mesh = field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
        x->scene = std::make_unique<renderer::RayScene>(x->mesh);
        renderer::FramingOptions framing;
        x->camera = std::make_unique<renderer::Camera>(renderer::frameMesh(x->mesh, kSize, kSize, framing));
        x->device = rtcNewDevice(nullptr);
        x->bare = rtcNewScene(x->device);
        RTCGeometry g = rtcNewGeometry(x->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto *v = static_cast<float *>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), x->mesh.nVertices() + 1));
        for (int i = 0; i < x->mesh.nVertices(); ++i)
            for (int k = 0; k < 3; ++k) v[3 * i + k] = float(x->mesh.position(i)[k]);
        auto *t = static_cast<unsigned *>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(unsigned), x->mesh.nFaces()));
        for (int f = 0; f < x->mesh.nFaces(); ++f)
            for (int k = 0; k < 3; ++k) t[3 * f + k] = unsigned(x->mesh.face(f)[k]);
        rtcCommitGeometry(g);
        rtcAttachGeometry(x->bare, g);
        rtcReleaseGeometry(g);
        if (std::getenv("BARE_ROBUST")) rtcSetSceneFlags(x->bare, RTC_SCENE_FLAG_ROBUST);
        rtcCommitScene(x->bare);
        return x;
    }();
    return *s;
}
} // namespace

static void BM_BareEmbreePrimaryRays(benchmark::State &state) {
    Setup &s = setup();
    std::vector<int> hit(size_t(kSize) * kSize);
    for (auto _ : state) {
        parallelFor(0, kSize, [&](int64_t y) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            for (int x = 0; x < kSize; ++x) {
                const renderer::Ray r = s.camera->generateRay(x + 0.5, y + 0.5);
                RTCRayHit rh{};
                rh.ray.org_x = float(r.origin.x()), rh.ray.org_y = float(r.origin.y()), rh.ray.org_z = float(r.origin.z());
                rh.ray.dir_x = float(r.dir.x()), rh.ray.dir_y = float(r.dir.y()), rh.ray.dir_z = float(r.dir.z());
                rh.ray.tnear = 0.0f;
                rh.ray.tfar = 1e30f;
                rh.ray.mask = ~0u;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(s.bare, &ctx, &rh);
                hit[size_t(y) * kSize + x] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : int(rh.hit.primID);
            }
        }, 1);
        benchmark::DoNotOptimize(hit.data());
    }
}
BENCHMARK(BM_BareEmbreePrimaryRays)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_GBuffer(benchmark::State &state) {
    Setup &s = setup();
    for (auto _ : state) benchmark::DoNotOptimize(renderer::renderGBuffer(*s.scene, s.mesh, *s.camera));
}
BENCHMARK(BM_GBuffer)->Unit(benchmark::kMillisecond)->UseRealTime();

// Every stage of the default render, scenes/bunny.yaml at its own 1024² camera,
// each on the previous stages' output computed once (the fixture below), so a
// stage's median is its own cost. The CLI's --timings reports the same stages
// inside one process run.
namespace {
struct BunnyScene {
    scenes::SceneDesc desc;
    scenes::RenderResult result; ///< the whole default render: every stage's output
    const scenes::Scene &scene() const { return *result.loaded.scene; }
    const field::TangentFrames &frames() const { return *result.loaded.frames; }
    const field::RosyField &field() const { return result.field.field.field; }
    const field::SingularityReport &singularities() const { return result.field.singularities; }
    const renderer::RayScene &rays() const { return *result.rays; }
    const renderer::Illustration &il() const { return *result.illustration; }
};

BunnyScene &bunnyScene() {
    static BunnyScene *b = [] {
        auto *x = new BunnyScene;
        x->desc = scenes::parseSceneFile(std::string(ROSY_DATA_DIR) + "/../scenes/bunny.yaml", {});
        x->result = scenes::renderScene(x->desc);
        return x;
    }();
    return *b;
}
} // namespace

static void BM_BunnyLoad(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state) benchmark::DoNotOptimize(scenes::buildScene(b.desc));
}
BENCHMARK(BM_BunnyLoad)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyBvh(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state) renderer::RayScene rays(b.scene().mesh);
}
BENCHMARK(BM_BunnyBvh)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyGBuffer(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state) benchmark::DoNotOptimize(renderer::renderGBuffer(b.rays(), b.scene().mesh, b.scene().camera));
}
BENCHMARK(BM_BunnyGBuffer)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyTone(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state)
        benchmark::DoNotOptimize(renderer::shadeLambert(b.il().gbuffer, b.rays(), b.scene().mesh, b.scene().camera,
                                                        b.scene().lights, b.scene().shading));
}
BENCHMARK(BM_BunnyTone)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyScreenField(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state)
        benchmark::DoNotOptimize(renderer::computeScreenField(b.il().gbuffer, b.frames(), b.field(),
                                                              b.singularities(), b.scene().camera));
}
BENCHMARK(BM_BunnyScreenField)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyHatching(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state)
        benchmark::DoNotOptimize(renderer::traceHatches(b.il().screen, b.il().targetDensity, b.il().gbuffer,
                                                        b.scene().style.hatch, b.scene().style.seed));
}
BENCHMARK(BM_BunnyHatching)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyMeasureHatching(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state)
        benchmark::DoNotOptimize(
            renderer::measureHatches(b.il().strokes, b.il().screen, b.il().targetDensity, b.scene().style.hatch));
}
BENCHMARK(BM_BunnyMeasureHatching)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyContours(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state)
        benchmark::DoNotOptimize(renderer::extractContours(b.scene().mesh, b.scene().camera, b.rays(), b.il().gbuffer,
                                                           b.scene().style.contour));
}
BENCHMARK(BM_BunnyContours)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyRaster(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state) {
        const renderer::InkLayers layers = renderer::rasterizeStrokes(b.il().strokes);
        benchmark::DoNotOptimize(renderer::compositeInk(layers, b.scene().style));
    }
}
BENCHMARK(BM_BunnyRaster)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyWritePng(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    const std::string path = "/tmp/rosy_render_bench_bunny.png";
    renderer::writeImage(b.il().composite, path); // loads the image module outside the timing
    for (auto _ : state) renderer::writeImage(b.il().composite, path);
    std::remove(path.c_str());
}
BENCHMARK(BM_BunnyWritePng)->Unit(benchmark::kMillisecond)->UseRealTime();

static void BM_BunnyIllustration(benchmark::State &state) {
    BunnyScene &b = bunnyScene();
    for (auto _ : state) // measureHatching off, as the CLI without --report
        benchmark::DoNotOptimize(
            scenes::drawHatching(b.result.loaded, b.field(), b.singularities(), b.rays(), renderer::HatchMeasure::None));
}
BENCHMARK(BM_BunnyIllustration)->Unit(benchmark::kMillisecond)->UseRealTime();

// The large case: a 1M-face mesh at 4096², end to end in one process.
// bunny00 (75,408 faces) midpoint-subdivided twice gives 1,206,528 faces with the
// same bounding sphere, so scenes/bunny.yaml's camera, lights and style apply
// unchanged; only the resolution is raised to 4096². Each stage is a counter in
// milliseconds (load includes the two subdivisions), and peak_rss_MiB is the
// process's peak resident memory (getrusage), which covers everything run before
// it in this process, so run it alone:
//   render_bench --benchmark_filter=Render1MFaces
static void BM_Render1MFaces4096(benchmark::State &state) {
    using Clock = std::chrono::steady_clock;
    const std::string scenePath = std::string(ROSY_DATA_DIR) + "/../scenes/bunny.yaml";
    for (auto _ : state) {
        const auto start = Clock::now();
        const scenes::SceneDesc desc = scenes::parseSceneFile(scenePath, {"camera.resolution=[4096, 4096]"});
        const double parseMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        scenes::PipelineOptions options;
        options.afterLoad = [](scenes::Scene &scene) {
            scene.mesh = field::subdivideMidpoint(field::subdivideMidpoint(scene.mesh));
        };
        const scenes::RenderResult result = scenes::renderScene(desc, options);
        scenes::StageTimings ms = result.timingsMs;
        ms.front().second += parseMs; // load counts the scene file's parse too, as it always has
        const renderer::Illustration &il = *result.illustration;
        auto t0 = Clock::now();
        renderer::writeImage(il.composite, "/tmp/rosy_render_bench_1m.png");
        ms.emplace_back("write", std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        const double total = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        for (const auto &[name, v] : ms) state.counters[name + "_ms"] = v;
        state.counters["total_ms"] = total;
        state.counters["faces"] = result.loaded.scene->mesh.nFaces();
        state.counters["strokes"] = double(il.strokes.strokes.size());
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    state.counters["peak_rss_MiB"] = double(usage.ru_maxrss) / 1024.0; // ru_maxrss is in KiB on Linux
    std::remove("/tmp/rosy_render_bench_1m.png");
}
BENCHMARK(BM_Render1MFaces4096)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

BENCHMARK_MAIN();
