#include "field/laplacian.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>

namespace rosy::field {
namespace {
// cot of the corner of face(h) at tail(prev(h)), i.e. the angle opposite halfedge h.
double oppositeCot(const Mesh &mesh, int h) {
    const Vec3 a = mesh.position(mesh.tail(h)) - mesh.position(mesh.tail(Mesh::prev(h)));
    const Vec3 b = mesh.position(mesh.head(h)) - mesh.position(mesh.tail(Mesh::prev(h)));
    const double s = a.cross(b).norm();
    const double c = a.dot(b);
    // Clamp: a zero-area face would give ±inf; 1e4 is far beyond any useful angle.
    if (s <= std::abs(c) * 1e-4) return c >= 0 ? 1e4 : -1e4;
    return std::clamp(c / s, -1e4, 1e4);
}
} // namespace

double cotanEdgeWeight(const Mesh &mesh, int e) {
    const int h = mesh.edgeHalfedge(e);
    double w = 0.5 * oppositeCot(mesh, h);
    if (mesh.twin(h) >= 0) w += 0.5 * oppositeCot(mesh, mesh.twin(h));
    return std::max(w, 1e-6);
}

std::vector<double> cotanEdgeWeights(const Mesh &mesh) {
    std::vector<double> w(mesh.nEdges());
    parallelFor(0, mesh.nEdges(), [&](int64_t e) { w[e] = cotanEdgeWeight(mesh, int(e)); }, 4096);
    return w;
}

// Built directly in compressed column form (no triplets): column j holds the
// diagonal and one entry per neighbour i, A(i, j) = −w_ij e^{iNΔθ} with the
// transport from j's frame to i's. Per-edge values are computed once, then
// columns are filled in parallel, each from j's own ring, so the matrix is
// identical for any thread count.
SparseMatrixC connectionLaplacian(const TangentFrames &frames, int nSym) {
    const Mesh &mesh = frames.mesh();
    const int nV = mesh.nVertices(), nE = mesh.nEdges();
    // Entry (a, b) of edge e with canonical halfedge h (tail a, head b, transport
    // b -> a as in Eq. 14): A(a, b) = −w e^{iNt(h)}, A(b, a) its conjugate, so the
    // matrix is exactly Hermitian.
    std::vector<double> w(nE);
    std::vector<Complex> offDiag(nE);
    parallelFor(0, nE, [&](int64_t e) {
        w[e] = cotanEdgeWeight(mesh, int(e));
        offDiag[e] = -w[e] * std::polar(1.0, nSym * frames.transportAngle(mesh.edgeHalfedge(int(e))));
    }, 4096);
    SparseMatrixC A(nV, nV);
    int nnz = nV;
    for (int v = 0; v < nV; ++v) nnz += mesh.valence(v);
    A.resizeNonZeros(nnz);
    int *outer = A.outerIndexPtr(), *inner = A.innerIndexPtr();
    Complex *value = A.valuePtr();
    outer[0] = 0;
    for (int v = 0; v < nV; ++v) outer[v + 1] = outer[v] + mesh.valence(v) + 1;
    parallelFor(0, nV, [&](int64_t jj) {
        const int j = int(jj);
        int *row = inner + outer[j];
        Complex *val = value + outer[j];
        int k = 0;
        double diag = 0;
        auto add = [&](int g, int i) {
            const int edge = mesh.edgeOf(g);
            // Insertion into the sorted column.
            int t = k++;
            for (; t > 0 && row[t - 1] > i; --t) {
                row[t] = row[t - 1];
                val[t] = val[t - 1];
            }
            row[t] = i;
            val[t] = mesh.tail(mesh.edgeHalfedge(edge)) == i ? offDiag[edge] : std::conj(offDiag[edge]);
            diag += w[edge];
        };
        const int *begin = mesh.outgoingBegin(j), *end = mesh.outgoingEnd(j);
        for (const int *it = begin; it != end; ++it) add(*it, mesh.head(*it));
        // The last neighbour of a boundary vertex, reached by the incoming boundary halfedge.
        if (mesh.isBoundaryVertex(j) && begin != end) add(Mesh::prev(*(end - 1)), mesh.tail(Mesh::prev(*(end - 1))));
        int t = k++;
        for (; t > 0 && row[t - 1] > j; --t) {
            row[t] = row[t - 1];
            val[t] = val[t - 1];
        }
        row[t] = j;
        val[t] = Complex(diag, 0);
        ROSY_CHECK(k == outer[j + 1] - outer[j]); // every neighbour of a manifold vertex is in its ring
    }, 2048);
    return A;
}

SparseMatrixC freeBlock(const SparseMatrixC &A, const std::vector<int> &freeId, int nFree,
                        const Eigen::VectorXcd &values, Eigen::VectorXcd &rhs) {
    std::vector<int> outer(size_t(nFree) + 1, 0), inner;
    std::vector<Complex> value;
    inner.reserve(size_t(A.nonZeros()));
    value.reserve(size_t(A.nonZeros()));
    for (int j = 0; j < A.outerSize(); ++j) {
        const int fj = freeId[j];
        for (SparseMatrixC::InnerIterator it(A, j); it; ++it) {
            const int fi = freeId[it.row()];
            if (fi < 0) continue;
            if (fj >= 0) {
                inner.push_back(fi);
                value.push_back(it.value());
            } else if (values.size() > 0) {
                rhs[fi] -= it.value() * values[j];
            }
        }
        if (fj >= 0) outer[size_t(fj) + 1] = int(inner.size());
    }
    SparseMatrixC K(nFree, nFree);
    K.resizeNonZeros(Eigen::Index(value.size()));
    std::copy(outer.begin(), outer.end(), K.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), K.innerIndexPtr());
    std::copy(value.begin(), value.end(), K.valuePtr());
    return K;
}

