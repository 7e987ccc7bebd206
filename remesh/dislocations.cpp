/// \file dislocations.cpp
/// The position field's dislocations moved (see dislocations.h and
/// docs/remeshing.md, "Dislocations moved").
#include "remesh/dislocations.h"
#include "core/parallel.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>

namespace rosy::remesh {
namespace {

/// v turned by k quarter turns counter-clockwise: (x, y) -> (−y, x) per turn.
inline Eigen::Vector2i turn(const Eigen::Vector2i &v, int k) {
    switch (k & 3) {
    case 0: return v;
    case 1: return {-v.y(), v.x()};
    case 2: return -v;
    default: return {v.y(), -v.x()};
    }
}

/// Edge m of a triangle enters its Burgers vector as sign · turn(t_e, rot), with
/// t_e the edge's offset from its smaller to its larger vertex, in the smaller's
/// lattice; `next` is the triangle on the other side (−1 at an open boundary or a
/// non-manifold edge) and `nextSlot` the edge's place in it.
struct Side {
    int edge = -1;
    int next = -1;
    int8_t sign = 1;
    int8_t rot = 0;
    int8_t nextSlot = -1;
    int8_t open = 0;      ///< crossable: an edge of the level, not at a held lattice point
    int8_t crossSign = 1; ///< a unit x here arrives in `next` as crossSign · turn(x, crossRot)
    int8_t crossRot = 0;
    int8_t exit = 0;      ///< an open boundary edge (a unit may leave the surface through it)
};

/// Defects searched at once before their moves are made in order (a fixed number,
/// so the windows, and the result, are the same for any thread count).
constexpr size_t kWindow = 8;

/// A vertex where the surface bends with a radius below 1 / kBentRadius lattice
/// spacings is held: a lattice cell there is not flat (a tube thinner than L, whose
/// dislocations moved collapsed it: an empty remesh).
constexpr double kBentRadius = 2;

/// A lattice spacing below this many L marks a thin part (held).
constexpr double kThinSpacing = 0.5;

} // namespace

DislocationStats moveDislocations(const DislocationInput &in, const DislocationOptions &options) {
    DislocationStats stats;
    const int nV = int(in.p.size());
    const SquareLattices lattices{in.p, in.n, in.q, in.o, in.s, in.s2};
    // Held (DislocationInput): the kept lattice points and thin parts, the rings
    // around them, and points where the surface bends with a radius below half the
    // spacing (kBentRadius): not moved, not crossed.
    std::vector<char> held(static_cast<size_t>(nV), 0);
    for (int i = 0; i < nV; ++i)
        held[size_t(i)] = in.pinned[size_t(i)] || (!in.onLine.empty() && in.onLine[size_t(i)]) ||
                          (!in.corner.empty() && in.corner[size_t(i)]) || std::min(in.s[i], in.s2[i]) < kThinSpacing * in.L;
    for (int ring = 0; ring < options.heldRings; ++ring) {
        std::vector<char> next(held);
        for (int i = 0; i < nV; ++i)
            if (!held[size_t(i)])
                for (int k = in.adjOffset[i]; k < in.adjOffset[i + 1]; ++k)
                    if (held[size_t(in.adj[k])]) next[size_t(i)] = 1;
        held.swap(next);
    }
    std::vector<char> bent(static_cast<size_t>(nV), 0);
    parallelFor(0, nV, [&](int64_t iv) {
        const int i = int(iv);
        const double spacing = std::max(in.s[i], in.s2[i]);
        for (int k = in.adjOffset[i]; k < in.adjOffset[i + 1]; ++k) {
            const int j = in.adj[k];
            const double angle = std::acos(std::clamp(in.n[i].dot(in.n[j]), -1.0, 1.0));
            if (angle * spacing > kBentRadius * (in.p[j] - in.p[i]).norm()) bent[size_t(i)] = 1;
        }
    }, 4096);
    for (int i = 0; i < nV; ++i) held[size_t(i)] = held[size_t(i)] || bent[size_t(i)];

    // Edges (i < j), their offsets t, t − c (c the real-valued offset) and rotations.
    std::vector<int> edgeOfSlot(in.adj.size(), -1);
    std::vector<std::array<int, 2>> ends;
    for (int i = 0; i < nV; ++i)
        for (int k = in.adjOffset[i]; k < in.adjOffset[i + 1]; ++k)
            if (in.adj[k] > i) edgeOfSlot[size_t(k)] = int(ends.size()), ends.push_back({i, in.adj[k]});
    const int nE = int(ends.size());
    std::vector<Eigen::Vector2i> t(static_cast<size_t>(nE));
    std::vector<Eigen::Vector2d> excess(static_cast<size_t>(nE)); // t − c
    std::vector<int> rot(static_cast<size_t>(nE));
    parallelFor(0, nE, [&](int64_t e) {
        const auto [i, j] = ends[size_t(e)];
        Eigen::Vector2d residual;
        t[size_t(e)] = squareOffset(lattices, i, j, &residual);
        excess[size_t(e)] = -residual;
        rot[size_t(e)] = compatIndex4(in.q[i], in.q[j], in.n[j]);
    }, 4096);
    const std::vector<Eigen::Vector2i> t0 = t;
    auto edgeOf = [&](int a, int b) {
        const int i = std::min(a, b), j = std::max(a, b);
        const int *begin = in.adj.data() + in.adjOffset[i], *end = in.adj.data() + in.adjOffset[i + 1];
        const int *it = std::lower_bound(begin, end, j);
        return it != end && *it == j ? edgeOfSlot[size_t(it - in.adj.data())] : -1;
    };

    // Triangles: their sides and singular turn (the rotations around them, mod 4).
    const int nT = int(in.triangles.size());
    std::vector<std::array<Side, 3>> sides(static_cast<size_t>(nT));
    std::vector<char> turnOf(size_t(nT), 0);
    std::vector<std::array<int, 2>> facesOfEdge(size_t(nE), {-1, -1});
    std::vector<char> faceCount(size_t(nE), 0);
    for (int f = 0; f < nT; ++f) {
        int around = 0; // rotation from the first corner's lattice to the current corner's
        for (int m = 0; m < 3; ++m) {
            const int a = in.triangles[size_t(f)][size_t(m)], b = in.triangles[size_t(f)][size_t((m + 1) % 3)];
            const int e = edgeOf(a, b);
            Side &sd = sides[size_t(f)][size_t(m)];
            sd.edge = e;
            if (e < 0) continue; // not an edge of the level: cannot happen for its own faces
            // t(a -> b) in a's lattice is t_e (a < b) or −turn(t_e, r_e); expressed in
            // the first corner's lattice it is turned by −around.
            if (a < b) sd.sign = 1, sd.rot = int8_t((-around) & 3);
            else sd.sign = -1, sd.rot = int8_t((-around + rot[size_t(e)]) & 3);
            around += a < b ? rot[size_t(e)] : -rot[size_t(e)];
            if (faceCount[size_t(e)] < 2) facesOfEdge[size_t(e)][size_t(faceCount[size_t(e)])] = f;
            faceCount[size_t(e)] = char(std::min(3, faceCount[size_t(e)] + 1));
        }
        turnOf[size_t(f)] = char(around & 3);
    }
    for (int f = 0; f < nT; ++f)
        for (int m = 0; m < 3; ++m) {
            Side &sd = sides[size_t(f)][size_t(m)];
            if (sd.edge < 0 || faceCount[size_t(sd.edge)] != 2) continue;
            const int g = facesOfEdge[size_t(sd.edge)][0] == f ? facesOfEdge[size_t(sd.edge)][1]
                                                               : facesOfEdge[size_t(sd.edge)][0];
            for (int k = 0; k < 3; ++k)
                if (sides[size_t(g)][size_t(k)].edge == sd.edge) sd.next = g, sd.nextSlot = int8_t(k);
        }
    for (int f = 0; f < nT; ++f)
        for (Side &sd : sides[size_t(f)]) {
            sd.open = sd.edge >= 0 && !held[size_t(ends[size_t(sd.edge)][0])] && !held[size_t(ends[size_t(sd.edge)][1])];
            sd.exit = sd.open && faceCount[size_t(sd.edge)] == 1;
            if (sd.next >= 0) {
                const Side &back = sides[size_t(sd.next)][size_t(sd.nextSlot)];
                sd.crossSign = int8_t(-sd.sign * back.sign);
                sd.crossRot = int8_t((back.rot - sd.rot) & 3);
            }
        }
    auto burgers = [&](int f) {
        Eigen::Vector2i b(0, 0);
        for (const Side &sd : sides[size_t(f)])
            if (sd.edge >= 0) b += sd.sign * turn(t[size_t(sd.edge)], sd.rot);
        return b;
    };
    std::vector<Eigen::Vector2i> b(static_cast<size_t>(nT));
    parallelFor(0, nT, [&](int64_t f) { b[size_t(f)] = burgers(int(f)); }, 4096);
    const Eigen::Vector2i zero(0, 0);
    for (int f = 0; f < nT; ++f) stats.before += turnOf[size_t(f)] == 0 && b[size_t(f)] != zero;

    // The reach in lattice spacings becomes a cost: a path across clear edges costs
    // about one per edge crossed, and a spacing is this many of the level's edges.
    double edgeSum = 0, spacingSum = 0;
    for (int e = 0; e < nE; ++e) edgeSum += (in.p[ends[size_t(e)][1]] - in.p[ends[size_t(e)][0]]).norm();
    for (int i = 0; i < nV; ++i) spacingSum += std::sqrt(in.s[i] * in.s2[i]);
    const double edgesPerSpacing = edgeSum > 0 && nV > 0 ? (spacingSum / nV) / (edgeSum / std::max(1, nE)) : 1.0;
    // A cone may also take a unit that leaves it one unit outside its class (the cone
    // with a dislocation beside it) at this extra cost, within coneReach; infinity: it
    // may not.
    const double parkPenalty = options.conePenalty * edgesPerSpacing;
    const double parkReach = options.coneReach * edgesPerSpacing;
    auto coneParks = [&](int f, const Eigen::Vector2i &x) { return (b[size_t(f)] + x).cwiseAbs().sum() <= 1; };
    // Does adding x to singular triangle f's vector leave it a translation the cone absorbs?
    auto coneTakes = [&](int f, const Eigen::Vector2i &x) {
        const Eigen::Vector2i y = b[size_t(f)] + x;
        return turnOf[size_t(f)] == 2 ? (y.x() % 2 == 0 && y.y() % 2 == 0) : ((y.x() + y.y()) % 2 == 0);
    };
    auto conesOutside = [&] {
        int count = 0;
        for (int f = 0; f < nT; ++f) count += turnOf[size_t(f)] != 0 && !coneTakes(f, zero);
        return count;
    };
    stats.conesWithOneBefore = conesOutside();
    // The unit change of edge e's offset that moves x out of triangle side sd.
    auto changeFor = [](const Side &sd, const Eigen::Vector2i &x) { return Eigen::Vector2i(-sd.sign * turn(x, -sd.rot)); };
    // 1 + 2 δ·(t − c) for the unit δ (one component ±1), at least costFloor.
    auto cost = [&](int e, const Eigen::Vector2i &delta) {
        const Eigen::Vector2d &ex = excess[size_t(e)];
        const double dot = delta.x() != 0 ? delta.x() * ex.x() : delta.y() * ex.y();
        return std::max(options.costFloor, 1.0 + 2.0 * dot);
    };

    // One unit's move: the path (edges and their changes) from f0 to the cheapest
    // place that takes it, found by Dijkstra's search within `cap`.
    struct Move {
        bool found = false;
        int sink = -1;                 ///< the triangle that takes the unit (-1: it leaves at the boundary)
        Eigen::Vector2i arriving{0, 0}; ///< the unit as it arrives there
        std::vector<std::pair<int, Eigen::Vector2i>> changes; ///< edge, change of its offset
    };
    struct Node {
        double dist = std::numeric_limits<double>::infinity();
        int parent = -1;
        int8_t parentSlot = -1;
        int8_t cx = 0, cy = 0; ///< the unit as it arrives, in this triangle's lattice
    };
    struct Scratch {
        std::vector<Node> node;
        std::vector<int> touched;
        std::vector<std::pair<double, int>> heap;
    };
    auto makeScratch = [&] {
        Scratch s;
        s.node.resize(size_t(nT));
        return s;
    };
    auto search = [&](int f0, const Eigen::Vector2i &unit, double cap, Scratch &s) {
        for (int f : s.touched) s.node[size_t(f)].dist = std::numeric_limits<double>::infinity();
        s.touched.assign(1, f0);
        s.heap.clear();
        const auto later = std::greater<std::pair<double, int>>();
        s.node[size_t(f0)] = Node{0.0, -1, -1, int8_t(unit.x()), int8_t(unit.y())};
        s.heap.push_back({0.0, f0});
        int sink = -1, exitFace = -1, exitSlot = -1, parkFace = -1;
        double exitCost = std::numeric_limits<double>::infinity(), parkCost = exitCost;
        while (!s.heap.empty()) {
            std::pop_heap(s.heap.begin(), s.heap.end(), later);
            const auto [d, f] = s.heap.back();
            s.heap.pop_back();
            const Node &nf = s.node[size_t(f)];
            if (d > nf.dist) continue;
            if (d > cap || d >= std::min(exitCost, parkCost)) break;
            const Eigen::Vector2i x(nf.cx, nf.cy);
            if (f != f0) {
                if (turnOf[size_t(f)] != 0) {
                    if (coneTakes(f, x)) {
                        sink = f;
                        break;
                    }
                    if (d + parkPenalty < parkCost && d + parkPenalty <= std::min(cap, parkReach) && coneParks(f, x))
                        parkCost = d + parkPenalty, parkFace = f;
                    continue; // a cone is not crossed
                }
                if ((b[size_t(f)] + x).cwiseAbs().sum() < b[size_t(f)].cwiseAbs().sum()) {
                    sink = f;
                    break;
                }
            }
            for (int m = 0; m < 3; ++m) {
                const Side &sd = sides[size_t(f)][size_t(m)];
                if (!sd.open) continue;
                const double c = d + cost(sd.edge, changeFor(sd, x));
                if (sd.next < 0) {
                    if (sd.exit && c < exitCost && c <= cap) exitCost = c, exitFace = f, exitSlot = m;
                    continue;
                }
                Node &ng = s.node[size_t(sd.next)];
                if (c >= ng.dist) continue;
                if (std::isinf(ng.dist)) s.touched.push_back(sd.next);
                const Eigen::Vector2i arriving = sd.crossSign * turn(x, sd.crossRot);
                ng = Node{c, f, int8_t(m), int8_t(arriving.x()), int8_t(arriving.y())};
                s.heap.push_back({c, sd.next});
                std::push_heap(s.heap.begin(), s.heap.end(), later);
            }
        }
        Move mv;
        auto carried = [&](int f) { return Eigen::Vector2i(s.node[size_t(f)].cx, s.node[size_t(f)].cy); };
        if (sink < 0 && parkFace >= 0 && parkCost <= exitCost) sink = parkFace; // nothing cheaper found
        int g = sink;
        if (sink >= 0) mv.sink = sink, mv.arriving = carried(sink);
        else if (exitFace >= 0) {
            const Side &sd = sides[size_t(exitFace)][size_t(exitSlot)];
            mv.changes.push_back({sd.edge, changeFor(sd, carried(exitFace))});
            g = exitFace;
        } else
            return mv; // nothing within reach
        mv.found = true;
        for (; g != f0; g = s.node[size_t(g)].parent) {
            const int f = s.node[size_t(g)].parent;
            const Side &sd = sides[size_t(f)][size_t(s.node[size_t(g)].parentSlot)];
            mv.changes.push_back({sd.edge, changeFor(sd, carried(f))});
        }
        return mv;
    };
    auto unitOf = [](const Eigen::Vector2i &v) {
        return v.x() != 0 ? Eigen::Vector2i(v.x() > 0 ? 1 : -1, 0) : Eigen::Vector2i(0, v.y() > 0 ? 1 : -1);
    };
    // Each pass: every defect's first move searched at once against the present
    // offsets (in parallel: each search reads only), then made one after the other
    // in triangle order — a move whose edges or end another move has changed since
    // is searched again, one that found nothing waits for the next pass — so the
    // result does not depend on the thread count.
    Scratch own = makeScratch();
    tbb::enumerable_thread_specific<Scratch> scratches(makeScratch);
    std::vector<char> edgeChanged(size_t(nE), 0), faceChanged(size_t(nT), 0);
    std::vector<int> changedEdges, changedFaces;
    auto commit = [&](int f0, const Eigen::Vector2i &unit, const Move &mv) {
        for (const auto &[e, delta] : mv.changes) {
            t[size_t(e)] += delta;
            excess[size_t(e)] += delta.cast<double>();
            edgeChanged[size_t(e)] = 1;
            changedEdges.push_back(e);
        }
        if (mv.sink >= 0) {
            b[size_t(mv.sink)] += mv.arriving;
            faceChanged[size_t(mv.sink)] = 1;
            changedFaces.push_back(mv.sink);
        }
        b[size_t(f0)] -= unit;
        faceChanged[size_t(f0)] = 1;
        changedFaces.push_back(f0);
        ++stats.moved;
    };
    const double reach = options.reach * edgesPerSpacing;
    const int passes = std::isfinite(options.reach) ? std::max(1, options.passes) : 1;
    for (int pass = 0; pass < passes && options.reach > 0; ++pass) {
        const double cap = reach / double(1 << (passes - 1 - pass));
        std::vector<int> defects;
        for (int f = 0; f < nT; ++f)
            if (turnOf[size_t(f)] == 0 && b[size_t(f)] != zero) defects.push_back(f);
        // in windows of a fixed size (the same windows for any thread count)
        for (size_t w0 = 0; w0 < defects.size(); w0 += kWindow) {
            const size_t w1 = std::min(defects.size(), w0 + kWindow);
            std::vector<Move> planned(w1 - w0);
            parallelFor(0, int64_t(w1 - w0), [&](int64_t k) {
                const int f0 = defects[w0 + size_t(k)];
                if (b[size_t(f0)] != zero) planned[size_t(k)] = search(f0, unitOf(b[size_t(f0)]), cap, scratches.local());
            }, 1);
            for (int e : changedEdges) edgeChanged[size_t(e)] = 0; // only this window's moves make a plan stale
            changedEdges.clear();
            for (int f : changedFaces) faceChanged[size_t(f)] = 0;
            changedFaces.clear();
            for (size_t k = w0; k < w1; ++k) {
                const int f0 = defects[k];
                const Move &mv = planned[k - w0];
                if (!mv.found) continue; // waits for the next pass
                bool first = true;
                while (b[size_t(f0)] != zero) {
                    const Eigen::Vector2i unit = unitOf(b[size_t(f0)]);
                    const bool stale = !first || faceChanged[size_t(f0)] ||
                                       (mv.sink >= 0 && faceChanged[size_t(mv.sink)]) ||
                                       std::any_of(mv.changes.begin(), mv.changes.end(),
                                                   [&](const auto &c) { return edgeChanged[size_t(c.first)] != 0; });
                    first = false;
                    if (!stale) {
                        commit(f0, unit, mv);
                        continue;
                    }
                    const Move again = search(f0, unit, cap, own);
                    if (!again.found) break;
                    commit(f0, unit, again);
                }
            }
        }
    }
    for (int f = 0; f < nT; ++f) stats.left += turnOf[size_t(f)] == 0 && burgers(f) != zero;
    stats.conesWithOne = conesOutside();
    if (stats.moved == 0) return stats;

    // The lattice points solved again for the changed offsets: unknowns x_i (the
    // change of o_i along q_i and w_i) of the free vertices, least squares of
    // (o_j + Δo_j) − (o_i + Δo_i) − T_ij over every edge, with the pull
    // `anchor` Σ |x_i|². The present points fit the old offsets T⁰ (what the
    // sweeps left), so only the offsets' change ΔT_ij = T_ij − T⁰_ij is solved
    // for: r_i = −Σ_j B_iᵀ ΔT_ij, and away from the moves nothing moves.
    std::vector<Vec3> w(static_cast<size_t>(nV));
    for (int i = 0; i < nV; ++i) w[size_t(i)] = in.n[i].cross(in.q[i]);
    std::vector<Vec3> changeOf(static_cast<size_t>(nE), Vec3::Zero()); // ΔT of i -> j (i < j), in i's lattice
    for (int e = 0; e < nE; ++e) {
        const Eigen::Vector2i d = t[size_t(e)] - t0[size_t(e)];
        const int a = ends[size_t(e)][0];
        if (d != zero) changeOf[size_t(e)] = in.s[a] * d.x() * in.q[a] + in.s2[a] * d.y() * w[size_t(a)];
    }
    const int n2 = 2 * nV;
    Eigen::VectorXd r(n2), x = Eigen::VectorXd::Zero(n2), z(n2), dir(n2), Ad(n2);
    parallelFor(0, nV, [&](int64_t iv) {
        const int i = int(iv);
        Vec3 sum = Vec3::Zero();
        if (!held[size_t(i)])
            for (int k = in.adjOffset[i]; k < in.adjOffset[i + 1]; ++k) {
                const int j = in.adj[k];
                sum -= j > i ? changeOf[size_t(edgeOfSlot[size_t(k)])] : Vec3(-changeOf[size_t(edgeOf(j, i))]);
            }
        r[2 * i] = in.q[i].dot(sum), r[2 * i + 1] = w[size_t(i)].dot(sum);
    }, 1024);
    auto multiply = [&](const Eigen::VectorXd &v, Eigen::VectorXd &out) {
        parallelFor(0, nV, [&](int64_t iv) {
            const int i = int(iv);
            if (held[size_t(i)]) {
                out[2 * i] = out[2 * i + 1] = 0;
                return;
            }
            const int deg = in.adjOffset[i + 1] - in.adjOffset[i];
            double y0 = (deg + options.anchor) * v[2 * i], y1 = (deg + options.anchor) * v[2 * i + 1];
            for (int k = in.adjOffset[i]; k < in.adjOffset[i + 1]; ++k) {
                const int j = in.adj[k];
                if (held[size_t(j)]) continue;
                const Vec3 d = v[2 * j] * in.q[j] + v[2 * j + 1] * w[size_t(j)];
                y0 -= in.q[i].dot(d), y1 -= w[size_t(i)].dot(d);
            }
            out[2 * i] = y0, out[2 * i + 1] = y1;
        }, 1024);
    };
    // Conjugate gradients, Jacobi-preconditioned (the diagonal is (degree + anchor) I:
    // B_iᵀB_i = I). Vector operations run over vertices in parallel; the dot
    // products sum fixed chunks in order, so the iterates are the same for any
    // thread count.
    std::vector<double> invDiag(static_cast<size_t>(nV));
    for (int i = 0; i < nV; ++i)
        invDiag[size_t(i)] = held[size_t(i)] ? 0.0 : 1.0 / (in.adjOffset[i + 1] - in.adjOffset[i] + options.anchor);
    constexpr int64_t kChunk = 4096; // vertices per partial sum
    const int64_t nChunks = (nV + kChunk - 1) / kChunk;
    std::vector<double> partial(static_cast<size_t>(nChunks));
    auto dot = [&](const Eigen::VectorXd &u, const Eigen::VectorXd &v) {
        parallelFor(0, nChunks, [&](int64_t c) {
            const int64_t lo = 2 * c * kChunk, hi = std::min<int64_t>(2 * (c + 1) * kChunk, n2);
            partial[size_t(c)] = u.segment(lo, hi - lo).dot(v.segment(lo, hi - lo));
        }, 1);
        double sum = 0;
        for (double s : partial) sum += s;
        return sum;
    };
    const double rhsNorm = std::sqrt(dot(r, r));
    if (rhsNorm > 0) {
        parallelFor(0, nV, [&](int64_t i) { z.segment<2>(2 * i) = invDiag[size_t(i)] * r.segment<2>(2 * i); }, 4096);
        dir = z;
        double rz = dot(r, z);
        for (int it = 0; it < options.maxIterations; ++it) {
            multiply(dir, Ad);
            const double alpha = rz / dot(dir, Ad);
            double rr = 0;
            parallelFor(0, nChunks, [&](int64_t c) {
                double s = 0;
                for (int64_t i = c * kChunk, end = std::min<int64_t>((c + 1) * kChunk, nV); i < end; ++i) {
                    x.segment<2>(2 * i) += alpha * dir.segment<2>(2 * i);
                    r.segment<2>(2 * i) -= alpha * Ad.segment<2>(2 * i);
                    z.segment<2>(2 * i) = invDiag[size_t(i)] * r.segment<2>(2 * i);
                    s += r.segment<2>(2 * i).squaredNorm();
                }
                partial[size_t(c)] = s;
            }, 1);
            for (double s : partial) rr += s;
            stats.iterations = it + 1;
            if (std::sqrt(rr) <= options.tolerance * rhsNorm) break;
            const double rzNext = dot(r, z);
            const double beta = rzNext / rz;
            parallelFor(0, nV, [&](int64_t i) { dir.segment<2>(2 * i) = z.segment<2>(2 * i) + beta * dir.segment<2>(2 * i); }, 4096);
            rz = rzNext;
        }
    }
    // Each free vertex: the changed lattice, then its point nearest the vertex.
    parallelFor(0, nV, [&](int64_t iv) {
        const int i = int(iv);
        if (held[size_t(i)]) return;
        Vec3 &o = in.o[size_t(i)];
        o += x[2 * i] * in.q[i] + x[2 * i + 1] * w[size_t(i)];
        const Vec3 d = in.p[i] - o;
        o += std::round(in.q[i].dot(d) / in.s[i]) * in.s[i] * in.q[i] +
             std::round(w[size_t(i)].dot(d) / in.s2[i]) * in.s2[i] * w[size_t(i)];
    }, 4096);
    return stats;
}

} // namespace rosy::remesh
