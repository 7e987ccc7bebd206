/// \file fuzz_field.cpp
/// libFuzzer harness for field construction on small meshes with fuzzed geometry and
/// parameters. The input bytes choose (FuzzedDataProvider):
///   - a base mesh: a small primitive of at most 96 faces (closed: icosphere, torus,
///     cube, Platonic solids; open: grid, disk, cylinder) or a raw polygon soup of up to
///     16 vertices and 32 polygons on an integer grid (small enough for about 10^3
///     executions per second under ASan, so 10^6 runs take minutes, not hours);
///   - up to 8 geometric defects: a vertex moved onto another (duplicate position), onto
///     the midpoint of two others (zero-area faces), next to one (needles), or the whole
///     mesh scaled by 1e-9 or 1e9;
///   - construction of a primitive through Mesh::fromTriangles (keeps zero-area faces) or
///     through the loaders' repairAndBuild (drops them; soups always go this way);
///   - a FieldSpec: N in 0..13 (0 and 13 are invalid), source, smoothing length, Laplace
///     weights, up to 3 design elements, global smoothing;
///   - optionally one topological edit (cancel a pair, move a singularity).
///
/// Oracle: a clean InputError, or a field whose representation vectors are all finite and
/// whose singularities satisfy Poincaré–Hopf: Σ k_f = N χ exactly on closed meshes and
/// Σ k_f / N + boundary index = χ with a boundary. A failed edit leaves the field bit for
/// bit unchanged; a successful cancellation removes exactly two singularities.

#include "fuzz_common.h"

#include "field/editing.h"
#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/primitives.h"
#include "field/singularities.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

using namespace rosy;
using field::Vec3;

