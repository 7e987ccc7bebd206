// Topological editing (P&Z Sec. 5.2): pair cancellation and singularity movement.
// Expected values come from theorems and construction, not from the editor:
// Poincaré–Hopf (Σ index = χ, with the boundary term on open meshes), the region's
// Euler characteristic V − E + F = 1 and single boundary loop for a disk, and the
// Dirichlet rows (values outside the region's interior are untouched bit for bit).

#include "core/error.h"
#include "field/design.h"
#include "field/editing.h"
#include "field/field_builder.h"
#include "field/mesh_io.h"
#include "field/mesh_stats.h"
#include "field/primitives.h"
#include "field/singularities.h"
#include "field/smoothing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <set>

using namespace rosy::field;

namespace {

/// Topology of a face set computed from scratch: components (through edges),
/// χ = V − E + F of its closure, number of boundary loops.
struct RegionTopology {
    int components = 0, euler = 0, boundaryLoops = 0;
};

RegionTopology topologyOf(const Mesh &mesh, const std::vector<int> &faces) {
    std::set<int> inR(faces.begin(), faces.end()), verts;
    std::map<std::pair<int, int>, int> edgeUse;
    for (int f : faces)
        for (int k = 0; k < 3; ++k) {
            int a = mesh.face(f)[k], b = mesh.face(f)[(k + 1) % 3];
            verts.insert(a);
            ++edgeUse[{std::min(a, b), std::max(a, b)}];
        }
    RegionTopology t;
    t.euler = int(verts.size()) - int(edgeUse.size()) + int(faces.size());
    // Components by flood fill over shared edges.
    std::set<int> unseen = inR;
    while (!unseen.empty()) {
        ++t.components;
        std::vector<int> stack{*unseen.begin()};
        unseen.erase(unseen.begin());
        while (!stack.empty()) {
            int f = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                int tw = mesh.twin(3 * f + k);
                if (tw >= 0 && unseen.count(tw / 3)) {
                    unseen.erase(tw / 3);
                    stack.push_back(tw / 3);
                }
            }
        }
    }
    // Boundary loops: boundary edges (used once) form cycles; count them by
    // union-find over their endpoints (a pinched vertex would merge two loops, which
    // the manifold disk must not have anyway).
    std::map<int, int> parent;
    std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    int nBoundaryEdges = 0;
    for (const auto &[e, use] : edgeUse)
        if (use == 1) {
            ++nBoundaryEdges;
            for (int v : {e.first, e.second})
                if (!parent.count(v)) parent[v] = v;
            parent[find(e.first)] = find(e.second);
        }
    std::set<int> roots;
    for (const auto &[v, p] : parent) roots.insert(find(v));
    t.boundaryLoops = int(roots.size());
    return t;
}

/// Vertices whose whole fan lies in the region (interior mesh vertices only).
std::set<int> regionInterior(const Mesh &mesh, const std::vector<int> &faces) {
    std::set<int> inR(faces.begin(), faces.end()), out;
    for (int f : faces)
        for (int v : mesh.face(f)) {
            if (mesh.isBoundaryVertex(v)) continue;
            bool all = true;
            for (const int *h = mesh.outgoingBegin(v); h != mesh.outgoingEnd(v); ++h)
                all = all && inR.count(*h / 3);
            if (all) out.insert(v);
        }
    return out;
}

bool sameBits(Complex a, Complex b) { return std::memcmp(&a, &b, sizeof(Complex)) == 0; }

/// Every vertex outside `interior` keeps its exact value.
void expectUnchangedOutside(const Eigen::VectorXcd &before, const Eigen::VectorXcd &after,
                            const std::set<int> &interior) {
    ASSERT_EQ(before.size(), after.size());
    int changedOutside = 0;
    for (int v = 0; v < before.size(); ++v)
        if (!interior.count(v) && !sameBits(before[v], after[v])) ++changedOutside;
    EXPECT_EQ(changedOutside, 0);
}

void expectDisk(const Mesh &mesh, const std::vector<int> &faces) {
    RegionTopology t = topologyOf(mesh, faces);
    EXPECT_EQ(t.components, 1);
    EXPECT_EQ(t.euler, 1);
    EXPECT_EQ(t.boundaryLoops, 1);
}

