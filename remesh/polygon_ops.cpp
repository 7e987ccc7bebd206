/// \file polygon_ops.cpp
/// See polygon_ops.h.

#include "remesh/polygon_ops.h"

#include "core/parallel.h"
#include "field/mesh/closest_point.h"
#include "field/mesh/mesh_stats.h"
#include "field/mesh/union_find.h"
#include "field/winding_number.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>
#include <functional>

namespace rosy::remesh {

void removeMarked(std::vector<std::vector<int>> &polygons, const std::vector<char> &gone) {
    std::vector<std::vector<int>> kept;
    for (size_t f = 0; f < polygons.size(); ++f)
        if (!gone[f]) kept.push_back(std::move(polygons[f]));
    polygons.swap(kept);
}

void dissolveValence2(std::vector<std::vector<int>> &polygons, int nVertices, int maxSides,
                      std::map<std::string, int> &repairs) {
    std::vector<std::vector<int>> facesOf(static_cast<size_t>(nVertices));
    for (int f = 0; f < int(polygons.size()); ++f)
        for (int v : polygons[size_t(f)]) facesOf[size_t(v)].push_back(f);
    std::vector<char> gone(polygons.size(), 0);
    int dissolved = 0, merged = 0;
    // v's neighbours in face h: (predecessor, successor)
    auto around = [&](int h, int v) {
        const std::vector<int> &P = polygons[size_t(h)];
        const size_t k = size_t(std::find(P.begin(), P.end(), v) - P.begin());
        return std::pair{P[(k + P.size() - 1) % P.size()], P[(k + 1) % P.size()]};
    };
    for (int v = 0; v < nVertices; ++v) {
        if (facesOf[size_t(v)].size() != 2) continue;
        const int f = facesOf[size_t(v)][0], g = facesOf[size_t(v)][1];
        if (f == g || gone[size_t(f)] || gone[size_t(g)]) continue;
        std::vector<int> &F = polygons[size_t(f)], &G = polygons[size_t(g)];
        if (F.size() == 3 && G.size() == 3) continue; // a double triangle: leave it
        // On an open mesh's boundary (its two faces do not share both its edges): valence 3, kept.
        const auto [fa, fb] = around(f, v);
        const auto [ga, gb] = around(g, v);
        if (!(fa == gb && fb == ga)) continue;
        const int a = fa, b = fb;
        // Is a–b an edge of a face other than f and g?
        bool joined = false;
        for (int h : facesOf[size_t(a)]) {
            if (h == f || h == g || gone[size_t(h)]) continue;
            const auto [p, n] = around(h, a);
            joined = joined || p == b || n == b;
        }
        if (joined && F.size() > 3 && G.size() > 3) {
            // F runs v -> b -> ... -> a -> v, G runs v -> a -> ... -> b -> v: the union
            // is F's path from b to a, then G's inner vertices from a back to b.
            auto after = [&](const std::vector<int> &P) { // P from v's successor to its predecessor
                const size_t k = size_t(std::find(P.begin(), P.end(), v) - P.begin());
                std::vector<int> path;
                for (size_t i = 1; i < P.size(); ++i) path.push_back(P[(k + i) % P.size()]);
                return path;
            };
            std::vector<int> u = after(F);
            const std::vector<int> w = after(G);
            u.insert(u.end(), w.begin() + 1, w.end() - 1);
            std::vector<int> sorted = u;
            std::sort(sorted.begin(), sorted.end());
            if (int(u.size()) > maxSides || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
                continue;
            for (int x : G) {
                std::vector<int> &list = facesOf[size_t(x)];
                list.erase(std::find(list.begin(), list.end(), g));
                if (x != v && std::find(list.begin(), list.end(), f) == list.end()) list.push_back(f);
            }
            F = std::move(u);
            gone[size_t(g)] = 1;
            facesOf[size_t(v)].clear();
            ++merged;
            ++dissolved;
            continue;
        }
        // (With a triangle (v, b, a), a–b is that triangle's own edge: it goes and the
        // other face takes its side b -> a.)
        for (int h : {f, g}) {
            std::vector<int> &P = polygons[size_t(h)];
            if (P.size() == 3) {
                gone[size_t(h)] = 1;
                for (int x : P) // its other two corners no longer list it
                    if (x != v) facesOf[size_t(x)].erase(std::find(facesOf[size_t(x)].begin(), facesOf[size_t(x)].end(), h));
            } else {
                P.erase(std::find(P.begin(), P.end(), v));
            }
        }
        facesOf[size_t(v)].clear();
        ++dissolved;
    }
    removeMarked(polygons, gone);
    repairs["valence2_dissolved_in_faces"] = dissolved;
    repairs["valence2_faces_merged"] += merged;
}

int splitPinchedVertices(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions, double maxStep) {
    struct Corner {
        int face, slot, prev, next;
    };
    std::vector<std::vector<Corner>> corners(positions.size());
    for (int f = 0; f < int(polygons.size()); ++f) {
        const std::vector<int> &P = polygons[size_t(f)];
        for (size_t k = 0; k < P.size(); ++k)
            corners[size_t(P[k])].push_back({f, int(k), P[(k + P.size() - 1) % P.size()], P[(k + 1) % P.size()]});
    }
    int made = 0;
    const size_t nV = positions.size();
    for (size_t v = 0; v < nV; ++v) {
        const std::vector<Corner> &cs = corners[v];
        if (cs.size() < 2) continue;
        // Around v, the corner after (prev p, next n) is the one whose prev is n.
        std::map<int, int> byPrev;
        bool ambiguous = false;
        for (size_t i = 0; i < cs.size(); ++i) ambiguous = ambiguous || !byPrev.emplace(cs[i].prev, int(i)).second;
        if (ambiguous) continue; // a directed edge twice: not a pinch, left to the report
        field::UnionFind fans(int(cs.size()));
        for (size_t i = 0; i < cs.size(); ++i)
            if (auto it = byPrev.find(cs[i].next); it != byPrev.end()) fans.unite(int(i), it->second);
        std::map<int, int> fanOf; // root -> fan number, in corner order
        for (size_t i = 0; i < cs.size(); ++i) fanOf.emplace(fans.find(int(i)), int(fanOf.size()));
        if (fanOf.size() < 2) continue;
        std::vector<Vec3> sum(fanOf.size(), Vec3::Zero());
        std::vector<int> count(fanOf.size(), 0);
        for (size_t i = 0; i < cs.size(); ++i) {
            const int k = fanOf[fans.find(int(i))];
            sum[size_t(k)] += positions[size_t(cs[i].prev)] + positions[size_t(cs[i].next)];
            count[size_t(k)] += 2;
        }
        const Vec3 at = positions[v];
        std::vector<int> id(fanOf.size(), int(v));
        for (size_t k = 0; k < fanOf.size(); ++k) {
            if (k > 0) {
                id[k] = int(positions.size());
                positions.push_back(at);
                ++made;
            }
            const Vec3 d = sum[k] / double(count[k]) - at;
            const double len = d.norm();
            if (len > 0) positions[size_t(id[k])] = at + d * (std::min(0.25 * len, maxStep) / len);
        }
        for (size_t i = 0; i < cs.size(); ++i)
            polygons[size_t(cs[i].face)][size_t(cs[i].slot)] = id[size_t(fanOf[fans.find(int(i))])];
    }
    return made;
}

Vec3 vectorArea(const std::vector<int> &poly, const std::vector<Vec3> &positions) {
    Vec3 a = Vec3::Zero();
    for (size_t k = 0; k < poly.size(); ++k) a += positions[poly[k]].cross(positions[poly[(k + 1) % poly.size()]]);
    return a;
}

bool facesInput(const std::vector<int> &poly, const std::vector<Vec3> &positions, const field::Mesh &input,
                const AabbTree &inputTree) {
    Vec3 c = Vec3::Zero();
    for (int v : poly) c += positions[v];
    const ClosestPoint cp = inputTree.closest(c / double(poly.size()));
    return cp.triangle >= 0 && vectorArea(poly, positions).dot(input.faceNormal(cp.triangle)) > 0;
}

double farthestFromInput(const std::vector<int> &poly, const std::vector<Vec3> &positions, const AabbTree &inputTree,
                         double L) {
    double worst = 0;
    int hint = -1;
    for (size_t t = 1; t + 1 < poly.size(); ++t)
        forEachSample(positions[poly[0]], positions[poly[t]], positions[poly[t + 1]], L, [&](const Vec3 &p) {
            const ClosestPoint cp = inputTree.closest(p, hint);
            hint = cp.triangle;
            worst = std::max(worst, cp.distance2);
        });
    return std::sqrt(worst);
}

std::vector<std::vector<int>> cutFarQuad(const std::vector<int> &quad, const std::vector<Vec3> &positions,
                                         const field::Mesh &input, const AabbTree &inputTree, double L,
                                         double minHeight, double limit) {
    if (quad.size() != 4) return {};
    std::vector<std::vector<int>> best;
    double bestFar = limit;
    for (size_t d = 0; d < 2; ++d) {
        const std::vector<int> t0 = {quad[d], quad[d + 1], quad[(d + 2) % 4]},
                               t1 = {quad[d], quad[(d + 2) % 4], quad[(d + 3) % 4]};
        bool sound = true;
        double far = 0;
        for (const std::vector<int> *t : {&t0, &t1}) {
            const Vec3 &a = positions[size_t((*t)[0])], &b = positions[size_t((*t)[1])], &c = positions[size_t((*t)[2])];
            const double area2 = (b - a).cross(c - a).norm();
            const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
            sound = sound && area2 >= minHeight * longest && facesInput(*t, positions, input, inputTree);
            if (sound) far = std::max(far, farthestFromInput(*t, positions, inputTree, L));
        }
        if (sound && (far < bestFar || (best.empty() && far <= bestFar))) bestFar = far, best = {t0, t1};
    }
    return best;
}

namespace {

/// The smallest corner angle of triangle (a, b, c), in radians (0 if degenerate).
double smallestAngle(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    auto angle = [](const Vec3 &p, const Vec3 &q, const Vec3 &r) { // at p
        const Vec3 u = q - p, v = r - p;
        const double nu = u.norm(), nv = v.norm();
        if (!(nu > 0) || !(nv > 0)) return 0.0;
        return std::acos(std::clamp(u.dot(v) / (nu * nv), -1.0, 1.0));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

/// The triangulation of a loop of corners (no new vertex) whose worst triangle faces
/// the input best: by dynamic programming over the loop's sub-chains, each triangle
/// scored by the cosine between its vector area and the input's normal at the point
/// nearest its centroid (-1 if twice its area along that normal is below `minArea`
/// or a side it cuts is `joined`); empty unless every triangle's score is positive,
/// or if the loop has more than `maxLoop` corners.
/// Triangles that all face one way on a surface patch cover the loop's inside once,
/// so no test for overlaps is needed.
std::vector<std::vector<int>> facingTriangulation(const std::vector<int> &loop, const std::vector<Vec3> &positions,
                                                  const field::Mesh &input, const AabbTree &inputTree,
                                                  const std::function<bool(int, int)> &joined, double minArea,
                                                  int maxLoop) {
    const int n = int(loop.size());
    // The search is cubic in the loop's length, with a closest-point query per
    // triangle: a longer loop is not cut (the caller keeps its fan or tries another
    // patch) rather than stall the remesher.
    if (n < 3 || n > maxLoop) return {};
    auto score = [&](int i, int k, int j) { // triangle (loop[i], loop[k], loop[j]), i < k < j
        const std::vector<int> t = {loop[size_t(i)], loop[size_t(k)], loop[size_t(j)]};
        for (auto [x, y] : {std::pair{i, k}, std::pair{k, j}, std::pair{i, j}}) {
            const bool side = y == x + 1 || (x == 0 && y == n - 1);
            if (!side && joined(loop[size_t(x)], loop[size_t(y)])) return -1.0;
        }
        const Vec3 c = (positions[size_t(t[0])] + positions[size_t(t[1])] + positions[size_t(t[2])]) / 3.0;
        const ClosestPoint cp = inputTree.closest(c);
        const Vec3 a = vectorArea(t, positions);
        if (cp.triangle < 0 || !(a.norm() > 0)) return -1.0;
        const double along = a.dot(input.faceNormal(cp.triangle));
        return along < minArea ? -1.0 : along / a.norm();
    };
    // best[i][j]: the worst score of the best triangulation of the chain i..j (j - i >= 2).
    std::vector<double> best(size_t(n * n), 1.0);
    std::vector<int> apex(size_t(n * n), -1);
    for (int len = 2; len < n; ++len)
        for (int i = 0; i + len < n; ++i) {
            const int j = i + len;
            double b = -2;
            for (int k = i + 1; k < j; ++k) {
                double v = score(i, k, j);
                if (k - i >= 2) v = std::min(v, best[size_t(i * n + k)]);
                if (j - k >= 2) v = std::min(v, best[size_t(k * n + j)]);
                if (v > b) b = v, apex[size_t(i * n + j)] = k;
            }
            best[size_t(i * n + j)] = b;
        }
    if (!(best[size_t(n - 1)] > 0)) return {};
    std::vector<std::vector<int>> tris;
    std::vector<std::pair<int, int>> chains = {{0, n - 1}};
    while (!chains.empty()) {
        const auto [i, j] = chains.back();
        chains.pop_back();
        const int k = apex[size_t(i * n + j)];
        tris.push_back({loop[size_t(i)], loop[size_t(k)], loop[size_t(j)]});
        if (k - i >= 2) chains.push_back({i, k});
        if (j - k >= 2) chains.push_back({k, j});
    }
    return tris;
}

} // namespace

namespace {

/// The smallest corner angle of a polygon (radians; 0 at a corner with a zero side).
double smallestAngleOf(const std::vector<int> &P, const std::vector<Vec3> &positions) {
    double smallest = std::numbers::pi;
    const size_t m = P.size();
    for (size_t k = 0; k < m; ++k) {
        const Vec3 u = positions[size_t(P[(k + m - 1) % m])] - positions[size_t(P[k])],
                   w = positions[size_t(P[(k + 1) % m])] - positions[size_t(P[k])];
        const double l = u.norm() * w.norm();
        smallest = std::min(smallest, l > 0 ? std::acos(std::clamp(u.dot(w) / l, -1.0, 1.0)) : 0.0);
    }
    return smallest;
}

} // namespace

std::vector<std::vector<int>> soundFan(const std::vector<int> &loop, int apex, const std::vector<Vec3> &positions,
                                       const field::Mesh &input, const AabbTree &inputTree, double L,
                                       double minHeight, double limit, double *farthest) {
    std::vector<std::vector<int>> fan;
    double far = 0;
    const size_t n = loop.size();
    const Vec3 &x = positions[size_t(apex)];
    for (size_t k = 0; k < n; ++k) {
        const Vec3 &a = positions[size_t(loop[k])], &b = positions[size_t(loop[(k + 1) % n])];
        const double h = (b - a).cross(x - a).norm() / std::max((b - a).norm(), 1e-300);
        fan.push_back({apex, loop[k], loop[(k + 1) % n]});
        if (!(h >= minHeight) || !facesInput(fan.back(), positions, input, inputTree)) return {};
        const double d = farthestFromInput(fan.back(), positions, inputTree, L);
        if (!(d <= limit)) return {};
        far = std::max(far, d);
    }
    if (farthest) *farthest = far;
    return fan;
}

JoinedFan fanAcrossSide(int f, const std::vector<Vec3> &targets, const std::vector<std::vector<int>> &polygons,
                        std::vector<Vec3> &positions, const std::function<int(int, int)> &across,
                        const std::function<bool(int)> &usable, const field::Mesh &input,
                        const AabbTree &inputTree, double L, double minHeight, double limit) {
    const std::vector<int> &poly = polygons[size_t(f)];
    const size_t n = poly.size();
    const int apex = int(positions.size());
    JoinedFan best;
    double bestFar = std::numeric_limits<double>::infinity();
    Vec3 bestApex = Vec3::Zero();
    for (size_t k = 0; k < n; ++k) {
        const int a = poly[k], b = poly[(k + 1) % n];
        const int g = across(b, a);
        if (g < 0 || g == f || size_t(g) >= polygons.size() || !usable(g)) continue;
        const std::vector<int> &G = polygons[size_t(g)];
        const size_t m = G.size();
        size_t kg = m;
        for (size_t i = 0; i < m; ++i)
            if (G[i] == b && G[(i + 1) % m] == a) kg = i;
        if (kg == m) continue;
        // f from b round to a, then g after a round to before b.
        std::vector<int> loop;
        for (size_t i = 1; i <= n; ++i) loop.push_back(poly[(k + i) % n]);
        for (size_t i = 2; i < m; ++i) loop.push_back(G[(kg + i) % m]);
        std::vector<int> sorted = loop;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
        const double lim = std::max({limit, kFarDistance * L, 0.9 * farthestFromInput(G, positions, inputTree, L)});
        for (const Vec3 &x : targets) {
            positions.push_back(x);
            double far = 0;
            std::vector<std::vector<int>> fan = soundFan(loop, apex, positions, input, inputTree, L, minHeight, lim, &far);
            positions.pop_back();
            if (!fan.empty() && far < bestFar) bestFar = far, best.neighbour = g, best.faces = std::move(fan), bestApex = x;
        }
    }
    if (best.neighbour >= 0) positions.push_back(bestApex);
    return best;
}

int moveCornerOnto(const std::vector<int> &poly, const Vec3 &x, const std::vector<std::vector<int>> &polygons,
                   std::vector<Vec3> &positions, const field::Mesh &input, const AabbTree &inputTree, double L,
                   double limit, const std::function<bool(size_t)> &fixed, const std::function<bool(int)> &usable,
                   std::vector<int> &around) {
    constexpr double kReach = 0.75, kMinCorner = 30.0 * std::numbers::pi / 180.0;
    std::vector<int> corners(poly.begin(), poly.end());
    std::sort(corners.begin(), corners.end(), [&](int a, int b) {
        const double da = (positions[size_t(a)] - x).squaredNorm(), db = (positions[size_t(b)] - x).squaredNorm();
        return da != db ? da < db : a < b;
    });
    for (int v : corners) {
        if (fixed && fixed(size_t(v))) continue;
        if ((positions[size_t(v)] - x).norm() > kReach * L) break;
        around.clear();
        bool free = true;
        for (size_t g = 0; g < polygons.size(); ++g)
            if (std::find(polygons[g].begin(), polygons[g].end(), v) != polygons[g].end()) {
                around.push_back(int(g));
                free = free && usable(int(g));
            }
        if (!free) continue;
        const Vec3 was = positions[size_t(v)], under = inputTree.closest(was).point;
        positions[size_t(v)] = x;
        bool good = true;
        double uncovered = std::numeric_limits<double>::infinity(); // the input under the old place, from the faces
        for (int g : around) {
            const std::vector<int> &P = polygons[size_t(g)];
            good = facesInput(P, positions, input, inputTree) && smallestAngleOf(P, positions) >= kMinCorner &&
                   farthestFromInput(P, positions, inputTree, L) <= limit;
            if (!good) break;
            for (size_t k = 1; k + 1 < P.size(); ++k)
                uncovered = std::min(uncovered, (field::closestPointOnTriangle(under, positions[size_t(P[0])],
                                                                              positions[size_t(P[k])],
                                                                              positions[size_t(P[k + 1])]) -
                                                 under)
                                                    .norm());
        }
        if (good && uncovered <= kFarDistance * L) return v;
        positions[size_t(v)] = was;
    }
    around.clear();
    return -1;
}

std::vector<std::vector<int>> fillHole(const std::vector<int> &hole, std::vector<Vec3> &positions,
                                       const field::Mesh &input, const AabbTree &inputTree,
                                       const std::function<bool(int, int)> &joined, bool &byEars) {
    byEars = false;
    Vec3 c = Vec3::Zero();
    for (int x : hole) c += positions[size_t(x)];
    const int centre = int(positions.size());
    positions.push_back(inputTree.closest(c / double(hole.size())).point);
    std::vector<std::vector<int>> fan;
    bool fanFaces = true;
    for (size_t k = 0; k < hole.size(); ++k) {
        fan.push_back({centre, hole[k], hole[(k + 1) % hole.size()]});
        fanFaces = fanFaces && facesInput(fan.back(), positions, input, inputTree);
    }
    if (fanFaces) return fan;
    // Each hole is cut once: long loops are affordable. (At 1 % the longest met on
    // twelve CGAL meshes had 12-40 corners, 78-89 on boeing and cheese, 123 on 3torus.)
    constexpr int kMaxHoleLoop = 128;
    std::vector<std::vector<int>> ears =
        facingTriangulation(hole, positions, input, inputTree, joined, 0.0, kMaxHoleLoop);
    if (ears.empty()) return fan;
    positions.pop_back(); // no centre
    byEars = true;
    return ears;
}

int untangleFlipped(const std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                    const field::Mesh &input, const AabbTree &inputTree, double L,
                    const std::function<bool(size_t)> &fixed) {
    constexpr int kUntangleRounds = 3;
    constexpr double kUntangleMinArea = 0.01;
    std::vector<std::vector<int>> facesOf(positions.size()), neighbours(positions.size());
    for (int f = 0; f < int(polygons.size()); ++f) {
        const std::vector<int> &P = polygons[size_t(f)];
        for (size_t k = 0; k < P.size(); ++k) {
            facesOf[size_t(P[k])].push_back(f);
            neighbours[size_t(P[k])].push_back(P[(k + 1) % P.size()]);
            neighbours[size_t(P[k])].push_back(P[(k + P.size() - 1) % P.size()]);
        }
    }
    for (auto &n : neighbours) {
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
    }
    // facing the input with some area
    auto sound = [&](int f) {
        const std::vector<int> &P = polygons[size_t(f)];
        Vec3 c = Vec3::Zero();
        for (int v : P) c += positions[size_t(v)];
        const ClosestPoint cp = inputTree.closest(c / double(P.size()));
        return cp.triangle >= 0 &&
               vectorArea(P, positions).dot(input.faceNormal(cp.triangle)) >= kUntangleMinArea * L * L;
    };
    int moved = 0;
    for (int round = 0; round < kUntangleRounds; ++round) {
        int movedNow = 0;
        for (int f = 0; f < int(polygons.size()); ++f) {
            if (facesInput(polygons[size_t(f)], positions, input, inputTree)) continue;
            for (int v : polygons[size_t(f)]) {
                if (fixed(size_t(v)) || neighbours[size_t(v)].empty()) continue;
                Vec3 mean = Vec3::Zero();
                for (int u : neighbours[size_t(v)]) mean += positions[size_t(u)];
                mean /= double(neighbours[size_t(v)].size());
                const Vec3 old = positions[size_t(v)];
                bool done = false;
                for (double t : {1.0, 0.75, 0.5, 0.25}) {
                    positions[size_t(v)] = inputTree.closest(old + t * (mean - old)).point;
                    done = std::all_of(facesOf[size_t(v)].begin(), facesOf[size_t(v)].end(), sound);
                    if (done) break;
                }
                if (done) {
                    ++movedNow;
                    break;
                }
                positions[size_t(v)] = old;
            }
        }
        moved += movedNow;
        if (movedNow == 0) break;
    }
    return moved;
}

int absorbFlippedTriangles(std::vector<std::vector<int>> &polygons, const std::vector<Vec3> &positions,
                           const field::Mesh &input, const AabbTree &inputTree, int maxSides) {
    const auto key = directedEdgeKey;
    std::unordered_map<uint64_t, int> faceOf; // directed edge -> face
    for (int f = 0; f < int(polygons.size()); ++f) {
        const std::vector<int> &P = polygons[size_t(f)];
        for (size_t k = 0; k < P.size(); ++k) faceOf[key(P[k], P[(k + 1) % P.size()])] = f;
    }
    std::vector<char> gone(polygons.size(), 0);
    int absorbed = 0;
    for (int t = 0; t < int(polygons.size()); ++t) {
        const std::vector<int> T = polygons[size_t(t)];
        if (gone[size_t(t)] || T.size() != 3 || facesInput(T, positions, input, inputTree)) continue;
        std::array<int, 3> order = {0, 1, 2}; // side k runs T[k] -> T[k+1], opposite T[k+2]
        auto length = [&](int k) { return (positions[size_t(T[size_t(k)])] - positions[size_t(T[size_t((k + 1) % 3)])]).norm(); };
        std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return length(x) > length(y); });
        for (int k : order) {
            const int a = T[size_t(k)], b = T[size_t((k + 1) % 3)], m = T[size_t((k + 2) % 3)];
            const auto it = faceOf.find(key(b, a));
            if (it == faceOf.end() || it->second == t || gone[size_t(it->second)]) continue;
            const int g = it->second;
            std::vector<int> G = polygons[size_t(g)];
            if (int(G.size()) >= maxSides || std::find(G.begin(), G.end(), m) != G.end()) continue;
            // G runs b -> a; m goes between them.
            const size_t ib = size_t(std::find(G.begin(), G.end(), b) - G.begin());
            G.insert(G.begin() + long(ib) + 1, m);
            if (!facesInput(G, positions, input, inputTree)) continue;
            faceOf.erase(key(b, a));
            for (size_t j = 0; j < 3; ++j) faceOf.erase(key(T[j], T[(j + 1) % 3]));
            faceOf[key(b, m)] = g;
            faceOf[key(m, a)] = g;
            polygons[size_t(g)] = std::move(G);
            gone[size_t(t)] = 1;
            ++absorbed;
            break;
        }
    }
    removeMarked(polygons, gone);
    return absorbed;
}

int collapseFoldedDiagonals(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                            const field::Mesh &input, const AabbTree &inputTree, double maxDiagonal,
                            const std::function<bool(size_t)> &fixed) {
    std::vector<std::vector<int>> facesOf(positions.size());
    for (int f = 0; f < int(polygons.size()); ++f)
        for (int v : polygons[size_t(f)]) facesOf[size_t(v)].push_back(f);
    auto neighbours = [&](int v) {
        std::vector<int> n;
        for (int f : facesOf[size_t(v)]) {
            const std::vector<int> &P = polygons[size_t(f)];
            const size_t k = size_t(std::find(P.begin(), P.end(), v) - P.begin());
            n.push_back(P[(k + 1) % P.size()]);
            n.push_back(P[(k + P.size() - 1) % P.size()]);
        }
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
        return n;
    };
    std::vector<char> gone(polygons.size(), 0);
    int collapsed = 0;
    for (int f = 0; f < int(polygons.size()); ++f) {
        const std::vector<int> P = polygons[size_t(f)];
        const int n = int(P.size());
        if (gone[size_t(f)] || n < 4 || facesInput(P, positions, input, inputTree)) continue;
        // Corner pairs that are not neighbours, nearest first.
        std::vector<std::pair<double, std::pair<int, int>>> pairs;
        for (int i = 0; i < n; ++i)
            for (int j = i + 2; j < n; ++j) {
                if (i == 0 && j == n - 1) continue;
                const double d = (positions[size_t(P[size_t(i)])] - positions[size_t(P[size_t(j)])]).norm();
                if (d < maxDiagonal) pairs.push_back({d, {i, j}});
            }
        std::stable_sort(pairs.begin(), pairs.end(), [](const auto &x, const auto &y) { return x.first < y.first; });
        for (const auto &[d, ij] : pairs) {
            const auto [i, j] = ij;
            const int a = P[size_t(i)], c = P[size_t(j)];
            if (fixed(size_t(a)) && fixed(size_t(c))) continue;
            const int keep = fixed(size_t(c)) ? c : a, drop = keep == a ? c : a;
            // The two sides of P between its corners i and j, each from keep.
            std::vector<int> side1 = {keep}, side2 = {keep};
            for (int k = i + 1; k < j; ++k) side1.push_back(P[size_t(k)]);
            for (int k = j + 1; k < i + n; ++k) side2.push_back(P[size_t(k % n)]);
            std::vector<int> middles;
            for (const std::vector<int> *side : {&side1, &side2})
                if (side->size() == 2) middles.push_back((*side)[1]);
            // Manifold: a and c share no face but P and no neighbour but the middles.
            bool ok = true;
            for (int g : facesOf[size_t(a)])
                if (g != f && !gone[size_t(g)]) {
                    const std::vector<int> &G = polygons[size_t(g)];
                    if (std::find(G.begin(), G.end(), c) != G.end()) ok = false;
                }
            const std::vector<int> na = neighbours(a), nc = neighbours(c);
            std::vector<int> common;
            std::set_intersection(na.begin(), na.end(), nc.begin(), nc.end(), std::back_inserter(common));
            for (int m : common)
                if (std::find(middles.begin(), middles.end(), m) == middles.end()) ok = false;
            if (!ok) continue;
            // The faces at a or c other than P (turned away from the input before:
            // P and these; after: the same faces and P's parts). Kept only if fewer.
            std::vector<int> around;
            for (int v : {a, c})
                for (int g : facesOf[size_t(v)])
                    if (g != f && !gone[size_t(g)]) around.push_back(g);
            std::sort(around.begin(), around.end());
            around.erase(std::unique(around.begin(), around.end()), around.end());
            auto turnedAway = [&](const std::vector<int> &G) { return !facesInput(G, positions, input, inputTree); };
            int awayBefore = 1;
            for (int g : around) awayBefore += turnedAway(polygons[size_t(g)]);
            // Apply, keeping what is needed to undo.
            const Vec3 oldKeep = positions[size_t(keep)];
            std::vector<std::pair<int, std::vector<int>>> before = {{f, P}};
            for (int g : facesOf[size_t(drop)])
                if (g != f) before.push_back({g, polygons[size_t(g)]});
            if (!fixed(size_t(keep)))
                positions[size_t(keep)] =
                    inputTree.closest(0.5 * (positions[size_t(a)] + positions[size_t(c)])).point;
            for (size_t b = 1; b < before.size(); ++b)
                for (int &v : polygons[size_t(before[b].first)])
                    if (v == drop) v = keep;
            std::vector<std::vector<int>> parts;
            for (std::vector<int> *side : {&side1, &side2})
                if (side->size() >= 3) parts.push_back(*side);
            int awayAfter = 0;
            for (int g : around) awayAfter += turnedAway(polygons[size_t(g)]);
            for (const std::vector<int> &part : parts) awayAfter += turnedAway(part);
            if (awayAfter >= awayBefore) {
                positions[size_t(keep)] = oldKeep;
                for (auto &[g, G] : before) polygons[size_t(g)] = G;
                continue;
            }
            // P becomes its first part (or goes); a second part is appended.
            for (int v : P) {
                auto &fv = facesOf[size_t(v)];
                fv.erase(std::remove(fv.begin(), fv.end(), f), fv.end());
            }
            for (int g : facesOf[size_t(drop)]) facesOf[size_t(keep)].push_back(g);
            facesOf[size_t(drop)].clear();
            if (parts.empty()) gone[size_t(f)] = 1;
            for (size_t k = 0; k < parts.size(); ++k) {
                const int g = k == 0 ? f : int(polygons.size());
                if (k == 0) {
                    polygons[size_t(f)] = parts[0];
                } else {
                    polygons.push_back(parts[k]);
                    gone.push_back(0);
                }
                for (int v : parts[k]) facesOf[size_t(v)].push_back(g);
            }
            ++collapsed;
            break;
        }
    }
    removeMarked(polygons, gone);
    return collapsed;
}

namespace {

/// The boundary of a set of faces as one loop (its corners in order, the faces on
/// its left), or empty if the boundary is not one loop through no vertex twice.
std::vector<int> boundaryLoop(const std::vector<int> &patch, const std::vector<std::vector<int>> &polygons) {
    std::map<std::pair<int, int>, int> directed;
    for (int f : patch) {
        const std::vector<int> &P = polygons[size_t(f)];
        for (size_t k = 0; k < P.size(); ++k) ++directed[{P[k], P[(k + 1) % P.size()]}];
    }
    std::map<int, int> next;
    for (const auto &[e, n] : directed) {
        if (n != 1) return {};
        if (directed.count({e.second, e.first})) continue;
        if (!next.emplace(e.first, e.second).second) return {}; // through a vertex twice
    }
    if (next.empty()) return {};
    std::vector<int> loop = {next.begin()->first};
    for (int v = next.at(loop[0]); v != loop[0]; v = next.at(v)) {
        if (loop.size() > next.size() || !next.count(v)) return {};
        loop.push_back(v);
    }
    return loop.size() == next.size() ? loop : std::vector<int>{};
}

/// Whether each triangle faces the input with twice its area along the input's normal
/// at least `minArea`; and their smallest angle (radians) in `angle`.
bool soundTriangles(const std::vector<std::vector<int>> &tris, const std::vector<Vec3> &positions,
                    const field::Mesh &input, const AabbTree &inputTree, double minArea, double &angle) {
    angle = std::numeric_limits<double>::infinity();
    for (const std::vector<int> &t : tris) {
        const Vec3 c = (positions[size_t(t[0])] + positions[size_t(t[1])] + positions[size_t(t[2])]) / 3.0;
        const ClosestPoint cp = inputTree.closest(c);
        if (cp.triangle < 0 || vectorArea(t, positions).dot(input.faceNormal(cp.triangle)) < minArea) return false;
        angle = std::min(angle, smallestAngle(positions[size_t(t[0])], positions[size_t(t[1])], positions[size_t(t[2])]));
    }
    return true;
}

} // namespace

int refillFlippedPatches(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                         const field::Mesh &input, const AabbTree &inputTree, double L,
                         const std::function<bool(size_t)> &fixed) {
    constexpr int kRefillRounds = 2;
    constexpr double kDegenerateArea = 1e-5, kRefillMinArea = 1e-4; // twice the area, in L²
    constexpr double kRefillReach = 0.5;                              // the distance, L/2 at L = 1 %
    // Patches are tried up to eight ways per bad face: their cut is searched only on
    // loops this short, so that a mesh the lattice fails on everywhere is not held up
    // here (3torus at 1 %, 710 flipped faces: 3.2 s without this step, 20 s with no
    // bound on the loops).
    constexpr int kMaxPatchLoop = 32;
    const double minArea = kRefillMinArea * L * L;
    int refilled = 0;
    for (int round = 0; round < kRefillRounds; ++round) {
        std::unordered_map<uint64_t, int> faceOf; // directed edge -> face
        std::vector<std::vector<int>> facesOf(positions.size());
        auto add = [&](int f) {
            const std::vector<int> &P = polygons[size_t(f)];
            for (size_t k = 0; k < P.size(); ++k) {
                faceOf[directedEdgeKey(P[k], P[(k + 1) % P.size()])] = f;
                facesOf[size_t(P[k])].push_back(f);
            }
        };
        for (int f = 0; f < int(polygons.size()); ++f) add(f);
        std::vector<char> gone(polygons.size(), 0);
        auto bad = [&](int f) {
            const std::vector<int> &P = polygons[size_t(f)];
            return !facesInput(P, positions, input, inputTree) || vectorArea(P, positions).norm() < kDegenerateArea * L * L;
        };
        // The faces at the corners of `patch`'s faces, `patch` included, sorted.
        auto grow = [&](const std::vector<int> &patch) {
            std::vector<int> out = patch;
            for (int g : patch)
                for (int v : polygons[size_t(g)])
                    for (int h : facesOf[size_t(v)])
                        if (!gone[size_t(h)]) out.push_back(h);
            std::sort(out.begin(), out.end());
            out.erase(std::unique(out.begin(), out.end()), out.end());
            return out;
        };
        int refilledNow = 0;
        const int nFaces = int(polygons.size());
        for (int f = 0; f < nFaces; ++f) {
            if (gone[size_t(f)] || !bad(f)) continue;
            const std::vector<int> &P = polygons[size_t(f)];
            // Patches, smallest first: the face and those across its sides; those at
            // its corners; those at their corners.
            std::vector<int> acrossSides = {f};
            for (size_t k = 0; k < P.size(); ++k) {
                const auto it = faceOf.find(directedEdgeKey(P[(k + 1) % P.size()], P[k]));
                if (it != faceOf.end() && !gone[size_t(it->second)]) acrossSides.push_back(it->second);
            }
            std::sort(acrossSides.begin(), acrossSides.end());
            acrossSides.erase(std::unique(acrossSides.begin(), acrossSides.end()), acrossSides.end());
            const std::vector<int> atCorners = grow({f}), beyond = grow(atCorners);
            // Last, the faces across the sides of the first patch's faces: a patch
            // that grows along a tangle but not round a feature corner beside it.
            std::vector<int> acrossTwice = acrossSides;
            for (int g : acrossSides) {
                const std::vector<int> &G = polygons[size_t(g)];
                for (size_t k = 0; k < G.size(); ++k) {
                    const auto it = faceOf.find(directedEdgeKey(G[(k + 1) % G.size()], G[k]));
                    if (it != faceOf.end() && !gone[size_t(it->second)]) acrossTwice.push_back(it->second);
                }
            }
            std::sort(acrossTwice.begin(), acrossTwice.end());
            acrossTwice.erase(std::unique(acrossTwice.begin(), acrossTwice.end()), acrossTwice.end());
            const std::array<const std::vector<int> *, 4> patches = {&acrossSides, &atCorners, &beyond, &acrossTwice};
            // Fixed vertices inside a patch are kept (a fan from one) unless no patch
            // can be refilled so: then they may go (a tangle on a crease).
            bool done = false;
            // A second-half pass differs from its first-half one only where that patch
            // had a fixed vertex inside; elsewhere it would fail again the same way.
            std::array<bool, 4> hadFixed{};
            for (int pass = 0; pass < 8 && !done; ++pass) {
                const bool keepFixed = pass < 4;
                if (!keepFixed && !hadFixed[size_t(pass % 4)]) continue;
                const std::vector<int> *patch = patches[size_t(pass % 4)];
                const std::vector<int> loop = boundaryLoop(*patch, polygons);
                if (loop.size() < 3) continue;
                // A disk (V - E + F = 1), with at most one fixed vertex inside.
                std::set<int> vertices;
                std::set<std::pair<int, int>> edges;
                for (int g : *patch) {
                    const std::vector<int> &G = polygons[size_t(g)];
                    for (size_t k = 0; k < G.size(); ++k) {
                        vertices.insert(G[k]);
                        const int a = G[k], b = G[(k + 1) % G.size()];
                        edges.insert({std::min(a, b), std::max(a, b)});
                    }
                }
                if (int(vertices.size()) - int(edges.size()) + int(patch->size()) != 1) continue;
                const std::set<int> onLoop(loop.begin(), loop.end());
                std::vector<int> inside, fixedInside;
                for (int v : vertices)
                    if (!onLoop.count(v)) {
                        inside.push_back(v);
                        if (fixed(size_t(v))) fixedInside.push_back(v);
                    }
                if (keepFixed) hadFixed[size_t(pass)] = !fixedInside.empty();
                if (!keepFixed) fixedInside.clear();
                else if (fixedInside.size() > 1) continue;
                // A new side may not be an edge outside the patch (the patch's own go).
                const std::function<bool(int, int)> joined = [&](int a, int b) {
                    if (edges.count({std::min(a, b), std::max(a, b)})) return false;
                    return faceOf.count(directedEdgeKey(a, b)) > 0 || faceOf.count(directedEdgeKey(b, a)) > 0;
                };
                auto fanFrom = [&](int centre) {
                    std::vector<std::vector<int>> fan;
                    for (size_t k = 0; k < loop.size(); ++k) fan.push_back({centre, loop[k], loop[(k + 1) % loop.size()]});
                    return fan;
                };
                // Candidates: (without a fixed vertex inside) the triangulation of the
                // loop and the fan from a new centre; the fan from each vertex inside
                // (the fixed one only, if there is one). The sound one with the largest
                // smallest angle wins.
                std::vector<std::vector<int>> best;
                double bestAngle = -1, angle = 0;
                // The vertices that go lie on the input: each must stay within
                // kRefillReach L of the new triangles (else a corner of the input, a
                // tip, would be cut off).
                auto keepsInside = [&](const std::vector<std::vector<int>> &tris) {
                    for (int v : inside) {
                        bool stays = false, near = false;
                        for (const std::vector<int> &t : tris) {
                            stays = stays || std::find(t.begin(), t.end(), v) != t.end();
                            const Vec3 &x = positions[size_t(v)];
                            near = near || (x - closestPointOnTriangle(x, positions[size_t(t[0])], positions[size_t(t[1])],
                                                                       positions[size_t(t[2])]))
                                                   .norm() <= kRefillReach * L;
                        }
                        if (!stays && !near) return false;
                    }
                    return true;
                };
                auto consider = [&](const std::vector<std::vector<int>> &tris) {
                    if (!tris.empty() && soundTriangles(tris, positions, input, inputTree, minArea, angle) &&
                        angle > bestAngle && keepsInside(tris))
                        best = tris, bestAngle = angle;
                };
                if (fixedInside.empty())
                    consider(facingTriangulation(loop, positions, input, inputTree, joined, minArea, kMaxPatchLoop));
                for (int v : fixedInside.empty() ? inside : fixedInside) consider(fanFrom(v));
                bool newCentre = false;
                if (fixedInside.empty()) {
                    Vec3 c = Vec3::Zero();
                    for (int v : loop) c += positions[size_t(v)];
                    positions.push_back(inputTree.closest(c / double(loop.size())).point);
                    const double before = bestAngle;
                    consider(fanFrom(int(positions.size()) - 1));
                    newCentre = bestAngle > before;
                    if (!newCentre) positions.pop_back();
                }
                if (best.empty()) continue;
                for (int g : *patch) {
                    const std::vector<int> &G = polygons[size_t(g)];
                    for (size_t k = 0; k < G.size(); ++k) faceOf.erase(directedEdgeKey(G[k], G[(k + 1) % G.size()]));
                    gone[size_t(g)] = 1;
                }
                for (int v : vertices) { // the faces gone no longer listed
                    std::vector<int> &list = facesOf[size_t(v)];
                    list.erase(std::remove_if(list.begin(), list.end(), [&](int g) { return gone[size_t(g)] != 0; }),
                               list.end());
                }
                facesOf.resize(positions.size());
                for (std::vector<int> &t : best) {
                    polygons.push_back(std::move(t));
                    gone.push_back(0);
                    add(int(polygons.size()) - 1);
                }
                ++refilledNow;
                done = true;
            }
        }
        removeMarked(polygons, gone);
        refilled += refilledNow;
        if (refilledNow == 0) break;
    }
    return refilled;
}

std::vector<EdgeCrossing> findCrossingEdges(const std::vector<std::set<int>> &graph, const std::vector<Vec3> &cp,
                                           const std::vector<Vec3> &cn) {
    std::vector<EdgeCrossing> found;
    const int nC = int(graph.size());
    // Projected to the plane normal to n, the orientation of (p, q, r) is the sign of
    // ((q − p) × (r − p)) · n: the sides are tested first, the patch only for a crossing.
    auto crosses = [&](int a, int b, int c, int d) {
        const Vec3 n = cn[size_t(a)] + cn[size_t(b)];
        auto orient = [&](int p, int q, int r) {
            return (cp[size_t(q)] - cp[size_t(p)]).cross(cp[size_t(r)] - cp[size_t(p)]).dot(n);
        };
        auto apart = [](double s, double t) { return (s > 0 && t < 0) || (s < 0 && t > 0); };
        if (!apart(orient(a, b, c), orient(a, b, d)) || !apart(orient(c, d, a), orient(c, d, b))) return false;
        const Vec3 unit = n.normalized();
        const Vec3 o = 0.5 * (cp[size_t(a)] + cp[size_t(b)]);
        const double nearPlane = 0.25 * (cp[size_t(a)] - cp[size_t(b)]).norm();
        for (int v : {a, b, c, d})
            if (cn[size_t(v)].dot(unit) < 0.9 || std::abs((cp[size_t(v)] - o).dot(unit)) > nearPlane) return false;
        return true;
    };
    // In fixed chunks of vertices on both cores, each chunk's crossings in its own
    // list, joined in chunk order: the same list, in the same order, for any thread count.
    constexpr int kChunk = 2048;
    const int nChunks = (nC + kChunk - 1) / kChunk;
    std::vector<std::vector<EdgeCrossing>> perChunk(static_cast<size_t>(nChunks));
    parallelFor(0, nChunks, [&](int64_t chunk) {
        std::vector<std::pair<int, int>> tested;
        std::vector<EdgeCrossing> &out = perChunk[size_t(chunk)];
        for (int a = int(chunk) * kChunk, end = std::min(nC, (int(chunk) + 1) * kChunk); a < end; ++a)
            for (int b : graph[size_t(a)]) {
                if (b <= a) continue;
                tested.clear();
                for (int s : {a, b})
                    for (int c : graph[size_t(s)])
                        for (int d : graph[size_t(c)]) {
                            if (c == a || c == b || d == a || d == b) continue;
                            const std::pair<int, int> cd{std::min(c, d), std::max(c, d)};
                            if (std::find(tested.begin(), tested.end(), cd) != tested.end()) continue;
                            tested.push_back(cd);
                            if (crosses(a, b, c, d)) out.push_back({a, b, cd.first, cd.second});
                        }
            }
    }, 1);
    for (const std::vector<EdgeCrossing> &part : perChunk) found.insert(found.end(), part.begin(), part.end());
    return found;
}

int removeCrossingEdges(std::vector<std::set<int>> &graph, const std::vector<EdgeCrossing> &crossings,
                        const std::vector<Vec3> &cp, const std::vector<char> &featureVertex, double L,
                        const std::vector<char> *only) {
    auto feature = [&](int x, int y) {
        return !featureVertex.empty() && (featureVertex[size_t(x)] || featureVertex[size_t(y)]);
    };
    auto marked = [&](int x) { return !only || (*only)[size_t(x)]; };
    std::set<std::pair<int, int>> drop; // decided on the graph as it is, then removed
    for (const auto &[a, b, c, d] : crossings) {
        if (!marked(a) && !marked(b) && !marked(c) && !marked(d)) continue;
        const bool fab = feature(a, b), fcd = feature(c, d);
        if (fab && fcd) continue;
        const double lab = std::abs((cp[size_t(a)] - cp[size_t(b)]).norm() - L);
        const double lcd = std::abs((cp[size_t(c)] - cp[size_t(d)]).norm() - L);
        if (fcd || (!fab && (lab > lcd || (lab == lcd && std::make_pair(a, b) > std::make_pair(c, d)))))
            drop.insert({a, b});
        else
            drop.insert({c, d});
    }
    for (const auto &[a, b] : drop) {
        graph[size_t(a)].erase(b);
        graph[size_t(b)].erase(a);
    }
    return int(drop.size());
}

int removeStrayPieces(std::vector<std::vector<int>> &polygons, const std::vector<Vec3> &positions,
                      const field::Mesh &input, const AabbTree &inputTree, double L) {
    if (polygons.empty()) return 0;
    field::UnionFind pieces(int(positions.size()));
    for (const std::vector<int> &poly : polygons)
        for (size_t i = 1; i < poly.size(); ++i) pieces.unite(poly[0], poly[i]);
    // Pieces numbered by their first face; area and vertices of each.
    std::vector<int> pieceOfRoot(positions.size(), -1), pieceOfFace(polygons.size());
    std::vector<double> area;
    std::vector<std::vector<int>> vertices;
    std::vector<char> seen(positions.size(), 0);
    for (size_t f = 0; f < polygons.size(); ++f) {
        const int root = pieces.find(polygons[f][0]);
        int &piece = pieceOfRoot[size_t(root)];
        if (piece < 0) {
            piece = int(area.size());
            area.push_back(0.0);
            vertices.emplace_back();
        }
        pieceOfFace[f] = piece;
        area[size_t(piece)] += 0.5 * vectorArea(polygons[f], positions).norm();
        for (int v : polygons[f])
            if (!seen[size_t(v)]) {
                seen[size_t(v)] = 1;
                vertices[size_t(piece)].push_back(v);
            }
    }
    const int nPieces = int(area.size());
    if (nPieces < 2) return 0;
    int nInput = 0;
    const std::vector<int> inputComponent = field::faceComponents(input, &nInput);
    // The input component under most of a piece's vertices (ties: the smaller id).
    std::vector<int> componentOf(size_t(nPieces), -1);
    for (int c = 0; c < nPieces; ++c) {
        std::map<int, int> votes;
        for (int v : vertices[size_t(c)]) {
            const int t = inputTree.closest(positions[size_t(v)]).triangle;
            if (t >= 0) ++votes[inputComponent[size_t(t)]];
        }
        int best = -1;
        for (const auto &[component, n] : votes)
            if (best < 0 || n > votes[best]) best = component;
        componentOf[size_t(c)] = best;
    }
    std::vector<int> largest(size_t(nInput), -1);
    for (int c = 0; c < nPieces; ++c) {
        const int k = componentOf[size_t(c)];
        if (k >= 0 && (largest[size_t(k)] < 0 || area[size_t(c)] > area[size_t(largest[size_t(k)])]))
            largest[size_t(k)] = c;
    }
    std::vector<char> stray(size_t(nPieces), 0);
    int candidates = 0;
    for (int c = 0; c < nPieces; ++c) {
        const int k = componentOf[size_t(c)];
        if (k < 0 || largest[size_t(k)] == c || area[size_t(c)] >= kStrayPieceArea * L * L) continue;
        stray[size_t(c)] = 1;
        ++candidates;
    }
    if (candidates == 0) return 0;
    // A candidate goes only if the pieces that stay pass within L of every corner
    // of it, or, closed, enclose it (every corner inside the solid they bound: winding
    // number at least 1/2 in size): then it adds no surface the output lacks (a tunnel's
    // wall inside a closed tunnel), whereas a small part of its own somewhere else
    // stays.
    std::vector<std::array<int, 3>> kept;
    for (size_t f = 0; f < polygons.size(); ++f)
        if (!stray[size_t(pieceOfFace[f])])
            for (size_t i = 1; i + 1 < polygons[f].size(); ++i)
                kept.push_back({polygons[f][0], polygons[f][i], polygons[f][i + 1]});
    const AabbTree rest(positions, kept);
    // A solid only when what stays is closed: every edge of its fan triangles used an
    // even number of times.
    std::map<std::pair<int, int>, int> edgeUses;
    for (const std::array<int, 3> &t : kept)
        for (int i = 0; i < 3; ++i) ++edgeUses[std::minmax(t[size_t(i)], t[size_t((i + 1) % 3)])];
    const bool closed = std::all_of(edgeUses.begin(), edgeUses.end(), [](const auto &e) { return e.second % 2 == 0; });
    int removed = 0;
    for (int c = 0; c < nPieces; ++c) {
        if (!stray[size_t(c)]) continue;
        const std::vector<int> &corners = vertices[size_t(c)];
        const bool near = std::all_of(corners.begin(), corners.end(), [&](int v) {
            return rest.closest(positions[size_t(v)]).distance2 <= L * L;
        });
        stray[size_t(c)] = near || (closed && std::all_of(corners.begin(), corners.end(), [&](int v) {
            return std::abs(field::windingNumber(positions, kept, positions[size_t(v)])) >= 0.5;
        }));
        removed += stray[size_t(c)];
    }
    if (removed == 0) return 0;
    std::vector<char> gone(polygons.size(), 0);
    for (size_t f = 0; f < polygons.size(); ++f) gone[f] = stray[size_t(pieceOfFace[f])];
    removeMarked(polygons, gone);
    return removed;
}

int respokeVertices(std::vector<std::vector<int>> &polygons, std::vector<Vec3> &positions,
                    const AabbTree &inputTree, double L, const std::function<bool(size_t)> &fixed) {
    constexpr int kMaxLoop = 16;
    constexpr double kMaxShift = 0.1; // L: how far from the new faces the old surface may lie
    const int nV = int(positions.size());
    std::unordered_map<uint64_t, int> faceOfEdge; // directed edge -> face
    std::vector<std::vector<int>> facesAt(static_cast<size_t>(nV));
    std::vector<std::set<int>> nb(static_cast<size_t>(nV));
    std::vector<char> alive(polygons.size(), 1);
    auto link = [&](int f, bool add) {
        const std::vector<int> &P = polygons[size_t(f)];
        for (size_t k = 0; k < P.size(); ++k) {
            const int a = P[k], b = P[(k + 1) % P.size()];
            if (add) {
                faceOfEdge[directedEdgeKey(a, b)] = f;
                nb[size_t(a)].insert(b);
                nb[size_t(b)].insert(a);
                facesAt[size_t(a)].push_back(f);
            } else {
                faceOfEdge.erase(directedEdgeKey(a, b));
                if (!faceOfEdge.count(directedEdgeKey(b, a))) nb[size_t(a)].erase(b), nb[size_t(b)].erase(a);
                auto &list = facesAt[size_t(a)];
                list.erase(std::find(list.begin(), list.end(), f));
            }
        }
    };
    for (int f = 0; f < int(polygons.size()); ++f) link(f, true);
    // Boundary vertices (an edge with one face): their valence is not judged, and the
    // re-cut never touches their edges (a star's centre is interior).
    std::vector<char> onBoundary(static_cast<size_t>(nV), 0);
    for (const auto &[key, f] : faceOfEdge) {
        const int a = int(key >> 32), b = int(key & 0xffffffffu);
        if (!faceOfEdge.count(directedEdgeKey(b, a))) onBoundary[size_t(a)] = onBoundary[size_t(b)] = 1;
    }
    const auto cost = valenceCost;
    auto faceCost = [](size_t sides) { return sides == 4 ? 0.0 : 1.0; };
    // Corners as a candidate cut has them: the star's centre at its new place.
    int centre = -1;
    Vec3 centrePoint = Vec3::Zero();
    auto at = [&](int v) -> const Vec3 & { return v == centre ? centrePoint : positions[size_t(v)]; };
    auto worstCorner = [&](const std::vector<int> &P, const Vec3 &normal) { return worstCornerDeviation(P, at, normal); };
    int respoked = 0;
    for (int pass = 0; pass < 3; ++pass) {
        int now = 0;
        for (int c = 0; c < nV; ++c) {
            if (onBoundary[size_t(c)] || facesAt[size_t(c)].empty() || (fixed && fixed(size_t(c)))) continue;
            const std::vector<int> star = facesAt[size_t(c)];
            // The irregular elements of the star: the centre, its faces that are not
            // quads, their interior corners of valence ≠ 4. One carries an index the cut
            // keeps inside its loop, so a gain needs at least two.
            int elements = nb[size_t(c)].size() != 4;
            {
                std::set<int> corners;
                for (int f : star) {
                    elements += polygons[size_t(f)].size() != 4;
                    for (int x : polygons[size_t(f)])
                        if (x != c && !onBoundary[size_t(x)] && nb[size_t(x)].size() != 4) corners.insert(x);
                }
                elements += int(corners.size());
            }
            if (elements < 2) continue;
            // The star's boundary loop: each face (c, a1, .., am) gives the path a1 .. am;
            // the face across (am, c) starts its path at am.
            std::unordered_map<int, int> pathFrom; // a1 -> face
            bool simple = true;
            for (int f : star) {
                const std::vector<int> &P = polygons[size_t(f)];
                if (std::count(P.begin(), P.end(), c) != 1) simple = false;
                const size_t k = size_t(std::find(P.begin(), P.end(), c) - P.begin());
                if (!pathFrom.emplace(P[(k + 1) % P.size()], f).second) simple = false;
            }
            if (!simple) continue;
            std::vector<int> loop;
            size_t used = 0;
            int cursor = -1;
            for (const auto &[a1, f] : pathFrom)
                if (f == star.front()) cursor = a1;
            const int first = cursor;
            while (used <= star.size()) {
                const auto it = pathFrom.find(cursor);
                if (it == pathFrom.end()) break;
                const std::vector<int> &P = polygons[size_t(it->second)];
                const size_t k = size_t(std::find(P.begin(), P.end(), c) - P.begin());
                for (size_t i = 1; i + 1 < P.size(); ++i) loop.push_back(P[(k + i) % P.size()]);
                cursor = P[(k + P.size() - 1) % P.size()];
                ++used;
                if (cursor == first) break;
            }
            if (cursor != first || used != star.size() || int(loop.size()) > kMaxLoop || loop.size() < 6) continue;
            {
                std::vector<int> sorted = loop;
                std::sort(sorted.begin(), sorted.end());
                if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end() ||
                    std::binary_search(sorted.begin(), sorted.end(), c))
                    continue;
            }
            const int n = int(loop.size());
            Vec3 normal = vectorArea(loop, positions);
            if (!(normal.norm() > 0)) continue;
            normal.normalize();
            // The vertex moves to the input point nearest its loop's centroid (the
            // smoothing after evens the rest).
            Vec3 mean = Vec3::Zero();
            for (int x : loop) mean += positions[size_t(x)];
            centre = c;
            centrePoint = inputTree.closest(mean / double(n)).point;
            double before = cost(int(nb[size_t(c)].size()));
            for (int x : loop)
                if (!onBoundary[size_t(x)]) before += cost(int(nb[size_t(x)].size()));
            for (int f : star) before += faceCost(polygons[size_t(f)].size());

            // Per loop position: whether its corner is a spoke now, its valence, and
            // whether it is judged (not on the boundary).
            std::array<int, kMaxLoop> valence{}, wasSpoke{}, judged{};
            for (int i = 0; i < n; ++i) {
                const int x = loop[size_t(i)];
                valence[size_t(i)] = int(nb[size_t(x)].size());
                wasSpoke[size_t(i)] = int(nb[size_t(c)].count(x));
                judged[size_t(i)] = !onBoundary[size_t(x)];
            }
            double bestGain = 0.5, bestWorst = 0, oldFarthest = -1; // the last when first needed
            std::vector<std::vector<int>> bestFaces;
            std::array<int, 8> gaps{};
            int nGaps = 0;
            // The faces of the cut given by the gaps from spoke s0 and, for the k-th
            // hexagon piece, bit k of `choice` (0: diagonal L(0)–L(3), 1: L(1)–L(4)).
            auto facesOf = [&](int s0, unsigned choice) {
                std::vector<std::vector<int>> faces;
                int s = s0;
                unsigned h = 0;
                for (int g = 0; g < nGaps; ++g) {
                    auto L = [&](int i) { return loop[size_t((s + i) % n)]; };
                    if (gaps[size_t(g)] == 1) faces.push_back({c, L(0), L(1)});
                    else if (gaps[size_t(g)] == 2) faces.push_back({c, L(0), L(1), L(2)});
                    else if (!((choice >> h++) & 1)) faces.push_back({L(0), L(1), L(2), L(3)}), faces.push_back({c, L(0), L(3), L(4)});
                    else faces.push_back({L(1), L(2), L(3), L(4)}), faces.push_back({c, L(0), L(1), L(4)});
                    s += gaps[size_t(g)];
                }
                return faces;
            };
            auto judge = [&](int s0) {
                if (nGaps < 3 || nGaps > 6) return;
                int hexagons = 0, triangles = 0;
                for (int g = 0; g < nGaps; ++g) hexagons += gaps[size_t(g)] == 4, triangles += gaps[size_t(g)] == 1;
                for (unsigned choice = 0; choice < (1u << hexagons); ++choice) {
                    std::array<int, kMaxLoop> added{};
                    bool ok = true;
                    int s = s0;
                    unsigned h = 0;
                    for (int g = 0; g < nGaps && ok; ++g) {
                        ++added[size_t(s % n)];
                        if (gaps[size_t(g)] == 4) {
                            const int i = (choice >> h++) & 1 ? s + 1 : s;
                            if (nb[size_t(loop[size_t(i % n)])].count(loop[size_t((i + 3) % n)])) ok = false; // already an edge
                            ++added[size_t(i % n)], ++added[size_t((i + 3) % n)];
                        }
                        s += gaps[size_t(g)];
                    }
                    if (!ok) continue;
                    double after = cost(nGaps) + triangles;
                    for (int i = 0; i < n && ok; ++i) {
                        if (!judged[size_t(i)]) continue;
                        const int v = valence[size_t(i)] - wasSpoke[size_t(i)] + added[size_t(i)];
                        if (v < 3) ok = false;
                        after += cost(v);
                    }
                    if (!ok) continue;
                    const double gain = before - after;
                    if (gain <= 0.5 || gain < bestGain - 1e-9) continue;
                    std::vector<std::vector<int>> faces = facesOf(s0, choice);
                    double worst = 0;
                    for (const auto &F : faces) {
                        const double w = worstCorner(F, normal);
                        if (w < 0) ok = false;
                        worst = std::max(worst, w);
                    }
                    if (!ok) continue;
                    // The surface may not move: no new face farther from the input than
                    // the old ones or kFarDistance L, and every sample of the old faces
                    // (the report's sampling; the centre's old place among them, so a tip
                    // it sat on is not cut off) within kMaxShift L of the new ones.
                    if (oldFarthest < 0)
                        for (int f : star)
                            oldFarthest = std::max(oldFarthest, farthestFromInput(polygons[size_t(f)], positions, inputTree, L));
                    double newFarthest = 0;
                    for (const auto &F : faces) {
                        std::vector<Vec3> corners;
                        for (int v : F) corners.push_back(at(v));
                        std::vector<int> idx(F.size());
                        for (size_t k = 0; k < F.size(); ++k) idx[k] = int(k);
                        newFarthest = std::max(newFarthest, farthestFromInput(idx, corners, inputTree, L));
                    }
                    if (newFarthest > std::max(oldFarthest, kFarDistance * L)) continue;
                    double moved = 0;
                    for (int f : star) {
                        const std::vector<int> &P = polygons[size_t(f)];
                        for (size_t k = 1; k + 1 < P.size(); ++k)
                            forEachSample(positions[size_t(P[0])], positions[size_t(P[k])], positions[size_t(P[k + 1])], L,
                                          [&](const Vec3 &q) {
                                              double d = std::numeric_limits<double>::infinity();
                                              for (const auto &F : faces)
                                                  for (size_t j = 1; j + 1 < F.size(); ++j)
                                                      d = std::min(d, (field::closestPointOnTriangle(q, at(F[0]), at(F[j]), at(F[j + 1])) - q).norm());
                                              moved = std::max(moved, d);
                                          });
                    }
                    if (moved > kMaxShift * L) continue;
                    if (gain > bestGain + 1e-9 || bestFaces.empty() || worst < bestWorst)
                        bestGain = gain, bestWorst = worst, bestFaces = std::move(faces);
                }
            };
            // Spoke sets by their first spoke s0 (the smallest loop index) and the gaps
            // (1, 2 or 4 loop steps) to the next spokes, the last one wrapping to s0.
            auto walk = [&](auto &&self, int s0, int pos, int triangles) -> void {
                if (pos == s0 + n) return judge(s0);
                if (nGaps == 6) return;
                for (int g : {2, 1, 4}) {
                    if (g == 1 && triangles >= 1) continue;
                    const int next = pos + g;
                    if (next > s0 + n || (next < s0 + n && next >= n)) continue;
                    gaps[size_t(nGaps++)] = g;
                    self(self, s0, next, triangles + (g == 1));
                    --nGaps;
                }
            };
            for (int s0 = 0; s0 < std::min(n, 4); ++s0) walk(walk, s0, s0, 0);
            centre = -1;
            if (bestFaces.empty()) continue;
            positions[size_t(c)] = centrePoint;
            for (int f : star) {
                link(f, false);
                alive[size_t(f)] = 0;
            }
            for (auto &F : bestFaces) {
                polygons.push_back(std::move(F));
                alive.push_back(1);
                link(int(polygons.size()) - 1, true);
            }
            ++now;
        }
        respoked += now;
        if (now == 0) break;
    }
    std::vector<char> gone(polygons.size(), 0);
    for (size_t f = 0; f < polygons.size(); ++f) gone[f] = !alive[f];
    removeMarked(polygons, gone);
    return respoked;
}

} // namespace rosy::remesh
