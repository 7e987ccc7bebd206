#include "field/field_builder.h"

#include "core/diagnostics.h"
#include "core/error.h"
#include "core/parallel.h"
#include "field/sparse_solver.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <string>

namespace rosy::field {
namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
} // namespace

const char *toString(FieldSource source) {
    switch (source) {
    case FieldSource::Curvature: return "curvature";
    case FieldSource::Smoothest: return "smoothest";
    case FieldSource::Design: return "design";
    }
    return "?";
}

void checkSymmetry(int nSym, const std::string &where) {
    if (nSym < 1 || nSym > kMaxSymmetry)
        throw InputError(FileLoc{where}, "symmetry N = " + std::to_string(nSym) + " is out of range",
                         "use an integer from 1 to " + std::to_string(kMaxSymmetry));
}

RosyField curvatureField(const TangentFrames &frames, const std::vector<VertexCurvature> &curvature,
                         int nSym) {
    const int n = frames.mesh().nVertices();
    RosyField field;
    field.nSym = nSym;
    field.u = Eigen::VectorXcd::Zero(n);
    if (n == 0) return field;
    std::vector<double> aniso(n);
    for (int v = 0; v < n; ++v) aniso[v] = std::abs(curvature[v].kMax - curvature[v].kMin);
    std::vector<double> sorted = aniso;
    const size_t k90 = size_t(0.9 * double(n - 1));
    std::nth_element(sorted.begin(), sorted.begin() + k90, sorted.end());
    const double p90 = sorted[k90];
    if (!(p90 > 0)) return field;
    parallelFor(0, n, [&](int64_t v) {
        const double a = std::min(aniso[size_t(v)] / p90, 1.0);
        field.u[v] = std::polar(a, nSym * frames.angleOfTangent(int(v), curvature[size_t(v)].dirMax));
    }, 2048);
    return field;
}

/// Each value is computed without the lock held (buildField() computes the curvature
/// and the Laplacian at once, and their loops must not wait on each other); two
/// threads asking for the same missing value both compute it, the first stored wins
/// and both are the same to the bit.
struct FieldCache::Impl {
    const TangentFrames *frames;
    std::mutex mutex;
    struct Curvature {
        CurvatureOptions options;
        std::shared_ptr<const std::vector<VertexCurvature>> values;
        double anisotropy = 0;
        std::map<int, RosyField> guides; // per N
    };
    std::vector<std::unique_ptr<Curvature>> curvatures;
    std::map<int, SparseMatrixC> laplacians;
    std::optional<Eigen::VectorXd> areas;
    std::map<int, SmoothestResult> smoothest;
    // Snapped positions by their coordinates' bits (a linear search of the faces each).
    std::map<std::array<uint64_t, 3>, SnappedElement> snaps;
    static constexpr size_t kMaxSnaps = 1u << 16;

    Curvature *find(const CurvatureOptions &options) { // with `mutex` held
        for (auto &c : curvatures)
            if (c->options.normals == options.normals && c->options.smoothingRounds == options.smoothingRounds)
                return c.get();
        return nullptr;
    }
    Curvature &curvature(const CurvatureOptions &options) { // without `mutex` held
        {
            std::lock_guard lock(mutex);
            if (Curvature *c = find(options)) return *c;
        }
        auto c = std::make_unique<Curvature>();
        c->options = options;
        c->values = std::make_shared<const std::vector<VertexCurvature>>(computeCurvature(frames->mesh(), options));
        c->anisotropy = field::curvatureAnisotropy(*c->values);
        std::lock_guard lock(mutex);
        if (Curvature *first = find(options)) return *first;
        curvatures.push_back(std::move(c));
        return *curvatures.back();
    }
};

FieldCache::FieldCache(const TangentFrames &frames) : m_impl(std::make_unique<Impl>()) { m_impl->frames = &frames; }
FieldCache::~FieldCache() = default;

const TangentFrames &FieldCache::frames() const { return *m_impl->frames; }

std::shared_ptr<const std::vector<VertexCurvature>> FieldCache::curvature(const CurvatureOptions &options) {
    Impl::Curvature &c = m_impl->curvature(options);
    return c.values; // set before the entry was stored, never changed
}

double FieldCache::curvatureAnisotropy(const CurvatureOptions &options) {
    return m_impl->curvature(options).anisotropy;
}

const RosyField &FieldCache::curvatureGuide(const CurvatureOptions &options, int nSym) {
    Impl::Curvature &c = m_impl->curvature(options);
    {
        std::lock_guard lock(m_impl->mutex);
        auto it = c.guides.find(nSym);
        if (it != c.guides.end()) return it->second;
    }
    RosyField guide = curvatureField(*m_impl->frames, *c.values, nSym);
    std::lock_guard lock(m_impl->mutex);
    return c.guides.emplace(nSym, std::move(guide)).first->second; // the first stored wins
}