/// (face, index numerator) of every singularity, for comparing lists.
std::map<int, int> byFace(const SingularityReport &r) {
    std::map<int, int> m;
    for (const Singularity &s : r.singularities) m[s.face] = s.indexNumerator;
    return m;
}

void expectPoincareHopf(const Mesh &mesh, const SingularityReport &r, int nSym) {
    EXPECT_NEAR(r.totalIndex(nSym), computeStats(mesh).eulerCharacteristic, 1e-9);
}

/// Cancels (a, b) and checks every invariant against the state before.
void cancelAndCheck(const TangentFrames &frames, RosyField &field, int a, int b) {
    const Mesh &mesh = frames.mesh();
    const SingularityReport before = findSingularities(frames, field);
    const Eigen::VectorXcd u0 = field.u;
    const int fa = before.singularities[a].face, fb = before.singularities[b].face;
    EditResult r = cancelPair(frames, field, a, b);
    const SingularityReport after = findSingularities(frames, field);
    EXPECT_EQ(after.singularities.size() + 2, before.singularities.size());
    std::map<int, int> expected = byFace(before);
    expected.erase(fa);
    expected.erase(fb);
    EXPECT_EQ(byFace(after), expected);
    EXPECT_TRUE(std::binary_search(r.regionFaces.begin(), r.regionFaces.end(), fa));
    EXPECT_TRUE(std::binary_search(r.regionFaces.begin(), r.regionFaces.end(), fb));
    expectDisk(mesh, r.regionFaces);
    expectUnchangedOutside(u0, field.u, regionInterior(mesh, r.regionFaces));
    expectPoincareHopf(mesh, after, field.nSym);
    EXPECT_TRUE(field.u.allFinite());
}

int idOfFace(const SingularityReport &r, int face) {
    for (size_t i = 0; i < r.singularities.size(); ++i)
        if (r.singularities[i].face == face) return int(i);
    return -1;
}

RosyField designedPair(const TangentFrames &frames, int nSym, const Vec3 &plus, const Vec3 &minus) {
    DesignElement p, m;
    p.position = plus;
    p.order = 1;
    m.position = minus;
    m.order = -1;
    DesignOptions o;
    o.weights = LaplaceWeights::Cotan;
    return designField(frames, nSym, {p, m}, o);
}

} // namespace

TEST(CancelPair, RemovesDesignedPairOnPlanarDisk) {
    const Mesh mesh = makeDisk(16);
    const TangentFrames frames(mesh);
    for (int nSym : {1, 2, 4}) {
        SCOPED_TRACE("N = " + std::to_string(nSym));
        RosyField field = designedPair(frames, nSym, Vec3(-0.3, 0.05, 0), Vec3(0.3, -0.05, 0));
        const SingularityReport before = findSingularities(frames, field);
        ASSERT_EQ(before.singularities.size(), 2u);
        ASSERT_EQ(before.singularities[0].indexNumerator, -before.singularities[1].indexNumerator);
        cancelAndCheck(frames, field, 0, 1);
        EXPECT_TRUE(findSingularities(frames, field).singularities.empty());
    }
}

TEST(CancelPair, NearestPairsOnBunnyCurvatureField) {
    const Mesh mesh = loadMesh(std::string(ROSY_DATA_DIR) + "/meshes/bunny00.off");
    const TangentFrames frames(mesh);
    // ℓ = 0.04 (the default until 2026-12-01) leaves many close opposite pairs, the
    // case cancellation is for; at the default 0.08 the close pairs are already
    // smoothed away and the nearest remaining ones are far apart (3 of 6 cancel).
    FieldSpec spec;
    spec.smoothingLength = 0.04;
    RosyField field = buildField(frames, spec).field;
    SingularityReport report = findSingularities(frames, field);
    // Closest opposite pairs first, identified by face (ids shift after each edit).
    std::vector<std::tuple<double, int, int>> pairs;
    for (const Singularity &s : report.singularities)
        for (const Singularity &t : report.singularities)
            if (s.indexNumerator == 1 && t.indexNumerator == -1)
                pairs.emplace_back((s.position - t.position).norm(), s.face, t.face);
    std::sort(pairs.begin(), pairs.end());
    ASSERT_GE(pairs.size(), 5u);
    std::set<int> used;
    int cancelled = 0, attempts = 0;
    for (const auto &[d, fa, fb] : pairs) {
        if (attempts == 6) break;
        if (used.count(fa) || used.count(fb)) continue;
        used.insert(fa);
        used.insert(fb);
        ++attempts;
        report = findSingularities(frames, field);
        const int a = idOfFace(report, fa), b = idOfFace(report, fb);
        ASSERT_GE(a, 0);
        ASSERT_GE(b, 0);
        const Eigen::VectorXcd u0 = field.u;
        try {
            cancelAndCheck(frames, field, a, b);
            ++cancelled;
        } catch (const rosy::InputError &) {
            EXPECT_TRUE(field.u == u0) << "a refused edit must leave the field unchanged";
        }
    }
    EXPECT_GE(cancelled, 4) << "of " << attempts << " nearest pairs";
}

