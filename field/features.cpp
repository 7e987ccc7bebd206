/// \file features.cpp
/// Feature curves and the field constraint along them (features.h).

#include "field/features.h"

#include "core/error.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <string>

namespace rosy::field {

FeatureCurves findFeatureCurves(const Mesh &mesh, double angleDeg) {
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
    // Per vertex, the other ends of its (at most two used) feature edges.
    std::vector<std::array<int, 2>> ends(size_t(nV), {-1, -1});
    for (int e = 0; e < mesh.nEdges(); ++e) {
        const int h = mesh.edgeHalfedge(e), t = mesh.twin(h);
        const bool boundary = t < 0;
        if (!boundary && !(fn[size_t(h / 3)].dot(fn[size_t(t / 3)]) < cosMax)) continue;
        const int a = mesh.tail(h), b = mesh.head(h);
        c.edges.push_back({std::min(a, b), std::max(a, b)});
        c.boundaryEdges += boundary ? 1 : 0;
        for (const auto &[v, w] : {std::pair{a, b}, std::pair{b, a}}) {
            if (c.degree[size_t(v)] < 2) ends[size_t(v)][size_t(c.degree[size_t(v)])] = w;
            ++c.degree[size_t(v)];
        }
    }
    const double cosTurn = std::cos(kFeatureCornerTurnDeg * std::numbers::pi / 180.0);
    for (int v = 0; v < nV; ++v) {
        if (c.degree[size_t(v)] == 0) continue;
        if (c.degree[size_t(v)] != 2) {
            c.corner[size_t(v)] = 1;
            continue;
        }
        const Vec3 &p = mesh.position(v);
        const Vec3 in = p - mesh.position(ends[size_t(v)][0]), out = mesh.position(ends[size_t(v)][1]) - p;
        const double li = in.norm(), lo = out.norm();
        if (!(li > 0 && lo > 0) || in.dot(out) < cosTurn * li * lo) {
            c.corner[size_t(v)] = 1;
            continue;
        }
        c.tangent[size_t(v)] = (in / li + out / lo).normalized();
    }
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
