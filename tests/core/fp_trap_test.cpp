/// \file fp_trap_test.cpp
/// Floating-point trap mode: field construction on degenerate meshes with the invalid
/// and divide-by-zero exceptions trapping (feenableexcept), so any 0/0, x/0, sqrt(-1),
/// acos(1 + ε) or NaN comparison in frames, curvature, Laplacians, solvers or singularity
/// detection stops the test with SIGFPE at the faulting instruction instead of
/// producing a NaN that may or may not surface later.
///
/// Meshes: zero-area faces (a vertex on the segment between two others), needles (a
/// vertex 1e-9 from another), duplicate vertices (two indices at one position, edges of
/// length zero), built both with Mesh::fromTriangles (which keeps them) and through the
/// loaders' repairAndBuild (which drops zero-area faces and merges duplicates). Expected
/// results come from topology, not from the code: finite values, Σ k_f = N χ (Poincaré–
/// Hopf) on the closed meshes.
///
/// Traps are per thread: the fixture limits TBB to the calling thread while it runs.

#include "field/curvature.h"
#include "field/field_builder.h"
#include "field/frames.h"
#include "field/mesh_io.h"
#include "field/mesh_stats.h"
#include "field/primitives.h"
#include "field/singularities.h"

#include "core/diagnostics.h"
#include "core/error.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cfenv>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

using namespace rosy;
using namespace rosy::field;

namespace {

class FpTrap : public ::testing::Test {
protected:
    void SetUp() override {
        m_oneThread = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
        std::feclearexcept(FE_ALL_EXCEPT);
        feenableexcept(FE_INVALID | FE_DIVBYZERO);
    }
    void TearDown() override {
        fedisableexcept(FE_INVALID | FE_DIVBYZERO);
        m_oneThread.reset();
    }

private:
    std::unique_ptr<tbb::global_control> m_oneThread;
};

/// Vertices of face f of `m`, for building defects next to a known face.
Face faceOf(const Mesh &m, int f) { return m.face(f); }

/// Icosphere(1) with vertex c of face 0 moved onto the midpoint of the face's other two
/// corners: face 0 has zero area, its neighbours become slivers. Closed, χ = 2.
Mesh zeroAreaSphere() {
    const Mesh base = makeIcosphere(1);
    std::vector<Vec3> p = base.positions();
    const Face f = faceOf(base, 0);
    p[f[2]] = 0.5 * (p[f[0]] + p[f[1]]);
    return Mesh::fromTriangles(p, base.faces(), "zero-area sphere");
}

/// Icosphere(1) with one vertex 1e-9 away from a neighbour: needles around that edge.
Mesh needleSphere() {
    const Mesh base = makeIcosphere(1);
    std::vector<Vec3> p = base.positions();
    const Face f = faceOf(base, 0);
    p[f[1]] = p[f[0]] + 1e-9 * (p[f[1]] - p[f[0]]).normalized();
    return Mesh::fromTriangles(p, base.faces(), "needle sphere");
}

/// Icosphere(1) with two adjacent vertices at the same position (an edge of length zero,
/// two faces of zero area); fromTriangles keeps the two indices.
Mesh duplicateVertexSphere() {
    const Mesh base = makeIcosphere(1);
    std::vector<Vec3> p = base.positions();
    const Face f = faceOf(base, 0);
    p[f[1]] = p[f[0]];
    return Mesh::fromTriangles(p, base.faces(), "duplicate-vertex sphere");
}

/// A flat grid whose middle row is squashed to height zero: a strip of zero-area faces
/// between two good halves (with boundary).
Mesh squashedGrid() {
    const Mesh base = makeGrid(6);
    std::vector<Vec3> p = base.positions();
    for (Vec3 &q : p)
        if (std::abs(q.y()) < 0.2) q.y() = 0.0;
    return Mesh::fromTriangles(p, base.faces(), "squashed grid");
}

/// The same defects through the loaders' repair path: a cube soup with a duplicated
/// vertex, a collinear (zero-area) face, a needle and a repeated face.
Mesh repairedSoup() {
    const Mesh cube = makeCube(2);
    std::vector<Vec3> p = cube.positions();
    std::vector<std::vector<int>> polys;
    for (const Face &f : cube.faces()) polys.push_back({f[0], f[1], f[2]});
    const Face f0 = cube.face(0);
    p.push_back(p[f0[0]]);                                       // duplicate of a used vertex
    polys.push_back({f0[1], f0[0], int(p.size()) - 1});          // collapses after merging
    p.push_back(0.5 * (p[f0[0]] + p[f0[1]]));                    // collinear point
    polys.push_back({f0[0], f0[1], int(p.size()) - 1});          // zero area: dropped
    polys.push_back({f0[0], f0[1], f0[2]});                      // duplicate face: dropped
    WarningCapture quiet;
    return repairAndBuild(p, polys, "repaired soup");
}

struct Case {
    std::string name;
    std::function<Mesh()> make;
};

std::vector<Case> degenerateMeshes() {
    return {{"zero-area sphere", zeroAreaSphere},
            {"needle sphere", needleSphere},
            {"duplicate-vertex sphere", duplicateVertexSphere},
            {"squashed grid", squashedGrid},
            {"repaired soup", repairedSoup}};
}

/// Builds the field of `spec` and checks finiteness and Poincaré–Hopf (exact on closed
/// meshes: Σ k_f = N χ; with boundary the boundary index closes the sum).
void buildAndCheck(const Mesh &mesh, const FieldSpec &spec, const std::string &what) {
    SCOPED_TRACE(what);
    const MeshStats stats = computeStats(mesh);
    const TangentFrames frames(mesh);
    for (int f = 0; f < mesh.nFaces(); ++f) ASSERT_TRUE(std::isfinite(frames.faceHolonomy(f))) << "face " << f;
    FieldResult r;
    try {
        WarningCapture quiet;
        r = buildField(frames, spec);
    } catch (const InputError &e) {
        // A clean rejection is allowed; nothing here should need one, so report it.
        ADD_FAILURE() << "rejected: " << e.what();
        return;
    }
    ASSERT_EQ(r.field.u.size(), mesh.nVertices());
    for (int v = 0; v < mesh.nVertices(); ++v)
        ASSERT_TRUE(std::isfinite(std::abs(r.field.u[v]))) << "vertex " << v;
    const SingularityReport s = findSingularities(frames, r.field);
    if (stats.boundaryLoops == 0) {
        EXPECT_EQ(s.indexNumeratorSum, spec.nSym * stats.eulerCharacteristic);
    }
    EXPECT_NEAR(s.totalIndex(spec.nSym), stats.eulerCharacteristic, 1e-6);
}

FieldSpec specOf(FieldSource source, int nSym, LaplaceWeights weights, const Mesh &mesh) {
    FieldSpec spec;
    spec.source = source;
    spec.nSym = nSym;
    spec.weights = weights;
    if (source == FieldSource::Design) {
        // One element of order +1 at the centroid of the last face (far from face 0's defect).
        const Face f = mesh.face(mesh.nFaces() - 1);
        DesignElement e;
        e.order = 1;
        e.position = (mesh.position(f[0]) + mesh.position(f[1]) + mesh.position(f[2])) / 3;
        e.label = "test element";
        spec.elements.push_back(e);
    }
    spec.globalSmoothingIterations = 2;
    return spec;
}

} // namespace

