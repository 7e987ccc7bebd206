/// \file quality.cpp
#include "remesh/quality.h"

#include "field/mesh/mesh_stats.h"
#include "field/mesh/union_find.h"
#include "remesh/aabb_tree.h"

#include "core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace rosy::remesh {
namespace {

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    const size_t k = std::min(v.size() - 1, size_t(std::floor(p * double(v.size() - 1) + 0.5)));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k];
}

double angleDeg(const Vec3 &a, const Vec3 &b) {
    const double na = a.norm(), nb = b.norm();
    if (na == 0 || nb == 0) return 0;
    return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0)) * 180.0 / M_PI;
}

} // namespace

QualityReport measureQuality(const std::vector<Vec3> &positions, const std::vector<std::vector<int>> &polygons,
                             const field::TangentFrames &frames, const field::RosyField &field,
                             const field::SingularityReport &singularities, double edgeLength) {
    const field::Mesh &mesh = frames.mesh();
    QualityReport q;
    q.nSym = field.nSym;
    q.edgeLength = edgeLength;
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    q.diagonal = (hi - lo).norm();
    const int regular = field.nSym == 6 ? 3 : 4;
    const double targetAngle = field.nSym == 6 ? 60.0 : 90.0;
    const int nP = int(positions.size());

    // --- input topology
    {
        int boundary = 0;
        for (int h = 0; h < mesh.nHalfedges(); ++h) boundary += mesh.isBoundaryHalfedge(h) ? 1 : 0;
        q.inputBoundaryEdges = boundary;
        q.inputEulerCharacteristic = mesh.nVertices() - mesh.nEdges() + mesh.nFaces();
        const field::MeshStats stats = field::computeStats(mesh);
        q.inputComponents = stats.components;
        q.inputGenus = stats.genus;
    }

    // --- edges: (min, max) -> uses in each direction
    struct EdgeUse {
        int forward = 0, backward = 0;
    };
    std::map<std::pair<int, int>, EdgeUse> edges;
    std::vector<char> usedVertex(nP, 0);
    std::vector<std::vector<std::pair<int, int>>> corners(nP); // (prev, next) per face corner
    q.faces = int(polygons.size());
    for (const auto &poly : polygons) {
        const int k = int(poly.size());
        q.facesBySides[k]++;
        std::vector<int> sorted = poly;
        std::sort(sorted.begin(), sorted.end());
        const bool repeated = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
        Vec3 newell = Vec3::Zero();
        for (int i = 0; i < k; ++i) newell += positions[poly[i]].cross(positions[poly[(i + 1) % k]]);
        if (repeated || 0.5 * newell.norm() < 1e-6 * edgeLength * edgeLength) q.degenerateFaces++;
        for (int i = 0; i < k; ++i) {
            const int a = poly[i], b = poly[(i + 1) % k];
            usedVertex[a] = 1;
            EdgeUse &e = edges[{std::min(a, b), std::max(a, b)}];
            (a < b ? e.forward : e.backward)++;
            corners[a].emplace_back(poly[(i + k - 1) % k], b);
        }
    }
    q.edges = int(edges.size());
    std::vector<char> onBoundary(nP, 0);
    for (const auto &[key, use] : edges) {
        const int total = use.forward + use.backward;
        if (total > 2) q.nonManifoldEdges++;
        if (use.forward > 1 || use.backward > 1) q.inconsistentEdges++;
        if (total == 1) {
            q.boundaryEdges++;
            onBoundary[key.first] = onBoundary[key.second] = 1;
            if (q.inputBoundaryEdges == 0 && int(q.problems.size()) < QualityReport::kMaxProblems)
                q.problems.push_back(0.5 * (positions[key.first] + positions[key.second]));
        }
    }
    // Vertex fans: link each corner (prev, next) to the corner whose prev is its next.
    for (int v = 0; v < nP; ++v) {
        if (!usedVertex[v]) {
            q.isolatedVertices++;
            continue;
        }
        const auto &cs = corners[v];
        std::map<int, int> byPrev;
        bool bad = false;
        for (size_t i = 0; i < cs.size(); ++i)
            if (!byPrev.emplace(cs[i].first, int(i)).second) bad = true;
        if (!bad) {
            // Count chains: a corner starts one when no corner's next is its prev.
            std::vector<char> seen(cs.size(), 0);
            int components = 0;
            std::map<int, int> byNext;
            for (size_t i = 0; i < cs.size(); ++i) byNext.emplace(cs[i].second, int(i));
            for (size_t i = 0; i < cs.size(); ++i) {
                if (seen[i]) continue;
                // walk back to a chain start (or around a cycle)
                int s = int(i);
                for (size_t guard = 0; guard < cs.size(); ++guard) {
                    auto it = byNext.find(cs[s].first);
                    if (it == byNext.end() || it->second == int(i)) break;
                    s = it->second;
                }
                ++components;
                for (int c = s; c >= 0 && !seen[c];) {
                    seen[c] = 1;
                    auto it = byPrev.find(cs[c].second);
                    c = it == byPrev.end() ? -1 : it->second;
                }
            }
            bad = components != 1;
        }
        if (bad) {
            q.nonManifoldVertices++;
            if (int(q.problems.size()) < QualityReport::kMaxProblems) q.problems.push_back(positions[v]);
        }
    }
    q.vertices = nP - q.isolatedVertices;
    q.eulerCharacteristic = q.vertices - q.edges + q.faces;
    {
        // Pieces through shared vertices; boundary loops as the pieces of the boundary
        // edges' graph (a loop through a vertex twice counts once: the mesh is then
        // not manifold, which is reported apart).
        field::UnionFind pieces(nP), loops(nP);
        for (const auto &poly : polygons)
            for (size_t i = 1; i < poly.size(); ++i) pieces.unite(poly[0], poly[i]);
        for (const auto &[key, use] : edges)
            if (use.forward + use.backward == 1) loops.unite(key.first, key.second);
        std::vector<char> pieceRoot(size_t(nP), 0), loopRoot(size_t(nP), 0);
        int nLoops = 0;
        for (int v = 0; v < nP; ++v)
            if (usedVertex[size_t(v)]) pieceRoot[size_t(pieces.find(v))] = 1;
        for (const auto &[key, use] : edges)
            if (use.forward + use.backward == 1 && !loopRoot[size_t(loops.find(key.first))]) {
                loopRoot[size_t(loops.find(key.first))] = 1;
                ++nLoops;
            }
        q.components = int(std::count(pieceRoot.begin(), pieceRoot.end(), 1));
        q.genus = (2 * q.components - q.eulerCharacteristic - nLoops) / 2;
    }
    q.manifold = q.nonManifoldEdges == 0 && q.nonManifoldVertices == 0;
    q.oriented = q.inconsistentEdges == 0;
    q.closed = q.boundaryEdges == 0;
    q.regularFaceFraction = q.faces ? double(q.facesBySides[regular]) / q.faces : 0;

    // --- valences and singularities
    std::vector<std::vector<int>> nbrs(nP);
    for (const auto &[key, use] : edges) {
        nbrs[key.first].push_back(key.second);
        nbrs[key.second].push_back(key.first);
    }
    std::vector<Vec3> sing;
    std::vector<int> singSign, singIndex; // each one's index sign and place in `singularities`
    for (size_t i = 0; i < singularities.singularities.size(); ++i) {
        const field::Singularity &s = singularities.singularities[i];
        if (std::abs(s.indexNumerator) != 1) continue;
        sing.push_back(s.position), singSign.push_back(s.indexNumerator), singIndex.push_back(int(i));
    }
    q.singularities = int(sing.size());
    auto nearestSing = [&](const Vec3 &p) {
        double best = std::numeric_limits<double>::infinity();
        for (const Vec3 &s : sing) best = std::min(best, (s - p).norm());
        return best;
    };
    const int regularValence = field.nSym == 6 ? 6 : 4;
    // An interior vertex the mesh uses whose valence is not the regular one.
    auto irregular = [&](int v) {
        return usedVertex[size_t(v)] && !onBoundary[size_t(v)] && int(nbrs[size_t(v)].size()) != regularValence;
    };
    // hit[s] = 1 for every singularity s within 2 L of p.
    auto markNear = [&](const Vec3 &p, std::vector<char> &hit) {
        for (size_t s = 0; s < sing.size(); ++s)
            if ((sing[s] - p).norm() <= 2 * edgeLength) hit[s] = 1;
    };
    std::vector<double> irregularDist;
    std::vector<char> singHit(sing.size(), 0);
    int interior = 0;
    for (int v = 0; v < nP; ++v) {
        if (!usedVertex[v] || onBoundary[v]) continue;
        const int val = int(nbrs[v].size());
        q.valenceHistogram[val]++;
        ++interior;
        if (val == 2) q.valence2Vertices++;
        if (val == regularValence) continue;
        q.irregularVertices++;
        const double d = nearestSing(positions[v]);
        irregularDist.push_back(d / edgeLength);
        if (d <= 2 * edgeLength) q.irregularNearSingularity++;
        markNear(positions[v], singHit);
    }
    q.irregularFraction = interior ? double(q.irregularVertices) / interior : 0;
    // Each singularity's nearest output vertex (the first of equals; -1 when none).
    std::vector<int> nearestVertex(sing.size(), -1);
    for (size_t k = 0; k < sing.size(); ++k) {
        double bestD = std::numeric_limits<double>::infinity();
        for (int v = 0; v < nP; ++v) {
            if (!usedVertex[size_t(v)]) continue;
            const double d = (positions[size_t(v)] - sing[k]).norm();
            if (d < bestD) bestD = d, nearestVertex[k] = v;
        }
    }
    // The vertices within two rings (along edges) of `sources`, breadth first; each
    // gets its ring in `depth` (-1 elsewhere, as the caller keeps it between calls).
    std::vector<int> depth(static_cast<size_t>(nP), -1);
    auto twoRings = [&](const std::vector<int> &sources) {
        std::vector<int> reached, frontier;
        for (int v : sources)
            if (v >= 0 && depth[size_t(v)] < 0) depth[size_t(v)] = 0, frontier.push_back(v), reached.push_back(v);
        for (int ring = 1; ring <= 2; ++ring) {
            std::vector<int> next;
            for (int v : frontier)
                for (int w : nbrs[size_t(v)])
                    if (depth[size_t(w)] < 0) depth[size_t(w)] = ring, next.push_back(w), reached.push_back(w);
            frontier.swap(next);
        }
        return reached;
    };
    auto clearRings = [&](const std::vector<int> &reached) {
        for (int v : reached) depth[size_t(v)] = -1;
    };
    {
        // Two rings from every singularity's nearest output vertex at once.
        const std::vector<int> reached = twoRings(nearestVertex);
        for (int v : reached) q.irregularWithinTwoRings += irregular(v);
        clearRings(reached);
    }
    {
        // Each singularity's own two rings (its neighbourhood), and in it the irregular
        // vertices and faces with their defects (regular count minus their own).
        std::vector<int> faceDefect(polygons.size(), 0);
        std::vector<std::vector<int>> facesOf(static_cast<size_t>(nP));
        for (size_t f = 0; f < polygons.size(); ++f) {
            // Curvature in units of 1/N of a turn: 4 − sides for N = 4, 2 (3 − sides) for
            // N = 6 (a quad among triangles is two units, as a valence-8 vertex).
            faceDefect[f] = field.nSym == 6 ? 2 * (3 - int(polygons[f].size())) : 4 - int(polygons[f].size());
            if (faceDefect[f] != 0)
                for (int v : polygons[f]) facesOf[size_t(v)].push_back(int(f));
        }
        std::vector<int> singularitiesAt(static_cast<size_t>(nP), 0); // singularities nearest each vertex
        for (int v : nearestVertex)
            if (v >= 0) ++singularitiesAt[size_t(v)];
        q.singularityAsOneIrregular.assign(singularities.singularities.size(), 1); // 1: not judged
        for (size_t k = 0; k < sing.size(); ++k) {
            char &asOne = q.singularityAsOneIrregular[size_t(singIndex[k])];
            asOne = 0;
            if (nearestVertex[k] < 0) continue;
            const std::vector<int> reached = twoRings({nearestVertex[k]});
            int elements = 0, ownSign = 0, singularitiesHere = 0;
            bool offByOne = true;
            auto count = [&](int defect) {
                ++elements;
                offByOne = offByOne && std::abs(defect) == 1;
                ownSign += (defect > 0) == (singSign[k] > 0);
            };
            std::vector<int> seenFaces;
            for (int v : reached) {
                singularitiesHere += singularitiesAt[size_t(v)];
                if (irregular(v)) count(regularValence - int(nbrs[size_t(v)].size()));
                for (int f : facesOf[size_t(v)]) {
                    bool inside = true;
                    for (int w : polygons[size_t(f)]) inside = inside && depth[size_t(w)] >= 0;
                    if (inside && std::find(seenFaces.begin(), seenFaces.end(), f) == seenFaces.end()) {
                        seenFaces.push_back(f);
                        count(faceDefect[size_t(f)]);
                    }
                }
            }
            asOne = offByOne && ownSign > 0 && elements <= singularitiesHere;
            q.singularitiesAsOneIrregular += asOne;
            clearRings(reached);
        }
    }
    q.irregularDistanceMedianL = percentile(irregularDist, 0.5);
    for (char h : singHit) q.singularitiesWithIrregularVertex += h;
    // Item 2's guarantee: an irregular vertex or an irregular face (a corner of it) near
    // each singularity.
    std::vector<char> singMarked = singHit, irregularCorner(static_cast<size_t>(nP), 0);
    for (const auto &poly : polygons)
        if (int(poly.size()) != regular)
            for (int v : poly) irregularCorner[size_t(v)] = 1;
    for (int v = 0; v < nP; ++v)
        if (irregularCorner[size_t(v)]) markNear(positions[size_t(v)], singMarked);
    for (char h : singMarked) q.singularitiesMarked += h;

    // --- corner angles: corner i of polygon f is angle[cornerStart[f] + i]
    std::vector<size_t> cornerStart(polygons.size() + 1, 0);
    for (size_t f = 0; f < polygons.size(); ++f) cornerStart[f + 1] = cornerStart[f] + polygons[f].size();
    std::vector<double> angle(cornerStart.back());
    std::vector<double> dev, devNear;
    for (size_t f = 0; f < polygons.size(); ++f) {
        const auto &poly = polygons[f];
        const int k = int(poly.size());
        for (int i = 0; i < k; ++i) {
            const Vec3 &p = positions[poly[i]];
            const double a = angleDeg(positions[poly[(i + k - 1) % k]] - p, positions[poly[(i + 1) % k]] - p);
            angle[cornerStart[f] + size_t(i)] = a;
            dev.push_back(std::abs(a - targetAngle));
            if (!sing.empty() && nearestSing(p) <= 2 * edgeLength) devNear.push_back(dev.back());
        }
    }
    q.angleDevMedianDeg = percentile(dev, 0.5);
    q.angleDevP90Deg = percentile(dev, 0.9);
    q.cornersNearSingularities = int(devNear.size());
    q.angleDevNearSingMedianDeg = percentile(devNear, 0.5);
    q.angleDevNearSingP90Deg = percentile(devNear, 0.9);
    {
        // Two rings of faces around each singularity's singular vertex.
        std::vector<std::vector<int>> facesAt(static_cast<size_t>(nP));
        for (size_t f = 0; f < polygons.size(); ++f)
            for (int v : polygons[f]) facesAt[size_t(v)].push_back(int(f));
        std::vector<char> faceTaken(polygons.size(), 0), singularVertex(static_cast<size_t>(nP), 0);
        std::vector<double> devRings;
        for (size_t k = 0; k < sing.size(); ++k) {
            int bestIrregular = -1;
            double bestIrregularD = std::numeric_limits<double>::infinity();
            for (int v = 0; v < nP; ++v) {
                if (!irregular(v)) continue;
                const double d = (positions[size_t(v)] - sing[k]).norm();
                if (d <= 2 * edgeLength && d < bestIrregularD) bestIrregularD = d, bestIrregular = v;
            }
            const int sv = bestIrregular >= 0 ? bestIrregular : nearestVertex[k];
            if (sv < 0) continue;
            singularVertex[size_t(sv)] = 1;
            std::vector<int> ring = nbrs[size_t(sv)];
            ring.push_back(sv);
            for (int v : ring)
                for (int f : facesAt[size_t(v)]) faceTaken[size_t(f)] = 1;
        }
        for (size_t f = 0; f < polygons.size(); ++f) {
            if (!faceTaken[f]) continue;
            const auto &poly = polygons[f];
            for (size_t i = 0; i < poly.size(); ++i) {
                const int v = poly[i];
                const double a = angle[cornerStart[f] + i];
                const bool cone = singularVertex[size_t(v)] && !nbrs[size_t(v)].empty();
                devRings.push_back(std::abs(a - (cone ? 360.0 / double(nbrs[size_t(v)].size()) : targetAngle)));
            }
        }
        q.cornersInSingularRings = int(devRings.size());
        q.angleDevSingularRingsMedianDeg = percentile(devRings, 0.5);
        q.angleDevSingularRingsP90Deg = percentile(devRings, 0.9);
    }

    // --- edge lengths and alignment with the field (each edge on its own in
    // parallel, gathered in edge order: the same numbers for any thread count)
    const AabbTree input(mesh);
    std::vector<std::pair<int, int>> edgeList;
    edgeList.reserve(edges.size());
    for (const auto &[key, use] : edges) edgeList.push_back(key);
    std::vector<double> lengths(edgeList.size()), edgeAlign(edgeList.size(), -1);
    parallelFor(0, int64_t(edgeList.size()), [&](int64_t e) {
        const auto &key = edgeList[size_t(e)];
        const Vec3 d = positions[key.second] - positions[key.first];
        lengths[size_t(e)] = d.norm();
        const ClosestPoint c = input.closest(0.5 * (positions[key.first] + positions[key.second]));
        if (c.triangle < 0) return;
        // the field at the triangle corner nearest the edge's midpoint
        int v = mesh.face(c.triangle)[0];
        for (int x : mesh.face(c.triangle))
            if ((mesh.position(x) - c.point).squaredNorm() < (mesh.position(v) - c.point).squaredNorm()) v = x;
        if (std::abs(field.u[v]) == 0) return;
        const Vec3 n = frames.normal(v);
        const Vec3 dt = d - n * n.dot(d);
        double best = 180;
        for (double a : field::memberAngles(field.u[v], field.nSym))
            best = std::min(best, angleDeg(dt, frames.tangentOfAngle(v, a)));
        edgeAlign[size_t(e)] = best;
    });
    std::vector<double> align;
    for (double a : edgeAlign)
        if (a >= 0) align.push_back(a);
    double sum = 0, sum2 = 0;
    for (double l : lengths) sum += l;
    q.edgeLengthMean = lengths.empty() ? 0 : sum / double(lengths.size());
    for (double l : lengths) sum2 += (l - q.edgeLengthMean) * (l - q.edgeLengthMean);
    q.edgeLengthCv = lengths.size() > 1 && q.edgeLengthMean > 0
                         ? std::sqrt(sum2 / double(lengths.size())) / q.edgeLengthMean
                         : 0;
    q.alignmentMedianDeg = percentile(align, 0.5);
    q.alignmentP90Deg = percentile(align, 0.9);

    // --- flipped faces and two one-sided distances
    std::vector<std::array<int, 3>> tris; // polygons fanned from their first corner
    for (const auto &poly : polygons)
        for (size_t i = 1; i + 1 < poly.size(); ++i) tris.push_back({poly[0], poly[i], poly[i + 1]});
    std::vector<char> flipped(polygons.size(), 0);
    parallelFor(0, int64_t(polygons.size()), [&](int64_t f) {
        const auto &poly = polygons[size_t(f)];
        Vec3 c = Vec3::Zero(), newell = Vec3::Zero();
        for (size_t i = 0; i < poly.size(); ++i) {
            c += positions[poly[i]];
            newell += positions[poly[i]].cross(positions[poly[(i + 1) % poly.size()]]);
        }
        const ClosestPoint cp = input.closest(c / double(poly.size()));
        flipped[size_t(f)] = cp.triangle >= 0 && newell.dot(mesh.faceNormal(cp.triangle)) < 0;
    });
    for (size_t f = 0; f < flipped.size(); ++f) {
        if (!flipped[f]) continue;
        q.flippedFaces++;
        if (int(q.problems.size()) < QualityReport::kMaxProblems) {
            Vec3 c = Vec3::Zero();
            for (int x : polygons[f]) c += positions[x];
            q.problems.push_back(c / double(polygons[f].size()));
        }
    }
    // Distances: every sample's in parallel (a sample's closest-point search starts
    // from the triangle found for the previous sample of the same triangle or
    // face), then max and sum in sample order as one sequential loop would.
    const double step = edgeLength / 3;
    std::vector<int> samplesOf(tris.size());
    std::vector<size_t> firstSample(tris.size() + 1, 0);
    for (size_t t = 0; t < tris.size(); ++t) {
        const Vec3 &a = positions[tris[t][0]], &b = positions[tris[t][1]], &c = positions[tris[t][2]];
        const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
        samplesOf[t] = std::clamp(int(std::ceil(longest / step)), 1, 64);
        firstSample[t + 1] = firstSample[t] + size_t((samplesOf[t] + 1) * (samplesOf[t] + 2) / 2);
    }
    std::vector<double> outDist(firstSample.back());
    parallelFor(0, int64_t(tris.size()), [&](int64_t t) {
        const Vec3 &a = positions[tris[size_t(t)][0]], &b = positions[tris[size_t(t)][1]], &c = positions[tris[size_t(t)][2]];
        const int k = samplesOf[size_t(t)];
        size_t at = firstSample[size_t(t)];
        int hint = -1;
        for (int i = 0; i <= k; ++i)
            for (int j = 0; i + j <= k; ++j) {
                const Vec3 p = a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k);
                const ClosestPoint cp = input.closest(p, hint);
                hint = cp.triangle;
                outDist[at++] = std::sqrt(cp.distance2);
            }
    }, 16);
    double maxOut = 0, sumOut = 0;
    const long long nOut = (long long)outDist.size();
    size_t farthestSample = 0;
    for (size_t i = 0; i < outDist.size(); ++i) {
        if (outDist[i] > maxOut) maxOut = outDist[i], farthestSample = i;
        sumOut += outDist[i];
    }
    if (maxOut > 0) { // the sample's point, enumerated as above
        const size_t t = size_t(std::upper_bound(firstSample.begin(), firstSample.end(), farthestSample) -
                                firstSample.begin()) - 1;
        const Vec3 &a = positions[tris[t][0]], &b = positions[tris[t][1]], &c = positions[tris[t][2]];
        const int k = samplesOf[t];
        size_t at = firstSample[t];
        for (int i = 0; i <= k; ++i)
            for (int j = 0; i + j <= k; ++j)
                if (at++ == farthestSample) q.farthestOutputPoint = a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k);
    }
    const AabbTree output(positions, tris);
    double maxIn = 0, sumIn = 0;
    long long nIn = 0;
    if (output.nTriangles() > 0) {
        const int nV = mesh.nVertices(), nF = mesh.nFaces();
        std::vector<double> vertexDist(static_cast<size_t>(nV)), faceDist(static_cast<size_t>(nF));
        std::vector<int> vertexTri(static_cast<size_t>(nV));
        // Vertices in fixed blocks, each search starting from the previous vertex's
        // answer (neighbouring indices are mostly near; the distance does not depend on it).
        parallelForRange(0, nV, [&](int64_t lo, int64_t hi) {
            int hint = -1;
            for (int64_t v = lo; v < hi; ++v) {
                const ClosestPoint cp = output.closest(mesh.position(int(v)), hint);
                vertexDist[size_t(v)] = std::sqrt(cp.distance2);
                vertexTri[size_t(v)] = hint = cp.triangle;
            }
        });
        parallelFor(0, nF, [&](int64_t f) {
            const auto &fc = mesh.face(int(f));
            const Vec3 p = (mesh.position(fc[0]) + mesh.position(fc[1]) + mesh.position(fc[2])) / 3;
            faceDist[size_t(f)] = std::sqrt(output.closest(p, vertexTri[size_t(fc[0])]).distance2);
        });
        for (int v = 0; v < nV; ++v) {
            const double d = vertexDist[size_t(v)];
            if (d > maxIn) maxIn = d, q.farthestInputPoint = mesh.position(v);
            sumIn += d, ++nIn;
        }
        for (int f = 0; f < nF; ++f) {
            const double d = faceDist[size_t(f)];
            if (d > maxIn) {
                maxIn = d;
                const auto &fc = mesh.face(f);
                q.farthestInputPoint = (mesh.position(fc[0]) + mesh.position(fc[1]) + mesh.position(fc[2])) / 3;
            }
            sumIn += d, ++nIn;
        }
    }
    const double pct = q.diagonal > 0 ? 100.0 / q.diagonal : 0;
    q.distanceOutToInPct = maxOut * pct;
    q.distanceInToOutPct = output.nTriangles() > 0 ? maxIn * pct : std::numeric_limits<double>::infinity();
    q.distanceOutToInMeanPct = nOut ? sumOut / double(nOut) * pct : 0;
    q.distanceInToOutMeanPct = nIn ? sumIn / double(nIn) * pct : 0;
    return q;
}

