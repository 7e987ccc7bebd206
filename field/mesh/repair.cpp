#include "field/mesh/mesh_io.h"

#include "core/diagnostics.h"
#include "core/error.h"
#include "field/mesh/mesh_scan.h"
#include "field/mesh/morton.h"
#include "field/mesh/uninitialized.h"
#include "field/mesh/union_find.h"
#include "core/parallel.h"

#include <fmt/format.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <numeric>
#include <optional>

// Repair of a polygon soup into a clean Mesh, as a sequence of named steps
// (repairAndBuild() at the end of the file reads as the list of them). Each
// step counts what it changed into a LoadReport; report() turns a nonzero count
// into one warning per kind, or into an InputError when repair is disabled.

namespace rosy::field {
namespace {

using detail::kMaxCoordinate;

uint64_t edgeKey(int a, int b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

/// Incident faces of every undirected edge, in face order.
struct EdgeFaces {
    std::vector<uint64_t> keys;      // sorted unique edge keys
    std::vector<int> offset, faces;  // CSR: faces of keys[i] at offset[i]..offset[i+1]
};

EdgeFaces buildEdgeFaces(const std::vector<Face> &tris) {
    // Bucket the edges by their smaller vertex (a counting sort), then sort each
    // small bucket by (larger vertex, face): the same order as one global sort of
    // (key, face) pairs, without its cost. The buckets are sorted, counted and
    // written out in parallel, each at offsets fixed by the counts before it.
    int nV = 0;
    for (const Face &t : tris) nV = std::max({nV, t[0] + 1, t[1] + 1, t[2] + 1});
    std::vector<int> start(size_t(nV) + 1, 0);
    for (const Face &t : tris)
        for (int k = 0; k < 3; ++k) ++start[size_t(std::min(t[k], t[(k + 1) % 3])) + 1];
    for (int v = 0; v < nV; ++v) start[v + 1] += start[v];
    detail::UninitializedVector<std::pair<int, int>> bucket(3 * tris.size()); // (larger vertex, face)
    {
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (int f = 0; f < int(tris.size()); ++f)
            for (int k = 0; k < 3; ++k) {
                const int a = tris[f][k], b = tris[f][(k + 1) % 3];
                bucket[fill[std::min(a, b)]++] = {std::max(a, b), f};
            }
    }
    // Distinct edges per bucket, then their first index (a prefix sum in vertex order).
    std::vector<int> edgeStart(size_t(nV) + 1, 0);
    parallelFor(0, nV, [&](int64_t v) {
        const auto first = bucket.begin() + start[v], last = bucket.begin() + start[v + 1];
        std::sort(first, last);
        int n = 0;
        for (auto it = first; it != last; ++it)
            if (it == first || it->first != (it - 1)->first) ++n;
        edgeStart[size_t(v) + 1] = n;
    }, 1024);
    for (int v = 0; v < nV; ++v) edgeStart[v + 1] += edgeStart[v];
    EdgeFaces ef;
    ef.keys.resize(size_t(edgeStart[nV]));
    ef.offset.resize(size_t(edgeStart[nV]) + 1);
    ef.faces.resize(bucket.size());
    parallelFor(0, nV, [&](int64_t v) {
        int e = edgeStart[v];
        for (int i = start[v]; i < start[v + 1]; ++i) {
            if (i == start[v] || bucket[i].first != bucket[i - 1].first) {
                ef.keys[size_t(e)] = edgeKey(int(v), bucket[i].first);
                ef.offset[size_t(e)] = i;
                ++e;
            }
            ef.faces[size_t(i)] = bucket[i].second;
        }
    }, 1024);
    ef.offset.back() = int(ef.faces.size());
    return ef;
}

int cornerOf(const Face &t, int v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

/// True if face t runs a -> b (rather than b -> a).
bool runs(const Face &t, int a, int b) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == a && t[(k + 1) % 3] == b) return true;
    return false;
}

/// Splits vertices so that around each vertex the faces form a single fan
/// connected through manifold edges. Edges with more than two faces join only
/// one pair of faces (the first consistently oriented pair, else the first two);
/// the others are cut loose along that edge. Returns the number of vertices
/// whose corners fell into more than one group under the given joining rule.
/// `edgeFaces`, when given, is buildEdgeFaces(tris).
int splitVertices(std::vector<Vec3> &positions, std::vector<Face> &tris, bool cutEdges,
                  int *nNonManifoldEdges, const EdgeFaces *edgeFaces = nullptr) {
    const int nF = int(tris.size());
    std::optional<EdgeFaces> built;
    if (!edgeFaces) built = buildEdgeFaces(tris);
    const EdgeFaces &ef = edgeFaces ? *edgeFaces : *built;
    UnionFind uf(3 * nF);
    int nBad = 0;
    for (size_t e = 0; e < ef.keys.size(); ++e) {
        const int *fs = ef.faces.data() + ef.offset[e];
        const int n = ef.offset[e + 1] - ef.offset[e];
        const int a = int(ef.keys[e] >> 32), b = int(ef.keys[e] & 0xffffffffu);
        auto join = [&](int f, int g) {
            uf.unite(3 * f + cornerOf(tris[f], a), 3 * g + cornerOf(tris[g], a));
            uf.unite(3 * f + cornerOf(tris[f], b), 3 * g + cornerOf(tris[g], b));
        };
        if (n == 2) join(fs[0], fs[1]);
        if (n > 2) {
            ++nBad;
            if (!cutEdges) {
                for (int i = 1; i < n; ++i) join(fs[0], fs[i]);
            } else {
                int partner = 1;
                const bool dir0 = runs(tris[fs[0]], a, b);
                for (int i = 1; i < n; ++i)
                    if (runs(tris[fs[i]], a, b) != dir0) {
                        partner = i;
                        break;
                    }
                join(fs[0], fs[partner]);
            }
        }
    }
    if (nNonManifoldEdges) *nNonManifoldEdges = nBad;
    // One vertex per (vertex, corner group); the first group keeps the old index.
    std::vector<int> groupVertex(3 * nF, -1);
    std::vector<int> firstRoot(positions.size(), -1);
    std::vector<uint8_t> counted(positions.size(), 0);
    int nSplit = 0;
    for (int c = 0; c < 3 * nF; ++c) {
        int r = uf.find(c);
        int v = tris[c / 3][c % 3];
        if (groupVertex[r] < 0) {
            if (firstRoot[v] < 0) {
                firstRoot[v] = r;
                groupVertex[r] = v;
            } else {
                groupVertex[r] = int(positions.size());
                positions.push_back(positions[v]);
                if (!counted[v]) {
                    counted[v] = 1;
                    ++nSplit;
                }
            }
        }
        tris[c / 3][c % 3] = groupVertex[r];
    }
    return nSplit;
}

void report(const std::string &name, const LoadOptions &options, const char *kind, int count,
            const std::string &what, const std::string &treatment) {
    if (count == 0) return;
    if (!options.repair)
        throw InputError(FileLoc{name}, std::to_string(count) + " " + what,
                         "fix the file or load it with repair enabled");
    rosy::warn(name, kind, std::to_string(count) + " " + what + ": " + treatment);
}

/// Rejects non-finite or absurd coordinates and more polygons than the face limit
/// (the readers check these too; repairAndBuild() is also called on generated soups).
void rejectBadCoordinatesAndCounts(const std::vector<Vec3> &positions, size_t nPolygons, const FileLoc &loc,
                                   const LoadOptions &options) {
    for (size_t v = 0; v < positions.size(); ++v) {
        if (!positions[v].allFinite())
            throw InputError(loc, "vertex " + std::to_string(v) + " has a non-finite coordinate",
                             "every coordinate must be a finite number");
        if (positions[v].cwiseAbs().maxCoeff() > kMaxCoordinate)
            throw InputError(loc, "vertex " + std::to_string(v) + " has an absurd coordinate (limit 1e15)",
                             "rescale the mesh; rendering does not depend on its scale");
    }
    if (int64_t(nPolygons) > options.maxFaces)
        throw InputError(loc,
                         "the mesh has " + std::to_string(nPolygons) + " faces, more than the limit of " +
                             std::to_string(options.maxFaces),
                         "simplify the mesh or raise the face limit");
}

/// Ear clipping of polygon `poly` (at least 4 distinct consecutive indices) in the
/// plane of its Newell normal `n`: the first ear in the polygon's order is cut
/// off (a convex corner whose triangle holds no other corner of the polygon, on its
/// edges included), then the search goes on from its predecessor. Appends the
/// triangles, wound as the polygon, and returns Clipped; appends nothing and returns
/// NoEar when no ear is left before the end (a polygon that crosses itself or folds
/// back in its plane), OutOfBudget when `budget` runs out.
enum class EarClip { Clipped, NoEar, OutOfBudget };
EarClip earClip(const std::vector<int> &poly, const std::vector<Vec3> &positions, const Vec3 &n,
                std::vector<Face> &out, long long &budget) {
    // An orthonormal frame (u, v) of the plane with u × v along n: the polygon is
    // counter-clockwise in it.
    const Vec3 nn = n.normalized();
    int axis = 0; // the coordinate axis least along n (the first on ties)
    nn.cwiseAbs().minCoeff(&axis);
    const Vec3 u = nn.cross(Vec3::Unit(axis)).normalized(), v = nn.cross(u);
    std::vector<int> rest = poly;
    std::vector<Eigen::Vector2d> q;
    for (int i : poly) q.emplace_back(positions[size_t(i)].dot(u), positions[size_t(i)].dot(v));
    std::vector<int> at(poly.size()); // rest[k] is poly[at[k]]
    std::iota(at.begin(), at.end(), 0);
    auto cross2 = [](const Eigen::Vector2d &a, const Eigen::Vector2d &b) { return a.x() * b.y() - a.y() * b.x(); };
    const size_t before = out.size();
    size_t start = 0;
    while (rest.size() > 3) {
        const size_t m = rest.size();
        bool cut = false;
        for (size_t t = 0; t < m && !cut; ++t) {
            const size_t i = (start + t) % m, j = (i + m - 1) % m, k = (i + 1) % m;
            const Eigen::Vector2d &a = q[size_t(at[j])], &b = q[size_t(at[i])], &c = q[size_t(at[k])];
            const double turn = cross2(b - a, c - b);
            if (!(turn > 1e-12 * (b - a).norm() * (c - b).norm())) continue; // reflex or straight
            budget -= static_cast<long long>(m);
            if (budget < 0) {
                out.resize(before);
                return EarClip::OutOfBudget;
            }
            bool ear = true;
            for (size_t r = 0; r < m && ear; ++r) {
                if (r == i || r == j || r == k) continue;
                const Eigen::Vector2d &p = q[size_t(at[r])];
                if (p == a || p == b || p == c) continue; // the same point again (a polygon touching itself)
                // Inside or on the triangle (a, b, c), counter-clockwise.
                ear = !(cross2(b - a, p - a) >= 0 && cross2(c - b, p - b) >= 0 && cross2(a - c, p - c) >= 0);
            }
            if (!ear) continue;
            out.push_back({rest[j], rest[i], rest[k]});
            rest.erase(rest.begin() + std::ptrdiff_t(i));
            at.erase(at.begin() + std::ptrdiff_t(i));
            start = j < i ? j : j - 1; // the predecessor, after the erase
            cut = true;
        }
        if (!cut) {
            out.resize(before);
            return EarClip::NoEar;
        }
    }
    out.push_back({rest[0], rest[1], rest[2]});
    return EarClip::Clipped;
}

/// Triangulates each polygon after removing consecutive repeated indices;
/// polygons left with fewer than 3 vertices are dropped (counted). A polygon
/// convex in the plane of its Newell normal (every triangle, most quads) is fanned
/// from its first vertex; a non-convex one (an L-shaped or letter-shaped CAD face,
/// whose fan would cover the notch with folded triangles) is ear-clipped. One that
/// crosses itself in that plane (its turns do not add up to one full turn, or no
/// ear is left) has no sound triangulation: it is fanned and counted in
/// rep.polygonsFanned; past LoadOptions::earClipBudget they are fanned too (rep.largePolygonsFanned).
std::vector<Face> triangulatePolygons(const std::vector<std::vector<int>> &polygons,
                                      const std::vector<Vec3> &positions, const FileLoc &loc, long long budget,
                                      LoadReport &rep) {
    const int nV = int(positions.size());
    std::vector<Face> tris;
    tris.reserve(polygons.size());
    std::vector<int> poly;
    for (size_t p = 0; p < polygons.size(); ++p) {
        for (int idx : polygons[p])
            if (idx < 0 || idx >= nV)
                throw InputError(loc,
                                 "face " + std::to_string(p) + " uses vertex index " + std::to_string(idx) +
                                     " outside [0, " + std::to_string(nV) + ")",
                                 "fix the face's indices");
        poly.clear();
        for (int idx : polygons[p])
            if (poly.empty() || poly.back() != idx) poly.push_back(idx);
        while (poly.size() > 1 && poly.back() == poly.front()) poly.pop_back();
        if (poly.size() < 3) {
            ++rep.degenerateFacesDropped;
            continue;
        }
        if (poly.size() > 3) {
            ++rep.polygonsTriangulated;
            // Convex in its plane? Every turn along the Newell normal non-negative,
            // and the turns add up to one full turn (a pentagram turns left at every
            // corner too, twice around).
            Vec3 n = Vec3::Zero();
            for (size_t k = 0; k < poly.size(); ++k)
                n += positions[size_t(poly[k])].cross(positions[size_t(poly[(k + 1) % poly.size()])]);
            const Vec3 axis = n.normalized();
            // The turn at corner k in the plane: the edges without their parts along the
            // normal (a twisted quad's edges climb and fall; in the plane it is convex).
            // Writes its sine and cosine times the edges' lengths, returns that product.
            auto turnAt = [&](size_t k, double &sine, double &cosine) {
                const Vec3 &a = positions[size_t(poly[(k + poly.size() - 1) % poly.size()])];
                const Vec3 &b = positions[size_t(poly[k])], &c = positions[size_t(poly[(k + 1) % poly.size()])];
                const Vec3 e0 = (b - a) - axis * axis.dot(b - a), e1 = (c - b) - axis * axis.dot(c - b);
                sine = e0.cross(e1).dot(axis);
                cosine = e0.dot(e1);
                return e0.norm() * e1.norm();
            };
            bool leftTurns = true, strictlyLeft = true;
            for (size_t k = 0; k < poly.size(); ++k) {
                double sine, cosine;
                const double scale = turnAt(k, sine, cosine);
                leftTurns = leftTurns && sine >= -1e-12 * scale;
                strictlyLeft = strictlyLeft && sine > 1e-12 * scale;
            }
            // A quad turning strictly left at every corner turns once around (four
            // turns in (0, π) adding up to a whole number of turns): every quad of a
            // quad mesh, without the angles' sum below.
            bool oneTurn = n.squaredNorm() > 0 && strictlyLeft && poly.size() == 4;
            if (!oneTurn && n.squaredNorm() > 0) {
                double turning = 0;
                for (size_t k = 0; k < poly.size(); ++k) {
                    double sine, cosine;
                    turnAt(k, sine, cosine);
                    turning += std::atan2(sine, cosine);
                }
                // One full turn: the boundary of a region (crossing itself, a polygon
                // winds twice or not at all).
                oneTurn = std::abs(turning - 2 * M_PI) < 1e-6;
            }
            if (!(leftTurns && oneTurn) && n.squaredNorm() > 0) {
                const EarClip clip = oneTurn ? earClip(poly, positions, n, tris, budget) : EarClip::NoEar;
                if (clip == EarClip::Clipped) {
                    ++rep.nonConvexPolygonsTriangulated;
                    continue;
                }
                ++(clip == EarClip::NoEar ? rep.polygonsFanned : rep.largePolygonsFanned);
            }
        }
        for (size_t k = 1; k + 1 < poly.size(); ++k) tris.push_back({poly[0], poly[k], poly[k + 1]});
    }
    return tris;
}

/// Points every face corner at the smallest-index vertex with the same
/// coordinates. Returns that representative per original vertex.
std::vector<int> mergeIdenticalVertices(const std::vector<Vec3> &positions, std::vector<Face> &tris,
                                        LoadReport &rep) {
    const int nV = int(positions.size());
    std::vector<int> order(nV);
    std::iota(order.begin(), order.end(), 0);
    auto less = [&](int a, int b) {
        const Vec3 &p = positions[a], &q = positions[b];
        if (p.x() != q.x()) return p.x() < q.x();
        if (p.y() != q.y()) return p.y() < q.y();
        if (p.z() != q.z()) return p.z() < q.z();
        return a < b;
    };
    tbb::parallel_sort(order.begin(), order.end(), less); // a total order: the result is unique
    std::vector<int> representative(nV);
    for (int i = 0; i < nV; ++i) {
        if (i > 0 && positions[order[i]] == positions[order[i - 1]]) {
            representative[order[i]] = representative[order[i - 1]];
            ++rep.duplicateVerticesMerged;
        } else {
            representative[order[i]] = order[i];
        }
    }
    for (Face &t : tris)
        for (int &v : t) v = representative[v];
    return representative;
}

/// Drops faces with a repeated vertex or (numerically) zero area. The area test
/// is relative to the longest edge so that it does not depend on scale.
void dropDegenerateFaces(const std::vector<Vec3> &positions, std::vector<Face> &tris, LoadReport &rep) {
    std::vector<Face> kept;
    kept.reserve(tris.size());
    for (const Face &t : tris) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            ++rep.degenerateFacesDropped;
            continue;
        }
        const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
        double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
        if ((b - a).cross(c - a).norm() <= 1e-12 * longest) {
            ++rep.degenerateFacesDropped;
            continue;
        }
        kept.push_back(t);
    }
    tris.swap(kept);
}

