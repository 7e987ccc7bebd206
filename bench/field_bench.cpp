// Field-stage benchmarks on bunny00 (37.7k vertices) from the CGAL sample data.
// The mesh and frames are loaded once; each benchmark times one stage.
#include "core/diagnostics.h"
#include "core/error.h"
#include "field/curvature.h"
#include "field/design.h"
#include "field/editing.h"
#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/primitives.h"
#include "field/separatrices.h"
#include "field/singularities.h"
#include "field/smoothing.h"

#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <tuple>

using namespace rosy::field;

namespace {
struct Bunny {
    Mesh mesh;
    std::unique_ptr<TangentFrames> frames;
    std::vector<VertexCurvature> curvature;
    RosyField guide, field;
};

Bunny &bunny() {
    static Bunny *b = [] {
        auto *x = new Bunny;
        x->mesh = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
        x->frames = std::make_unique<TangentFrames>(x->mesh);
        x->curvature = computeCurvature(x->mesh);
        x->guide = curvatureField(*x->frames, x->curvature, 4);
        x->field = alignedField(*x->frames, x->guide, FieldSpec{}.smoothingLength);
        return x;
    }();
    return *b;
}
} // namespace

static void BM_Frames(benchmark::State &state) {
    Bunny &b = bunny();
    for (auto _ : state) benchmark::DoNotOptimize(TangentFrames(b.mesh));
}
BENCHMARK(BM_Frames)->Unit(benchmark::kMillisecond);

static void BM_Curvature(benchmark::State &state) {
    Bunny &b = bunny();
    for (auto _ : state) benchmark::DoNotOptimize(computeCurvature(b.mesh));
}
BENCHMARK(BM_Curvature)->Unit(benchmark::kMillisecond);

static void BM_CurvatureAligned4Rosy(benchmark::State &state) {
    Bunny &b = bunny();
    for (auto _ : state) benchmark::DoNotOptimize(alignedField(*b.frames, b.guide, FieldSpec{}.smoothingLength));
}
BENCHMARK(BM_CurvatureAligned4Rosy)->Unit(benchmark::kMillisecond);

static void BM_Smoothest4Rosy(benchmark::State &state) {
    Bunny &b = bunny();
    for (auto _ : state) benchmark::DoNotOptimize(smoothestField(*b.frames, 4));
}
BENCHMARK(BM_Smoothest4Rosy)->Unit(benchmark::kMillisecond);

// Three elements (L = 0, +1, −1) relaxed over bunny00; argument 0: the paper's
// mean-value weights (UMFPACK LU), 1: cotan weights (two-level PCG).
static void BM_DesignRelaxation4Rosy(benchmark::State &state) {
    Bunny &b = bunny();
    std::vector<DesignElement> elements(3);
    elements[0].position = b.mesh.position(100);
    elements[1].position = b.mesh.position(20000);
    elements[1].order = 1;
    elements[2].position = b.mesh.position(30000);
    elements[2].order = -1;
    DesignOptions options;
    options.weights = state.range(0) == 0 ? LaplaceWeights::MeanValue : LaplaceWeights::Cotan;
    rosy::WarningCapture quiet;
    for (auto _ : state) benchmark::DoNotOptimize(designField(*b.frames, 4, elements, options));
}
BENCHMARK(BM_DesignRelaxation4Rosy)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

static void BM_Singularities(benchmark::State &state) {
    Bunny &b = bunny();
    for (auto _ : state) benchmark::DoNotOptimize(findSingularities(*b.frames, b.field));
}
BENCHMARK(BM_Singularities)->Unit(benchmark::kMillisecond);

// Separatrices of every singularity of the default field (Eq. 9 roots, traced).
static void BM_Separatrices(benchmark::State &state) {
    Bunny &b = bunny();
    const SingularityReport rep = findSingularities(*b.frames, b.field);
    size_t n = 0;
    for (auto _ : state) {
        const auto seps = traceSeparatrices(*b.frames, b.field, rep.singularities);
        n = seps.size();
        benchmark::DoNotOptimize(seps.data());
    }
    state.counters["separatrices"] = double(n);
}
BENCHMARK(BM_Separatrices)->Unit(benchmark::kMillisecond);

