/// \file features.cpp
/// Feature curves and the field constraint along them (features.h).

#include "field/features.h"

#include "core/error.h"
#include "field/mesh/union_find.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

namespace rosy::field {

namespace {

/// Degrees, corners and tangents of c.edges (c.degree, c.corner, c.tangent sized).
void classify(const Mesh &mesh, FeatureCurves &c) {
    const int nV = mesh.nVertices();
    std::fill(c.degree.begin(), c.degree.end(), 0);
    std::fill(c.corner.begin(), c.corner.end(), 0);
    std::fill(c.tangent.begin(), c.tangent.end(), Vec3::Zero());
    // Per vertex, the other ends of its first two feature edges.
    std::vector<std::array<int, 2>> ends(size_t(nV), {-1, -1});
    for (const auto &[a, b] : c.edges)
        for (const auto &[v, w] : {std::pair{a, b}, std::pair{b, a}}) {
            if (c.degree[size_t(v)] < 2) ends[size_t(v)][size_t(c.degree[size_t(v)])] = w;
            ++c.degree[size_t(v)];
        }
    const double cosTurn = std::cos(kFeatureCornerTurnDeg * std::numbers::pi / 180.0);
    for (int v = 0; v < nV; ++v) {
        const int degree = c.degree[size_t(v)];
        if (degree == 0) continue;
        if (degree > 2) {
            c.corner[size_t(v)] = 1;
            continue;
        }
        const Vec3 &p = mesh.position(v);
        // A curve's end (degree 1): along its one edge; inside: the mean of the two.
        const Vec3 in = p - mesh.position(ends[size_t(v)][0]);
        const Vec3 out = degree == 2 ? Vec3(mesh.position(ends[size_t(v)][1]) - p) : in;
        const double li = in.norm(), lo = out.norm();
        if (!(li > 0 && lo > 0) || in.dot(out) < cosTurn * li * lo) {
            c.corner[size_t(v)] = 1;
            continue;
        }
        c.tangent[size_t(v)] = (in / li + out / lo).normalized();
    }
}

} // namespace

FeatureCurves findFeatureCurves(const Mesh &mesh, double angleDeg, double minCurveLength) {
    if (!(angleDeg > 0 && angleDeg < 180))
        throw InputError(FileLoc{mesh.name()}, "the feature angle must be in (0, 180) degrees",
                         "e.g. 40 (creases whose faces' normals differ by more than 40 degrees)");
    const int nV = mesh.nVertices();
    FeatureCurves c;
    c.degree.assign(size_t(nV), 0);
    c.corner.assign(size_t(nV), 0);
    c.tangent.assign(size_t(nV), Vec3::Zero());
    const double cosMax = std::cos(angleDeg * std::numbers::pi / 180.0);
    const std::vector<Vec3> &fn = mesh.faceNormals();
    std::vector<char> isBoundary;
    for (int e = 0; e < mesh.nEdges(); ++e) {
        const int h = mesh.edgeHalfedge(e), t = mesh.twin(h);
        const bool boundary = t < 0;
        if (!boundary && !(fn[size_t(h / 3)].dot(fn[size_t(t / 3)]) < cosMax)) continue;
        const int a = mesh.tail(h), b = mesh.head(h);
        c.edges.push_back({std::min(a, b), std::max(a, b)});
        isBoundary.push_back(char(boundary));
    }
    classify(mesh, c);
    if (minCurveLength > 0 && !c.edges.empty()) {
        // Curves are the edges joined through vertices that are not corners; the
        // shorter ones are dropped (a crease of a few edges on an organic mesh is noise).
        const int nE = int(c.edges.size());
        UnionFind curve(nE);
        std::vector<int> firstAt(size_t(nV), -1);
        for (int e = 0; e < nE; ++e)
            for (int v : c.edges[size_t(e)]) {
                if (c.corner[size_t(v)]) continue;
                if (firstAt[size_t(v)] < 0) firstAt[size_t(v)] = e;
                else curve.unite(e, firstAt[size_t(v)]);
            }
        std::vector<double> length(size_t(nE), 0.0);
        for (int e = 0; e < nE; ++e)
            length[size_t(curve.find(e))] +=
                (mesh.position(c.edges[size_t(e)][0]) - mesh.position(c.edges[size_t(e)][1])).norm();
        std::vector<std::array<int, 2>> kept;
        std::vector<char> keptBoundary;
        for (int e = 0; e < nE; ++e)
            if (isBoundary[size_t(e)] || length[size_t(curve.find(e))] >= minCurveLength)
                kept.push_back(c.edges[size_t(e)]), keptBoundary.push_back(isBoundary[size_t(e)]);
        c.edges.swap(kept);
        isBoundary.swap(keptBoundary);
        classify(mesh, c);
    }
    for (char b : isBoundary) c.boundaryEdges += b;
    return c;
}

int addFeatureConstraints(const TangentFrames &frames, int nSym, const FeatureCurves &curves,
                          std::vector<char> &fixed, Eigen::VectorXcd &values) {
    const int nV = frames.mesh().nVertices();
    if (fixed.empty()) fixed.assign(size_t(nV), 0);
    if (values.size() == 0) values = Eigen::VectorXcd::Zero(nV);
    int added = 0;
    for (int v = 0; v < nV; ++v) {
        if (fixed[size_t(v)] || !curves.onCurve(v) || curves.corner[size_t(v)]) continue;
        const Vec3 &t = curves.tangent[size_t(v)];
        const Vec3 &n = frames.normal(v);
        if ((t - n * n.dot(t)).norm() < 1e-6) continue; // the tangent is along the normal: no direction
        fixed[size_t(v)] = 1;
        values[v] = std::polar(1.0, nSym * frames.angleOfTangent(v, t));
        ++added;
    }
    return added;
}

} // namespace rosy::field
