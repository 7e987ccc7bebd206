/// \file streamline_network.cpp
/// The streamline network remesher (streamline_network.h): placement, crossings,
/// the arrangement's faces.
#include "remesh/streamline_network.h"

#include "core/error.h"
#include "field/mesh/union_find.h"
#include "field/singularities.h"
#include "field/separatrices.h"
#include "field/streamlines.h"
#include "remesh/polygon_ops.h"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace rosy::remesh {
namespace {

using Clock = std::chrono::steady_clock;
using field::Mesh;
using Vec2 = Eigen::Vector2d;

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// A placed line: a polyline on the surface with the face of each segment.
struct Line {
    std::vector<Vec3> points;
    std::vector<int> segFace; ///< #points − 1: the face each segment lies in
    std::vector<double> arc;  ///< #points: arc length from the seed (negative before it)
    /// A separatrix: the singularity (index into the report) its first point is.
    int singularity = -1;
    int endSingularity = -1; ///< a separatrix that ends on another singularity's point
    bool closed = false; ///< a loop: its last point is its first
    /// A separatrix that reached StreamlineNetworkOptions::separatrixLength uncut: it
    /// runs on as an ordinary line once its own seeds are placed (extend()).
    bool extendable = false;
    /// The last k of the seeds placed every L along it (spawnFrom()); an extended
    /// separatrix is seeded again only beyond it.
    int seededTo = std::numeric_limits<int>::min();

};

/// A point of a placed line, for the spacing tests.
struct Sample {
    Vec3 p;
    Vec3 t; ///< unit tangent
    int line;
    double arc;
};

/// Samples of all placed lines in a uniform grid of cell size L.
class SampleGrid {
public:
    explicit SampleGrid(double cell) : m_cell(cell) {}

    void insert(const Sample &s) {
        m_cells[key(s.p)].push_back(int(m_samples.size()));
        m_samples.push_back(s);
    }

    /// Is a sample running along `t` (|cos| above `parallelCos`) within `r` (≤ cell) of p?
    /// Samples of `line` itself count only when more than `selfArc` of arc away from `arc`
    /// and more than `seedWindow` from the line's seed (a loop about to close).
    bool near(const Vec3 &p, const Vec3 &t, double r, int line, double arc, double selfArc,
              double parallelCos, double seedWindow = 0) const {
        return anyWithin(p, r, [&](const Sample &s) {
            if (std::abs(s.t.dot(t)) < parallelCos) return false;
            return s.line != line || (std::abs(s.arc - arc) > selfArc && std::abs(s.arc) > seedWindow);
        });
    }

    /// Is any sample within r (≤ cell) of p?
    bool any(const Vec3 &p, double r) const {
        return anyWithin(p, r, [](const Sample &) { return true; });
    }

private:
    /// Does `accept` hold for a sample within r (≤ cell) of p? (The 27 cells around p.)
    template <typename Accept> bool anyWithin(const Vec3 &p, double r, Accept &&accept) const {
        const long long cx = coord(p.x()), cy = coord(p.y()), cz = coord(p.z());
        for (long long dx = -1; dx <= 1; ++dx)
            for (long long dy = -1; dy <= 1; ++dy)
                for (long long dz = -1; dz <= 1; ++dz) {
                    auto it = m_cells.find(pack(cx + dx, cy + dy, cz + dz));
                    if (it == m_cells.end()) continue;
                    for (int i : it->second)
                        if ((m_samples[i].p - p).squaredNorm() <= r * r && accept(m_samples[i])) return true;
                }
        return false;
    }

    long long coord(double x) const { return (long long)std::floor(x / m_cell); }
    static uint64_t pack(long long x, long long y, long long z) {
        const uint64_t m = (1ull << 21) - 1;
        return (uint64_t(x) & m) | ((uint64_t(y) & m) << 21) | ((uint64_t(z) & m) << 42);
    }
    uint64_t key(const Vec3 &p) const { return pack(coord(p.x()), coord(p.y()), coord(p.z())); }

    double m_cell;
    std::unordered_map<uint64_t, std::vector<int>> m_cells;
    std::vector<Sample> m_samples;
};

/// A point of the surface with a heading: where a line starts.
struct Seed {
    int face = -1;
    Vec3 p = Vec3::Zero();
    Vec3 dir = Vec3::Zero();
};

/// A crossing of two lines (or of one line with itself) inside a face.
struct Crossing {
    int line[2];
    double param[2]; ///< segment index + fraction along it
    Vec3 p;
    int face;
};

class NetworkBuilder {
public:
    NetworkBuilder(const field::TangentFrames &frames, const field::RosyField &field,
                   const field::SingularityReport &singularities, const StreamlineNetworkOptions &opt)
        : m_frames(frames), m_field(field), m_sing(singularities), m_opt(opt), m_mesh(frames.mesh()),
          m_L(opt.edgeLength), m_grid(opt.edgeLength) {
        Vec3 lo, hi;
        m_mesh.bounds(lo, hi);
        m_diag = (hi - lo).norm();
        m_faceIndex = field::faceIndexNumerators(frames, field);
        m_trace.stepLength = std::min(0.25 * m_L, 0.5 * m_mesh.meanEdgeLength());
        m_trace.stopAtSingularFaces = true;
        m_sampleStep = 0.125 * m_L;
    }