void writeQualityJson(JsonWriter &json, const QualityReport &q) {
    json.beginObject();
    json.field("symmetry", q.nSym).field("edge_length", q.edgeLength).field("bbox_diagonal", q.diagonal);
    json.field("vertices", q.vertices).field("edges", q.edges).field("faces", q.faces);
    json.key("faces_by_sides").beginObject();
    for (const auto &[k, n] : q.facesBySides) json.field(std::to_string(k), n);
    json.endObject();
    json.field(q.nSym == 6 ? "triangle_fraction" : "quad_fraction", q.regularFaceFraction);
    json.key("topology").beginObject();
    json.field("closed", q.closed).field("manifold", q.manifold).field("oriented", q.oriented);
    json.field("euler_characteristic", q.eulerCharacteristic);
    json.field("input_euler_characteristic", q.inputEulerCharacteristic);
    json.field("components", q.components).field("input_components", q.inputComponents);
    json.field("genus", q.genus).field("input_genus", q.inputGenus);
    json.field("boundary_edges", q.boundaryEdges).field("input_boundary_edges", q.inputBoundaryEdges);
    json.field("non_manifold_edges", q.nonManifoldEdges).field("non_manifold_vertices", q.nonManifoldVertices);
    json.field("inconsistent_edges", q.inconsistentEdges).field("isolated_vertices", q.isolatedVertices);
    json.field("degenerate_faces", q.degenerateFaces).field("flipped_faces", q.flippedFaces);
    json.field("kept", !q.topologyLost());
    json.key("problems_at").beginArray();
    for (const Vec3 &p : q.problems) json.beginArray().value(p.x()).value(p.y()).value(p.z()).endArray();
    json.endArray();
    json.endObject();
    json.key("valence_histogram").beginObject();
    for (const auto &[k, n] : q.valenceHistogram) json.field(std::to_string(k), n);
    json.endObject();
    json.key("irregular").beginObject();
    json.field("vertices", q.irregularVertices).field("fraction", q.irregularFraction);
    json.field("valence2", q.valence2Vertices);
    json.field("within_2L_of_singularity", q.irregularNearSingularity);
    json.field("within_two_rings_of_singularity", q.irregularWithinTwoRings);
    json.field("distance_to_singularity_median_L", q.irregularDistanceMedianL);
    json.field("singularities", q.singularities);
    json.field("singularities_with_irregular_vertex", q.singularitiesWithIrregularVertex);
    json.field("singularities_with_irregular_vertex_or_face", q.singularitiesMarked);
    json.field("singularities_as_one_irregular", q.singularitiesAsOneIrregular);
    json.endObject();
    json.key("angle_deviation_deg").beginObject();
    json.field("target", q.nSym == 6 ? 60.0 : 90.0);
    json.field("median", q.angleDevMedianDeg).field("p90", q.angleDevP90Deg);
    json.field("near_singularities_corners", q.cornersNearSingularities);
    json.field("near_singularities_median", q.angleDevNearSingMedianDeg);
    json.field("near_singularities_p90", q.angleDevNearSingP90Deg);
    json.field("singular_rings_corners", q.cornersInSingularRings);
    json.field("singular_rings_median", q.angleDevSingularRingsMedianDeg);
    json.field("singular_rings_p90", q.angleDevSingularRingsP90Deg);
    json.endObject();
    json.key("edge_length").beginObject();
    json.field("mean", q.edgeLengthMean).field("mean_over_L", q.edgeLength > 0 ? q.edgeLengthMean / q.edgeLength : 0);
    json.field("cv", q.edgeLengthCv).endObject();
    json.key("alignment_deg").beginObject().field("median", q.alignmentMedianDeg).field("p90", q.alignmentP90Deg);
    json.endObject();
    json.key("distance_pct_of_diagonal").beginObject();
    json.field("output_to_input", q.distanceOutToInPct).field("input_to_output", q.distanceInToOutPct);
    json.field("output_to_input_mean", q.distanceOutToInMeanPct).field("input_to_output_mean", q.distanceInToOutMeanPct);
    for (const auto &[key, at] : {std::pair{"output_to_input_at", q.farthestOutputPoint},
                                  std::pair{"input_to_output_at", q.farthestInputPoint}})
        json.key(key).beginArray().value(at.x()).value(at.y()).value(at.z()).endArray();
    json.endObject();
    json.endObject();
}

} // namespace rosy::remesh