/// Duplicate faces (same vertex set, either orientation): keeps the first.
void dropDuplicateFaces(std::vector<Face> &tris, LoadReport &rep) {
    // Faces bucketed by their smallest vertex (a counting sort); each bucket sorted by
    // (middle, largest vertex, face) in parallel, so equal vertex sets lie together,
    // the first face of each first.
    const int nF = int(tris.size());
    int nV = 0;
    for (const Face &t : tris) nV = std::max({nV, t[0] + 1, t[1] + 1, t[2] + 1});
    auto sortedFace = [&](int f) {
        std::array<int, 3> s = tris[size_t(f)];
        if (s[0] > s[1]) std::swap(s[0], s[1]);
        if (s[1] > s[2]) std::swap(s[1], s[2]);
        if (s[0] > s[1]) std::swap(s[0], s[1]);
        return s;
    };
    std::vector<int> start(size_t(nV) + 1, 0);
    for (int f = 0; f < nF; ++f) ++start[size_t(sortedFace(f)[0]) + 1];
    for (int v = 0; v < nV; ++v) start[v + 1] += start[v];
    detail::UninitializedVector<std::array<int, 3>> bucket(tris.size()); // (middle, largest, face)
    {
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (int f = 0; f < nF; ++f) {
            const std::array<int, 3> s = sortedFace(f);
            bucket[size_t(fill[size_t(s[0])]++)] = {s[1], s[2], f};
        }
    }
    std::vector<uint8_t> drop(tris.size(), 0);
    parallelFor(0, nV, [&](int64_t v) {
        const auto first = bucket.begin() + start[v], last = bucket.begin() + start[v + 1];
        std::sort(first, last);
        for (auto it = first; it != last; ++it)
            if (it != first && (*it)[0] == (*(it - 1))[0] && (*it)[1] == (*(it - 1))[1]) drop[size_t((*it)[2])] = 1;
    }, 1024);
    std::vector<Face> kept;
    kept.reserve(tris.size());
    for (int f = 0; f < nF; ++f) {
        if (drop[size_t(f)]) ++rep.duplicateFacesDropped;
        else kept.push_back(tris[size_t(f)]);
    }
    tris.swap(kept);
}