    /// Places all lines (separatrices first), in a fixed order.
    void place() {
        if (m_opt.separatrices) placeSeparatrices();
        // Lines spread from the lines placed (breadth first); when the queue runs dry,
        // a face no line comes near starts a new one (another component, a region
        // the lines stopped short of).
        int scan = 0;
        for (;;) {
            while (!m_queue.empty()) {
                const int l = m_queue.front();
                m_queue.pop_front();
                spawnFrom(l);
                if (m_lines[l].extendable) extend(l);
            }
            bool started = false;
            for (; scan < m_mesh.nFaces() && !started; ++scan) {
                if (m_faceIndex[scan] != 0) continue;
                const auto &f = m_mesh.face(scan);
                const Vec3 c = (m_mesh.position(f[0]) + m_mesh.position(f[1]) + m_mesh.position(f[2])) / 3.0;
                if (m_grid.any(c, m_L)) continue;
                started = tryLine(Seed{scan, c, m_frames.faceAxisX(scan)}, m_opt.seedDistance);
            }
            if (!started) break;
        }
    }

    std::vector<Crossing> crossings() const;
    RemeshResult build(std::map<std::string, int> &repairs) const;

    const std::vector<Line> &lines() const { return m_lines; }

private:
    Vec3 faceNormal(int f) const { return m_mesh.faceNormal(f); }

    /// Where a half line may close into a loop: the first half onto the line's seed
    /// (heading as it started), the second onto the end of the first where that was cut
    /// (meeting it head-on: both halves of one loop).
    struct Loop {
        Vec3 seed = Vec3::Zero(), dir = Vec3::Zero(); ///< the point and the heading on arrival
        bool enabled = false;
        bool closed = false; ///< set by accept()
    };

    /// Appends the segments of `s` to a half line until one comes closer than the stop
    /// distance to a line running its way (or to this line more than 3 L of arc away);
    /// inserts the samples of what it keeps. Returns whether it was cut short (or closed).
    /// Within `freeRadius` of the line's first point nothing is tested (the separatrices
    /// of one singularity start at one point).
    bool accept(const field::Streamline &s, int lineId, double sign, double &arc, std::vector<Vec3> &pts,
                std::vector<int> &faces, std::vector<double> &arcs, Loop *loop = nullptr, double freeRadius = 0) {
        const Vec3 start = s.points.front();
        const double stop = m_opt.stopDistance * m_L;
        // Segment k of s runs from points[k] to points[k + 1] in faces[k].
        for (size_t k = 0; k + 1 < s.points.size(); ++k) {
            const Vec3 a = s.points[k], b = s.points[k + 1];
            const double len = (b - a).norm();
            if (!(len > 0)) continue;
            const Vec3 t = (b - a) / len;
            // Back on the seed, heading as it started: the loop closes there.
            double closeAt = -1;
            if (loop && loop->enabled && t.dot(loop->dir) > kParallelCos) {
                const double u = std::clamp((loop->seed - a).dot(t), 0.0, len);
                if (arc + u > 3 * m_L && (a + u * t - loop->seed).norm() < 0.05 * m_L) closeAt = u;
            }
            // Test the segment at sample spacing; cut it at the last point that passes.
            const int n = std::max(1, int(std::ceil(len / m_sampleStep)));
            double keep = closeAt >= 0 ? closeAt : len;
            bool cut = closeAt >= 0;
            for (int i = 1; i <= n && len * i / n <= keep; ++i) {
                const double u = len * i / n;
                const Vec3 q = a + u * t;
                const double seedWindow = loop && (q - loop->seed).norm() < 1.5 * stop ? 2 * stop : 0;
                // Closing on its own seed, a loop is not stopped by its neighbours' ends.
                bool closing = false;
                if (loop && loop->enabled && arc + u > 3 * m_L) {
                    const Vec3 ahead = loop->seed - q;
                    closing = ahead.norm() < 1.5 * m_L && ahead.dot(t) > 0.9 * ahead.norm() &&
                              t.dot(loop->dir) > kParallelCos;
                }
                if (!closing && (q - start).norm() >= freeRadius &&
                    m_grid.near(q, t, stop, lineId, sign * (arc + u), 3 * m_L, kParallelCos, seedWindow)) {
                    keep = len * (i - 1) / n;
                    cut = true;
                    closeAt = -1;
                    break;
                }
            }
            if (keep > 0) {
                for (int i = 1; i <= n && len * i / n <= keep * (1 + 1e-12); ++i)
                    m_grid.insert(Sample{a + (len * i / n) * t, t, lineId, sign * (arc + len * i / n)});
                pts.push_back(closeAt >= 0 ? loop->seed : Vec3(a + keep * t));
                faces.push_back(s.faces[k]);
                arc += keep;
                arcs.push_back(arc);
            }
            if (closeAt >= 0) loop->closed = true;
            if (cut) return true;
        }
        return false;
    }

