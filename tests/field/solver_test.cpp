// Field solvers against independent references: the connection Laplacian
// against its defining energy, the two-level Krylov solvers against sparse
// direct solves, the smoothest field's eigen-solver against dense eigenvalues.
#include "core/diagnostics.h"
#include "field/curvature.h"
#include "field/design.h"
#include "field/field_builder.h"
#include "field/laplacian.h"
#include "field/mesh_io.h"
#include "field/multilevel.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "field/smoothing.h"
#include "field/sparse_solver.h"

#include <Eigen/Eigenvalues>
#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace rosy::field;

namespace {
Eigen::VectorXcd randomVector(int n, unsigned seed) {
    std::srand(seed);
    return Eigen::VectorXcd::Random(n);
}
std::vector<int> allFree(int n) {
    std::vector<int> id(n);
    for (int i = 0; i < n; ++i) id[i] = i;
    return id;
}
} // namespace

// uᴴAu must equal Σ_edges w_ij |u_i − e^{iNΔθ} u_j|², summed edge by edge here
// from the definitions (cotan weight, transport of the canonical halfedge).
TEST(ConnectionLaplacian, EqualsItsEnergyAndIsExactlyHermitian) {
    for (const Mesh &m : {makeTorus(2.0, 0.7, 20, 10), makeDisk(5), makeIcosphere(2)}) {
        const TangentFrames fr(m);
        for (int nSym : {1, 4}) {
            const SparseMatrixC A = connectionLaplacian(fr, nSym);
            const Eigen::VectorXcd u = randomVector(m.nVertices(), 7);
            double energy = 0;
            for (int e = 0; e < m.nEdges(); ++e) {
                const int h = m.edgeHalfedge(e);
                const Complex r = std::polar(1.0, nSym * fr.transportAngle(h));
                energy += cotanEdgeWeight(m, e) * std::norm(u[m.tail(h)] - r * u[m.head(h)]);
            }
            const Complex q = u.dot(A * u);
            EXPECT_NEAR(q.real(), energy, 1e-10 * energy) << m.name();
            EXPECT_NEAR(q.imag(), 0.0, 1e-10 * energy);
            const SparseMatrixC At = A.adjoint();
            EXPECT_EQ((A - At).norm(), 0.0);
        }
    }
}

TEST(FreeBlock, MatchesDenseSubmatrixAndMovesFixedColumnsToTheRightHandSide) {
    const Mesh m = makeIcosphere(1);
    const TangentFrames fr(m);
    const SparseMatrixC A = connectionLaplacian(fr, 4);
    const int n = m.nVertices();
    std::vector<int> freeId(n, -1);
    int nFree = 0;
    for (int v = 0; v < n; ++v)
        if (v % 3 != 0) freeId[v] = nFree++;
    const Eigen::VectorXcd values = randomVector(n, 3);
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(nFree);
    const SparseMatrixC K = freeBlock(A, freeId, nFree, values, rhs);
    const Eigen::MatrixXcd D(A);
    for (int i = 0; i < n; ++i) {
        if (freeId[i] < 0) continue;
        Complex expected(0, 0);
        for (int j = 0; j < n; ++j) {
            if (freeId[j] >= 0)
                EXPECT_EQ(K.coeff(freeId[i], freeId[j]), D(i, j));
            else
                expected -= D(i, j) * values[j];
        }
        EXPECT_NEAR(std::abs(rhs[freeId[i]] - expected), 0.0, 1e-12);
    }
}

