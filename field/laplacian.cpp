#include "field/laplacian.h"

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

SparseMatrixC connectionLaplacian(const TangentFrames &frames, int nSym) {
    const Mesh &mesh = frames.mesh();
    std::vector<Eigen::Triplet<Complex>> trip;
    trip.reserve(4 * mesh.nEdges());
    std::vector<double> diag(mesh.nVertices(), 0.0);
    for (int e = 0; e < mesh.nEdges(); ++e) {
        const int h = mesh.edgeHalfedge(e);
        const double w = cotanEdgeWeight(mesh, e);
        const int i = mesh.tail(h), j = mesh.head(h);
        const Complex r = std::polar(1.0, nSym * frames.transportAngle(h)); // j -> i
        trip.emplace_back(i, j, -w * r);
        trip.emplace_back(j, i, -w * std::conj(r));
        diag[i] += w;
        diag[j] += w;
    }
    for (int v = 0; v < mesh.nVertices(); ++v) trip.emplace_back(v, v, diag[v]);
    SparseMatrixC A(mesh.nVertices(), mesh.nVertices());
    A.setFromTriplets(trip.begin(), trip.end());
    return A;
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
        // Mean-value weight of neighbour j of i: (tan(a1/2) + tan(a2/2)) / |p_j − p_i|,
        // a1, a2 the corner angles at i on either side of edge ij.
        for (int i = 0; i < nV; ++i) {
            std::vector<std::pair<int, double>> row;
            const int *begin = mesh.outgoingBegin(i), *end = mesh.outgoingEnd(i);
            auto addTo = [&](int j, double x) {
                for (auto &p : row)
                    if (p.first == j) { p.second += x; return; }
                row.push_back({j, x});
            };
            for (const int *it = begin; it != end; ++it) {
                const int h = *it;                  // i -> head(h), corner at i spans to tail(prev(h))
                const double a = mesh.cornerAngle(h);
                // tan(a/2) clamped: a corner of ~π (needle) would blow up.
                const double t = std::min(std::tan(0.5 * std::clamp(a, 0.0, M_PI)), 1e4);
                const int j1 = mesh.head(h), j2 = mesh.tail(Mesh::prev(h));
                const double l1 = std::max(mesh.vector(h).norm(), 1e-300);
                const double l2 = std::max((mesh.position(j2) - mesh.position(i)).norm(), 1e-300);
                addTo(j1, t / l1);
                addTo(j2, t / l2);
            }
            double sum = 0;
            for (auto &p : row) sum += p.second;
            for (auto &p : row) {
                // An all-degenerate fan has every weight zero: fall back to uniform.
                double w = sum > 0 ? p.second / sum : 1.0 / double(row.size());
                trip.emplace_back(i, p.first, w);
            }
        }
    }
    Eigen::SparseMatrix<double> W(nV, nV);
    W.setFromTriplets(trip.begin(), trip.end());
    return W;
}

} // namespace rosy::field
