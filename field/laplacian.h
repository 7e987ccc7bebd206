#pragma once
/// \file laplacian.h
/// Discrete operators on N-RoSy representation vectors: the connection
/// Laplacian (edges weighted, neighbours transported into the centre frame) and
/// the lumped mass matrix.

#include "field/frames.h"

#include <Eigen/Sparse>

#include <vector>

namespace rosy::field {

using SparseMatrixC = Eigen::SparseMatrix<Complex>;

enum class LaplaceWeights {
    /// Mean-value coordinates (Floater 2003), as in Palacios & Zhang Eq. 14.
    /// Positive on any mesh; not symmetric (each row normalised).
    MeanValue,
    /// Cotangent weights, each cotangent clamped to [−1e4, 1e4] and the edge
    /// weight floored at 1e-6 so needle and zero-area faces give finite, positive
    /// weights (a negative or infinite weight would break positive definiteness).
    Cotan,
};

/// Cotangent weight of edge e, (cot α + cot β) / 2 with each cotangent clamped to
/// [−1e4, 1e4] and the result floored at 1e-6 (see LaplaceWeights::Cotan).
double cotanEdgeWeight(const Mesh &mesh, int e);
/// cotanEdgeWeight of every edge (parallel).
std::vector<double> cotanEdgeWeights(const Mesh &mesh);

/// Hermitian positive semi-definite connection Laplacian A (#V × #V) of the
/// Dirichlet energy Σ_edges w_ij |u_i − e^{iNΔθ_ij} u_j|² (cotan weights).
/// Compressed, both triangles, sorted rows; assembled column-parallel without
/// triplets (bunny00: a few ms).
SparseMatrixC connectionLaplacian(const TangentFrames &frames, int nSym);

/// The block of a Hermitian A (both triangles) on the rows and columns with
/// freeId ≥ 0 (freeId increasing with the vertex id, nFree of them); when `values`
/// is not empty, rhs −= A(free, fixed) · values(fixed).
SparseMatrixC freeBlock(const SparseMatrixC &A, const std::vector<int> &freeId, int nFree,
                        const Eigen::VectorXcd &values, Eigen::VectorXcd &rhs);

/// Lumped (barycentric) vertex areas, floored at 1e-12 × the mean so no row is zero.
Eigen::VectorXd vertexAreas(const Mesh &mesh);

/// One neighbour j of a vertex i: a halfedge joining them and the weight ω_ij.
struct NeighbourWeight {
    int vertex;
    int halfedge;
    double weight;
};

/// Row-normalised mean-value weights of vertex i's neighbours (Floater 2003),
/// summing to 1 (uniform if every corner is degenerate). `row` is overwritten.
void meanValueWeights(const Mesh &mesh, int i, std::vector<NeighbourWeight> &row);

/// Row-normalised weights ω_ij of vertex i's neighbours for the relaxation of
/// Eq. 14 (ω summing to 1 per vertex). Returned as a real sparse matrix W with
/// W(i, j) = ω_ij; the diagonal is empty.
Eigen::SparseMatrix<double> relaxationWeights(const Mesh &mesh, LaplaceWeights weights);

} // namespace rosy::field
