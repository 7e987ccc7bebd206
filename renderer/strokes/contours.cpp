#include "renderer/strokes/contours.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace rosy::renderer {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Sampling and noise-tolerant chaining, in raster pixels (Blender Line Art's
// noise-tolerant chaining idea: occlusion flips shorter than a couple of pixels
// are noise of the discrete visibility test, not real T-junctions).
constexpr double kSampleStepPx = 1.0; // visibility sample spacing along a chain
constexpr double kMaxGapPx = 3.0;     // hidden gaps up to this (between visible samples) are bridged
constexpr double kMinRunPx = 2.0;     // shorter visible runs are dropped
constexpr double kDepthTolPx = 2.0;   // depth tolerance, in pixels' worth of world size
constexpr double kTaperPx = 6.0;      // taper length at open chain ends
constexpr double kTaperMinWidth = 0.35; // width fraction at the very tip
constexpr double kOutlineReachPx = 0.9; // a silhouette line reaches at most this far past the outline
constexpr double kOutlineProbePx = 2.0; // across-line distance at which its two sides are read
// At a junction (a node with other than two segments) a chain continues only into
// a segment turning less than this, preferring the straightest one.
constexpr double kMaxJunctionTurnDeg = 45.0;
// Outlines are judged at the picture's scale (ContourStyle::featureScalePx) when more
// than kScanNoiseEdgeFraction of the mesh's edges, and more than kScanNoiseCreaseFraction
// of the edges whose faces bend past the crease angle, are creases only below it (a
// scan's noise; Extractor::computeFaceNormalsAndCreases). The walks over the surface
// that measure a crease cross at most kMaxWalkFaces faces.
constexpr double kScanNoiseEdgeFraction = 0.05;
constexpr double kScanNoiseCreaseFraction = 0.75;
constexpr int kMaxWalkFaces = 64;

enum class SegClass : uint8_t { Silhouette, Crease, Border };

/// One piece of contour: a face segment of the interpolated silhouette or a mesh edge.
struct Segment {
    std::array<Vec3, 2> p = {Vec3::Zero(), Vec3::Zero()}; // world endpoints
    std::array<int, 2> node = {-1, -1}; // chaining keys of the endpoints (see nodeOf* below)
    std::array<int, 2> face = {-1, -1}; // faces the segment lies on (second -1 if one)
    SegClass cls = SegClass::Silhouette;
    bool valid = false;
};

/// Silhouettes chain only with silhouettes; creases with creases and borders, so a
/// stroke keeps one width class.
int groupOf(SegClass c) { return c == SegClass::Silhouette ? 0 : 1; }

struct Chain {
    std::vector<Vec3> points;  // world polyline; closed chains do not repeat the first point
    std::vector<int> segments; // segment of each polyline edge (points.size() - 1, or size() when closed)
    bool closed = false;
    int group = 0;
};

struct Sample {
    Vec2 pRaster = Vec2::Zero();
    Vec3 pWorld = Vec3::Zero();
    int segment = -1;
    double arc = 0.0;
    enum State : uint8_t { Visible, Hidden, Invalid } state = Hidden;
};

double smoothstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

class Extractor {
public:
    Extractor(const field::Mesh &mesh, const Camera &camera, const RayScene &scene,
              const GBuffer &gbuffer, const styles::ContourStyle &style, bool scanCopy)
        : m_mesh(mesh), m_camera(camera), m_scene(scene), m_gbuffer(gbuffer), m_style(style), m_scanCopy(scanCopy) {}

    StrokeList run(ContourReport *report);

private:
    void computeFaceNormalsAndCreases();
    bool creaseAtPictureScale(int h, double cosLimitChord) const;
    /// A straight walk over the surface (creaseAtPictureScale): the face it is in, entered
    /// through halfedge `entry`, its point and unit heading, how far it has come and
    /// through how many faces, and whether it has stopped for good.
    struct SurfaceWalk {
        int entry;
        Vec3 p, dir;
        double walked = 0.0;
        int faces = 0;
        bool stopped = false;
    };
    Vec3 advance(SurfaceWalk &w, double dist, double reach, double ownDot, bool &sharper) const;
    void computeCornerValues();
    void buildSegments();
    void buildChains();
    bool tooSmallToDraw(const Chain &chain) const;
    void traceChain(int start, Chain &chain, std::vector<uint8_t> &used) const;
    int nextSegment(int node, int group, const Vec2 &dirIn, const std::vector<uint8_t> &used) const;
    std::vector<Stroke> strokesOfChain(const Chain &chain) const;
    bool sampleVisible(const Sample &s) const;
    bool onSegmentFace(int face, int segment) const;
    double pixelWorldSize(double depth) const;
    void insetSilhouette(Stroke &st, bool closedLoop) const;
    void emitRun(const std::vector<Sample> &samples, int begin, int end, bool hidden,
                 bool closedLoop, int group, std::vector<Stroke> &out) const;

    const field::Mesh &m_mesh;
    const Camera &m_camera;
    const RayScene &m_scene;
    const GBuffer &m_gbuffer;
    const styles::ContourStyle &m_style;