// The paper's non-symmetric mean-value system: BiCGSTAB with the two-level
// preconditioner against UMFPACK's LU, bit-identical for 1 and 2 threads.
TEST(TwoLevelBicgstab, MatchesLuOnTheMeanValueSystemAndIsThreadIndependent) {
    const Mesh m = makeTorus(2.0, 0.7, 60, 30);
    const TangentFrames fr(m);
    const int n = m.nVertices();
    // u_i − Σ ω_ij T_ij u_j with a small diagonal boost (as a guide term adds).
    std::vector<Eigen::Triplet<Complex>> trip;
    std::vector<NeighbourWeight> row;
    for (int i = 0; i < n; ++i) {
        trip.emplace_back(i, i, 1.05);
        meanValueWeights(m, i, row);
        double sum = 0;
        for (const NeighbourWeight &w : row) {
            sum += w.weight;
            const int h = m.edgeHalfedge(m.edgeOf(w.halfedge));
            const Complex r = std::polar(1.0, 4 * fr.transportAngle(h));
            trip.emplace_back(i, w.vertex, -w.weight * (m.tail(h) == i ? r : std::conj(r)));
        }
        ASSERT_NEAR(sum, 1.0, 1e-12);
    }
    SparseMatrixRowC K(n, n);
    K.setFromTriplets(trip.begin(), trip.end());
    const Eigen::VectorXcd b = randomVector(n, 11);
    const Eigen::VectorXcd direct = solveGeneral(SparseMatrixC(K), b);
    PcgReport rep;
    Eigen::VectorXcd x2;
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        x2 = solveTwoLevelBicgstab(fr, 4, allFree(n), K, b, {}, 1e-10, 1000, &rep);
    }
    EXPECT_LT((x2 - direct).norm() / direct.norm(), 1e-8);
    EXPECT_LT(rep.iterations, 200);
    EXPECT_LE(rep.relativeResidual, 1e-10);
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const Eigen::VectorXcd x1 = solveTwoLevelBicgstab(fr, 4, allFree(n), K, b, {}, 1e-10, 1000);
    for (int i = 0; i < n; ++i) ASSERT_EQ(x1[i], x2[i]) << i;
}

// The smoothest field's eigenvalue against the smallest generalized eigenvalue
// of the dense (A, M) pencil, and its vector against the residual A u − λ M u.
TEST(SmoothestEigenSolver, MatchesDenseEigenvalueAndIsThreadIndependent) {
    const Mesh m = makeEllipsoid(3, 1.6, 1.2, 0.8); // 642 vertices, no degenerate eigenvalue
    const TangentFrames fr(m);
    const SparseMatrixC A = connectionLaplacian(fr, 4);
    const Eigen::VectorXd area = vertexAreas(m);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> dense(Eigen::MatrixXcd(A),
                                                                      Eigen::MatrixXcd(area.cast<Complex>().asDiagonal()));
    const double lambda0 = dense.eigenvalues()[0];
    SmoothestResult r2;
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        r2 = smoothestField(fr, 4);
    }
    // The solver stops at ‖Au − λMu‖_{M⁻¹} ≤ 1e-3 λ ‖u‖_M; the Rayleigh quotient is
    // then above λ0 by at most ‖r‖² / (λ1 − λ) (Kato–Temple), λ1 the next eigenvalue.
    const double lambda1 = dense.eigenvalues()[1];
    ASSERT_GT(lambda1, r2.eigenvalue);
    EXPECT_GE(r2.eigenvalue, lambda0 * (1 - 1e-12));
    EXPECT_LE(r2.eigenvalue - lambda0, std::pow(1e-3 * r2.eigenvalue, 2) / (lambda1 - r2.eigenvalue) * 1.01);
    const Eigen::VectorXcd &u = r2.field.u;
    const Eigen::VectorXcd res = A * u - r2.eigenvalue * area.cast<Complex>().cwiseProduct(u);
    const double uM = std::sqrt(std::real(u.dot(area.cast<Complex>().cwiseProduct(u))));
    EXPECT_LT(res.cwiseAbs2().cwiseQuotient(area).sum(), std::pow(1e-3 * lambda0 * uM, 2) * 1.0001);
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    const SmoothestResult r1 = smoothestField(fr, 4);
    for (int i = 0; i < m.nVertices(); ++i) ASSERT_EQ(r1.field.u[i], u[i]) << i;
}

