#include "remesh/edge_lines.h"

#include <algorithm>
#include <cmath>

namespace rosy::remesh {

namespace {

using HH = OpenMesh::HalfedgeHandle;
using VH = OpenMesh::VertexHandle;

/// Lines go on through an irregular vertex only along an edge this close to straight on.
constexpr double kMaxIrregularTurnDeg = 20.0;
/// Rounds of averaging the edges' family scores over their neighbours.
constexpr int kFamilyRounds = 8;
/// A vertex votes for a family only when the normal turns by more than this (radians,
/// over its two edges in the faster direction) and the two directions' turns differ
/// by more than kMinVoteContrast of the larger.
constexpr double kMinVoteTurn = 0.02;
constexpr double kMinVoteContrast = 0.25;
/// Vertices of this valence or more are the centres of fans (remesh.cpp fills
/// polygons of more than six sides with a fan round their centroid): their spokes
/// are no lattice lines, and drawn they read as a star, so they are on no line.
constexpr size_t kFanValence = 7;
constexpr int kFan = -2;

/// The halfedge a line arriving along h leaves by at h's head (edge_lines.h), or an
/// invalid handle where lines end there.
HH straightOn(const field::PolyMesh &mesh, HH h) {
    const VH v = mesh.to_vertex_handle(h);
    const size_t valence = mesh.valence(v);
    if (!mesh.is_boundary(v)) {
        // Outgoing halfedges of v in turn: opposite(h), then two steps round.
        if (valence == 4)
            return mesh.cw_rotated_halfedge_handle(mesh.cw_rotated_halfedge_handle(mesh.opposite_halfedge_handle(h)));
        // Irregular: on along the edge that turns least, if it turns less than
        // kMaxIrregularTurnDeg (an edge two steps round turns by 360° / valence
        // less than straight on, so a line at a valence-3 or -5 vertex mostly ends).
        const auto &pv = mesh.point(v);
        const auto in = pv - mesh.point(mesh.from_vertex_handle(h));
        HH best;
        double bestCos = std::cos(kMaxIrregularTurnDeg * M_PI / 180.0);
        for (auto it = mesh.cvoh_iter(v); it.is_valid(); ++it) {
            const auto out = mesh.point(mesh.to_vertex_handle(*it)) - pv;
            const double c = OpenMesh::dot(in, out) / std::max(in.norm() * out.norm(), 1e-300);
            if (c > bestCos) {
                bestCos = c;
                best = *it;
            }
        }
        return best;
    }
    if (valence != 3 || !mesh.is_boundary(mesh.edge_handle(h))) return HH();
    for (auto it = mesh.cvoh_iter(v); it.is_valid(); ++it) {
        const HH out = *it;
        if (mesh.edge_handle(out) != mesh.edge_handle(h) && mesh.is_boundary(mesh.edge_handle(out))) return out;
    }
    return HH();
}

} // namespace

std::vector<EdgeLine> edgeLines(const field::PolyMesh &mesh) {
    const size_t nEdges = mesh.n_edges();
    // −1: on no line yet; kFan: on none ever (an edge at a fan's centre).
    std::vector<int> lineOf(nEdges, -1);
    for (size_t e = 0; e < nEdges; ++e) {
        const HH h = mesh.halfedge_handle(mesh.edge_handle(int(e)), 0);
        if (mesh.valence(mesh.from_vertex_handle(h)) >= kFanValence ||
            mesh.valence(mesh.to_vertex_handle(h)) >= kFanValence)
            lineOf[e] = kFan;
    }
    std::vector<EdgeLine> lines;
    std::vector<std::vector<int>> lineEdges; // per line, its edges in order along it
    auto point = [&](VH v) {
        const auto &p = mesh.point(v);
        return Vec3(p[0], p[1], p[2]);
    };
    // Unit vertex normals (the mean of the faces' around each), once: the lines carry
    // them and the family votes compare them.
    std::vector<Vec3> vertexNormal(mesh.n_vertices(), Vec3::Zero());
    for (auto v : mesh.vertices()) {
        Vec3 n = Vec3::Zero();
        for (auto f : mesh.vf_range(v)) {
            const auto fn = mesh.calc_face_normal(f);
            n += Vec3(fn[0], fn[1], fn[2]);
        }
        const double len = n.norm();
        if (len > 0) vertexNormal[size_t(v.idx())] = n / len;
    }
    for (size_t e = 0; e < nEdges; ++e) {
        if (lineOf[e] != -1) continue;
        const auto eh = mesh.edge_handle(int(e));
        if (mesh.has_edge_status() && mesh.status(eh).deleted()) continue;
        const int id = int(lines.size());
        EdgeLine line;
        lineOf[e] = id;
        std::vector<int> forwardEdges{int(e)}, backwardEdges;
        // Forward from the edge's first halfedge, then backward from its opposite.
        const HH start = mesh.halfedge_handle(eh, 0);
        std::vector<VH> forward{mesh.from_vertex_handle(start), mesh.to_vertex_handle(start)};
        for (HH h = straightOn(mesh, start); h.is_valid(); h = straightOn(mesh, h)) {
            const size_t ei = size_t(mesh.edge_handle(h).idx());
            if (ei == e) { // round to the first edge: a closed line
                line.closed = true;
                forward.pop_back(); // the first vertex again
                break;
            }
            if (lineOf[ei] != -1) break; // another line took it through an irregular vertex, or a fan's
            lineOf[ei] = id;
            forwardEdges.push_back(int(ei));
            forward.push_back(mesh.to_vertex_handle(h));
        }
        std::vector<VH> backward;
        if (!line.closed)
            for (HH h = straightOn(mesh, mesh.opposite_halfedge_handle(start)); h.is_valid(); h = straightOn(mesh, h)) {
                const size_t ei = size_t(mesh.edge_handle(h).idx());
                if (lineOf[ei] != -1) break;
                lineOf[ei] = id;
                backwardEdges.push_back(int(ei));
                backward.push_back(mesh.to_vertex_handle(h));
            }
        std::vector<VH> all(backward.rbegin(), backward.rend());
        all.insert(all.end(), forward.begin(), forward.end());
        line.points.reserve(all.size());
        line.normals.reserve(all.size());
        for (VH v : all) {
            line.points.push_back(point(v));
            line.normals.push_back(vertexNormal[size_t(v.idx())]);
        }
        lines.push_back(std::move(line));
        std::vector<int> edges(backwardEdges.rbegin(), backwardEdges.rend());
        edges.insert(edges.end(), forwardEdges.begin(), forwardEdges.end());
        lineEdges.push_back(std::move(edges));
    }

    // Neighbouring parallel lines: the lines of the opposite sides of every quad.
    std::vector<std::vector<int>> neighbours(lines.size());
    for (auto f : mesh.faces()) {
        if ((mesh.has_face_status() && mesh.status(f).deleted()) || mesh.valence(f) != 4) continue;
        int side[4], k = 0;
        for (auto h : mesh.fh_range(f)) side[k++] = lineOf[size_t(mesh.edge_handle(h).idx())];
        for (int a = 0; a < 2; ++a) {
            const int l1 = side[a], l2 = side[a + 2];
            if (l1 < 0 || l2 < 0 || l1 == l2) continue;
            neighbours[size_t(l1)].push_back(l2);
            neighbours[size_t(l2)].push_back(l1);
        }
    }
    // Breadth-first 2-colouring from each uncoloured line in order; a neighbour
    // already coloured keeps its colour (odd cycles around singular vertices).
    std::vector<int> colour(lines.size(), -1), queue;
    for (size_t root = 0; root < lines.size(); ++root) {
        if (colour[root] >= 0) continue;
        colour[root] = 0;
        queue.assign(1, int(root));
        for (size_t q = 0; q < queue.size(); ++q) {
            const int l = queue[q];
            for (int n : neighbours[size_t(l)])
                if (colour[size_t(n)] < 0) {
                    colour[size_t(n)] = 1 - colour[size_t(l)];
                    queue.push_back(n);
                }
        }
    }
    for (size_t l = 0; l < lines.size(); ++l) lines[l].parity = colour[l];

    // Families: edges 2-coloured over the quads, breadth-first from each quad not yet
    // reached, in face order; an edge keeps the first colour it gets.
    std::vector<int> edgeColour(nEdges, -1);
    std::vector<char> seen(mesh.n_faces(), 0);
    std::vector<OpenMesh::FaceHandle> faces;
    auto colourFace = [&](OpenMesh::FaceHandle f) {
        HH side[4];
        int k = 0;
        for (auto h : mesh.fh_range(f)) side[k++] = h;
        int first = -1;
        for (int j = 0; j < 4 && first < 0; ++j)
            if (edgeColour[size_t(mesh.edge_handle(side[j]).idx())] >= 0) first = j;
        const int base = first < 0 ? 0 : edgeColour[size_t(mesh.edge_handle(side[first]).idx())];
        if (first < 0) first = 0;
        for (int j = 0; j < 4; ++j) {
            int &c = edgeColour[size_t(mesh.edge_handle(side[(first + j) % 4]).idx())];
            if (c < 0) c = base ^ (j & 1);
        }
    };
    for (auto f0 : mesh.faces()) {
        if (seen[size_t(f0.idx())] || (mesh.has_face_status() && mesh.status(f0).deleted()) || mesh.valence(f0) != 4) continue;
        seen[size_t(f0.idx())] = 1;
        faces.assign(1, f0);
        for (size_t q = 0; q < faces.size(); ++q) {
            colourFace(faces[q]);
            for (auto g : mesh.ff_range(faces[q]))
                if (!seen[size_t(g.idx())] && !(mesh.has_face_status() && mesh.status(g).deleted()) && mesh.valence(g) == 4) {
                    seen[size_t(g.idx())] = 1;
                    faces.push_back(g);
                }
        }
    }
    // Around the form first: at each regular interior vertex, of the two directions
    // crossing there the one along which the normal turns clearly more (over its two
    // edges, which are about L long both ways) scores +1 on its edges, the other −1 — on a
    // cylinder the rings, not the rulings. The scores are averaged over the edges'
    // neighbours (the opposite side of each quad, the next edge along the line) for
    // kFamilyRounds rounds, so an edge of an umbilic patch, whose own vote is noise,
    // follows those around it; family 0 where the result is positive, 1 where it is
    // negative, the colouring above where it is zero (flat parts).
    auto turning = [&](HH h) { // the angle the normal turns by along h (about |Δn|)
        const VH a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
        return (vertexNormal[size_t(b.idx())] - vertexNormal[size_t(a.idx())]).norm();
    };
    std::vector<double> score(nEdges, 0.0), weight(nEdges, 0.0), next(nEdges);
    for (auto v : mesh.vertices()) {
        if (mesh.is_boundary(v) || mesh.valence(v) != 4) continue;
        HH out[4];
        int k = 0;
        for (auto it = mesh.cvoh_iter(v); it.is_valid() && k < 4; ++it) out[k++] = *it;
        // Only a clear difference votes: on a flat or umbilic part the normals' turns
        // are rounding noise, which would hatch a flat face in a maze of patches; there
        // the colouring decides, the same all over the face.
        const double ka = turning(out[0]) + turning(out[2]), kb = turning(out[1]) + turning(out[3]);
        const double larger = std::max(ka, kb);
        const bool clear = larger > kMinVoteTurn && std::abs(ka - kb) > kMinVoteContrast * larger;
        const double vote = !clear ? 0.0 : ka > kb ? 1.0 : -1.0;
        for (int j = 0; j < 4; ++j) {
            const size_t ej = size_t(mesh.edge_handle(out[j]).idx());
            score[ej] += j % 2 == 0 ? vote : -vote;
            weight[ej] += 1.0;
        }
    }
    std::vector<std::vector<int>> edgeNeighbours(nEdges);
    for (auto f : mesh.faces()) {
        if ((mesh.has_face_status() && mesh.status(f).deleted()) || mesh.valence(f) != 4) continue;
        int side[4], k = 0;
        for (auto h : mesh.fh_range(f)) side[k++] = mesh.edge_handle(h).idx();
        for (int a = 0; a < 2; ++a) {
            edgeNeighbours[size_t(side[a])].push_back(side[a + 2]);
            edgeNeighbours[size_t(side[a + 2])].push_back(side[a]);
        }
    }
    for (size_t l = 0; l < lines.size(); ++l) {
        const std::vector<int> &edges = lineEdges[l];
        for (size_t k = 0; k + 1 < edges.size(); ++k) {
            edgeNeighbours[size_t(edges[k])].push_back(edges[k + 1]);
            edgeNeighbours[size_t(edges[k + 1])].push_back(edges[k]);
        }
    }
    for (size_t e = 0; e < nEdges; ++e)
        if (weight[e] > 0) score[e] /= weight[e];
    for (int round = 0; round < kFamilyRounds; ++round) {
        for (size_t e = 0; e < nEdges; ++e) {
            double sum = weight[e] * score[e], w = weight[e];
            for (int n : edgeNeighbours[e]) {
                sum += weight[size_t(n)] * score[size_t(n)];
                w += weight[size_t(n)];
            }
            next[e] = w > 0 ? sum / w : 0.0;
        }
        score.swap(next);
    }
    for (size_t l = 0; l < lines.size(); ++l) {
        std::vector<int> &families = lines[l].families;
        families.reserve(lineEdges[l].size());
        for (int e : lineEdges[l]) {
            const double sc = score[size_t(e)];
            families.push_back(sc > 0 ? 0 : sc < 0 ? 1 : std::max(edgeColour[size_t(e)], 0));
        }
    }
    return lines;
}

} // namespace rosy::remesh