    const std::vector<Vec3> &m_faceNormal = m_mesh.faceNormals(); // #F unit (zero for degenerate faces)
    std::vector<uint8_t> m_crease;    // #E 1 if a crease edge
    std::vector<double> m_cornerG;    // #3F n·v at corner tail(h) of face h/3, auto-smoothed n
    std::vector<Segment> m_segments;  // compacted, deterministic order: faces then edges
    // (group * nNodes + node, segment) sorted: the incidence of chaining nodes. Sorted
    // pairs rather than a CSR over all possible nodes, which would be mostly empty.
    std::vector<std::pair<int64_t, int>> m_incidence;
    int64_t m_nNodes = 0;
    std::vector<Chain> m_chains;
    int m_smallLoopsDropped = 0;
    int m_creasesBelowScale = 0; // edges whose faces bend past the threshold but not the surface at the picture's scale
    bool m_scanCopy = false;     // the mesh is a noisy scan's smoothed copy: judged as a scan
    bool m_pictureScale = false; // outlines judged at the picture's scale (a scan's noise; see computeFaceNormalsAndCreases)
};

void Extractor::computeFaceNormalsAndCreases() {
    const int nE = m_mesh.nEdges();
    // Dihedral angle (180° = flat) below the threshold <=> the normals turn by more
    // than 180° − threshold, i.e. n0·n1 < cos(180° − threshold).
    const double threshold = m_style.creaseAngleDeg * kPi / 180.0;
    const double cosLimit = std::cos(kPi - threshold);
    const bool judge = m_style.featureScalePx > 0.0;
    // 1: a crease; 2: its faces bend past the threshold but the surface does not at
    // the picture's scale (creaseAtPictureScale).
    m_crease.assign(size_t(nE), 0);
    parallelFor(0, nE, [&](int64_t e) {
        int h = m_mesh.edgeHalfedge(int(e)), t = m_mesh.twin(h);
        if (t < 0) return;
        const Vec3 &n0 = m_faceNormal[size_t(field::Mesh::faceOf(h))];
        const Vec3 &n1 = m_faceNormal[size_t(field::Mesh::faceOf(t))];
        // A zero-area face has no orientation to bend against.
        if (n0.squaredNorm() == 0.0 || n1.squaredNorm() == 0.0) return;
        if (n0.dot(n1) >= cosLimit) return;
        m_crease[size_t(e)] = judge && !creaseAtPictureScale(h, std::cos(threshold)) ? 2 : 1;
    });
    int64_t bent = 0;
    m_creasesBelowScale = 0;
    for (uint8_t c : m_crease) {
        bent += c != 0;
        m_creasesBelowScale += c == 2;
    }
    // The outlines are judged at the picture's scale only where such creases are both
    // common and most of the creases there are: on a scan, whose noise and needles make
    // them everywhere. On a modelled mesh they are the few narrow real details (a
    // toenail's rim, a groove; a machine part's small fillets in a small picture) among
    // its real creases, and every crease is drawn as before.
    // A noisy scan's smoothed copy (field/scan_noise.h) keeps its needles, whose
    // residue still bends below the scale in places: it is a scan whatever the counts.
    m_pictureScale = judge && (m_scanCopy || (m_creasesBelowScale > kScanNoiseEdgeFraction * nE &&
                                              m_creasesBelowScale > kScanNoiseCreaseFraction * double(bent)));
    for (uint8_t &c : m_crease) c = c == 1 || (c == 2 && !m_pictureScale) ? 1 : 0;
}

/// Advances a straight walk over the surface to `dist` from its start and returns the
/// point reached. At each edge crossed the heading is unfolded into the next face: it
/// keeps its component along the edge and turns the rest into the next face's plane.
/// The walk stops for good at a border, a degenerate face, or after kMaxWalkFaces
/// faces (the point is then where it stopped). `sharper` is set when an edge crossed
/// within `reach` of the start bends more than normals of dot product `ownDot`.
Vec3 Extractor::advance(SurfaceWalk &w, double dist, double reach, double ownDot, bool &sharper) const {
    while (!w.stopped && w.faces < kMaxWalkFaces) {
        const Vec3 &n = m_faceNormal[size_t(field::Mesh::faceOf(w.entry))];
        if (n.squaredNorm() == 0.0) break;
        // Leave through the nearer of the two other edges that the heading points out of.
        double best = std::numeric_limits<double>::infinity();
        int exit = -1;
        for (int he = field::Mesh::next(w.entry); he != w.entry; he = field::Mesh::next(he)) {
            const Vec3 &a = m_mesh.position(m_mesh.tail(he));
            const Vec3 inward = n.cross(m_mesh.position(m_mesh.head(he)) - a);
            const double rate = w.dir.dot(inward);
            if (rate >= 0.0) continue;
            const double t = std::max(0.0, (a - w.p).dot(inward) / rate);
            if (t < best) {
                best = t;
                exit = he;
            }
        }
        if (exit < 0) break;
        if (w.walked + best >= dist) return w.p + (dist - w.walked) * w.dir;
        const int next = m_mesh.twin(exit);
        if (next < 0) break;
        const Vec3 &n2 = m_faceNormal[size_t(field::Mesh::faceOf(next))];
        if (n2.squaredNorm() == 0.0) break;
        w.p += best * w.dir;
        w.walked += best;
        if (w.walked <= reach && n.dot(n2) < ownDot) sharper = true;
        const Vec3 a = m_mesh.position(m_mesh.tail(next)), b = m_mesh.position(m_mesh.head(next));
        const Vec3 along = (b - a).normalized();
        const double c = w.dir.dot(along);
        w.dir = c * along + std::sqrt(std::max(0.0, 1.0 - c * c)) * n2.cross(b - a).normalized();
        w.entry = next;
        ++w.faces;
    }
    w.stopped = true;
    return w.p;
}