// kFieldTolerance (field/sparse_solver.h) is chosen so that stopping early changes
// nothing a user can see: against a solve to 1e-10 (residual 10⁶ times smaller) the
// member directions differ by less than 0.1° everywhere and the singularities (face
// and index) are the same. Both the Hermitian (curvature-aligned, PCG) and the
// general (mean-value design relaxation, BiCGSTAB) paths on a real scan.
namespace {
double maxDirectionDifferenceDeg(const RosyField &a, const RosyField &b) {
    double worst = 0;
    for (int v = 0; v < a.u.size(); ++v) {
        // Members differ by arg(u_a / u_b) / N (representation vectors carry N θ).
        if (std::abs(a.u[v]) < 1e-9 && std::abs(b.u[v]) < 1e-9) continue;
        worst = std::max(worst, std::abs(std::arg(a.u[v] * std::conj(b.u[v]))) / a.nSym);
    }
    return worst * 180.0 / M_PI;
}
void expectSameSingularities(const TangentFrames &fr, const RosyField &a, const RosyField &b) {
    const SingularityReport ra = findSingularities(fr, a), rb = findSingularities(fr, b);
    ASSERT_EQ(ra.singularities.size(), rb.singularities.size());
    for (size_t i = 0; i < ra.singularities.size(); ++i) {
        EXPECT_EQ(ra.singularities[i].face, rb.singularities[i].face) << i;
        EXPECT_EQ(ra.singularities[i].indexNumerator, rb.singularities[i].indexNumerator) << i;
    }
}
} // namespace

TEST(Solver, DefaultToleranceMatchesTheConvergedFieldForTheAlignedSystem) {
    const Mesh m = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
    const TangentFrames fr(m);
    const RosyField guide = curvatureField(fr, computeCurvature(m), 4);
    const RosyField fast = alignedField(fr, guide, 0.05);
    const RosyField tight = alignedField(fr, guide, 0.05, {}, {}, 1e-10);
    EXPECT_LT(maxDirectionDifferenceDeg(fast, tight), 0.1);
    expectSameSingularities(fr, fast, tight);
}

TEST(Solver, DefaultToleranceMatchesTheConvergedFieldForTheMeanValueDesign) {
    const Mesh m = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
    const TangentFrames fr(m);
    // A +1, a −1 and a regular element at vertices spread over the bunny.
    std::vector<DesignElement> elements(3);
    const int n = m.nVertices();
    elements[0].position = m.position(n / 7);
    elements[0].order = 1;
    elements[1].position = m.position(n / 2);
    elements[1].order = -1;
    elements[2].position = m.position(5 * n / 6);
    elements[2].direction = Vec3(0.3, 1, 0.2);
    DesignOptions fastOptions;
    DesignOptions tightOptions;
    tightOptions.solverTolerance = 1e-10;
    const RosyField fast = designField(fr, 4, elements, fastOptions);
    const RosyField tight = designField(fr, 4, elements, tightOptions);
    EXPECT_LT(maxDirectionDifferenceDeg(fast, tight), 0.1);
    expectSameSingularities(fr, fast, tight);
}

TEST(Solver, DefaultToleranceMatchesTheConvergedFieldForTheAlignedSystemWithElements) {
    const Mesh m = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
    const TangentFrames fr(m);
    const RosyField guide = curvatureField(fr, computeCurvature(m), 4);
    std::vector<DesignElement> elements(2);
    elements[0].position = m.position(m.nVertices() / 3);
    elements[0].order = 1;
    elements[1].position = m.position(2 * m.nVertices() / 3);
    elements[1].order = -1;
    std::vector<char> fixed;
    Eigen::VectorXcd values;
    elementConstraints(fr, 4, elements, fixed, values);
    const RosyField fast = alignedField(fr, guide, 0.05, fixed, values);
    const RosyField tight = alignedField(fr, guide, 0.05, fixed, values, 1e-10);
    EXPECT_LT(maxDirectionDifferenceDeg(fast, tight), 0.1);
    expectSameSingularities(fr, fast, tight);
}