    /// One half of a line from `seed`, traced in chunks (8 L, then doubling) until it
    /// stops by itself or accept() cuts it (returns true then). The points start with the
    /// seed; faces are those of the segments; arcs the distances from the seed.
    bool traceHalf(const Seed &seed, int lineId, double sign, std::vector<Vec3> &pts, std::vector<int> &faces,
                   std::vector<double> &arcs, Loop *loop, double startArc = 0) {
        pts.assign(1, seed.p);
        faces.clear();
        arcs.assign(1, startArc);
        int face = seed.face;
        Vec3 p = seed.p, dir = seed.dir;
        double arc = startArc, chunk = 8 * m_L;
        for (;;) {
            field::StreamlineOptions o = m_trace;
            o.maxLength = chunk;
            const field::Streamline s =
                field::traceStreamline(m_frames, m_field, face, field::barycentricOf(m_mesh, face, p), dir, o, &m_faceIndex);
            if (accept(s, lineId, sign, arc, pts, faces, arcs, loop)) return true;
            if (s.stop != field::StreamlineStop::MaxLength || arc >= 4 * m_diag || s.points.size() < 2) return false;
            // Go on from the end, heading along the last segment.
            face = s.faces.back();
            p = s.points.back();
            dir = s.points.back() - s.points[s.points.size() - 2];
            if (!(dir.norm() > 0)) return false;
            chunk *= 2;
        }
    }

    /// Traces a line through `seed` both ways if no line running its way is within
    /// seedDistance; adds it and queues it. Returns whether it was added.
    bool tryLine(const Seed &seed, double seedDistance) {
        Vec3 n = faceNormal(seed.face);
        Vec3 d = seed.dir - seed.dir.dot(n) * n;
        if (!(d.norm() > 1e-12)) return false;
        d.normalize();
        // The member the line will follow at the seed.
        d = memberClosest(seed.face, seed.p, d);
        if (m_grid.near(seed.p, d, seedDistance * m_L, -1, 0, 0, kParallelCos)) return false;
        const int id = int(m_lines.size());
        std::vector<Vec3> fp, bp;
        std::vector<int> ff, bf;
        std::vector<double> fa, ba;
        Loop loop{seed.p, d, true, false};
        const bool cut = traceHalf(Seed{seed.face, seed.p, d}, id, 1.0, fp, ff, fa, &loop);
        if (!loop.closed) {
            // The second half may meet the first's cut end head-on (a loop whose halves
            // came round to each other): then it joins it.
            loop.enabled = cut && fp.size() >= 2;
            if (loop.enabled) {
                loop.seed = fp.back();
                loop.dir = -(fp.back() - fp[fp.size() - 2]).normalized();
            }
            traceHalf(Seed{seed.face, seed.p, -d}, id, -1.0, bp, bf, ba, &loop);
        } else {
            bp.assign(1, seed.p), ba.assign(1, 0.0), bf.clear();
        }
        Line line;
        for (size_t i = bp.size(); i-- > 1;) line.points.push_back(bp[i]), line.arc.push_back(-ba[i]);
        for (size_t i = bf.size(); i-- > 0;) line.segFace.push_back(bf[i]);
        line.points.insert(line.points.end(), fp.begin(), fp.end());
        for (double a : fa) line.arc.push_back(a);
        line.segFace.insert(line.segFace.end(), ff.begin(), ff.end());
        if (line.points.size() < 2) return false; // a seed whose line stopped at once (its samples: none)
        line.closed = loop.closed;
        m_lines.push_back(std::move(line));
        m_queue.push_back(id);
        return true;
    }

    /// A separatrix that reached its length runs on from its end as the same line, after
    /// the lines seeded along it (the rings of quads about its singularity) are placed,
    /// stopping like any line; queued again for seeds along what it gained, and only
    /// there (Line::seededTo). Without it the separatrix's end was a T-junction beside
    /// the gap its side lines leave (Figure 4 at 1.5-4 %: 70-172 irregular vertices with
    /// it ended, 68-132 run on).
    void extend(int l) {
        Line &line = m_lines[l];
        line.extendable = false;
        if (line.points.size() < 2 || line.segFace.empty()) return;
        const Vec3 end = line.points.back();
        const Vec3 dir = (end - line.points[line.points.size() - 2]).normalized();
        std::vector<Vec3> pts;
        std::vector<int> faces;
        std::vector<double> arcs;
        traceHalf(Seed{line.segFace.back(), end, dir}, l, 1.0, pts, faces, arcs, nullptr, line.arc.back());
        for (size_t i = 1; i < pts.size(); ++i) line.points.push_back(pts[i]), line.arc.push_back(arcs[i]);
        line.segFace.insert(line.segFace.end(), faces.begin(), faces.end());
        if (pts.size() > 1) m_queue.push_back(l);
    }