/// Whether the edge of h, whose two faces bend by more than the crease threshold, is a
/// crease at the picture's scale s = featureScalePx. From the edge's midpoint the
/// surface is walked straight away from the edge on either side, s/4 and s pixels'
/// worth of world size; at both lengths the two points reached must make an angle at
/// the midpoint below the threshold (cosine above cosLimitChord): for flat faces the
/// angle between the two chords is the dihedral angle itself, so a fold with flat
/// sides passes at any length, while a scan's noise (a few tenths of a pixel over a
/// pixel or two) and its needle triangles do not survive the longer one. And no edge
/// crossed within s/2 may bend more than this one: beside a real fold, the long chords
/// of the noise next to it see that fold, not their own. Where the walks stay inside
/// the edge's own two faces (every crease of a coarse solid) the faces' test stands.
bool Extractor::creaseAtPictureScale(int h, double cosLimitChord) const {
    const int t = m_mesh.twin(h);
    const Vec3 a = m_mesh.position(m_mesh.tail(h)), b = m_mesh.position(m_mesh.head(h));
    const Vec3 &n0 = m_faceNormal[size_t(field::Mesh::faceOf(h))], &n1 = m_faceNormal[size_t(field::Mesh::faceOf(t))];
    const Vec3 mid = 0.5 * (a + b);
    const double s = m_style.featureScalePx * pixelWorldSize(std::max(m_camera.depth(mid), 1e-12));
    const Vec3 in0 = n0.cross(b - a).normalized(), in1 = n1.cross(a - b).normalized();
    const double ownDot = n0.dot(n1);
    SurfaceWalk w0{h, mid, in0}, w1{t, mid, in1};
    bool sharper = false;
    for (double dist : {0.25 * s, s}) {
        const Vec3 p0 = advance(w0, dist, 0.5 * s, ownDot, sharper);
        const Vec3 p1 = advance(w1, dist, 0.5 * s, ownDot, sharper);
        if (sharper) return false;
        if (w0.faces == 0 && w1.faces == 0) continue;
        // A walk that could not leave the edge (a border or a degenerate face right
        // there) keeps its face's own direction.
        Vec3 u0 = p0 - mid, u1 = p1 - mid;
        u0 = u0.squaredNorm() > 1e-6 * dist * dist ? Vec3(u0.normalized()) : in0;
        u1 = u1.squaredNorm() > 1e-6 * dist * dist ? Vec3(u1.normalized()) : in1;
        if (u0.dot(u1) <= cosLimitChord) return false;
    }
    return true;
}

void Extractor::computeCornerValues() {
    // Auto-smoothed corner normals: the angle-weighted average of the face normals
    // around a vertex, but only over the fan reachable without crossing a crease.
    // On a flat-faced solid each corner then keeps its own face normal and the
    // interpolated silhouette degenerates exactly to the front/back crease edges.
    const int nV = m_mesh.nVertices();
    const std::vector<double> &cornerAngle = m_mesh.cornerAngles();
    m_cornerG.resize(size_t(m_mesh.nHalfedges()));
    parallelFor(0, nV, [&](int64_t vi) {
        int v = int(vi);
        const int *ring = m_mesh.outgoingBegin(v);
        int d = m_mesh.degree(v);
        // Scratch on the stack for ordinary valences; the heap only for huge fans.
        constexpr int kSmall = 32;
        int parentBuf[kSmall];
        Vec3 sumBuf[kSmall];
        std::vector<int> parentHeap;
        std::vector<Vec3> sumHeap;
        int *parent = parentBuf;
        Vec3 *sum = sumBuf;
        if (d > kSmall) {
            parentHeap.resize(size_t(d));
            sumHeap.resize(size_t(d));
            parent = parentHeap.data();
            sum = sumHeap.data();
        }
        auto root = [&](int i) {
            while (parent[i] != i) i = parent[i] = parent[parent[i]];
            return i;
        };
        for (int i = 0; i < d; ++i) {
            parent[i] = i;
            sum[i] = Vec3::Zero();
        }
        for (int i = 0; i < d; ++i) {
            int h = ring[i], t = m_mesh.twin(h);
            if (t < 0 || m_crease[size_t(m_mesh.edgeOf(h))]) continue;
            int other = field::Mesh::next(t); // leaves v in the neighbouring face
            for (int j = 0; j < d; ++j) {
                if (ring[j] != other) continue;
                int a = root(i), b = root(j);
                // Union toward the smaller index: the sums below then run in ring order.
                if (a != b) parent[std::max(a, b)] = std::min(a, b);
                break;
            }
        }
        for (int i = 0; i < d; ++i) {
            int h = ring[i];
            sum[root(i)] += cornerAngle[size_t(h)] * m_faceNormal[size_t(field::Mesh::faceOf(h))];
        }
        Vec3 view = m_camera.toViewer(m_mesh.position(v));
        for (int i = 0; i < d; ++i) {
            int h = ring[i];
            const Vec3 &n = sum[root(i)];
            // Unnormalized sums give the same sign; normalizing keeps g an honest cosine
            // so the linear zero crossing is not skewed by fan sizes.
            double len = n.norm();
            Vec3 nh = len > 0.0 ? Vec3(n / len) : m_faceNormal[size_t(field::Mesh::faceOf(h))];
            m_cornerG[size_t(h)] = nh.dot(view);
        }
    });
}