// Topological editing on the default field: cancel the opposite pair nearest to
// the first singularity, and move the first singularity one face-width away
// (each on a fresh copy of the field, copy included).
static void BM_CancelPair(benchmark::State &state) {
    Bunny &b = bunny();
    const SingularityReport rep = findSingularities(*b.frames, b.field);
    // The closest opposite pair that can be cancelled (some cannot: another
    // singularity sits in every region around them), found outside the timing.
    std::vector<std::tuple<double, int, int>> pairs;
    for (size_t i = 0; i < rep.singularities.size(); ++i)
        for (size_t j = 0; j < rep.singularities.size(); ++j)
            if (rep.singularities[i].indexNumerator == 1 && rep.singularities[j].indexNumerator == -1)
                pairs.emplace_back((rep.singularities[i].position - rep.singularities[j].position).norm(), int(i),
                                   int(j));
    std::sort(pairs.begin(), pairs.end());
    int a = -1, c = -1;
    for (const auto &[d, i, j] : pairs) {
        RosyField f = b.field;
        try {
            cancelPair(*b.frames, f, i, j);
            a = i, c = j;
            break;
        } catch (const rosy::InputError &) {
        }
    }
    if (a < 0) {
        state.SkipWithError("no pair of the default field can be cancelled");
        return;
    }
    for (auto _ : state) {
        RosyField f = b.field;
        benchmark::DoNotOptimize(cancelPair(*b.frames, f, a, c));
    }
}
BENCHMARK(BM_CancelPair)->Unit(benchmark::kMillisecond);

static void BM_MoveSingularity(benchmark::State &state) {
    Bunny &b = bunny();
    const SingularityReport rep = findSingularities(*b.frames, b.field);
    const Mesh &m = b.mesh;
    // The first singularity that can move to a face two rings away (the centroid
    // of twin(next(twin(h))) of its face's first halfedge), found outside the timing.
    int s = -1;
    Vec3 to = Vec3::Zero();
    for (size_t k = 0; k < rep.singularities.size() && s < 0; ++k) {
        const int h1 = m.twin(3 * rep.singularities[k].face);
        const int h2 = h1 < 0 ? -1 : m.twin(Mesh::next(h1));
        if (h2 < 0) continue;
        const auto &c = m.face(h2 / 3);
        const Vec3 target = (m.position(c[0]) + m.position(c[1]) + m.position(c[2])) / 3;
        RosyField f = b.field;
        try {
            moveSingularity(*b.frames, f, int(k), target);
            s = int(k);
            to = target;
        } catch (const rosy::InputError &) {
        }
    }
    if (s < 0) {
        state.SkipWithError("no singularity of the default field can be moved two rings");
        return;
    }
    for (auto _ : state) {
        RosyField f = b.field;
        benchmark::DoNotOptimize(moveSingularity(*b.frames, f, s, to));
    }
}
BENCHMARK(BM_MoveSingularity)->Unit(benchmark::kMillisecond);

// The whole field stage of the product's default (frames, curvature, the
// curvature-aligned 4-RoSy of the default FieldSpec, singularities) on bunny00
// subdivided twice at edge midpoints: 603k vertices, 1.21M faces. The mesh is
// built once, outside the timing. Counters: per-stage milliseconds of the last run.
static void BM_FieldStage1M(benchmark::State &state) {
    static const Mesh *big = [] {
        const Mesh &m = bunny().mesh;
        return new Mesh(subdivideMidpoint(subdivideMidpoint(m)));
    }();
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    for (auto _ : state) {
        const auto t0 = Clock::now();
        const TangentFrames frames(*big);
        const auto t1 = Clock::now();
        const FieldResult r = buildField(frames, FieldSpec{});
        const auto t2 = Clock::now();
        const SingularityReport rep = findSingularities(frames, r.field);
        const auto t3 = Clock::now();
        benchmark::DoNotOptimize(rep);
        state.counters["faces"] = big->nFaces();
        state.counters["frames_ms"] = ms(t0, t1);
        state.counters["curvature_ms"] = r.timingsMs.at("curvature");
        state.counters["solve_ms"] = r.timingsMs.at("solve");
        state.counters["singularities_ms"] = ms(t2, t3);
        state.counters["singularities"] = double(rep.singularities.size());
    }
    // The process's peak resident memory (getrusage): run this benchmark alone
    // (--benchmark_filter=1M) so it covers only the mesh and its field stage.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    state.counters["peak_rss_MiB"] = double(usage.ru_maxrss) / 1024.0; // KiB on Linux
}
BENCHMARK(BM_FieldStage1M)->Unit(benchmark::kMillisecond)->Iterations(1);

BENCHMARK_MAIN();
