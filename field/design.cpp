#include "field/design.h"

#include "core/diagnostics.h"
#include "core/error.h"
#include "core/parallel.h"
#include "field/smoothing.h"

#include "field/mesh/closest_point.h"
#include "field/mesh/union_find.h"
#include "field/multilevel.h"
#include "field/sparse_solver.h"

#include <fmt/format.h>
#include <cmath>
#include <limits>
#include <sstream>

namespace rosy::field {
namespace {

// Vertex components through edges (ids by smallest vertex, deterministic).
std::vector<int> vertexComponents(const Mesh &mesh, int &nComp) {
    UnionFind components(mesh.nVertices());
    for (int e = 0; e < mesh.nEdges(); ++e) {
        const int h = mesh.edgeHalfedge(e);
        components.unite(mesh.tail(h), mesh.head(h));
    }
    std::vector<int> id(mesh.nVertices(), -1), comp(mesh.nVertices());
    nComp = 0;
    for (int v = 0; v < mesh.nVertices(); ++v) {
        int r = components.find(v);
        if (id[r] < 0) id[r] = nComp++;
        comp[v] = id[r];
    }
    return comp;
}

std::string fmtPoint(const Vec3 &p) {
    std::ostringstream os;
    os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    return os.str();
}

} // namespace

SnappedElement snapToSurface(const Mesh &mesh, const Vec3 &p) {
    SnappedElement best;
    best.distance = std::numeric_limits<double>::infinity();
    for (int f = 0; f < mesh.nFaces(); ++f) {
        const Face &t = mesh.face(f);
        Vec3 q = closestPointOnTriangle(p, mesh.position(t[0]), mesh.position(t[1]), mesh.position(t[2]));
        double d = (q - p).norm();
        if (d < best.distance) best = {f, q, d};
    }
    return best;
}

void elementConstraints(const TangentFrames &frames, int nSym,
                        const std::vector<DesignElement> &elements, std::vector<char> &fixed,
                        Eigen::VectorXcd &values, const std::vector<SnappedElement> *snapped) {
    ROSY_CHECK(!snapped || snapped->size() == elements.size());
    const Mesh &mesh = frames.mesh();
    fixed.assign(mesh.nVertices(), 0);
    values = Eigen::VectorXcd::Zero(mesh.nVertices());
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    const double diag = (hi - lo).norm();
    const DesignOptions defaults;
    for (size_t k = 0; k < elements.size(); ++k) {
        const DesignElement &el = elements[k];
        const FileLoc loc{el.label.empty() ? "design element " + std::to_string(k) : el.label};
        if (el.order < -1 || el.order > 1)
            throw InputError(loc, "design element order " + std::to_string(el.order) +
                                      " is not supported", "use -1, 0 or 1");
        if (!(el.strength > 0) || !std::isfinite(el.strength))
            throw InputError(loc, "design element strength must be a positive number");
        if (!el.position.allFinite() || !std::isfinite(el.phaseRad))
            throw InputError(loc, "design element position or phase is not finite");
        const SnappedElement snap = snapped ? (*snapped)[k] : snapToSurface(mesh, el.position);
        if (snap.face < 0 || snap.distance > defaults.maxSnapDistance * diag)
            throw InputError(loc, "design element at " + fmtPoint(el.position) + " is " +
                                      fmt::format("{:.3g} units from the surface (mesh size {:.3g})",
                                                  snap.distance, diag),
                             "place it on the surface");
        const int f = snap.face;
        if (mesh.faceArea(f) <= 1e-14 * diag * diag)
            throw InputError(loc, "design element lands in degenerate face " + std::to_string(f),
                             "move it slightly");
        const Face &t = mesh.face(f);
        // Element centre in the face frame: the centroid for L ≠ 0 (keeps the
        // singularity strictly inside f), the snapped point for L = 0 (irrelevant there).
        Vec2 centre = Vec2::Zero();
        for (int c = 0; c < 3; ++c) centre += frames.toFace2D(f, mesh.position(t[c])) / 3.0;
        double theta0 = el.phaseRad;
        if (el.order == 0) {
            const Vec3 d = el.direction;
            Vec2 d2(d.dot(frames.faceAxisX(f)), d.dot(frames.faceAxisY(f)));
            if (!d.allFinite() || d2.norm() < 1e-12 * std::max(1.0, d.norm()))
                throw InputError(loc, "design element direction is zero or normal to the surface",
                                 "give a direction along the surface");
            theta0 = std::atan2(d2.y(), d2.x());
        }
        for (int c = 0; c < 3; ++c) {
            Vec2 q = frames.toFace2D(f, mesh.position(t[c])) - centre;
            const double theta = std::atan2(q.y(), q.x());
            // Eq. 13 in the face frame, then rotated into the vertex frame.
            const double faceAngle = el.order * theta + nSym * theta0;
            const double vertexAngle = faceAngle - nSym * frames.vertexToFace(3 * f + c);
            values[t[c]] += std::polar(el.strength, vertexAngle);
            fixed[t[c]] = 1;
        }
    }
}

Eigen::VectorXcd solveRelaxation(const TangentFrames &frames, int nSym,
                                 const std::vector<char> &fixed, const Eigen::VectorXcd &values,
                                 const DesignOptions &options) {
    const Mesh &mesh = frames.mesh();
    const int nV = mesh.nVertices();
    const double g = options.guide ? options.guideWeight : 0.0;

    std::vector<int> freeId(nV, -1);
    int nFree = 0;
    for (int v = 0; v < nV; ++v)
        if (fixed.empty() || !fixed[v]) freeId[v] = nFree++;
    Eigen::VectorXcd result = values.size() == nV ? values : Eigen::VectorXcd::Zero(nV);
    if (nFree == 0) return result;
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(nFree);

    if (options.weights == LaplaceWeights::Cotan) {
        // Σ_j w_ij (u_i − T_ij u_j) = 0 is the free block of the Hermitian connection
        // Laplacian: two-level CG. The guide term is the normalised row's
        // g (u_i − q_i) multiplied back by the row sum A_ii.
        SparseMatrixC K = freeBlock(connectionLaplacian(frames, nSym), freeId, nFree, result, rhs);
        if (g > 0)
            for (int v = 0; v < nV; ++v)
                if (freeId[v] >= 0) {
                    Complex &d = K.coeffRef(freeId[v], freeId[v]);
                    rhs[freeId[v]] += g * d.real() * options.guide->u[v];
                    d *= 1.0 + g;
                }
        const Eigen::VectorXcd x = solveHermitianSystem(frames, nSym, freeId, K, rhs, {}, options.solverTolerance);
        for (int v = 0; v < nV; ++v)
            if (freeId[v] >= 0) result[v] = x[freeId[v]];
        return result;
    }

    // The paper's form (Eq. 14–15): u_i − Σ_j ω_ij T_ij u_j = 0 with row-normalised
    // mean-value weights, a general (non-symmetric) system, built by rows in
    // parallel (T_ij the transport from j to i across the edge).
    std::vector<int> outer(size_t(nFree) + 1, 0);
    std::vector<int> rowVertex(nFree);
    for (int v = 0; v < nV; ++v)
        if (freeId[v] >= 0) {
            rowVertex[freeId[v]] = v;
            outer[freeId[v] + 1] = outer[freeId[v]] + mesh.valence(v) + 1;
        }
    std::vector<int> inner(outer.back());
    std::vector<Complex> value(outer.back());
    std::vector<int> rowSize(nFree);
    parallelFor(0, nFree, [&](int64_t row) {
        const int i = rowVertex[row];
        std::vector<NeighbourWeight> w;
        meanValueWeights(mesh, i, w);
        std::vector<std::pair<int, Complex>> entry;
        entry.reserve(w.size() + 1);
        entry.push_back({int(row), Complex(1.0 + g, 0.0)});
        Complex b = g > 0 ? g * options.guide->u[i] : Complex(0, 0);
        for (const NeighbourWeight &nw : w) {
            const int j = nw.vertex;
            const double wij = nw.weight;
            const int h = mesh.edgeHalfedge(mesh.edgeOf(nw.halfedge));
            const Complex r = std::polar(1.0, nSym * frames.transportAngle(h));
            const Complex a = -wij * (mesh.tail(h) == i ? r : std::conj(r));
            if (freeId[j] >= 0)
                entry.push_back({freeId[j], a});
            else
                b -= a * result[j];
        }
        std::sort(entry.begin(), entry.end(), [](const auto &p, const auto &q) { return p.first < q.first; });
        for (size_t t = 0; t < entry.size(); ++t) {
            inner[outer[row] + t] = entry[t].first;
            value[outer[row] + t] = entry[t].second;
        }
        rowSize[row] = int(entry.size());
        rhs[row] = b;
    }, 1024);
    // Close the gaps left by fixed neighbours.
    int nnz = 0;
    for (int row = 0; row < nFree; ++row) {
        const int begin = outer[row];
        outer[row] = nnz;
        for (int t = 0; t < rowSize[row]; ++t) {
            inner[nnz] = inner[begin + t];
            value[nnz] = value[begin + t];
            ++nnz;
        }
    }
    outer[nFree] = nnz;
    SparseMatrixRowC K(nFree, nFree);
    K.resizeNonZeros(nnz);
    std::copy(outer.begin(), outer.end(), K.outerIndexPtr());
    std::copy(inner.begin(), inner.begin() + nnz, K.innerIndexPtr());
    std::copy(value.begin(), value.begin() + nnz, K.valuePtr());
    const Eigen::VectorXcd x = solveGeneralSystem(frames, nSym, freeId, K, rhs, {}, options.solverTolerance);
    for (int v = 0; v < nV; ++v)
        if (freeId[v] >= 0) result[v] = x[freeId[v]];
    return result;
}

RosyField designField(const TangentFrames &frames, int nSym, const std::vector<DesignElement> &elements,
                      const DesignOptions &options) {
    const Mesh &mesh = frames.mesh();
    if (elements.empty() && !options.guide)
        throw InputError(FileLoc{mesh.name()}, "a designed field needs at least one design element",
                         "add field.elements or use source: curvature or smoothest");
    std::vector<char> fixed;
    Eigen::VectorXcd values;
    elementConstraints(frames, nSym, elements, fixed, values, options.snapped);

    // A component without any element (and no guide) would make the system
    // singular: give it the globally smoothest field instead, and say so.
    int nComp = 0;
    const std::vector<int> comp = vertexComponents(mesh, nComp);
    std::vector<char> constrained(nComp, 0);
    for (int v = 0; v < mesh.nVertices(); ++v)
        if (fixed[v]) constrained[comp[v]] = 1;
    RosyField smoothest;
    int nUnconstrained = 0;
    if (!options.guide)
        for (int c = 0; c < nComp; ++c) nUnconstrained += !constrained[c];
    if (nUnconstrained > 0) {
        smoothest = smoothestField(frames, nSym).field;
        for (int v = 0; v < mesh.nVertices(); ++v)
            if (!constrained[comp[v]]) {
                fixed[v] = 1;
                values[v] = smoothest.u[v];
            }
        warn(mesh.name(), "unconstrained-components",
             std::to_string(nUnconstrained) +
                 " mesh component(s) hold no design element; they get the globally smoothest field");
    }
    RosyField field;
    field.nSym = nSym;
    field.u = solveRelaxation(frames, nSym, fixed, values, options);
    return field;
}

} // namespace rosy::field