/// Counts vertices no face uses (merged duplicates do not count: they were
/// reported as merged). compactVertices() drops them.
int countIsolatedVertices(const std::vector<Face> &tris, const std::vector<int> &representative) {
    const int nV = int(representative.size());
    std::vector<uint8_t> used(nV, 0);
    for (const Face &t : tris)
        for (int v : t) used[v] = 1;
    int n = 0;
    for (int v = 0; v < nV; ++v)
        if (!used[v] && representative[v] == v) ++n;
    return n;
}

/// Counts non-manifold edges and pinched vertices without changing the mesh: a
/// pass that joins every face on an edge tells which vertices are genuinely
/// pinched (several fans).
void countNonManifoldElements(const std::vector<Vec3> &positions, const std::vector<Face> &tris,
                              const EdgeFaces &edgeFaces, LoadReport &rep) {
    std::vector<Vec3> probePositions = positions;
    std::vector<Face> probe = tris;
    int nBadEdges = 0;
    rep.nonManifoldVerticesSplit = splitVertices(probePositions, probe, false, &nBadEdges, &edgeFaces);
    rep.nonManifoldEdgesSplit = nBadEdges;
}

/// Cuts edges with more than two faces and duplicates pinched vertices once per fan.
void splitNonManifoldElements(std::vector<Vec3> &positions, std::vector<Face> &tris) {
    int remaining = 0;
    splitVertices(positions, tris, true, &remaining);
    if (remaining == 0) return;
    // A cut face can still meet its edge through other faces around both ends;
    // detach such faces completely, then split fans again.
    EdgeFaces ef = buildEdgeFaces(tris);
    std::vector<uint8_t> detach(tris.size(), 0);
    for (size_t e = 0; e < ef.keys.size(); ++e)
        for (int i = ef.offset[e] + 2; i < ef.offset[e + 1]; ++i) detach[ef.faces[i]] = 1;
    for (int f = 0; f < int(tris.size()); ++f)
        if (detach[f])
            for (int &v : tris[f]) {
                positions.push_back(positions[v]);
                v = int(positions.size()) - 1;
            }
    splitVertices(positions, tris, true, &remaining);
}