void Extractor::buildSegments() {
    const int nV = m_mesh.nVertices(), nE = m_mesh.nEdges(), nF = m_mesh.nFaces();
    // Node keys: mesh vertex v -> v; silhouette crossing on a smooth edge e -> nV + e
    // (shared by both faces, so chains pass through); crossing on a crease or border
    // halfedge h -> nV + nE + h (each side has its own normals, hence its own point).
    m_nNodes = int64_t(nV) + nE + 3 * int64_t(nF);
    // Segments are gathered per fixed block of faces or edges and concatenated in block
    // order: the same list for any thread count, without a slot per mesh element.
    constexpr int64_t kBlock = 4096;
    const int64_t nFaceBlocks = (nF + kBlock - 1) / kBlock, nEdgeBlocks = (nE + kBlock - 1) / kBlock;
    std::vector<std::vector<Segment>> blocks(size_t(nFaceBlocks + nEdgeBlocks));

    auto faceSegment = [&](int f) {
        Segment s;
        int found = 0;
        for (int k = 0; k < 3 && found < 2; ++k) {
            int h = 3 * f + k, hn = field::Mesh::next(h);
            // g >= 0 counts as front so that each face has exactly 0 or 2 crossings.
            if ((m_cornerG[size_t(h)] >= 0.0) == (m_cornerG[size_t(hn)] >= 0.0)) continue;
            int e = m_mesh.edgeOf(h);
            bool smooth = m_mesh.twin(h) >= 0 && !m_crease[size_t(e)];
            // Evaluate along the canonical halfedge so both faces of a smooth edge
            // compute bit-identical crossing points.
            int hc = smooth ? m_mesh.edgeHalfedge(e) : h;
            double ga, gb;
            if (hc == h) {
                ga = m_cornerG[size_t(h)];
                gb = m_cornerG[size_t(hn)];
            } else {
                ga = m_cornerG[size_t(hn)];
                gb = m_cornerG[size_t(h)];
            }
            const Vec3 &pa = m_mesh.position(m_mesh.tail(hc));
            const Vec3 &pb = m_mesh.position(m_mesh.head(hc));
            double t = std::clamp(ga / (ga - gb), 0.0, 1.0);
            s.p[size_t(found)] = pa + t * (pb - pa);
            s.node[size_t(found)] = smooth ? nV + e : nV + nE + h;
            ++found;
        }
        if (found != 2) return s;
        s.face = {f, -1};
        s.cls = SegClass::Silhouette;
        s.valid = true;
        return s;
    };

    auto edgeSegment = [&](int e) {
        int h = m_mesh.edgeHalfedge(e), t = m_mesh.twin(h);
        Segment s;
        int f0 = field::Mesh::faceOf(h);
        if (t < 0) {
            if (!m_style.borders) return s;
            s.cls = SegClass::Border;
            s.face = {f0, -1};
        } else {
            if (!m_crease[size_t(e)]) return s;
            int f1 = field::Mesh::faceOf(t);
            // Facing is judged with the view vector at the edge midpoint (perspective).
            Vec3 view = m_camera.toViewer(0.5 * (m_mesh.position(m_mesh.tail(h)) +
                                                 m_mesh.position(m_mesh.head(h))));
            bool front0 = m_faceNormal[size_t(f0)].dot(view) > 0.0;
            bool front1 = m_faceNormal[size_t(f1)].dot(view) > 0.0;
            s.cls = front0 != front1 ? SegClass::Silhouette : SegClass::Crease;
            s.face = {f0, f1};
        }
        s.p = {m_mesh.position(m_mesh.tail(h)), m_mesh.position(m_mesh.head(h))};
        s.node = {m_mesh.tail(h), m_mesh.head(h)};
        s.valid = true;
        return s;
    };

    parallelFor(
        0, nFaceBlocks + nEdgeBlocks,
        [&](int64_t b) {
            std::vector<Segment> &out = blocks[size_t(b)];
            bool faces = b < nFaceBlocks;
            int64_t begin = (faces ? b : b - nFaceBlocks) * kBlock;
            int64_t end = std::min<int64_t>(begin + kBlock, faces ? nF : nE);
            for (int64_t i = begin; i < end; ++i) {
                Segment s = faces ? faceSegment(int(i)) : edgeSegment(int(i));
                if (s.valid) out.push_back(s);
            }
        },
        1);

    m_segments.clear();
    for (const std::vector<Segment> &b : blocks) m_segments.insert(m_segments.end(), b.begin(), b.end());

    m_incidence.clear();
    m_incidence.reserve(2 * m_segments.size());
    for (int i = 0; i < int(m_segments.size()); ++i) {
        const Segment &sg = m_segments[size_t(i)];
        for (int k = 0; k < 2; ++k)
            m_incidence.push_back({groupOf(sg.cls) * m_nNodes + sg.node[size_t(k)], i});
    }
    std::sort(m_incidence.begin(), m_incidence.end());
}

