#include "field/editing.h"

#include "field/design.h"
#include "field/laplacian.h"
#include "field/sparse_solver.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <queue>
#include <sstream>
#include <string>

namespace rosy::field {
namespace {

Vec3 centroid(const Mesh &mesh, int f) {
    const Face &t = mesh.face(f);
    return (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
}

// Index numerator of one face, computed exactly as faceIndexNumerators() does
// (each edge's change from its canonical halfedge, negated for the other one), so
// the local check and a later global findSingularities() agree bit for bit.
int faceIndex(const TangentFrames &frames, const Eigen::VectorXcd &u, int nSym, int f) {
    const Mesh &mesh = frames.mesh();
    double total = nSym * frames.faceHolonomy(f);
    for (int c = 0; c < 3; ++c) {
        const int h = 3 * f + c;
        const int hc = mesh.edgeHalfedge(mesh.edgeOf(h));
        const double change =
            wrapAngle(std::arg(u[mesh.head(hc)]) + nSym * frames.transportAngle(hc) - std::arg(u[mesh.tail(hc)]));
        total += hc == h ? change : -change;
    }
    return int(std::lround(total / (2.0 * M_PI)));
}

std::string describe(const Singularity &s, int id) {
    std::ostringstream os;
    os << "#" << id << " (face " << s.face << ", index " << (s.indexNumerator > 0 ? "+" : "")
       << s.indexNumerator << "/" << s.nSym << ")";
    return os.str();
}

/// A face region kept a topological disk while it grows (see editing.h).
class Region {
public:
    Region(const Mesh &mesh, std::vector<char> forbidden, const Vec3 &focusA, const Vec3 &focusB)
        : m_mesh(mesh), m_forbidden(std::move(forbidden)), m_in(mesh.nFaces(), 0),
          m_count(mesh.nVertices(), 0), m_a(focusA), m_b(focusB) {}

    bool contains(int f) const { return m_in[f] != 0; }
    const std::vector<int> &faces() const { return m_faces; }

    // Adding f keeps a disk a disk when f meets it in one edge and brings a new
    // vertex, or in two edges (filling a notch, which closes the shared vertex's
    // fan). Meeting it only at a vertex or in one edge whose opposite vertex is
    // already in R would pinch it; three edges would close a sphere.
    bool canAdd(int f) const {
        if (m_in[f] || m_forbidden[f]) return false;
        if (m_faces.empty()) return true;
        int shared = 0, lastShared = -1;
        for (int k = 0; k < 3; ++k) {
            const int t = m_mesh.twin(3 * f + k);
            if (t >= 0 && m_in[Mesh::faceOf(t)]) {
                ++shared;
                lastShared = k;
            }
        }
        if (shared == 2) return true;
        if (shared != 1) return false;
        return m_count[m_mesh.face(f)[(lastShared + 2) % 3]] == 0;
    }

    void add(int f) {
        m_in[f] = 1;
        m_faces.push_back(f);
        for (int v : m_mesh.face(f)) ++m_count[v];
    }

    double key(int f) const {
        const Vec3 c = centroid(m_mesh, f);
        return (c - m_a).norm() + (c - m_b).norm();
    }

    /// Grows cheapest-first (elliptic key) until `target` joins; false if it cannot.
    bool growUntil(int target) {
        using Item = std::pair<double, int>;
        std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
        auto pushNeighbours = [&](int f) {
            for (int k = 0; k < 3; ++k) {
                const int t = m_mesh.twin(3 * f + k);
                if (t >= 0 && !m_in[Mesh::faceOf(t)] && !m_forbidden[Mesh::faceOf(t)])
                    queue.emplace(key(Mesh::faceOf(t)), Mesh::faceOf(t));
            }
        };
        for (int f : m_faces) pushNeighbours(f);
        if (m_in[target]) return true;
        // A face refused now is pushed again whenever a neighbour joins, which is
        // exactly when its answer can change.
        while (!queue.empty()) {
            const int f = queue.top().second;
            queue.pop();
            if (!canAdd(f)) continue;
            add(f);
            if (f == target) return true;
            pushNeighbours(f);
        }
        return false;
    }

    /// Adds one ring: every allowed face sharing a vertex with R, cheapest first,
    /// as long as R stays a disk. Returns the number of faces added.
    int dilate() {
        std::vector<int> candidates;
        std::vector<char> seen(m_mesh.nFaces(), 0);
        for (int f : m_faces)
            for (int v : m_mesh.face(f))
                for (const int *h = m_mesh.outgoingBegin(v); h != m_mesh.outgoingEnd(v); ++h) {
                    const int g = Mesh::faceOf(*h);
                    if (!m_in[g] && !m_forbidden[g] && !seen[g]) {
                        seen[g] = 1;
                        candidates.push_back(g);
                    }
                }
        std::vector<std::pair<double, int>> order;
        order.reserve(candidates.size());
        for (int g : candidates) order.emplace_back(key(g), g);
        std::sort(order.begin(), order.end());
        int added = 0;
        for (bool changed = true; changed;) {
            changed = false;
            for (const auto &item : order)
                if (canAdd(item.second)) {
                    add(item.second);
                    ++added;
                    changed = true;
                }
        }
        return added;
    }

    /// Interior mesh vertices whose whole fan lies in R, ascending.
    std::vector<int> interiorVertices() const {
        std::vector<int> out;
        for (int f : m_faces)
            for (int v : m_mesh.face(f))
                if (!m_mesh.isBoundaryVertex(v) && m_count[v] == m_mesh.degree(v)) out.push_back(v);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    std::vector<int> sortedFaces() const {
        std::vector<int> out = m_faces;
        std::sort(out.begin(), out.end());
        return out;
    }

private:
    const Mesh &m_mesh;
    std::vector<char> m_forbidden, m_in; // #F
    std::vector<int> m_count;            // #V: faces of R around each vertex
    std::vector<int> m_faces;
    Vec3 m_a, m_b;
};

/// Solves Eq. 14–15 with cotangent weights for the `free` vertices only, every
/// other value of `u` being a Dirichlet value. The system is the free block of the
/// Hermitian connection Laplacian, assembled from the free vertices' own edges.
/// A failed factorization or solve (the solver checks info() and finiteness) is an
/// InputError at `where` naming `edit` and the cause; `u` is then untouched. No
/// input is known to reach it: cotangents clamped to [1e-6, 1e4] keep this block
/// diagonally dominant with a positive diagonal, and LDLT fails only on an exact
/// zero pivot. It keeps the error contract of buildField should one appear.
void relaxFree(const TangentFrames &frames, int nSym, const std::vector<int> &free,
               Eigen::VectorXcd &u, const FileLoc &where, const std::string &edit) {
    const Mesh &mesh = frames.mesh();
    const int n = int(free.size());
    std::vector<int> localId(mesh.nVertices(), -1);
    for (int k = 0; k < n; ++k) localId[free[k]] = k;
    std::vector<Eigen::Triplet<Complex>> trip;
    trip.reserve(size_t(n) * 4);
    Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(n);
    for (int k = 0; k < n; ++k) {
        const int i = free[k];
        double diag = 0;
        for (const int *it = mesh.outgoingBegin(i); it != mesh.outgoingEnd(i); ++it) {
            const int h = *it, j = mesh.head(h);
            const double w = cotanEdgeWeight(mesh, mesh.edgeOf(h));
            const Complex r = std::polar(1.0, nSym * frames.transportAngle(h)); // j -> i
            diag += w;
            const int lj = localId[j];
            if (lj < 0)
                rhs[k] += w * r * u[j];
            else if (lj < k)
                trip.emplace_back(k, lj, -w * r);
        }
        trip.emplace_back(k, k, Complex(diag, 0.0));
    }
    SparseMatrixC K(n, n);
    K.setFromTriplets(trip.begin(), trip.end());
    Eigen::VectorXcd x;
    try {
        x = HermitianSolver(K).solve(rhs);
    } catch (const SolverFailure &e) {
        throwDegenerateGeometry(
            where, "cannot " + edit + ": the solve on its region of " + std::to_string(n) + " vertices", e);
    }
    for (int k = 0; k < n; ++k) u[free[k]] = x[k];
}

FileLoc whereOf(const EditOptions &options, const Mesh &mesh) {
    if (!options.where.path.empty()) return options.where;
    return FileLoc{mesh.name().empty() ? std::string("<mesh>") : mesh.name()};
}

std::vector<char> forbiddenFaces(const Mesh &mesh, const SingularityReport &report,
                                 std::initializer_list<int> allowedFaces) {
    std::vector<char> forbidden(mesh.nFaces(), 0);
    for (const Singularity &s : report.singularities) forbidden[s.face] = 1;
    for (int f : allowedFaces) forbidden[f] = 0;
    return forbidden;
}

void checkId(const SingularityReport &report, int id, const FileLoc &where) {
    if (id < 0 || id >= int(report.singularities.size()))
        throw InputError(where, "singularity #" + std::to_string(id) + " does not exist (the field has " +
                                    std::to_string(report.singularities.size()) + ", numbered from 0)",
                         "take the ids from the report's singularity list");
}

} // namespace

EditResult cancelPair(const TangentFrames &frames, RosyField &field, int a, int b,
                      const EditOptions &options) {
    const Mesh &mesh = frames.mesh();
    const FileLoc where = whereOf(options, mesh);
    const SingularityReport report = findSingularities(frames, field);
    checkId(report, a, where);
    checkId(report, b, where);
    if (a == b)
        throw InputError(where, "cannot cancel singularity #" + std::to_string(a) + " with itself",
                         "give two different ids");
    const Singularity &sa = report.singularities[a], &sb = report.singularities[b];
    const std::string pair = describe(sa, a) + " and " + describe(sb, b);
    if (std::abs(sa.indexNumerator) != 1 || std::abs(sb.indexNumerator) != 1)
        throw InputError(where, "cannot cancel " + pair + ": only first-order singularities (index ±1/N) cancel",
                         "split higher-order singularities first");
    if (sa.indexNumerator == sb.indexNumerator)
        throw InputError(where, "cannot cancel " + pair + ": their indices have the same sign, so they do not sum to zero",
                         "pair a +1/N singularity with a -1/N one");

    Region region(mesh, forbiddenFaces(mesh, report, {sa.face, sb.face}), sa.position, sb.position);
    region.add(sa.face);
    if (!region.growUntil(sb.face))
        throw InputError(where, "cannot cancel " + pair +
                                    ": every region joining them contains another singularity (or they lie on different components)",
                         "cancel or move the singularities between them first");
    for (int k = 0; k < options.initialRings; ++k) region.dilate();

    EditResult result;
    for (int round = 1; round <= options.maxRounds; ++round) {
        const std::vector<int> free = region.interiorVertices();
        if (!free.empty()) {
            Eigen::VectorXcd u = field.u;
            relaxFree(frames, field.nSym, free, u, where, "cancel " + pair);
            ++result.rounds;
            bool clean = true;
            for (int f : region.faces())
                if (faceIndex(frames, u, field.nSym, f) != 0) {
                    clean = false;
                    break;
                }
            if (clean) {
                field.u = std::move(u);
                result.regionFaces = region.sortedFaces();
                result.freeVertices = int(free.size());
                return result;
            }
        }
        if (round < options.maxRounds && region.dilate() == 0) break;
    }
    throw InputError(where, "cannot cancel " + pair + ": after " + std::to_string(options.maxRounds) +
                                " rings the region (" + std::to_string(region.faces().size()) +
                                " faces) still holds a singularity",
                     "cancel a closer pair, or clear the singularities around them first");
}

EditResult moveSingularity(const TangentFrames &frames, RosyField &field, int s, const Vec3 &target,
                           const EditOptions &options) {
    const Mesh &mesh = frames.mesh();
    const FileLoc where = whereOf(options, mesh);
    const SingularityReport report = findSingularities(frames, field);
    checkId(report, s, where);
    const Singularity &sing = report.singularities[s];
    const std::string name = describe(sing, s);
    const int order = sing.indexNumerator;
    if (std::abs(order) != 1)
        throw InputError(where, "cannot move " + name + ": only first-order singularities (index ±1/N) can be moved",
                         "move singularities of index ±1/N");
    if (!target.allFinite()) throw InputError(where, "the target point of the move is not finite");
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    const double diag = (hi - lo).norm();
    const SnappedElement snap = snapToSurface(mesh, target);
    std::ostringstream pt;
    pt << "(" << target.x() << ", " << target.y() << ", " << target.z() << ")";
    if (snap.face < 0 || snap.distance > 0.05 * diag)
        throw InputError(where, "cannot move " + name + ": target " + pt.str() + " is " +
                                    fmt::format("{:g}", snap.distance) + " units from the surface",
                         "give a point on the surface");
    const int targetFace = snap.face;
    EditResult result;
    result.targetFace = targetFace;
    if (targetFace == sing.face) return result;
    for (size_t j = 0; j < report.singularities.size(); ++j)
        if (report.singularities[j].face == targetFace)
            throw InputError(where, "cannot move " + name + ": target " + pt.str() + " lies in the face of singularity " +
                                        describe(report.singularities[j], int(j)),
                             "cancel that one instead, or pick another target");
    const Face &tf = mesh.face(targetFace);
    for (int v : tf)
        if (mesh.isBoundaryVertex(v))
            throw InputError(where, "cannot move " + name + ": target face " + std::to_string(targetFace) +
                                        " touches the mesh boundary",
                             "pick a target at least one face away from the boundary");

    // Eq. 13 element at the target, phase fitted to the current field there: with
    // face-frame values γ_c at corner angles θ_c around the centroid, the element
    // e^{i(Lθ_c + Nθ0)} is closest in least squares for Nθ0 = arg Σ γ_c e^{−iLθ_c}.
    DesignElement element;
    element.position = centroid(mesh, targetFace);
    element.order = order;
    element.label = where.str();
    const std::array<Complex, 3> gamma = frames.faceValues(targetFace, field);
    Vec2 centre = Vec2::Zero();
    for (int v : tf) centre += frames.toFace2D(targetFace, mesh.position(v)) / 3.0;
    Complex fit(0, 0);
    double magnitude = 0;
    for (int c = 0; c < 3; ++c) {
        const Vec2 q = frames.toFace2D(targetFace, mesh.position(tf[c])) - centre;
        fit += gamma[c] * std::polar(1.0, -order * std::atan2(q.y(), q.x()));
        magnitude += std::abs(gamma[c]) / 3.0;
    }
    element.phaseRad = std::abs(fit) > 0 ? std::arg(fit) / field.nSym : 0.0;
    element.strength = magnitude > 1e-12 ? magnitude : 1.0;
    std::vector<char> elementFixed;
    Eigen::VectorXcd elementValues;
    elementConstraints(frames, field.nSym, {element}, elementFixed, elementValues);

    Region region(mesh, forbiddenFaces(mesh, report, {sing.face, targetFace}), sing.position, snap.point);
    region.add(sing.face);
    if (!region.growUntil(targetFace))
        throw InputError(where, "cannot move " + name + " to " + pt.str() +
                                    ": every region joining them contains another singularity (or another component)",
                         "cancel or move the singularities in between first");
    for (int k = 0; k < options.initialRings; ++k) region.dilate();

    for (int round = 1; round <= options.maxRounds; ++round) {
        std::vector<int> free = region.interiorVertices();
        const bool targetInside = std::all_of(tf.begin(), tf.end(), [&](int v) {
            return std::binary_search(free.begin(), free.end(), v);
        });
        if (targetInside) {
            free.erase(std::remove_if(free.begin(), free.end(),
                                      [&](int v) { return v == tf[0] || v == tf[1] || v == tf[2]; }),
                       free.end());
            // The fitted phase usually works; a quarter-turn of the whole element is
            // the cheap fallback before growing the region.
            for (int turn = 0; turn < 4; ++turn) {
                Eigen::VectorXcd u = field.u;
                const Complex rot = std::polar(1.0, 0.5 * M_PI * turn);
                for (int v : tf) u[v] = elementValues[v] * rot;
                relaxFree(frames, field.nSym, free, u, where, "move " + name);
                ++result.rounds;
                bool ok = true;
                for (int f : region.faces()) {
                    const int k = faceIndex(frames, u, field.nSym, f);
                    if (f == targetFace ? k != order : k != 0) {
                        ok = false;
                        break;
                    }
                }
                if (ok) {
                    field.u = std::move(u);
                    result.regionFaces = region.sortedFaces();
                    result.freeVertices = int(free.size()) + 3;
                    return result;
                }
            }
        }
        if (round < options.maxRounds && region.dilate() == 0) break;
    }
    throw InputError(where, "cannot move " + name + " to " + pt.str() + ": after " +
                                std::to_string(options.maxRounds) + " rings the region (" +
                                std::to_string(region.faces().size()) +
                                " faces) does not leave exactly one singularity in the target face",
                     "move it in shorter steps, or clear the singularities around the path first");
}

std::pair<int, int> nearestOppositePair(const std::vector<Singularity> &singularities, const Vec3 &p,
                                        const Vec3 &q, const FileLoc &where) {
    std::pair<int, int> best{-1, -1};
    double bestCost = std::numeric_limits<double>::infinity();
    const int n = int(singularities.size());
    for (int i = 0; i < n; ++i) {
        if (std::abs(singularities[i].indexNumerator) != 1) continue;
        const double di = (singularities[i].position - p).norm();
        for (int j = 0; j < n; ++j) {
            if (singularities[j].indexNumerator != -singularities[i].indexNumerator) continue;
            const double cost = di + (singularities[j].position - q).norm();
            if (cost < bestCost) {
                bestCost = cost;
                best = {i, j};
            }
        }
    }
    if (best.first < 0)
        throw InputError(where, "the field has no pair of first-order singularities of opposite signs",
                         "nothing to cancel");
    return best;
}

} // namespace rosy::field