/// Drops unused vertices and re-indexes the rest in their old order.
void compactVertices(std::vector<Vec3> &positions, std::vector<Face> &tris) {
    std::vector<int> newIndex(positions.size(), -1);
    for (const Face &t : tris)
        for (int v : t) newIndex[v] = 0;
    std::vector<Vec3> compact;
    compact.reserve(positions.size());
    for (size_t v = 0; v < positions.size(); ++v)
        if (newIndex[v] == 0) {
            newIndex[v] = int(compact.size());
            compact.push_back(positions[v]);
        }
    for (Face &t : tris)
        for (int &v : t) v = newIndex[v];
    positions.swap(compact);
}

/// The face across each corner's edge (k -> k+1) where that edge has exactly two
/// faces, else -1. Each edge writes only its own two faces' slots.
std::vector<int> faceNeighbours(const std::vector<Face> &tris, const EdgeFaces &ef) {
    std::vector<int> nbr(3 * tris.size(), -1);
    parallelFor(0, int64_t(ef.keys.size()), [&](int64_t e) {
        if (ef.offset[e + 1] - ef.offset[e] != 2) return;
        const int f = ef.faces[ef.offset[e]], g = ef.faces[ef.offset[e] + 1];
        const int a = int(ef.keys[e] >> 32), b = int(ef.keys[e] & 0xffffffffu);
        for (int k = 0; k < 3; ++k) {
            const int x = tris[f][k], y = tris[f][(k + 1) % 3];
            if ((x == a && y == b) || (x == b && y == a)) nbr[3 * f + k] = g;
            const int u = tris[g][k], w = tris[g][(k + 1) % 3];
            if ((u == a && w == b) || (u == b && w == a)) nbr[3 * g + k] = f;
        }
    }, 4096);
    return nbr;
}