int Extractor::nextSegment(int node, int group, const Vec2 &dirIn, const std::vector<uint8_t> &used) const {
    int64_t key = group * m_nNodes + node;
    auto lo = std::lower_bound(m_incidence.begin(), m_incidence.end(), std::make_pair(key, -1));
    auto hi = lo;
    while (hi != m_incidence.end() && hi->first == key) ++hi;
    if (hi - lo == 2) {
        for (auto it = lo; it != hi; ++it)
            if (!used[size_t(it->second)]) return it->second;
        return -1;
    }
    // Junction: continue into the straightest unused segment, if straight enough.
    const double cosLimit = std::cos(kMaxJunctionTurnDeg * kPi / 180.0);
    int best = -1;
    double bestCos = cosLimit;
    double lenIn = dirIn.norm();
    if (lenIn == 0.0) return -1;
    for (auto it = lo; it != hi; ++it) {
        int s = it->second;
        if (used[size_t(s)]) continue;
        const Segment &seg = m_segments[size_t(s)];
        int k = seg.node[0] == node ? 0 : 1;
        Vec2 out = m_camera.project(seg.p[size_t(1 - k)]) - m_camera.project(seg.p[size_t(k)]);
        double lenOut = out.norm();
        if (lenOut == 0.0) continue;
        double c = dirIn.dot(out) / (lenIn * lenOut);
        if (c > bestCos) {
            bestCos = c;
            best = s;
        }
    }
    return best;
}

void Extractor::traceChain(int start, Chain &chain, std::vector<uint8_t> &used) const {
    const Segment &s0 = m_segments[size_t(start)];
    int group = groupOf(s0.cls);
    used[size_t(start)] = 1;
    // Grow from one end; returns the points and segments beyond `node`.
    auto grow = [&](int node, Vec3 prev, Vec3 here, std::vector<Vec3> &pts, std::vector<int> &segs) {
        for (;;) {
            Vec2 dirIn = m_camera.project(here) - m_camera.project(prev);
            int s = nextSegment(node, group, dirIn, used);
            if (s < 0) return node;
            used[size_t(s)] = 1;
            const Segment &seg = m_segments[size_t(s)];
            int k = seg.node[0] == node ? 0 : 1;
            prev = here;
            here = seg.p[size_t(1 - k)];
            node = seg.node[size_t(1 - k)];
            pts.push_back(here);
            segs.push_back(s);
        }
    };
    std::vector<Vec3> fwdPts, bwdPts;
    std::vector<int> fwdSegs, bwdSegs;
    int endNode = grow(s0.node[1], s0.p[0], s0.p[1], fwdPts, fwdSegs);
    bool closed = endNode == s0.node[0];
    if (!closed) grow(s0.node[0], s0.p[1], s0.p[0], bwdPts, bwdSegs);

    chain.group = group;
    chain.closed = closed;
    chain.points.assign(bwdPts.rbegin(), bwdPts.rend());
    chain.segments.assign(bwdSegs.rbegin(), bwdSegs.rend());
    chain.points.push_back(s0.p[0]);
    chain.points.push_back(s0.p[1]);
    chain.segments.push_back(start);
    chain.points.insert(chain.points.end(), fwdPts.begin(), fwdPts.end());
    chain.segments.insert(chain.segments.end(), fwdSegs.begin(), fwdSegs.end());
    if (closed) chain.points.pop_back(); // the loop's last point is its first
}

void Extractor::buildChains() {
    // Sequential on purpose: chaining is linear in the number of segments and its
    // order defines stroke order, so it must not depend on scheduling.
    std::vector<uint8_t> used(m_segments.size(), 0);
    m_chains.clear();
    for (int i = 0; i < int(m_segments.size()); ++i) {
        if (used[size_t(i)]) continue;
        Chain c;
        traceChain(i, c, used);
        if (c.closed && c.group == 0 && tooSmallToDraw(c)) {
            ++m_smallLoopsDropped;
            continue;
        }
        m_chains.push_back(std::move(c));
    }
}

/// A closed silhouette loop whose picture is less than half the feature scale across
/// is a dot, not an outline: the outline of a bump of a scan's noise seen edge-on.
/// (Thin loops are not dropped: a fold seen edge-on projects its silhouette loop to a
/// thin out-and-back curve, half of it hidden, like the base of the bunny's ear.)
bool Extractor::tooSmallToDraw(const Chain &chain) const {
    if (!m_pictureScale || chain.points.empty()) return false;
    Eigen::AlignedBox2d box;
    for (const Vec3 &p : chain.points) box.extend(m_camera.project(p));
    return box.diagonal().norm() < 0.5 * m_style.featureScalePx;
}

double Extractor::pixelWorldSize(double depth) const {
    if (m_camera.projection() == Projection::Orthographic)
        return m_camera.viewHeight() / m_camera.height();
    return depth * 2.0 * std::tan(0.5 * m_camera.fovYDeg() * kPi / 180.0) / m_camera.height();
}

bool Extractor::onSegmentFace(int face, int segment) const {
    // Only the sample's own faces count: sharing a vertex is not enough on coarse
    // meshes (a cube's front face touches the corners of its hidden back edges).
    const Segment &s = m_segments[size_t(segment)];
    return face == s.face[0] || face == s.face[1];
}