Eigen::VectorXd vertexAreas(const Mesh &mesh) {
    Eigen::VectorXd a = Eigen::VectorXd::Zero(mesh.nVertices());
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const double third = mesh.faceArea(f) / 3.0;
        for (int v : mesh.face(f)) a[v] += third;
    }
    const double floor = 1e-12 * (a.size() > 0 ? std::max(a.mean(), 1e-300) : 1.0);
    for (int v = 0; v < a.size(); ++v) a[v] = std::max(a[v], floor);
    return a;
}

void meanValueWeights(const Mesh &mesh, int i, std::vector<NeighbourWeight> &row) {
    // Mean-value weight of neighbour j of i: (tan(a1/2) + tan(a2/2)) / |p_j − p_i|,
    // a1, a2 the corner angles at i on either side of edge ij.
    row.clear();
    const std::vector<double> &angles = mesh.cornerAngles();
    auto addTo = [&](int j, int h, double x) {
        for (auto &p : row)
            if (p.vertex == j) {
                p.weight += x;
                return;
            }
        row.push_back({j, h, x});
    };
    for (const int *it = mesh.outgoingBegin(i); it != mesh.outgoingEnd(i); ++it) {
        const int h = *it; // i -> head(h), corner at i spans to tail(prev(h))
        const double a = angles[size_t(h)];
        // tan(a/2) clamped: a corner of ~π (needle) would blow up.
        const double t = std::min(std::tan(0.5 * std::clamp(a, 0.0, M_PI)), 1e4);
        const int j1 = mesh.head(h), j2 = mesh.tail(Mesh::prev(h));
        const double l1 = std::max(mesh.vector(h).norm(), 1e-300);
        const double l2 = std::max((mesh.position(j2) - mesh.position(i)).norm(), 1e-300);
        addTo(j1, h, t / l1);
        addTo(j2, Mesh::prev(h), t / l2);
    }
    double sum = 0;
    for (auto &p : row) sum += p.weight;
    // An all-degenerate fan has every weight zero: fall back to uniform.
    for (auto &p : row) p.weight = sum > 0 ? p.weight / sum : 1.0 / double(row.size());
}

Eigen::SparseMatrix<double> relaxationWeights(const Mesh &mesh, LaplaceWeights weights) {
    const int nV = mesh.nVertices();
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(2 * mesh.nEdges() + nV);
    if (weights == LaplaceWeights::Cotan) {
        std::vector<double> rowSum(nV, 0.0);
        std::vector<std::array<double, 3>> tmp;
        for (int e = 0; e < mesh.nEdges(); ++e) {
            const int h = mesh.edgeHalfedge(e);
            const double w = cotanEdgeWeight(mesh, e);
            tmp.push_back({double(mesh.tail(h)), double(mesh.head(h)), w});
            rowSum[mesh.tail(h)] += w;
            rowSum[mesh.head(h)] += w;
        }
        for (const auto &t : tmp) {
            int i = int(t[0]), j = int(t[1]);
            trip.emplace_back(i, j, t[2] / rowSum[i]);
            trip.emplace_back(j, i, t[2] / rowSum[j]);
        }
    } else {
        std::vector<NeighbourWeight> row;
        for (int i = 0; i < nV; ++i) {
            meanValueWeights(mesh, i, row);
            for (const NeighbourWeight &p : row) trip.emplace_back(i, p.vertex, p.weight);
        }
    }
    Eigen::SparseMatrix<double> W(nV, nV);
    W.setFromTriplets(trip.begin(), trip.end());
    return W;
}

} // namespace rosy::field