/// Edges with more than two faces.
int countCrowdedEdges(const EdgeFaces &ef) {
    int n = 0;
    for (size_t e = 0; e < ef.keys.size(); ++e) n += ef.offset[e + 1] - ef.offset[e] > 2;
    return n;
}

/// The number of vertices whose faces form more than one fan, where no edge has
/// more than two faces: what splitVertices(..., cutEdges = false) counts there (its
/// corner groups at v are v's faces joined across shared edges at v), found per
/// vertex in parallel by walking v's fan across the two-face edges `nbr`.
int countPinchedVertices(int nV, const std::vector<Face> &tris, const std::vector<int> &nbr) {
    std::vector<int> degree(size_t(nV), 0), someFace(size_t(nV), -1);
    for (int f = 0; f < int(tris.size()); ++f)
        for (int v : tris[f]) {
            ++degree[size_t(v)];
            someFace[size_t(v)] = f;
        }
    std::vector<uint8_t> pinched(size_t(nV), 0);
    parallelFor(0, nV, [&](int64_t vi) {
        const int v = int(vi), f0 = someFace[size_t(vi)];
        if (f0 < 0) return;
        // Faces reached from f0 leaving through its edge `slot` (one of its two edges at v).
        auto walk = [&](int slot) {
            int reached = 0, f = f0;
            while (reached < degree[size_t(v)]) {
                const int g = nbr[3 * f + slot];
                if (g < 0) return std::pair(reached, false);
                if (g == f0) return std::pair(reached, true);
                // The edge crossed is {v, w}; leave g through its other edge at v.
                const Face &t = tris[f];
                const int w = t[slot] == v ? t[(slot + 1) % 3] : t[slot];
                const int c = cornerOf(tris[g], v);
                slot = tris[g][(c + 1) % 3] == w ? (c + 2) % 3 : c;
                f = g;
                ++reached;
            }
            return std::pair(reached, true);
        };
        const int c0 = cornerOf(tris[f0], v);
        const auto [forward, closed] = walk(c0);
        const int fan = 1 + forward + (closed ? 0 : walk((c0 + 2) % 3).first);
        pinched[size_t(vi)] = fan != degree[size_t(vi)];
    }, 1024);
    int n = 0;
    for (uint8_t p : pinched) n += p;
    return n;
}