TEST_F(FpTrap, TrapsAreActive) {
    // The mode is only worth something if a division by zero really stops the program.
    volatile double zero = 0.0;
    EXPECT_DEATH({ volatile double x = 1.0 / zero; (void)x; }, "");
}

TEST_F(FpTrap, DegenerateMeshesLoadAndHaveFiniteFrames) {
    for (const Case &c : degenerateMeshes()) {
        const Mesh m = c.make();
        const MeshStats s = computeStats(m);
        EXPECT_EQ(s.eulerCharacteristic, s.vertices - s.edges + s.faces) << c.name;
        const TangentFrames frames(m);
        double total = 0;
        for (int f = 0; f < m.nFaces(); ++f) total += frames.faceHolonomy(f);
        for (int v = 0; v < m.nVertices(); ++v)
            if (m.isBoundaryVertex(v)) total += M_PI - frames.angleTotal(v);
        EXPECT_NEAR(total, 2 * M_PI * s.eulerCharacteristic, 1e-9) << c.name << " (Gauss-Bonnet)";
    }
}

TEST_F(FpTrap, CurvatureFieldsOnDegenerateMeshes) {
    for (const Case &c : degenerateMeshes()) {
        const Mesh m = c.make();
        for (int n : {1, 2, 4, 6})
            buildAndCheck(m, specOf(FieldSource::Curvature, n, LaplaceWeights::MeanValue, m),
                          c.name + ", curvature, N=" + std::to_string(n));
    }
}

TEST_F(FpTrap, SmoothestFieldsOnDegenerateMeshes) {
    for (const Case &c : degenerateMeshes()) {
        const Mesh m = c.make();
        for (int n : {1, 4})
            buildAndCheck(m, specOf(FieldSource::Smoothest, n, LaplaceWeights::MeanValue, m),
                          c.name + ", smoothest, N=" + std::to_string(n));
    }
}

TEST_F(FpTrap, DesignFieldsWithBothWeightsOnDegenerateMeshes) {
    for (const Case &c : degenerateMeshes()) {
        const Mesh m = c.make();
        for (LaplaceWeights w : {LaplaceWeights::MeanValue, LaplaceWeights::Cotan})
            buildAndCheck(m, specOf(FieldSource::Design, 4, w, m),
                          c.name + (w == LaplaceWeights::Cotan ? ", design, cotan" : ", design, mean-value"));
    }
}