    /// The unit field member closest to d at p in `face` (world).
    Vec3 memberClosest(int face, const Vec3 &p, const Vec3 &d) const {
        field::StreamlineOptions o = m_trace;
        o.maxLength = 1e-3 * m_L;
        o.stopAtSingularFaces = false;
        const field::Streamline s =
            field::traceStreamline(m_frames, m_field, face, field::barycentricOf(m_mesh, face, p), d, o, nullptr);
        if (s.points.size() < 2) return d;
        const Vec3 e = s.points.back() - s.points.front();
        return e.norm() > 0 ? Vec3(e.normalized()) : d;
    }

    /// Point, unit tangent and face at arc length `a` of line l (within its range).
    bool pointAt(const Line &l, double a, Vec3 &p, Vec3 &t, int &face) const {
        if (a < l.arc.front() || a > l.arc.back()) return false;
        size_t k = std::upper_bound(l.arc.begin(), l.arc.end(), a) - l.arc.begin();
        k = std::clamp<size_t>(k, 1, l.arc.size() - 1) - 1; // segment k: arc[k] ≤ a ≤ arc[k + 1]
        const double len = l.arc[k + 1] - l.arc[k];
        const Vec3 d = l.points[k + 1] - l.points[k];
        if (!(len > 0) || !(d.norm() > 0)) return false;
        t = d.normalized();
        p = l.points[k] + (a - l.arc[k]) / len * d;
        face = l.segFace[k];
        return true;
    }

    /// Seeds along line l every L from its seed: a crossing line through the point,
    /// and lines running its way L to either side (walked along the crossing member).
    void spawnFrom(int l) {
        const int kMax = int(std::floor(m_lines[l].arc.back() / m_L));
        const int kMin = m_lines[l].seededTo == std::numeric_limits<int>::min()
                             ? int(std::ceil(m_lines[l].arc.front() / m_L))
                             : m_lines[l].seededTo + 1; // only what an extension added
        m_lines[l].seededTo = kMax;
        // Alternate outward from the seed (0, 1, −1, 2, −2, …) so that the crossing
        // lines start where the line is surest.
        std::vector<int> order;
        for (int k = 0; k <= std::max(kMax, -kMin); ++k) {
            if (k <= kMax && k >= kMin) order.push_back(k);
            if (k > 0 && -k >= kMin && -k <= kMax) order.push_back(-k);
        }
        for (int k : order) {
            Vec3 p, t;
            int face;
            if (!pointAt(m_lines[l], k * m_L, p, t, face)) continue;
            const Vec3 n = faceNormal(face);
            const Vec3 across = n.cross(t).normalized();
            tryLine(Seed{face, p, across}, m_opt.seedDistance);
            for (double side : {1.0, -1.0}) {
                field::StreamlineOptions o = m_trace;
                o.maxLength = m_L;
                const field::Streamline w = field::traceStreamline(
                    m_frames, m_field, face, field::barycentricOf(m_mesh, face, p), side * across, o, &m_faceIndex);
                if (w.points.size() < 2 || w.length < 0.99 * m_L) continue;
                const int g = w.faces.back();
                // The seed's heading: the walk's end direction turned back by a quarter.
                const Vec3 e = (w.points.back() - w.points[w.points.size() - 2]).normalized();
                const Vec3 dir = side * faceNormal(g).cross(e) * -1.0;
                tryLine(Seed{g, w.points.back(), dir.dot(t) >= 0 ? dir : Vec3(-dir)}, m_opt.seedDistance);
            }
        }
    }

    /// The separatrices of every singularity, traced from its position outwards (one
    /// half line each, in the order of field::traceSeparatrices) for at most
    /// separatrixLength × L, cut where they come too close to a line running their way,
    /// and queued first.
    void placeSeparatrices() {
        for (int i = 0; i < int(m_sing.singularities.size()); ++i)
            if (m_sing.singularities[i].indexNumerator != 0) m_singularityOfFace.emplace(m_sing.singularities[i].face, i);
        field::SeparatrixOptions so;
        so.streamline = m_trace;
        // Each for a certain distance (StreamlineNetworkOptions::separatrixLength).
        so.streamline.maxLength = std::min(4 * m_diag, m_opt.separatrixLength * m_L);
        const std::vector<field::Separatrix> seps = field::traceSeparatrices(m_frames, m_field, m_sing.singularities, so);
        for (const field::Separatrix &sep : seps) {
            if (sep.line.points.size() < 2) continue;
            const int id = int(m_lines.size());
            Line line;
            line.singularity = sep.singularity;
            line.points.assign(1, sep.line.points.front());
            line.arc.assign(1, 0.0);
            double arc = 0;
            const bool cut = accept(sep.line, id, 1.0, arc, line.points, line.segFace, line.arc, nullptr, m_L);
            // One that reaches another singularity ends on its point: the two are joined
            // by an edge (that one's separatrix back along it is cut at once, as it runs
            // beside this one).
            if (!cut && sep.line.stop == field::StreamlineStop::Singularity && !sep.line.faces.empty()) {
                auto it = m_singularityOfFace.find(sep.line.faces.back());
                if (it != m_singularityOfFace.end() && it->second != sep.singularity) {
                    const Vec3 end = m_sing.singularities[it->second].position;
                    line.arc.push_back(line.arc.back() + (end - line.points.back()).norm());
                    line.points.push_back(end);
                    line.segFace.push_back(sep.line.faces.back());
                    line.endSingularity = it->second;
                }
            }
            if (line.points.size() < 2) continue;
            line.extendable = !cut && sep.line.stop == field::StreamlineStop::MaxLength;
            m_lines.push_back(std::move(line));
            m_queue.push_back(id);
        }
    }