namespace {

struct Soup {
    std::vector<Vec3> positions;
    std::vector<std::vector<int>> polygons;
    bool primitive = true; ///< triangles of a clean primitive (fromTriangles may take them)
};

Soup fromMesh(const field::Mesh &m) {
    Soup s;
    s.positions = m.positions();
    for (const auto &f : m.faces()) s.polygons.push_back({f[0], f[1], f[2]});
    return s;
}

Soup baseSoup(FuzzedDataProvider &in) {
    switch (in.ConsumeIntegralInRange<int>(0, 8)) {
    case 0: return fromMesh(field::makeIcosphere(in.ConsumeIntegralInRange<int>(0, 1)));
    case 1: {
        const double minor[] = {0.35, 0.9, 1e-3, 0.5};
        return fromMesh(field::makeTorus(1.0, minor[in.ConsumeIntegralInRange<int>(0, 3)],
                                         in.ConsumeIntegralInRange<int>(3, 8),
                                         in.ConsumeIntegralInRange<int>(3, 6)));
    }
    case 2: return fromMesh(field::makeCube(in.ConsumeIntegralInRange<int>(1, 2)));
    case 3:
        return fromMesh(field::makePlatonic(field::Platonic(in.ConsumeIntegralInRange<int>(0, 4)),
                                            in.ConsumeIntegralInRange<int>(0, 1)));
    case 4: return fromMesh(field::makeGrid(in.ConsumeIntegralInRange<int>(1, 5)));
    case 5: return fromMesh(field::makeDisk(in.ConsumeIntegralInRange<int>(1, 4)));
    case 6:
        return fromMesh(field::makeCylinder(1.0, 2.0, in.ConsumeIntegralInRange<int>(3, 8),
                                            in.ConsumeIntegralInRange<int>(1, 3)));
    default: break;
    }
    // A raw soup on a small integer grid: coincident, collinear and coplanar points are likely.
    Soup s;
    s.primitive = false;
    const int nV = in.ConsumeIntegralInRange<int>(3, 16);
    for (int v = 0; v < nV; ++v)
        s.positions.emplace_back(in.ConsumeIntegralInRange<int>(-3, 3), in.ConsumeIntegralInRange<int>(-3, 3),
                                 in.ConsumeIntegralInRange<int>(-3, 3));
    const int nF = in.ConsumeIntegralInRange<int>(1, 32);
    for (int f = 0; f < nF && in.remaining_bytes() > 0; ++f) {
        std::vector<int> poly(in.ConsumeIntegralInRange<int>(3, 5));
        for (int &i : poly) i = in.ConsumeIntegralInRange<int>(0, nV - 1);
        s.polygons.push_back(poly);
    }
    return s;
}

void addDefects(FuzzedDataProvider &in, std::vector<Vec3> &p) {
    const int n = int(p.size()) - 1;
    const int nDefects = in.ConsumeIntegralInRange<int>(0, 8);
    for (int d = 0; d < nDefects; ++d) {
        const int v = in.ConsumeIntegralInRange<int>(0, n), a = in.ConsumeIntegralInRange<int>(0, n),
                  b = in.ConsumeIntegralInRange<int>(0, n);
        switch (in.ConsumeIntegralInRange<int>(0, 4)) {
        case 0: p[v] = p[a]; break;                         // duplicate position
        case 1: p[v] = 0.5 * (p[a] + p[b]); break;          // collinear: zero-area faces
        case 2: {                                           // needle next to a
            const double eps[] = {1e-12, 1e-9, 1e-6, 1e-3};
            p[v] = p[a] + eps[in.ConsumeIntegralInRange<int>(0, 3)] * Vec3(1, 0.5, 0.25);
            break;
        }
        case 3: p[v] = p[a] + in.ConsumeIntegralInRange<int>(-2, 2) * 0.5 * (p[b] - p[a]); break; // flip or fold
        default: {                                          // extreme scale, whole mesh
            const double s = in.ConsumeBool() ? 1e-9 : 1e9;
            for (Vec3 &q : p) q *= s;
        }
        }
    }
}

field::FieldSpec fuzzedSpec(FuzzedDataProvider &in, const field::Mesh &mesh) {
    field::FieldSpec spec;
    spec.nSym = in.ConsumeIntegralInRange<int>(0, 13);
    spec.source = field::FieldSource(in.ConsumeIntegralInRange<int>(0, 2));
    const double lengths[] = {0.04, 0.0, 1e-4, 0.5, 10.0};
    spec.smoothingLength = lengths[in.ConsumeIntegralInRange<int>(0, 4)];
    spec.weights = in.ConsumeBool() ? field::LaplaceWeights::Cotan : field::LaplaceWeights::MeanValue;
    const int nElements = in.ConsumeIntegralInRange<int>(0, 3);
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    for (int i = 0; i < nElements; ++i) {
        field::DesignElement e;
        if (in.ConsumeBool()) { // on the surface: a vertex or a face centroid
            const int f = in.ConsumeIntegralInRange<int>(0, mesh.nFaces() - 1);
            const auto &c = mesh.face(f);
            e.position = in.ConsumeBool() ? mesh.position(c[0])
                                          : (mesh.position(c[0]) + mesh.position(c[1]) + mesh.position(c[2])) / 3;
        } else { // anywhere in (or a little beyond) the bounding box
            e.position = lo + (hi - lo).cwiseProduct(Vec3(in.ConsumeIntegralInRange<int>(-1, 9),
                                                          in.ConsumeIntegralInRange<int>(-1, 9),
                                                          in.ConsumeIntegralInRange<int>(-1, 9)) / 8.0);
        }
        e.order = in.ConsumeIntegralInRange<int>(-1, 1);
        e.direction = Vec3(in.ConsumeIntegralInRange<int>(-2, 2), in.ConsumeIntegralInRange<int>(-2, 2),
                           in.ConsumeIntegralInRange<int>(-2, 2));
        if (e.direction.isZero()) e.direction = Vec3::UnitX(); // the scene parser rejects a zero direction
        e.phaseRad = in.ConsumeIntegralInRange<int>(-8, 8) * M_PI / 4;
        const double strengths[] = {1.0, 1e-9, 1e9, 0.5};
        e.strength = strengths[in.ConsumeIntegralInRange<int>(0, 3)];
        e.label = "element " + std::to_string(i);
        spec.elements.push_back(e);
    }
    spec.globalSmoothingIterations = in.ConsumeIntegralInRange<int>(0, 3);
    const double smoothing[] = {0.5, 1.0, 0.1};
    spec.globalSmoothingStrength = smoothing[in.ConsumeIntegralInRange<int>(0, 2)];
    return spec;
}

/// `chi` is the frames' Gauss–Bonnet total / 2π: χ on every mesh without zero-area faces
/// (checkMesh() asserts that), the frames' own curvature total otherwise.
void checkField(const field::TangentFrames &frames, const field::RosyField &f, int nSym, double chi,
                bool closed, int *nSingularities) {
    const field::Mesh &mesh = frames.mesh();
    ROSY_FUZZ_ASSERT(f.nSym == nSym && f.u.size() == mesh.nVertices(), "field shape");
    for (int v = 0; v < mesh.nVertices(); ++v)
        ROSY_FUZZ_ASSERT(std::isfinite(f.u[v].real()) && std::isfinite(f.u[v].imag()),
                         "finite field at vertex " + std::to_string(v));
    const field::SingularityReport r = field::findSingularities(frames, f);
    if (closed)
        ROSY_FUZZ_ASSERT(r.indexNumeratorSum == nSym * std::lround(chi),
                         "sum k = " + std::to_string(r.indexNumeratorSum) + ", N chi = " + std::to_string(nSym * chi));
    ROSY_FUZZ_ASSERT(std::abs(r.totalIndex(nSym) - chi) < 1e-6,
                     "Poincare-Hopf: total " + std::to_string(r.totalIndex(nSym)) + " chi " + std::to_string(chi));
    for (const auto &s : r.singularities) {
        ROSY_FUZZ_ASSERT(s.face >= 0 && s.face < mesh.nFaces() && s.indexNumerator != 0, "singularity face");
        ROSY_FUZZ_ASSERT(s.position.allFinite() && s.barycentric.allFinite(), "singularity position");
    }
    *nSingularities = int(r.singularities.size());
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fuzz::initOnce();
    FuzzedDataProvider in(data, size);

    Soup soup = baseSoup(in);
    addDefects(in, soup.positions);
    const bool direct = soup.primitive && in.ConsumeBool();
    if (std::getenv("ROSY_FUZZ_VERBOSE")) { // the mesh as an OFF file, for reproducing a finding
        std::fprintf(stderr, "%s\nOFF\n%zu %zu 0\n", direct ? "# Mesh::fromTriangles" : "# repairAndBuild",
                     soup.positions.size(), soup.polygons.size());
        for (const Vec3 &p : soup.positions) std::fprintf(stderr, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
        for (const auto &poly : soup.polygons) {
            std::fprintf(stderr, "%zu", poly.size());
            for (int i : poly) std::fprintf(stderr, " %d", i);
            std::fprintf(stderr, "\n");
        }
    }
    field::Mesh mesh;
    try {
        if (direct) {
            std::vector<field::Face> faces;
            for (const auto &p : soup.polygons) faces.push_back({p[0], p[1], p[2]});
            mesh = field::Mesh::fromTriangles(soup.positions, faces, "fuzz");
        } else {
            field::LoadOptions options;
            options.maxFaces = 1000;
            mesh = field::repairAndBuild(soup.positions, soup.polygons, "fuzz", options);
        }
    } catch (const InputError &) {
        return 0;
    }
    if (mesh.nFaces() == 0) return 0;
    double chi = 0;
    const field::MeshStats stats = fuzz::checkMesh(mesh, &chi);
    const bool closed = stats.boundaryLoops == 0;

    const field::TangentFrames frames(mesh);
    const field::FieldSpec spec = fuzzedSpec(in, mesh);
    if (std::getenv("ROSY_FUZZ_VERBOSE"))
        std::fprintf(stderr, "# spec: N %d, source %s, smoothing length %g, %s weights, %zu elements, "
                             "global smoothing %d x %g\n",
                     spec.nSym, field::toString(spec.source), spec.smoothingLength,
                     spec.weights == field::LaplaceWeights::Cotan ? "cotan" : "mean-value", spec.elements.size(),
                     spec.globalSmoothingIterations, spec.globalSmoothingStrength);
    field::FieldResult result;
    try {
        result = field::buildField(frames, spec);
    } catch (const InputError &e) {
        ROSY_FUZZ_ASSERT(std::strstr(e.what(), "error:") != nullptr, std::string("diagnostic format: ") + e.what());
        return 0;
    }
    int nSing = 0;
    checkField(frames, result.field, spec.nSym, chi, closed, &nSing);

    // One topological edit (P&Z Sec. 5.2) with fuzzed ids: a clean error keeps the field.
    if (nSing == 0 || in.remaining_bytes() == 0) return 0;
    field::RosyField edited = result.field;
    const bool cancel = in.ConsumeBool();
    const int a = in.ConsumeIntegralInRange<int>(0, nSing), b = in.ConsumeIntegralInRange<int>(0, nSing);
    try {
        if (cancel) {
            field::cancelPair(frames, edited, a, b);
        } else {
            const auto &c = mesh.face(in.ConsumeIntegralInRange<int>(0, mesh.nFaces() - 1));
            field::moveSingularity(frames, edited, a,
                                   (mesh.position(c[0]) + mesh.position(c[1]) + mesh.position(c[2])) / 3);
        }
    } catch (const InputError &) {
        ROSY_FUZZ_ASSERT(edited.u == result.field.u, "a failed edit changed the field");
        return 0;
    }
    int nAfter = 0;
    checkField(frames, edited, spec.nSym, chi, closed, &nAfter);
    if (cancel) ROSY_FUZZ_ASSERT(nAfter == nSing - 2, "cancellation removes two singularities");
    else ROSY_FUZZ_ASSERT(nAfter == nSing, "a move keeps the number of singularities");
    return 0;
}