/// True if the two faces of every two-face edge run it in opposite directions: then
/// orientFacesConsistently() flips nothing (every face keeps its seed's orientation).
bool orientedConsistently(const std::vector<Face> &tris, const EdgeFaces &ef) {
    std::atomic<bool> consistent{true};
    parallelFor(0, int64_t(ef.keys.size()), [&](int64_t e) {
        if (ef.offset[e + 1] - ef.offset[e] != 2) return;
        const int f = ef.faces[ef.offset[e]], g = ef.faces[ef.offset[e] + 1];
        const int a = int(ef.keys[e] >> 32), b = int(ef.keys[e] & 0xffffffffu);
        if (runs(tris[f], a, b) == runs(tris[g], a, b)) consistent = false;
    }, 4096);
    return consistent;
}

/// Consistent orientation by BFS over manifold edges, per component. The
/// orientation that flips fewer faces wins (ties keep the first face's).
/// \throws InputError if a component is not orientable.
/// `neighbours`, when given, is faceNeighbours(tris, buildEdgeFaces(tris)).
void orientFacesConsistently(std::vector<Face> &tris, const FileLoc &loc, LoadReport &rep,
                             const std::vector<int> *neighbours = nullptr) {
    const int nF = int(tris.size());
    std::optional<std::vector<int>> built;
    if (!neighbours) built = faceNeighbours(tris, buildEdgeFaces(tris));
    const std::vector<int> &nbr = neighbours ? *neighbours : *built;
    std::vector<int8_t> flip(nF, -1);
    std::vector<int> queue, comp;
    for (int seed = 0; seed < nF; ++seed) {
        if (flip[seed] >= 0) continue;
        flip[seed] = 0;
        queue.assign(1, seed);
        comp.clear();
        for (size_t qi = 0; qi < queue.size(); ++qi) {
            const int f = queue[qi];
            comp.push_back(f);
            for (int k = 0; k < 3; ++k) {
                const int g = nbr[3 * f + k];
                if (g < 0) continue;
                const int a = tris[f][k], b = tris[f][(k + 1) % 3];
                // g must run b -> a once both carry their flips.
                const bool sameDir = runs(tris[g], a, b);
                const int8_t want = int8_t(sameDir ? !flip[f] : flip[f]);
                if (flip[g] < 0) {
                    flip[g] = want;
                    queue.push_back(g);
                } else if (flip[g] != want) {
                    throw InputError(loc,
                                     "the surface is not orientable (a Moebius-like band "
                                     "around face " + std::to_string(f) + ")",
                                     "N-RoSy frames need an orientation; cut the band open "
                                     "or use an orientable surface");
                }
            }
        }
        int nFlipped = 0;
        for (int f : comp) nFlipped += flip[f];
        if (2 * nFlipped > int(comp.size()))
            for (int f : comp) flip[f] = int8_t(!flip[f]);
        for (int f : comp)
            if (flip[f]) {
                std::swap(tris[f][1], tris[f][2]);
                ++rep.facesReoriented;
            }
    }
}