    static constexpr double kParallelCos = 0.70710678118654752; // within 45°
    static constexpr double kSlack = 1e-9; // segment parameters, crossings()

    const field::TangentFrames &m_frames;
    const field::RosyField &m_field;
    const field::SingularityReport &m_sing;
    const StreamlineNetworkOptions &m_opt;
    const Mesh &m_mesh;
    double m_L;
    double m_diag = 0;
    double m_sampleStep;
    SampleGrid m_grid;
    std::vector<int> m_faceIndex;
    field::StreamlineOptions m_trace;
    std::vector<Line> m_lines;
    std::deque<int> m_queue;
    std::map<int, int> m_singularityOfFace; ///< singular face → index in the report
};

std::vector<Crossing> NetworkBuilder::crossings() const {
    // Segments by face, then every pair in a face intersected in its plane.
    std::vector<std::vector<std::pair<int, int>>> byFace(m_mesh.nFaces());
    for (int l = 0; l < int(m_lines.size()); ++l)
        for (int k = 0; k < int(m_lines[l].segFace.size()); ++k) byFace[m_lines[l].segFace[k]].push_back({l, k});
    std::vector<Crossing> out;
    for (int f = 0; f < m_mesh.nFaces(); ++f) {
        const auto &segs = byFace[f];
        if (segs.size() < 2) continue;
        const Vec3 o = m_mesh.position(m_mesh.face(f)[0]);
        const Vec3 X = m_frames.faceAxisX(f), Y = faceNormal(f).cross(X);
        auto plane = [&](const Vec3 &p) { return Vec2((p - o).dot(X), (p - o).dot(Y)); };
        auto cross2 = [](const Vec2 &a, const Vec2 &b) { return a.x() * b.y() - a.y() * b.x(); };
        for (size_t i = 0; i < segs.size(); ++i) {
            const auto [la, ka] = segs[i];
            const Vec2 p = plane(m_lines[la].points[ka]), r = plane(m_lines[la].points[ka + 1]) - p;
            for (size_t j = i + 1; j < segs.size(); ++j) {
                const auto [lb, kb] = segs[j];
                if (la == lb && std::abs(ka - kb) < 2) continue; // neighbours share an end
                // Separatrices of one singularity start at its point: that is their
                // common vertex, not a crossing.
                if (ka == 0 && kb == 0 && m_lines[la].singularity >= 0 &&
                    m_lines[la].singularity == m_lines[lb].singularity)
                    continue;
                const Vec2 q = plane(m_lines[lb].points[kb]), sv = plane(m_lines[lb].points[kb + 1]) - q;
                const double den = cross2(r, sv);
                if (!(std::abs(den) > 1e-14 * r.norm() * sv.norm())) continue; // parallel
                const double t = cross2(q - p, sv) / den, u = cross2(q - p, r) / den;
                // Half-open, with a little slack below 0: a line's seed lies on the line
                // it was started from (up to rounding), and a crossing at a shared end
                // point must be counted in one of the two segments, not in none.
                if (t < -kSlack || t >= 1 - kSlack || u < -kSlack || u >= 1 - kSlack) continue;
                Crossing c;
                c.line[0] = la, c.line[1] = lb;
                c.param[0] = ka + t, c.param[1] = kb + u;
                c.p = m_lines[la].points[ka] + t * (m_lines[la].points[ka + 1] - m_lines[la].points[ka]);
                c.face = f;
                out.push_back(c);
            }
        }
    }
    // The slack may count one crossing in two faces (at their common edge): keep one.
    // Each crossing keyed by its line pair (lower first) and its parameter on the first.
    std::vector<std::tuple<int, int, double, int>> keys(out.size());
    for (size_t i = 0; i < out.size(); ++i) {
        const Crossing &c = out[i];
        const int s = c.line[0] < c.line[1] || (c.line[0] == c.line[1] && c.param[0] < c.param[1]) ? 0 : 1;
        keys[i] = {c.line[s], c.line[1 - s], c.param[s], int(i)};
    }
    std::sort(keys.begin(), keys.end());
    std::vector<char> duplicate(out.size(), 0);
    for (size_t k = 1; k < keys.size(); ++k) {
        const auto &[a0, a1, ap, ai] = keys[k - 1];
        const auto &[b0, b1, bp, bi] = keys[k];
        if (a0 == b0 && a1 == b1 && (out[size_t(bi)].p - out[size_t(ai)].p).norm() < 1e-9 * m_L)
            duplicate[size_t(std::max(ai, bi))] = 1;
    }
    std::vector<Crossing> kept;
    for (size_t i = 0; i < out.size(); ++i)
        if (!duplicate[i]) kept.push_back(out[i]);
    return kept;
}

RemeshResult NetworkBuilder::build(std::map<std::string, int> &repairs) const {
    const std::vector<Crossing> cross = crossings();
    repairs["crossings"] = int(cross.size());
    // Each line's crossings in order along it.
    struct OnLine {
        double param;
        int crossing, side;
    };
    // Vertices: the crossings, then the singular points separatrices start from.
    std::vector<Vec3> vPos;
    std::vector<int> vFace;
    for (const Crossing &c : cross) vPos.push_back(c.p), vFace.push_back(c.face);
    std::vector<std::vector<OnLine>> along(m_lines.size());
    for (int c = 0; c < int(cross.size()); ++c)
        for (int s = 0; s < 2; ++s) along[cross[c].line[s]].push_back({cross[c].param[s], c, s});
    std::map<int, int> singularVertex;
    auto vertexOf = [&](int si) {
        auto [it, added] = singularVertex.emplace(si, int(vPos.size()));
        if (added) {
            vPos.push_back(m_sing.singularities[si].position);
            vFace.push_back(m_sing.singularities[si].face);
        }
        return it->second;
    };
    for (int l = 0; l < int(m_lines.size()); ++l) {
        if (m_lines[l].singularity >= 0) along[l].push_back({0.0, vertexOf(m_lines[l].singularity), 0});
        if (m_lines[l].endSingularity >= 0)
            along[l].push_back({double(m_lines[l].segFace.size()), vertexOf(m_lines[l].endSingularity), 0});
    }
    for (auto &v : along)
        std::sort(v.begin(), v.end(), [](const OnLine &a, const OnLine &b) {
            return a.param < b.param || (a.param == b.param && a.crossing < b.crossing);
        });
    auto tangent = [&](int l, double param) {
        const Line &line = m_lines[l];
        const int k = std::clamp(int(std::floor(param)), 0, int(line.segFace.size()) - 1);
        return Vec3((line.points[k + 1] - line.points[k]).normalized());
    };
    // Edges between consecutive crossings; half-edge 2e runs from[e] → to[e], 2e + 1 back.
    // Each half-edge leaves its vertex at an angle in the crossing face's plane.
    std::vector<int> heFrom, heTo;
    std::vector<double> heAngle;
    auto angleAt = [&](int c, const Vec3 &d) {
        const int f = vFace[c];
        const Vec3 X = m_frames.faceAxisX(f), Y = faceNormal(f).cross(X);
        const double a = std::atan2(d.dot(Y), d.dot(X));
        return std::isfinite(a) ? a : 0.0; // a degenerate face: any order, but a strict one
    };
    int loops = 0;
    for (int l = 0; l < int(m_lines.size()); ++l) {
        // A closed line also joins its last crossing to its first, across its seed.
        const size_t n = along[l].size();
        const size_t pairs = m_lines[l].closed && n >= 3 ? n : n - std::min<size_t>(n, 1);
        for (size_t i = 0; i < pairs; ++i) {
            const OnLine &a = along[l][i], &b = along[l][(i + 1) % n];
            if (a.crossing == b.crossing) { // a line crossing itself at once: a curl, no face
                ++loops;
                continue;
            }
            heFrom.push_back(a.crossing), heTo.push_back(b.crossing);
            heAngle.push_back(angleAt(a.crossing, tangent(l, a.param)));
            heFrom.push_back(b.crossing), heTo.push_back(a.crossing);
            heAngle.push_back(angleAt(b.crossing, -tangent(l, b.param)));
        }
    }
    repairs["curls_dropped"] = loops;
    const int nHe = int(heFrom.size()), nV = int(vPos.size());
    // Ends beyond a line's first and last crossing are already gone; prune what dangles
    // after that (a vertex with one edge, repeatedly).
    std::vector<char> alive(nHe / 2, 1);
    std::vector<int> degree(nV, 0);
    std::vector<std::vector<int>> out(nV);
    for (int h = 0; h < nHe; ++h) out[heFrom[h]].push_back(h), ++degree[heFrom[h]];
    std::vector<int> stack;
    auto kill = [&](int e) {
        alive[e] = 0;
        for (int v : {heFrom[2 * e], heTo[2 * e]})
            if (--degree[v] == 1) stack.push_back(v);
    };
    // Two edges between the same two vertices (two separatrices of one singularity
    // that cross again, two lines crossing twice in a row) bound no face: keep the first.
    auto edgeKey = [](int a, int b) { return directedEdgeKey(std::min(a, b), std::max(a, b)); }; // undirected
    int doubled = 0;
    {
        std::unordered_set<uint64_t> seen;
        for (int e = 0; e < nHe / 2; ++e)
            if (!seen.insert(edgeKey(heFrom[2 * e], heTo[2 * e])).second) kill(e), ++doubled;
    }
    repairs["doubled_edges_removed"] = doubled;
    for (int v = 0; v < nV; ++v)
        if (degree[v] == 1) stack.push_back(v);
    field::UnionFind parts(m_mesh.nFaces()); // the surface's connected parts
    for (int h = 0; h < 3 * m_mesh.nFaces(); ++h)
        if (m_mesh.twin(h) >= 0) parts.unite(h / 3, m_mesh.twin(h) / 3);
    int pruned = 0, bridges = 0, piecesDropped = 0, pinches = 0, stuckBends = 0;
    std::vector<int> rotIndex(nHe, -1), faceOf(nHe, -1);
    std::vector<std::vector<int>> polygons;
    int small = 0;
    for (;;) {
        while (!stack.empty()) {
            const int v = stack.back();
            stack.pop_back();
            if (degree[v] != 1) continue;
            for (int h : out[v])
                if (alive[h / 2]) {
                    kill(h / 2);
                    ++pruned;
                    break;
                }
        }
        {
            // A piece of the network that touches no other (a few crossings cut off
            // between lines that stopped) would close into a surface of its own, and the
            // face around it would not be a disk: on each part of the surface only the
            // largest piece is kept.
            field::UnionFind pieces(nV);
            for (int e = 0; e < nHe / 2; ++e)
                if (alive[e]) pieces.unite(heFrom[2 * e], heTo[2 * e]);
            std::vector<int> size(nV, 0), largest(m_mesh.nFaces(), -1);
            int dropped = 0;
            for (int v = 0; v < nV; ++v)
                if (degree[v] > 0) ++size[pieces.find(v)];
            for (int v = 0; v < nV; ++v) {
                if (degree[v] == 0 || pieces.find(v) != v) continue;
                int &best = largest[parts.find(vFace[v])];
                if (best < 0 || size[v] > size[best]) best = v;
            }
            for (int e = 0; e < nHe / 2; ++e) {
                if (!alive[e]) continue;
                const int root = pieces.find(heFrom[2 * e]);
                if (largest[parts.find(vFace[root])] != root) kill(e), ++dropped;
            }
            piecesDropped += dropped;
            if (dropped > 0) continue; // prune again (nothing dangles; degrees fall to 0)
        }
        // Rotation system: each vertex's live half-edges counter-clockwise about the normal.
        for (int v = 0; v < nV; ++v) {
            auto &o = out[v];
            o.erase(std::remove_if(o.begin(), o.end(), [&](int h) { return !alive[h / 2]; }), o.end());
            std::sort(o.begin(), o.end(), [&](int a, int b) {
                return heAngle[a] < heAngle[b] || (heAngle[a] == heAngle[b] && a < b);
            });
            for (int k = 0; k < int(o.size()); ++k) rotIndex[o[k]] = k;
        }
        // Faces: after arriving at v along h, leave along the edge clockwise next to h's
        // twin, so that the face lies to the left of every half-edge (counter-clockwise).
        std::vector<char> used(nHe, 0);
        polygons.clear();
        small = 0;
        for (int h0 = 0; h0 < nHe; ++h0) {
            if (!alive[h0 / 2] || used[h0]) continue;
            std::vector<int> poly;
            for (int h = h0; !used[h];) {
                used[h] = 1;
                faceOf[h] = int(polygons.size());
                poly.push_back(heFrom[h]);
                const int v = heTo[h], twin = h ^ 1;
                const auto &o = out[v];
                h = o[(rotIndex[twin] + int(o.size()) - 1) % int(o.size())];
            }
            polygons.push_back(std::move(poly));
        }
        // An edge with the same face on both sides (a bridge to a piece that hangs
        // off) would make that face pass its ends twice: remove it and what then dangles.
        int now = 0;
        for (int e = 0; e < nHe / 2; ++e)
            if (alive[e] && faceOf[2 * e] == faceOf[2 * e + 1]) kill(e), ++now;
        bridges += now;
        // A face through one vertex twice (the vertex joins two pieces that touch only
        // there): take the vertex out with its edges.
        int pinched = 0;
        std::vector<int> stamp(nV, -1);
        for (int f = 0; f < int(polygons.size()); ++f)
            for (int v : polygons[f]) {
                if (stamp[v] != f) {
                    stamp[v] = f;
                    continue;
                }
                for (int h : out[v])
                    if (alive[h / 2]) kill(h / 2);
                ++pinched;
            }
        pinches += pinched;
        // A vertex with two edges that cannot be dissolved below (a face would keep
        // fewer than three corners, or an edge between its neighbours exists): take it
        // out with its edges, joining its two faces.
        int bends = 0;
        {
            std::unordered_set<uint64_t> live;
            for (int e = 0; e < nHe / 2; ++e)
                if (alive[e]) live.insert(edgeKey(heFrom[2 * e], heTo[2 * e]));
            for (int v = 0; v < nV; ++v) {
                if (degree[v] != 2) continue;
                int hs[2], k = 0;
                for (int h : out[v])
                    if (alive[h / 2] && k < 2) hs[k++] = h;
                if (k != 2) continue;
                const int f1 = faceOf[hs[0]], f2 = faceOf[hs[1]];
                if (polygons[f1].size() > 3 && polygons[f2].size() > 3 && !live.count(edgeKey(heTo[hs[0]], heTo[hs[1]])))
                    continue;
                kill(hs[0] / 2), kill(hs[1] / 2);
                ++bends;
            }
        }
        stuckBends += bends;
        if (now == 0 && pinched == 0 && bends == 0) break;
    }
    repairs["dangling_edges_removed"] = pruned;
    repairs["bridges_removed"] = bridges;
    repairs["piece_edges_removed"] = piecesDropped;
    repairs["pinched_vertices_removed"] = pinches;
    repairs["bends_removed"] = stuckBends;
    polygons.erase(std::remove_if(polygons.begin(), polygons.end(), [&](const std::vector<int> &p) {
                       small += p.size() < 3;
                       return p.size() < 3;
                   }),
                   polygons.end());
    repairs["faces_under_three_sides_dropped"] = small;
    // A vertex with two edges is a bend of one line or where two lines both end: no
    // corner. It is dissolved (its two edges become one) unless that would leave a face
    // fewer than three corners or double an edge that exists.
    std::vector<int> corners(polygons.size());
    for (size_t f = 0; f < polygons.size(); ++f) corners[f] = int(polygons[f].size());
    std::unordered_set<uint64_t> edges;
    for (int e = 0; e < nHe / 2; ++e)
        if (alive[e]) edges.insert(edgeKey(heFrom[2 * e], heTo[2 * e]));
    std::vector<char> gone(nV, 0);
    int dissolved = 0, keptBends = 0;
    for (int v = 0; v < nV; ++v) {
        if (out[v].size() != 2) continue;
        const int h1 = out[v][0], h2 = out[v][1];
        const int u = heTo[h1], w = heTo[h2], f1 = faceOf[h1], f2 = faceOf[h2];
        if (u == w || edges.count(edgeKey(u, w)) || corners[f1] <= 3 || corners[f2] <= 3 || f1 == f2) {
            ++keptBends;
            continue;
        }
        gone[v] = 1;
        --corners[f1], --corners[f2];
        edges.erase(edgeKey(u, v)), edges.erase(edgeKey(v, w));
        edges.insert(edgeKey(u, w));
        ++dissolved;
    }
    repairs["valence2_dissolved"] = dissolved;
    repairs["valence2_kept"] = keptBends;
    std::vector<std::vector<int>> kept;
    for (auto &poly : polygons) {
        std::vector<int> q;
        for (int v : poly)
            if (!gone[v]) q.push_back(v);
        kept.push_back(std::move(q));
    }
    RemeshResult result;
    result.nSym = 4;
    intoPolyMesh(vPos, kept, result);
    for (auto &[k, n] : repairs) result.repairs[k] = n;
    return result;
}

} // namespace

