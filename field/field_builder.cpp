#include "field/field_builder.h"

#include "core/diagnostics.h"
#include "core/error.h"
#include "field/sparse_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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
    for (int v = 0; v < n; ++v) {
        const double a = std::min(aniso[v] / p90, 1.0);
        field.u[v] = std::polar(a, nSym * frames.angleOfTangent(v, curvature[v].dirMax));
    }
    return field;
}

namespace {
FieldResult buildFieldUnchecked(const TangentFrames &frames, const FieldSpec &spec);
} // namespace

FieldResult buildField(const TangentFrames &frames, const FieldSpec &spec) {
    try {
        return buildFieldUnchecked(frames, spec);
    } catch (const SolverFailure &e) {
        // The fuzzer reached this with valid topology and degenerate geometry
        // (tests/fuzz/field/crashers/degenerate_*): a rejected mesh, not a bug.
        throwDegenerateGeometry(FileLoc{frames.mesh().name()}, "the field solver", e);
    }
}

namespace {
FieldResult buildFieldUnchecked(const TangentFrames &frames, const FieldSpec &spec) {
    const Mesh &mesh = frames.mesh();
    checkSymmetry(spec.nSym, mesh.name());
    FieldResult out;
    DesignOptions design;
    design.weights = spec.weights;
    switch (spec.source) {
    case FieldSource::Smoothest: {
        auto t0 = Clock::now();
        SmoothestResult smoothest = smoothestField(frames, spec.nSym);
        out.field = std::move(smoothest.field);
        out.eigenSolve = smoothest.solver;
        out.timingsMs["solve"] = msSince(t0);
        break;
    }
    case FieldSource::Design: {
        auto t0 = Clock::now();
        out.field = designField(frames, spec.nSym, spec.elements, design);
        out.timingsMs["solve"] = msSince(t0);
        break;
    }
    case FieldSource::Curvature: {
        auto t0 = Clock::now();
        out.curvature = computeCurvature(mesh, spec.curvature);
        out.timingsMs["curvature"] = msSince(t0);
        t0 = Clock::now();
        RosyField guide = curvatureField(frames, out.curvature, spec.nSym);
        // Planar or (nearly) umbilic: the principal directions are rounding or
        // discretisation noise, which curvatureField would normalise to full strength.
        const double anisotropy = curvatureAnisotropy(out.curvature);
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
            SmoothestResult smoothest = smoothestField(frames, spec.nSym);
            out.field = std::move(smoothest.field);
            out.eigenSolve = smoothest.solver;
        } else if (!spec.elements.empty()) {
            // Elements are Dirichlet constraints; the curvature field guides the rest.
            std::vector<char> fixed;
            Eigen::VectorXcd values;
            elementConstraints(frames, spec.nSym, spec.elements, fixed, values);
            if (spec.smoothingLength > 0) {
                out.field = alignedField(frames, guide, spec.smoothingLength, fixed, values);
            } else {
                design.guide = &guide;
                out.field = {spec.nSym, solveRelaxation(frames, spec.nSym, fixed, values, design)};
            }
        } else if (spec.smoothingLength > 0) {
            out.field = alignedField(frames, guide, spec.smoothingLength);
        } else {
            out.field = std::move(guide);
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
        if (!spec.elements.empty()) elementConstraints(frames, spec.nSym, spec.elements, fixed, values);
        relaxationSmooth(frames, out.field, spec.globalSmoothingIterations,
                         spec.globalSmoothingStrength, fixed, spec.weights);
        out.timingsMs["smoothing"] = msSince(t0);
    }
    return out;
}
} // namespace

} // namespace rosy::field