bool Extractor::sampleVisible(const Sample &s) const {
    double depth = m_camera.depth(s.pWorld);
    double tol = kDepthTolPx * pixelWorldSize(depth) + 1e-7 * std::abs(depth);
    int ix = int(std::floor(s.pRaster.x())), iy = int(std::floor(s.pRaster.y()));
    const int w = m_gbuffer.width, h = m_gbuffer.height;
    if (ix < 0 || iy < 0 || ix >= w || iy >= h) {
        // Outside the image the G-buffer knows nothing: ask Embree, starting a
        // little toward the viewer so the sample's own faces do not occlude it.
        Ray ray;
        ray.dir = m_camera.toViewer(s.pWorld);
        ray.origin = s.pWorld;
        ray.tMin = 1e-3 * m_scene.sceneRadius();
        ray.tMax = m_camera.projection() == Projection::Perspective
                       ? (m_camera.position() - s.pWorld).norm()
                       : std::numeric_limits<double>::infinity();
        return ray.tMin >= ray.tMax || !m_scene.occluded(ray);
    }
    // The pixel under the sample: extend its face plane to the sample's exact ray,
    // which makes the test independent of how steeply that face runs in depth
    // (concave creases, grazing faces next to silhouettes).
    {
        size_t q = size_t(m_gbuffer.index(ix, iy));
        int fid = m_gbuffer.faceId[q];
        if (fid < 0 || onSegmentFace(fid, s.segment)) return true;
        double surfaceDepth = m_gbuffer.depth[q];
        const Vec3 &n = m_faceNormal[size_t(fid)];
        Ray ray = m_camera.generateRay(s.pRaster.x(), s.pRaster.y());
        double denom = n.dot(ray.dir);
        if (std::abs(denom) > 1e-9) {
            double t = n.dot(m_mesh.position(m_mesh.face(fid)[0]) - ray.origin) / denom;
            double d = m_camera.depth(ray.origin + t * ray.dir);
            if (std::isfinite(d) && d > 0.0) surfaceDepth = d;
        }
        if (depth <= surfaceDepth + tol) return true;
    }
    // Neighbours: a silhouette sits between pixels of its own sheet and whatever lies
    // beyond it (background or farther surface); one such neighbour makes it visible.
    // A scan's smoothed copy runs up to its noise away from the surface drawn in the
    // G-buffer, which at grazing angles is a pixel or more: two pixels around then.
    const int reach = m_scanCopy ? 2 : 1;
    for (int dy = -reach; dy <= reach; ++dy) {
        for (int dx = -reach; dx <= reach; ++dx) {
            int x = ix + dx, y = iy + dy;
            if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= w || y >= h) continue;
            size_t q = size_t(m_gbuffer.index(x, y));
            int fid = m_gbuffer.faceId[q];
            if (fid < 0 || onSegmentFace(fid, s.segment)) return true;
            if (depth <= m_gbuffer.depth[q] + tol) return true;
        }
    }
    return false;
}

void Extractor::emitRun(const std::vector<Sample> &samples, int begin, int end, bool hidden,
                        bool closedLoop, int group, std::vector<Stroke> &out) const {
    Stroke st;
    st.kind = hidden ? StrokeKind::HiddenContour : StrokeKind::Contour;
    st.family = -1;
    for (int i = begin; i < end; ++i) {
        const Vec2 &p = samples[size_t(i)].pRaster;
        if (!st.points.empty() && (p - st.points.back()).squaredNorm() < 1e-18) continue;
        st.points.push_back(p);
    }
    if (closedLoop && st.points.size() >= 3 && (st.points.back() - st.points.front()).squaredNorm() < 1e-18)
        st.points.pop_back();
    size_t n = st.points.size();
    if (n < 2) return;
    // One Laplacian pass on silhouettes removes the residual kinks of the piecewise
    // linear zero set; ends stay put so strokes still meet at junctions. Creases and
    // borders are straight mesh edges already and keep their corners.
    if (group == 0 && n >= 3) {
        std::vector<Vec2> q = st.points;
        size_t first = closedLoop ? 0 : 1, last = closedLoop ? n : n - 1;
        for (size_t i = first; i < last; ++i) {
            const Vec2 &a = st.points[(i + n - 1) % n];
            const Vec2 &b = st.points[(i + 1) % n];
            q[i] = 0.5 * st.points[i] + 0.25 * (a + b);
        }
        st.points = std::move(q);
    }
    if (closedLoop) st.points.push_back(st.points.front());
    n = st.points.size();
    std::vector<double> arc(n, 0.0);
    for (size_t i = 1; i < n; ++i) arc[i] = arc[i - 1] + (st.points[i] - st.points[i - 1]).norm();
    double length = arc.back();
    // A visible piece of silhouette shorter than half the feature scale is a dot (what
    // the hidden rest of a noise bump's outline leaves), not a line.
    const double minLength =
        group == 0 && !hidden && m_pictureScale ? std::max(kMinRunPx, 0.5 * m_style.featureScalePx) : kMinRunPx;
    if (length < minLength) return;
    double base = group == 0 ? m_style.widthPx : m_style.creaseWidthPx;
    double taper = std::min(kTaperPx, 0.25 * length);
    st.widths.resize(n);
    for (size_t i = 0; i < n; ++i) {
        double f = 1.0;
        if (!closedLoop && taper > 0.0) {
            double s = std::min(arc[i], length - arc[i]) / taper;
            f = kTaperMinWidth + (1.0 - kTaperMinWidth) * smoothstep(s);
        }
        st.widths[i] = float(base * f);
    }
    if (group == 0 && !hidden) insetSilhouette(st, closedLoop);
    out.push_back(std::move(st));
}