/// Vertices this far apart in the numbering are taken to be far apart in memory
/// (4096 vertices' positions alone are 96 KiB, more than a core's first-level cache,
/// and a loop reads several such arrays per vertex).
constexpr int kFarInMemory = 4096;

/// Does the file list its vertices in no spatial order? More than half of the face
/// edges join vertices kFarInMemory or more apart in the numbering: bunny00 64 %,
/// a subdivided and perturbed armadillo of 270k faces (a scan-like stress mesh) 72 %;
/// of the other meshes of the example scenes the most is camel's 33 %.
bool scatteredInMemory(const std::vector<Face> &tris) {
    size_t far = 0;
    for (const Face &t : tris)
        for (int k = 0; k < 3; ++k) far += std::abs(t[size_t(k)] - t[size_t((k + 1) % 3)]) >= kFarInMemory;
    return 2 * far > 3 * tris.size();
}

/// Renumbers the vertices along a Morton curve of their positions (ties: the order
/// before) and orders the faces by their smallest vertex in the new numbering (ties:
/// the order before), so that what is near on the surface is near in memory (bunny00:
/// 64 % of its face edges far apart before, 2 % after). Every per-vertex loop, sparse
/// product and ray waited on memory before: the render of bunny00 took 0.53 s before
/// and 0.47 s after, its field stage 124 ms and 105 ms, the 270k-face stress mesh 1.61 s
/// and 1.27 s (alternating runs, docs/benchmarks.md). Each face keeps its corners in
/// their order (its winding and first corner).
void renumberForLocality(std::vector<Vec3> &positions, std::vector<Face> &tris) {
    const int nV = int(positions.size()), nF = int(tris.size());
    if (nV == 0) return;
    Vec3 lo = positions[0], hi = positions[0];
    for (const Vec3 &p : positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    const double extent = (hi - lo).maxCoeff();
    const double scale = extent > 0 ? 1.0 / extent : 1.0;
    // Keys are unique (the index breaks ties), so the parallel sort's result is one.
    std::vector<std::pair<uint64_t, int>> order(static_cast<size_t>(nV));
    parallelFor(0, nV, [&](int64_t v) { order[size_t(v)] = {mortonCode(positions[size_t(v)], lo, scale), int(v)}; },
                4096);
    tbb::parallel_sort(order.begin(), order.end());
    std::vector<int> newIndex(static_cast<size_t>(nV));
    std::vector<Vec3> sorted(static_cast<size_t>(nV));
    for (int k = 0; k < nV; ++k) {
        newIndex[size_t(order[size_t(k)].second)] = k;
        sorted[size_t(k)] = positions[size_t(order[size_t(k)].second)];
    }
    positions.swap(sorted);
    std::vector<std::pair<int, int>> faceOrder(static_cast<size_t>(nF));
    for (int f = 0; f < nF; ++f) {
        Face &t = tris[size_t(f)];
        for (int &v : t) v = newIndex[size_t(v)];
        faceOrder[size_t(f)] = {std::min({t[0], t[1], t[2]}), f};
    }
    tbb::parallel_sort(faceOrder.begin(), faceOrder.end());
    std::vector<Face> sortedTris(static_cast<size_t>(nF));
    for (int k = 0; k < nF; ++k) sortedTris[size_t(k)] = tris[size_t(faceOrder[size_t(k)].second)];
    tris.swap(sortedTris);
}

} // namespace