TEST(CancelPair, RefusesSameSignsBadIdsAndSelf) {
    const Mesh mesh = makeIcosphere(3);
    const TangentFrames frames(mesh);
    RosyField field = smoothestField(frames, 4).field;
    const SingularityReport report = findSingularities(frames, field);
    // Sphere, N = 4: indices sum to χ = 2 and the smoothest field has only +1/4's.
    ASSERT_GE(report.singularities.size(), 2u);
    ASSERT_EQ(report.singularities[0].indexNumerator, report.singularities[1].indexNumerator);
    const Eigen::VectorXcd u0 = field.u;
    const int n = int(report.singularities.size());
    for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 1}, {-1, 0}, {0, n}, {1, 1}}) {
        EXPECT_THROW(cancelPair(frames, field, a, b), rosy::InputError) << a << "," << b;
        EXPECT_TRUE(field.u == u0);
    }
    try {
        cancelPair(frames, field, 0, 1);
    } catch (const rosy::InputError &e) {
        EXPECT_NE(std::string(e.what()).find("#0"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("same sign"), std::string::npos) << e.what();
    }
}

TEST(CancelPair, RefusesPairSeparatedByAnotherSingularity) {
    // Two 8×6 grid patches joined by a corridor one quad (a strip of triangles)
    // wide: every face path between the patches crosses each corridor face.
    std::vector<Vec3> pos;
    std::vector<Face> faces;
    std::map<std::pair<int, int>, int> id;
    auto vertex = [&](int x, int y) {
        auto [it, fresh] = id.try_emplace({x, y}, int(pos.size()));
        if (fresh) pos.emplace_back(x, y, 0);
        return it->second;
    };
    for (int x = 0; x < 20; ++x)
        for (int y = 0; y < 6; ++y) {
            if (x >= 8 && x < 12 && y != 3) continue;
            int a = vertex(x, y), b = vertex(x + 1, y), c = vertex(x + 1, y + 1), d = vertex(x, y + 1);
            faces.push_back({a, b, c});
            faces.push_back({a, c, d});
        }
    const Mesh mesh = Mesh::fromTriangles(pos, faces, "dumbbell");
    const TangentFrames frames(mesh);
    DesignElement plus, minus, middle;
    plus.position = Vec3(3.7, 3.2, 0);
    plus.order = 1;
    minus.position = Vec3(16.7, 3.2, 0);
    minus.order = -1;
    middle.position = Vec3(10.7, 3.2, 0);
    middle.order = 1;
    DesignOptions o;
    o.weights = LaplaceWeights::Cotan;
    RosyField field = designField(frames, 4, {plus, minus, middle}, o);
    const SingularityReport report = findSingularities(frames, field);
    const int a = idOfFace(report, snapToSurface(mesh, plus.position).face);
    const int b = idOfFace(report, snapToSurface(mesh, minus.position).face);
    ASSERT_GE(a, 0);
    ASSERT_GE(b, 0);
    ASSERT_GE(idOfFace(report, snapToSurface(mesh, middle.position).face), 0);
    const Eigen::VectorXcd u0 = field.u;
    try {
        cancelPair(frames, field, a, b);
        ADD_FAILURE() << "cancelled across a singular corridor";
    } catch (const rosy::InputError &e) {
        EXPECT_NE(std::string(e.what()).find("another singularity"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(field.u == u0);
}

TEST(MoveSingularity, AwayAndBackOnIcosphere) {
    const Mesh mesh = makeIcosphere(3);
    const TangentFrames frames(mesh);
    RosyField field = smoothestField(frames, 4).field;
    const SingularityReport start = findSingularities(frames, field);
    ASSERT_FALSE(start.singularities.empty());
    const Singularity s0 = start.singularities[0];
    // Target: a face 4 edge-steps away (breadth-first), the farthest such face from
    // every other singularity.
    std::vector<int> depth(mesh.nFaces(), -1);
    std::vector<int> queue{s0.face};
    depth[s0.face] = 0;
    for (size_t i = 0; i < queue.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            int g = mesh.twin(3 * queue[i] + k) / 3;
            if (depth[g] < 0) {
                depth[g] = depth[queue[i]] + 1;
                queue.push_back(g);
            }
        }
    int target = -1;
    double bestClearance = -1;
    for (int f = 0; f < mesh.nFaces(); ++f) {
        if (depth[f] != 4) continue;
        const Face &t = mesh.face(f);
        const Vec3 c = (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
        double clearance = 1e300;
        for (size_t j = 1; j < start.singularities.size(); ++j)
            clearance = std::min(clearance, (start.singularities[j].position - c).norm());
        if (clearance > bestClearance) {
            bestClearance = clearance;
            target = f;
        }
    }
    ASSERT_GE(target, 0);
    auto centroidOf = [&](int f) {
        const Face &t = mesh.face(f);
        return Vec3((mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0);
    };

    auto moveAndCheck = [&](int from, int to) {
        const SingularityReport before = findSingularities(frames, field);
        const Eigen::VectorXcd u0 = field.u;
        const int id = idOfFace(before, from);
        ASSERT_GE(id, 0);
        EditResult r = moveSingularity(frames, field, id, centroidOf(to));
        EXPECT_EQ(r.targetFace, to);
        const SingularityReport after = findSingularities(frames, field);
        std::map<int, int> expected = byFace(before);
        const int k = expected[from];
        expected.erase(from);
        expected[to] = k;
        EXPECT_EQ(byFace(after), expected);
        expectDisk(mesh, r.regionFaces);
        expectUnchangedOutside(u0, field.u, regionInterior(mesh, r.regionFaces));
        expectPoincareHopf(mesh, after, 4);
    };
    moveAndCheck(s0.face, target);
    moveAndCheck(target, s0.face);
}

TEST(MoveSingularity, RefusesBadIdAndOccupiedOrOffSurfaceTarget) {
    const Mesh mesh = makeIcosphere(3);
    const TangentFrames frames(mesh);
    RosyField field = smoothestField(frames, 4).field;
    const SingularityReport report = findSingularities(frames, field);
    ASSERT_GE(report.singularities.size(), 2u);
    const Eigen::VectorXcd u0 = field.u;
    EXPECT_THROW(moveSingularity(frames, field, int(report.singularities.size()), Vec3(1, 0, 0)),
                 rosy::InputError);
    EXPECT_THROW(moveSingularity(frames, field, 0, report.singularities[1].position), rosy::InputError);
    EXPECT_THROW(moveSingularity(frames, field, 0, Vec3(10, 0, 0)), rosy::InputError);
    EXPECT_TRUE(field.u == u0);
}

TEST(NearestOppositePair, PicksTheOppositeSignsClosestToEachPoint) {
    std::vector<Singularity> s(4);
    s[0].indexNumerator = 1, s[0].position = Vec3(0, 0, 0);
    s[1].indexNumerator = -1, s[1].position = Vec3(5, 0, 0);
    s[2].indexNumerator = 1, s[2].position = Vec3(4, 0, 0);
    s[3].indexNumerator = -1, s[3].position = Vec3(1, 0, 0);
    // Near (0,0,0) and (5,0,0): #0 (+) with #1 (−), cost 0.
    EXPECT_EQ(nearestOppositePair(s, Vec3(0, 0, 0), Vec3(5, 0, 0)), std::make_pair(0, 1));
    // Near (4.1,0,0) and (1.1,0,0): #2 (+) with #3 (−).
    EXPECT_EQ(nearestOppositePair(s, Vec3(4.1, 0, 0), Vec3(1.1, 0, 0)), std::make_pair(2, 3));
    s[1].indexNumerator = s[3].indexNumerator = 1;
    EXPECT_THROW(nearestOppositePair(s, Vec3::Zero(), Vec3::Zero()), rosy::InputError);
}