RemeshResult remeshStreamlines(const field::TangentFrames &frames, const field::RosyField &field,
                               const field::SingularityReport &singularities,
                               const StreamlineNetworkOptions &options) {
    if (field.nSym != 4)
        throw InputError(FileLoc{"-n"}, "the streamline network is built for 4-RoSy fields, not N = " +
                                            std::to_string(field.nSym),
                         "use -n 4, or --method position for 6-RoSy triangle meshes");
    if (!(options.edgeLength > 0) || !std::isfinite(options.edgeLength))
        throw InputError(FileLoc{"--edge"}, "the edge length must be positive and finite", "use e.g. --edge 1%");
    if (!(options.separatrixLength > 0))
        throw InputError(FileLoc{"--separatrix-length"}, "the separatrix length must be positive",
                         "use e.g. --separatrix-length 6 (multiples of the edge length), or inf for full separatrices");
    const Mesh &mesh = frames.mesh();
    for (int h = 0; h < 3 * mesh.nFaces(); ++h)
        if (mesh.twin(h) < 0)
            throw InputError(FileLoc{mesh.name()},
                             "the streamline network needs a closed surface: this mesh has a boundary (face " +
                                 std::to_string(h / 3) + ")",
                             "use --method position, which follows boundaries");
    double area = 0;
    for (int f = 0; f < mesh.nFaces(); ++f) area += mesh.faceArea(f);
    const double L = options.edgeLength;
    if (area / (L * L) > double(options.maxVertices)) {
        char msg[160];
        std::snprintf(msg, sizeof msg, "at edge length %.4g the streamline network would have about %.3g vertices, more than %lld",
                      L, area / (L * L), options.maxVertices);
        throw InputError(FileLoc{"--edge"}, msg, "use a longer --edge");
    }
    auto t0 = Clock::now();
    NetworkBuilder builder(frames, field, singularities, options);
    builder.place();
    const double placeMs = msSince(t0);
    t0 = Clock::now();
    std::map<std::string, int> repairs;
    repairs["lines"] = int(builder.lines().size());
    RemeshResult result = builder.build(repairs);
    result.timingsMs["streamlines"] = placeMs;
    result.timingsMs["arrangement"] = msSince(t0);
    return result;
}

} // namespace rosy::remesh