// A silhouette line is centred on the outline, so half its width lies past it. Lines
// wider than two pixels (the engraving preset's 2.4 px) would then ink pixels beyond
// the one-pixel border that inspect's ink_outside_silhouette_px allows. Each point of
// such a line moves toward its own sheet by half its width less kOutlineReachPx, so the
// line still covers the outline and never reaches further than that past it. The
// sheet's side is read off the G-buffer across the line: covered against background,
// or the nearer surface where a silhouette passes in front of another part.
void Extractor::insetSilhouette(Stroke &st, bool closedLoop) const {
    const size_t n = st.points.size();
    std::vector<Vec2> moved = st.points;
    auto depthAt = [&](const Vec2 &p) {
        const int x = int(std::floor(p.x())), y = int(std::floor(p.y()));
        if (x < 0 || y < 0 || x >= m_gbuffer.width || y >= m_gbuffer.height) return std::numeric_limits<double>::infinity();
        const size_t q = size_t(m_gbuffer.index(x, y));
        return m_gbuffer.faceId[q] < 0 ? std::numeric_limits<double>::infinity() : double(m_gbuffer.depth[q]);
    };
    for (size_t i = 0; i < n; ++i) {
        const double inset = 0.5 * double(st.widths[i]) - kOutlineReachPx;
        if (!(inset > 0.0)) continue;
        const size_t a = i > 0 ? i - 1 : (closedLoop ? n - 2 : 0);
        const size_t b = i + 1 < n ? i + 1 : (closedLoop ? 1 : n - 1);
        const Vec2 t = st.points[b] - st.points[a];
        const double tl = t.norm();
        if (!(tl > 1e-12)) continue;
        const Vec2 nrm(-t.y() / tl, t.x() / tl);
        const double dPlus = depthAt(st.points[i] + kOutlineProbePx * nrm);
        const double dMinus = depthAt(st.points[i] - kOutlineProbePx * nrm);
        if (dPlus == dMinus) continue; // both background, or no side to tell
        moved[i] = st.points[i] + (dPlus < dMinus ? inset : -inset) * nrm;
    }
    if (closedLoop && n >= 2) moved[n - 1] = moved[0];
    st.points = std::move(moved);
}

std::vector<Stroke> Extractor::strokesOfChain(const Chain &chain) const {
    // Sample the chain about every kSampleStepPx on screen.
    std::vector<Sample> samples;
    const size_t nPts = chain.points.size();
    const size_t nEdges = chain.segments.size();
    const double nearDepth = 1e-6 * m_scene.sceneRadius();
    // A cap keeps a segment that nearly reaches the camera plane from exploding.
    const double maxSamples = 4.0 * (m_camera.width() + m_camera.height());
    for (size_t i = 0; i < nEdges; ++i) {
        const Vec3 &a = chain.points[i];
        const Vec3 &b = chain.points[(i + 1) % nPts];
        int seg = chain.segments[i];
        bool inFront = m_camera.depth(a) > nearDepth && m_camera.depth(b) > nearDepth;
        double len = inFront ? (m_camera.project(b) - m_camera.project(a)).norm() : 0.0;
        int n = int(std::clamp(std::ceil(len / kSampleStepPx), 1.0, maxSamples));
        for (int j = 0; j < n; ++j) {
            Sample s;
            s.pWorld = a + (double(j) / n) * (b - a);
            s.segment = seg;
            s.state = inFront ? Sample::Hidden : Sample::Invalid;
            samples.push_back(s);
        }
    }
    if (!chain.closed) {
        Sample s;
        s.pWorld = chain.points.back();
        s.segment = chain.segments.back();
        s.state = m_camera.depth(s.pWorld) > nearDepth ? Sample::Hidden : Sample::Invalid;
        samples.push_back(s);
    }
    for (Sample &s : samples) {
        if (s.state == Sample::Invalid) continue;
        s.pRaster = m_camera.project(s.pWorld);
        s.state = sampleVisible(s) ? Sample::Visible : Sample::Hidden;
    }

    std::vector<Stroke> out;
    int m = int(samples.size());
    if (m == 0) return out;
    bool allVisible = true, allHidden = true;
    for (const Sample &s : samples) {
        allVisible &= s.state == Sample::Visible;
        allHidden &= s.state == Sample::Hidden;
    }
    if (chain.closed && (allVisible || allHidden)) {
        if (allVisible || m_style.hidden) {
            emitRun(samples, 0, m, !allVisible, true, chain.group, out);
        }
        return out;
    }
    if (chain.closed) {
        // Open the loop at the start of its longest non-visible run, so that no visible
        // run is cut at an arbitrary seam; the loop's first sample closes it again.
        for (int i = 0; i < m; ++i) {
            const Sample &a = samples[size_t(i)], &b = samples[size_t((i + 1) % m)];
            samples[size_t(i)].arc = (b.state == Sample::Invalid || a.state == Sample::Invalid)
                                         ? 0.0
                                         : (b.pRaster - a.pRaster).norm();
        }
        int bestStart = 0;
        double bestLen = -1.0;
        for (int i = 0; i < m; ++i) {
            if (samples[size_t(i)].state == Sample::Visible ||
                samples[size_t((i + m - 1) % m)].state != Sample::Visible)
                continue;
            double len = 0.0;
            for (int j = i; samples[size_t(j % m)].state != Sample::Visible && j < i + m; ++j)
                len += samples[size_t(j % m)].arc;
            if (len > bestLen) {
                bestLen = len;
                bestStart = i;
            }
        }
        std::rotate(samples.begin(), samples.begin() + bestStart, samples.end());
        samples.push_back(samples.front());
        m = int(samples.size());
    }
    samples[0].arc = 0.0;
    for (int i = 1; i < m; ++i) {
        const Sample &a = samples[size_t(i - 1)], &b = samples[size_t(i)];
        double step = (a.state == Sample::Invalid || b.state == Sample::Invalid) ? 0.0
                                                                                   : (b.pRaster - a.pRaster).norm();
        samples[size_t(i)].arc = a.arc + step;
    }

    // Noise-tolerant visibility: bridge short hidden gaps, then drop short visible runs.
    auto runEnd = [&](int i, auto pred) {
        while (i < m && pred(samples[size_t(i)].state)) ++i;
        return i;
    };
    for (int i = 0; i < m;) {
        if (samples[size_t(i)].state != Sample::Hidden) {
            ++i;
            continue;
        }
        int j = runEnd(i, [](Sample::State s) { return s == Sample::Hidden; });
        if (i > 0 && j < m && samples[size_t(i - 1)].state == Sample::Visible &&
            samples[size_t(j)].state == Sample::Visible &&
            samples[size_t(j)].arc - samples[size_t(i - 1)].arc <= kMaxGapPx) {
            for (int k = i; k < j; ++k) samples[size_t(k)].state = Sample::Visible;
        }
        i = j;
    }
    for (int i = 0; i < m;) {
        if (samples[size_t(i)].state != Sample::Visible) {
            ++i;
            continue;
        }
        int j = runEnd(i, [](Sample::State s) { return s == Sample::Visible; });
        if (samples[size_t(j - 1)].arc - samples[size_t(i)].arc < kMinRunPx)
            for (int k = i; k < j; ++k) samples[size_t(k)].state = Sample::Hidden;
        i = j;
    }
    for (int i = 0; i < m;) {
        Sample::State st = samples[size_t(i)].state;
        int j = runEnd(i, [st](Sample::State s) { return s == st; });
        if (st == Sample::Visible) {
            emitRun(samples, i, j, false, false, chain.group, out);
        } else if (st == Sample::Hidden && m_style.hidden) {
            // Hidden strokes reach one sample into their visible neighbours so the
            // two kinds meet without a gap.
            int b = i > 0 && samples[size_t(i - 1)].state == Sample::Visible ? i - 1 : i;
            int e = j < m && samples[size_t(j)].state == Sample::Visible ? j + 1 : j;
            emitRun(samples, b, e, true, false, chain.group, out);
        }
        i = j;
    }
    return out;
}