Mesh repairAndBuild(std::vector<Vec3> positions, const std::vector<std::vector<int>> &polygons,
                    const std::string &name, const LoadOptions &options, LoadReport *reportOut) {
    LoadReport rep;
    const FileLoc loc{name};
    rejectBadCoordinatesAndCounts(positions, polygons.size(), loc, options);
    std::vector<Face> tris = triangulatePolygons(polygons, positions, loc, options.earClipBudget, rep);
    const std::vector<int> representative = mergeIdenticalVertices(positions, tris, rep);
    dropDegenerateFaces(positions, tris, rep);
    dropDuplicateFaces(tris, rep);
    // The simple repairs are reported before the topological ones, so that with
    // repair disabled the first problem found in the file is the one named.
    report(name, options, "self-crossing-polygons", rep.polygonsFanned,
           "polygons that cross themselves or fold back in their plane (no ear clipping finds their triangles)",
           "fanned from their first vertex; their triangles may overlap");
    report(name, options, "large-nonconvex-polygons", rep.largePolygonsFanned,
           fmt::format("non-convex polygons too large to ear-clip within the loader's budget (about {:.0f} corners "
                       "in all)",
                       1000 * std::round(std::sqrt(double(options.earClipBudget)) / 1000)),
           "fanned from their first vertex; their triangles may overlap (triangulate them before loading)");
    report(name, options, "degenerate-faces", rep.degenerateFacesDropped,
           "faces with a repeated vertex or zero area", "dropped");
    report(name, options, "duplicate-vertices", rep.duplicateVerticesMerged,
           "vertices with identical coordinates", "merged");
    report(name, options, "duplicate-faces", rep.duplicateFacesDropped,
           "duplicate faces (same vertices)", "dropped");
    rep.isolatedVerticesDropped = countIsolatedVertices(tris, representative);
    report(name, options, "isolated-vertices", rep.isolatedVerticesDropped,
           "vertices not used by any face", "dropped");
    if (tris.empty())
        throw InputError(loc, "the mesh has no faces" +
                                  std::string(polygons.empty() ? "" : " left after dropping degenerate ones"),
                         "a surface mesh needs at least one triangle");

    // Counting the non-manifold elements and orienting the faces read the same
    // triangles and the same edge-face incidences, built once. Without an edge of
    // more than two faces (the usual case) the pinched vertices are counted by
    // walking each vertex's fan and the orientation is decided before any split:
    // when nothing is split, dropping unused vertices only renames them, which
    // changes no flip and no message. Otherwise the steps run in their order.
    const EdgeFaces edgeFaces = buildEdgeFaces(tris);
    rep.nonManifoldEdgesSplit = countCrowdedEdges(edgeFaces);
    std::vector<int> neighbours;
    if (rep.nonManifoldEdgesSplit == 0) {
        neighbours = faceNeighbours(tris, edgeFaces);
        rep.nonManifoldVerticesSplit = countPinchedVertices(int(positions.size()), tris, neighbours);
    } else {
        countNonManifoldElements(positions, tris, edgeFaces, rep);
    }
    report(name, options, "nonmanifold-edges", rep.nonManifoldEdgesSplit,
           "edges shared by more than two faces", "extra faces split off onto duplicated vertices");
    report(name, options, "nonmanifold-vertices", rep.nonManifoldVerticesSplit,
           "non-manifold vertices (several fans)", "duplicated once per fan");
    if (rep.nonManifoldEdgesSplit > 0 || rep.nonManifoldVerticesSplit > 0) {
        splitNonManifoldElements(positions, tris);
        compactVertices(positions, tris);
        orientFacesConsistently(tris, loc, rep);
    } else {
        // Already consistent (the usual case): the search below would flip nothing.
        if (!orientedConsistently(tris, edgeFaces)) orientFacesConsistently(tris, loc, rep, &neighbours);
        compactVertices(positions, tris);
    }
    report(name, options, "reoriented-faces", rep.facesReoriented,
           "faces with inconsistent orientation", "flipped to agree with their neighbours");

    // Not a repair (nothing is reported): a file whose order is already spatial keeps
    // its numbering, so its field, pictures and exports number vertices as it does.
    if (scatteredInMemory(tris)) renumberForLocality(positions, tris);

    if (reportOut) *reportOut = rep;
    return Mesh::fromTriangles(std::move(positions), std::move(tris), name);
}

} // namespace rosy::field