// A stalled single-vector LOBPCG (its limit forced down to 2 iterations) is
// continued by block LOBPCG and still meets the dense eigenvalue within the
// Kato–Temple bound, without a warning; with the block disabled the inverse
// iteration fallback runs, is reported with its reason and warned about.
TEST(SmoothestEigenSolver, StalledLobpcgIsContinuedByABlockOrFallsBackLoudly) {
    const Mesh m = makeEllipsoid(3, 1.6, 1.2, 0.8);
    const TangentFrames fr(m);
    const SparseMatrixC A = connectionLaplacian(fr, 4);
    const Eigen::VectorXd area = vertexAreas(m);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> dense(Eigen::MatrixXcd(A),
                                                                      Eigen::MatrixXcd(area.cast<Complex>().asDiagonal()));
    const double lambda0 = dense.eigenvalues()[0], lambda1 = dense.eigenvalues()[1];
    SmoothestOptions stalled;
    stalled.lobpcgIterations = 2;
    {
        rosy::WarningCapture capture;
        SmoothestResult r2, r1;
        {
            tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
            r2 = smoothestField(fr, 4, stalled);
        }
        EXPECT_EQ(r2.solver.method, "block-lobpcg");
        EXPECT_GT(r2.solver.iterations, 2);
        EXPECT_TRUE(r2.solver.fallbackReason.empty()) << r2.solver.fallbackReason;
        EXPECT_TRUE(capture.warnings().empty());
        EXPECT_GE(r2.eigenvalue, lambda0 * (1 - 1e-12));
        EXPECT_LE(r2.eigenvalue - lambda0, std::pow(1e-3 * r2.eigenvalue, 2) / (lambda1 - r2.eigenvalue) * 1.01);
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        r1 = smoothestField(fr, 4, stalled);
        for (int i = 0; i < m.nVertices(); ++i) ASSERT_EQ(r1.field.u[i], r2.field.u[i]) << i;
    }
    SmoothestOptions noBlock = stalled;
    noBlock.blockSize = 0;
    rosy::WarningCapture capture;
    const SmoothestResult r = smoothestField(fr, 4, noBlock);
    EXPECT_EQ(r.solver.method, "inverse-iteration");
    EXPECT_EQ(r.solver.lobpcgIterations, 2);
    EXPECT_NE(r.solver.fallbackReason.find("did not converge in 2 iterations"), std::string::npos)
        << r.solver.fallbackReason;
    ASSERT_EQ(capture.warnings().size(), 1u);
    EXPECT_EQ(capture.warnings()[0].kind, "smoothest-fallback");
    EXPECT_NEAR(r.eigenvalue, lambda0, 1e-6 * lambda0);
}

// double-torus-example.off (CGAL data) with N = 4 stalls single-vector LOBPCG past its
// 400 iterations; inverse iteration then stopped at its cap short of convergence. The
// block continuation must meet the dense eigenvalue within the Kato–Temple bound, with
// no fallback and no warning.
TEST(SmoothestEigenSolver, StallingCgalMeshConvergesThroughTheBlock) {
    const Mesh m = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/double-torus-example.off");
    const TangentFrames fr(m);
    const SparseMatrixC A = connectionLaplacian(fr, 4);
    const Eigen::VectorXd area = vertexAreas(m);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> dense(Eigen::MatrixXcd(A),
                                                                      Eigen::MatrixXcd(area.cast<Complex>().asDiagonal()));
    const double lambda0 = dense.eigenvalues()[0], lambda1 = dense.eigenvalues()[1];
    rosy::WarningCapture capture;
    const SmoothestResult r = smoothestField(fr, 4);
    EXPECT_TRUE(r.solver.fallbackReason.empty()) << r.solver.fallbackReason;
    EXPECT_NE(r.solver.method, "inverse-iteration");
    EXPECT_TRUE(capture.warnings().empty());
    EXPECT_GE(r.eigenvalue, lambda0 * (1 - 1e-12));
    EXPECT_LE(r.eigenvalue - lambda0, std::pow(1e-3 * r.eigenvalue, 2) / (lambda1 - r.eigenvalue) * 1.01);
}