StrokeList Extractor::run(ContourReport *report) {
    ROSY_CHECK_EQ(m_gbuffer.width, m_camera.width());
    ROSY_CHECK_EQ(m_gbuffer.height, m_camera.height());
    StrokeList list;
    list.width = m_camera.width();
    list.height = m_camera.height();
    ContourReport rep;
    if (m_mesh.nFaces() > 0) {
        computeFaceNormalsAndCreases();
        computeCornerValues();
        buildSegments();
        buildChains();
        // Chains are independent; each writes its own slot, merged in chain order.
        std::vector<std::vector<Stroke>> perChain(m_chains.size());
        parallelFor(
            0, int64_t(m_chains.size()),
            [&](int64_t c) { perChain[size_t(c)] = strokesOfChain(m_chains[size_t(c)]); }, 4);
        for (size_t c = 0; c < perChain.size(); ++c) {
            for (Stroke &s : perChain[size_t(c)]) {
                double len = 0.0;
                for (size_t i = 1; i < s.points.size(); ++i) len += (s.points[i] - s.points[i - 1]).norm();
                if (s.kind == StrokeKind::HiddenContour) {
                    ++rep.nHiddenStrokes;
                    rep.hiddenLengthPx += len;
                } else {
                    ++(m_chains[c].group == 0 ? rep.nSilhouetteStrokes : rep.nCreaseStrokes);
                    rep.visibleLengthPx += len;
                }
                s.id = kContourIdBase + uint32_t(list.strokes.size());
                list.strokes.push_back(std::move(s));
            }
        }
        for (const Segment &s : m_segments) {
            if (s.cls == SegClass::Silhouette) ++rep.nSilhouetteSegments;
            else if (s.cls == SegClass::Crease) ++rep.nCreaseSegments;
            else ++rep.nBorderSegments;
        }
        rep.nChains = int(m_chains.size());
        rep.nSmallLoopsDropped = m_smallLoopsDropped;
        rep.nCreasesBelowScale = m_creasesBelowScale;
        rep.judgedAtPictureScale = m_pictureScale;
    }
    if (report) *report = rep;
    return list;
}

} // namespace

StrokeList extractContours(const field::Mesh &mesh, const Camera &camera, const RayScene &scene,
                           const GBuffer &gbuffer, const styles::ContourStyle &style,
                           ContourReport *report, bool scanCopy) {
    Extractor extractor(mesh, camera, scene, gbuffer, style, scanCopy);
    return extractor.run(report);
}

} // namespace rosy::renderer
