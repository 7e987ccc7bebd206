// The remesher (docs/remeshing.md) on bunny00 at L = 1 % of the bounding-box
// diagonal, against the field stage it starts from, measured in the same run:
// BM_FieldStage is buildField() + findSingularities() with the default spec (what
// `rosyhatch remesh` runs before remeshing); BM_Remesh (/3: the default
// anisotropic scale μ = 0.3, /0: without it) and BM_Quality report
// their time also as `x_field`, a multiple of the field stage's median measured
// just before them in this process.
#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/singularities.h"
#include "remesh/quality.h"
#include "remesh/remesh.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <memory>

using namespace rosy;

namespace {
struct Bunny {
    field::Mesh mesh;
    std::unique_ptr<field::TangentFrames> frames;
    field::FieldResult field;
    field::SingularityReport singularities;
    double edgeLength = 0;
    double fieldStageMs = 0; ///< median of 5 runs of the field stage
};

double fieldStageOnce(Bunny &b) {
    const auto t0 = std::chrono::steady_clock::now();
    b.field = field::buildField(*b.frames, field::FieldSpec{});
    b.singularities = field::findSingularities(*b.frames, b.field.field);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Bunny &bunny() {
    static Bunny *b = [] {
        auto *x = new Bunny;
        x->mesh = field::loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
        x->frames = std::make_unique<field::TangentFrames>(x->mesh);
        field::Vec3 lo, hi;
        x->mesh.bounds(lo, hi);
        x->edgeLength = 0.01 * (hi - lo).norm();
        std::vector<double> t;
        for (int i = 0; i < 5; ++i) t.push_back(fieldStageOnce(*x));
        std::sort(t.begin(), t.end());
        x->fieldStageMs = t[2];
        return x;
    }();
    return *b;
}

void reportRatio(benchmark::State &state, double totalMs) {
    const double perIteration = totalMs / double(state.iterations());
    state.counters["x_field"] = perIteration / bunny().fieldStageMs;
    state.counters["field_ms"] = bunny().fieldStageMs;
}
} // namespace

static void BM_FieldStage(benchmark::State &state) {
    Bunny &b = bunny();
    for (auto _ : state) benchmark::DoNotOptimize(fieldStageOnce(b));
}
BENCHMARK(BM_FieldStage)->Unit(benchmark::kMillisecond);

// Argument: the anisotropic scale μ in tenths (3: the default 0.3; 0: one
// spacing L, no scale solve), so the solve's cost is read off the same run.
static void BM_Remesh(benchmark::State &state) {
    Bunny &b = bunny();
    remesh::RemeshOptions opt;
    opt.edgeLength = b.edgeLength;
    opt.anisotropicScale = 0.1 * double(state.range(0));
    double ms = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(remesh::remesh(*b.frames, b.field.field, b.singularities, opt));
        ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    reportRatio(state, ms);
}
BENCHMARK(BM_Remesh)->Arg(3)->Arg(0)->Unit(benchmark::kMillisecond);

static void BM_Quality(benchmark::State &state) {
    Bunny &b = bunny();
    remesh::RemeshOptions opt;
    opt.edgeLength = b.edgeLength;
    const remesh::RemeshResult r = remesh::remesh(*b.frames, b.field.field, b.singularities, opt);
    double ms = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(
            remesh::measureQuality(r.positions, r.polygons, *b.frames, b.field.field, b.singularities, b.edgeLength));
        ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    reportRatio(state, ms);
}
BENCHMARK(BM_Quality)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