const SparseMatrixC &FieldCache::connectionLaplacian(int nSym) {
    {
        std::lock_guard lock(m_impl->mutex);
        auto it = m_impl->laplacians.find(nSym);
        if (it != m_impl->laplacians.end()) return it->second;
    }
    SparseMatrixC laplacian = field::connectionLaplacian(*m_impl->frames, nSym);
    std::lock_guard lock(m_impl->mutex);
    return m_impl->laplacians.emplace(nSym, std::move(laplacian)).first->second;
}

const Eigen::VectorXd &FieldCache::vertexAreas() {
    {
        std::lock_guard lock(m_impl->mutex);
        if (m_impl->areas) return *m_impl->areas;
    }
    Eigen::VectorXd areas = field::vertexAreas(m_impl->frames->mesh());
    std::lock_guard lock(m_impl->mutex);
    if (!m_impl->areas) m_impl->areas = std::move(areas);
    return *m_impl->areas;
}

const SmoothestResult &FieldCache::smoothest(int nSym) {
    std::lock_guard lock(m_impl->mutex);
    auto it = m_impl->smoothest.find(nSym);
    if (it == m_impl->smoothest.end()) it = m_impl->smoothest.emplace(nSym, smoothestField(*m_impl->frames, nSym)).first;
    return it->second;
}

std::vector<SnappedElement> FieldCache::snapped(const std::vector<DesignElement> &elements) {
    std::lock_guard lock(m_impl->mutex);
    std::vector<SnappedElement> out;
    out.reserve(elements.size());
    for (const DesignElement &el : elements) {
        std::array<uint64_t, 3> key;
        for (int c = 0; c < 3; ++c) std::memcpy(&key[size_t(c)], &el.position[c], sizeof(double));
        auto it = m_impl->snaps.find(key);
        if (it == m_impl->snaps.end()) {
            if (m_impl->snaps.size() >= Impl::kMaxSnaps) m_impl->snaps.clear();
            it = m_impl->snaps.emplace(key, snapToSurface(m_impl->frames->mesh(), el.position)).first;
        }
        out.push_back(it->second);
    }
    return out;
}

namespace {
FieldResult buildFieldUnchecked(const TangentFrames &frames, const FieldSpec &spec, FieldCache &cache);
} // namespace

FieldResult buildField(const TangentFrames &frames, const FieldSpec &spec, FieldCache *cache) {
    ROSY_CHECK(!cache || &cache->frames() == &frames);
    try {
        if (cache) return buildFieldUnchecked(frames, spec, *cache);
        FieldCache fresh(frames); // the same steps, kept for this call only
        return buildFieldUnchecked(frames, spec, fresh);
    } catch (const SolverFailure &e) {
        // The fuzzer reached this with valid topology and degenerate geometry
        // (tests/fuzz/field/crashers/degenerate_*): a rejected mesh, not a bug.
        throwDegenerateGeometry(FileLoc{frames.mesh().name()}, "the field solver", e);
    }
}

namespace {
FieldResult buildFieldUnchecked(const TangentFrames &frames, const FieldSpec &spec, FieldCache &cache) {
    const Mesh &mesh = frames.mesh();
    checkSymmetry(spec.nSym, mesh.name());
    FieldResult out;
    DesignOptions design;
    design.weights = spec.weights;
    const std::vector<SnappedElement> snapped = cache.snapped(spec.elements);
    design.snapped = &snapped;
    // Feature curves (FieldSpec::featureAngleDeg) are Dirichlet constraints like elements.
    std::vector<char> featureFixed;
    Eigen::VectorXcd featureValues;
    if (spec.featureAngleDeg > 0) {
        auto t0 = Clock::now();
        Vec3 lo, hi;
        mesh.bounds(lo, hi);
        const FeatureCurves curves = findFeatureCurves(mesh, spec.featureAngleDeg, spec.featureMinLength * (hi - lo).norm());
        addFeatureConstraints(frames, spec.nSym, curves, featureFixed, featureValues);
        out.timingsMs["features"] = msSince(t0);
    }
    const bool features = !featureFixed.empty() && std::find(featureFixed.begin(), featureFixed.end(), 1) != featureFixed.end();
    // The elements' constraints, then the features' where no element is.
    auto constraints = [&](std::vector<char> &fixed, Eigen::VectorXcd &values) {
        if (!spec.elements.empty()) elementConstraints(frames, spec.nSym, spec.elements, fixed, values, &snapped);
        if (!features) return;
        if (fixed.empty()) {
            fixed = featureFixed;
            values = featureValues;
            return;
        }
        for (size_t v = 0; v < fixed.size(); ++v)
            if (!fixed[v] && featureFixed[v]) fixed[v] = 1, values[Eigen::Index(v)] = featureValues[Eigen::Index(v)];
    };
    // A field that follows `guide` with the constraints fixed.
    auto alignedTo = [&](const RosyField &guide) {
        std::vector<char> fixed;
        Eigen::VectorXcd values;
        constraints(fixed, values);
        if (spec.smoothingLength > 0)
            return alignedField(frames, cache.connectionLaplacian(spec.nSym), cache.vertexAreas(), guide,
                                spec.smoothingLength, fixed, values);
        DesignOptions guided = design;
        guided.guide = &guide;
        return RosyField{spec.nSym, solveRelaxation(frames, spec.nSym, fixed, values, guided)};
    };
    switch (spec.source) {
    case FieldSource::Smoothest: {
        auto t0 = Clock::now();
        const SmoothestResult &smoothest = cache.smoothest(spec.nSym);
        out.field = features ? alignedTo(smoothest.field) : smoothest.field;
        out.eigenSolve = smoothest.solver;
        out.timingsMs["solve"] = msSince(t0);
        break;
    }
    case FieldSource::Design: {
        auto t0 = Clock::now();
        if (features) {
            std::vector<char> fixed;
            Eigen::VectorXcd values;
            constraints(fixed, values);
            out.field = {spec.nSym, solveRelaxation(frames, spec.nSym, fixed, values, design)};
        } else {
            out.field = designField(frames, spec.nSym, spec.elements, design);
        }
        out.timingsMs["solve"] = msSince(t0);
        break;
    }
    case FieldSource::Curvature: {
        auto t0 = Clock::now();
        // Without elements or features the smoothing's system (K = A + s M and its
        // two-level preconditioner: the Laplacian, the aggregates, the coarse
        // factorization, partly sequential) needs no curvature, so it is built beside
        // it (bunny00: the set-up's ~15 ms overlap the curvature's ~17). Its time is
        // then in "curvature" and no longer in "solve".
        // A smoothing length out of range keeps the old order: the curvature first, and
        // the error only where the smoothing is reached (not on the smoothest fallback).
        const bool smoothingOnly = spec.elements.empty() && !features &&
                                   spec.smoothingLength >= kMinSmoothingLength &&
                                   spec.smoothingLength <= kMaxSmoothingLength;
        std::optional<AlignedSystem> system;
        if (smoothingOnly)
            tbb::parallel_invoke([&] { out.curvature = cache.curvature(spec.curvature); },
                                 [&] {
                                     system.emplace(frames, cache.connectionLaplacian(spec.nSym),
                                                    cache.vertexAreas(), spec.nSym, spec.smoothingLength);
                                 });
        else
            out.curvature = cache.curvature(spec.curvature);
        out.timingsMs["curvature"] = msSince(t0);
        t0 = Clock::now();
        const RosyField &guide = cache.curvatureGuide(spec.curvature, spec.nSym);
        // Planar or (nearly) umbilic: the principal directions are rounding or
        // discretisation noise, which curvatureField would normalise to full strength.
        const double anisotropy = cache.curvatureAnisotropy(spec.curvature);
        if (guide.u.size() > 0 &&
            (anisotropy < kMinCurvatureAnisotropy || guide.u.cwiseAbs().maxCoeff() == 0)) {
            char measured[64];
            std::snprintf(measured, sizeof measured, "%.2g, below %.2g", anisotropy,
                          kMinCurvatureAnisotropy);
            warn(mesh.name(), "no-curvature-direction",
                 std::string("the surface has almost no curvature anisotropy (planar or umbilic: "
                             "area-weighted |k1 - k2| / (|k1| + |k2|) = ") +
                     measured + "), so curvature gives no direction; using the globally smoothest "
                     "field instead (or choose `source: smoothest` or `source: design`)");
            const SmoothestResult &smoothest = cache.smoothest(spec.nSym);
            out.field = features ? alignedTo(smoothest.field) : smoothest.field;
            out.eigenSolve = smoothest.solver;
        } else if (!spec.elements.empty() || features) {
            // Elements and feature curves are Dirichlet constraints; the curvature field guides the rest.
            out.field = alignedTo(guide);
        } else if (system) {
            out.field = system->solve(guide);
        } else if (spec.smoothingLength > 0) {
            out.field = alignedField(frames, cache.connectionLaplacian(spec.nSym), cache.vertexAreas(), guide,
                                     spec.smoothingLength);
        } else {
            out.field = guide;
        }
        out.timingsMs["solve"] = msSince(t0);
        break;
    }
    }
    if (spec.globalSmoothingIterations > 0) {
        if (!(spec.globalSmoothingStrength > 0 && spec.globalSmoothingStrength <= 1))
            throw InputError(FileLoc{mesh.name()}, "global smoothing strength must be in (0, 1]");
        auto t0 = Clock::now();
        std::vector<char> fixed;
        Eigen::VectorXcd values;
        constraints(fixed, values);
        relaxationSmooth(frames, out.field, spec.globalSmoothingIterations,
                         spec.globalSmoothingStrength, fixed, spec.weights);
        out.timingsMs["smoothing"] = msSince(t0);
    }
    return out;
}
} // namespace

} // namespace rosy::field
