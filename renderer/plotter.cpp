/// \file plotter.cpp
/// Merge, simplify and order strokes for a pen plotter (see plotter.h).

#include "renderer/plotter.h"

#include "core/error.h"
#include "core/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace rosy::renderer {

namespace {

using Vec2 = Eigen::Vector2d;

double dist(const Vec2 &a, const Vec2 &b) { return (a - b).norm(); }

void reverseStroke(Stroke &s) {
    std::reverse(s.points.begin(), s.points.end());
    std::reverse(s.widths.begin(), s.widths.end());
}

/// Endpoints (2i: start of stroke i, 2i+1: its end) sorted by the key of their
/// grid cell, for the merge, which only ever asks for the 3×3 cells around a
/// point. A sorted array instead of a hash map: one allocation, cache friendly.
class SparseEndGrid {
public:
    SparseEndGrid(const std::vector<Stroke> &strokes, double cell) : m_cell(cell) {
        m_entries.reserve(2 * strokes.size());
        for (size_t i = 0; i < strokes.size(); ++i) {
            m_entries.push_back({key(strokes[i].points.front()), int(2 * i)});
            m_entries.push_back({key(strokes[i].points.back()), int(2 * i + 1)});
        }
        std::sort(m_entries.begin(), m_entries.end());
    }
    /// Nearest endpoint of a free stroke within `tol` of p; ties go to the lowest id. -1 if none.
    template <typename Free, typename PointOf>
    int nearest(const Vec2 &p, double tol, Free &&isFree, PointOf &&pointOf) const {
        const auto [cx, cy] = cellOf(p);
        int best = -1;
        double bestD = tol;
        // Keys order cells by column, then row: the three cells of a column are one run.
        for (int64_t dx = -1; dx <= 1; ++dx) {
            const uint64_t lo = pack(cx + dx, cy - 1), hi = pack(cx + dx, cy + 1);
            auto it = std::lower_bound(m_entries.begin(), m_entries.end(), std::pair<uint64_t, int>{lo, -1});
            for (; it != m_entries.end() && it->first <= hi; ++it) {
                const int e = it->second;
                if (!isFree(e / 2)) continue;
                const double d = dist(p, pointOf(e));
                if (d < bestD || (d == bestD && (best < 0 || e < best))) {
                    bestD = d;
                    best = e;
                }
            }
        }
        return best;
    }

private:
    std::pair<int64_t, int64_t> cellOf(const Vec2 &p) const {
        // Clamped before the cast: absurd coordinates share an edge cell instead of overflowing.
        const auto c = [&](double v) { return int64_t(std::clamp(std::floor(v / m_cell), -4e9, 4e9)); };
        return {c(p.x()), c(p.y())};
    }
    /// Offsetting by 2^31 keeps the order of negative and positive cells.
    static uint64_t pack(int64_t x, int64_t y) {
        const auto biased = [](int64_t v) { return uint64_t(std::clamp<int64_t>(v, -(int64_t(1) << 31) + 1, (int64_t(1) << 31) - 2) + (int64_t(1) << 31)); };
        return (biased(x) << 32) | biased(y);
    }
    uint64_t key(const Vec2 &p) const {
        const auto [x, y] = cellOf(p);
        return pack(x, y);
    }
    double m_cell;
    std::vector<std::pair<uint64_t, int>> m_entries;
};

/// Dense uniform grid of endpoints for the greedy tour; endpoints are removed as
/// their strokes are drawn, and the grid is rebuilt coarser as it empties so
/// late queries do not walk thousands of empty cells.
class DenseEndGrid {
public:
    explicit DenseEndGrid(const std::vector<Vec2> &ends) : m_ends(ends) {}

    void build(const std::vector<int> &alive) {
        Eigen::AlignedBox2d box;
        for (int e : alive) box.extend(m_ends[e]);
        m_origin = box.min();
        const Vec2 size = (box.max() - box.min()).cwiseMax(1e-6);
        // About two endpoints per cell.
        m_cell = std::max(std::sqrt(size.x() * size.y() / std::max<double>(1, double(alive.size()) / 2)), 1e-6);
        m_w = std::clamp(int(size.x() / m_cell) + 1, 1, 4096);
        m_h = std::clamp(int(size.y() / m_cell) + 1, 1, 4096);
        m_cell = std::max(size.x() / m_w, size.y() / m_h) * (1 + 1e-9) + 1e-12;
        m_cells.assign(size_t(m_w) * m_h, {});
        for (int e : alive) m_cells[cellIndex(m_ends[e])].push_back(e);
        m_count = int(alive.size());
        m_builtCount = m_count;
    }

    void remove(int e) {
        auto &c = m_cells[cellIndex(m_ends[e])];
        auto it = std::find(c.begin(), c.end(), e);
        if (it == c.end()) return;
        *it = c.back();
        c.pop_back();
        --m_count;
    }

    int count() const { return m_count; }
    bool sparse() const { return m_count > 64 && m_count * 4 < m_builtCount; }

    /// Nearest remaining endpoint to p (ties: lowest id); -1 when empty.
    int nearest(const Vec2 &p) const {
        if (m_count == 0) return -1;
        const int cx = std::clamp(int(std::floor((p.x() - m_origin.x()) / m_cell)), 0, m_w - 1);
        const int cy = std::clamp(int(std::floor((p.y() - m_origin.y()) / m_cell)), 0, m_h - 1);
        int best = -1;
        double bestD = std::numeric_limits<double>::infinity();
        const int maxR = std::max(m_w, m_h);
        for (int r = 0; r <= maxR; ++r) {
            for (int y = cy - r; y <= cy + r; ++y) {
                if (y < 0 || y >= m_h) continue;
                const bool edgeRow = (y == cy - r || y == cy + r);
                for (int x = cx - r; x <= cx + r; x += (edgeRow || r == 0) ? 1 : 2 * r) {
                    if (x < 0 || x >= m_w) continue;
                    for (int e : m_cells[size_t(y) * m_w + x]) {
                        const double d = (m_ends[e] - p).squaredNorm();
                        if (d < bestD || (d == bestD && e < best)) {
                            bestD = d;
                            best = e;
                        }
                    }
                }
            }
            // Anything in ring r+1 or beyond is at least r cells away.
            if (best >= 0 && std::sqrt(bestD) <= r * m_cell) break;
        }
        return best;
    }

private:
    size_t cellIndex(const Vec2 &p) const {
        const int cx = std::clamp(int(std::floor((p.x() - m_origin.x()) / m_cell)), 0, m_w - 1);
        const int cy = std::clamp(int(std::floor((p.y() - m_origin.y()) / m_cell)), 0, m_h - 1);
        return size_t(cy) * m_w + cx;
    }
    const std::vector<Vec2> &m_ends;
    Vec2 m_origin = Vec2::Zero();
    double m_cell = 1;
    int m_w = 1, m_h = 1;
    std::vector<std::vector<int>> m_cells;
    int m_count = 0, m_builtCount = 0;
};

} // namespace

bool removeDuplicatePoints(Stroke &stroke) {
    const bool hasWidths = stroke.widths.size() == stroke.points.size();
    std::vector<Vec2> pts;
    std::vector<float> ws;
    pts.reserve(stroke.points.size());
    ws.reserve(stroke.points.size());
    for (size_t i = 0; i < stroke.points.size(); ++i) {
        const Vec2 &p = stroke.points[i];
        if (!p.allFinite()) continue;
        if (!pts.empty() && (pts.back() - p).squaredNorm() <= 1e-18) continue;
        pts.push_back(p);
        float w = hasWidths ? stroke.widths[i] : 1.0f;
        ws.push_back(std::isfinite(w) ? std::max(w, 0.0f) : 0.0f);
    }
    if (pts.empty()) {
        stroke.points.clear();
        stroke.widths.clear();
        return false;
    }
    if (pts.size() == 1) {
        pts.push_back(pts.front());
        ws.push_back(ws.front());
    }
    stroke.points = std::move(pts);
    stroke.widths = std::move(ws);
    return true;
}

void simplifyStroke(Stroke &stroke, double tolerancePx) {
    const size_t n = stroke.points.size();
    if (n <= 2 || !(tolerancePx > 0)) return;
    const auto &p = stroke.points;
    std::vector<char> keep(n, 0);
    keep[0] = keep[n - 1] = 1;
    // Explicit stack: recursion depth would follow the point count on a long spiral.
    std::vector<std::pair<size_t, size_t>> stack{{0, n - 1}};
    while (!stack.empty()) {
        // Plain copies, not a structured binding: clang 14 cannot capture those in the lambda below.
        const size_t a = stack.back().first;
        const size_t b = stack.back().second;
        stack.pop_back();
        if (b <= a + 1) continue;
        const Vec2 chord = p[b] - p[a];
        const double len2 = chord.squaredNorm();
        double worst = -1;
        size_t worstI = a;
        for (size_t i = a + 1; i < b; ++i) {
            const Vec2 d = p[i] - p[a];
            // A closed span (a == b in space) measures distance to the point itself.
            double dd;
            if (len2 <= 1e-18) {
                dd = d.norm();
            } else {
                const double t = std::clamp(d.dot(chord) / len2, 0.0, 1.0);
                dd = (d - t * chord).norm();
            }
            // Ties go to the point nearest the middle of the span, so a regular
            // zigzag splits in halves instead of peeling one point per step (O(n²)).
            const auto offMid = [&](size_t k) { return k > (a + b) / 2 ? k - (a + b) / 2 : (a + b) / 2 - k; };
            if (dd > worst || (dd == worst && offMid(i) < offMid(worstI))) {
                worst = dd;
                worstI = i;
            }
        }
        if (worst > tolerancePx) {
            keep[worstI] = 1;
            stack.push_back({a, worstI});
            stack.push_back({worstI, b});
        }
    }
    size_t k = 0;
    for (size_t i = 0; i < n; ++i)
        if (keep[i]) {
            stroke.points[k] = stroke.points[i];
            stroke.widths[k] = stroke.widths[i];
            ++k;
        }
    stroke.points.resize(k);
    stroke.widths.resize(k);
}

namespace {

/// The t in [0, 1] where lo <= f0 + t·df <= hi, as [t0, t1]; t0 > t1 when empty.
std::pair<double, double> linearBand(double f0, double df, double lo, double hi) {
    if (std::abs(df) < 1e-300) return (f0 >= lo && f0 <= hi) ? std::pair{0.0, 1.0} : std::pair{1.0, 0.0};
    double a = (lo - f0) / df, b = (hi - f0) / df;
    if (a > b) std::swap(a, b);
    return {std::max(a, 0.0), std::min(b, 1.0)};
}

/// Uniform grid of segments (compressed rows: cell -> segment ids in increasing
/// order), each segment in every cell its box, grown by `pad`, touches.
class SegmentGrid {
public:
    SegmentGrid(const std::vector<std::pair<Vec2, Vec2>> &segs, double pad) : m_pad(pad) {
        Eigen::AlignedBox2d box;
        for (const auto &[a, b] : segs) {
            box.extend(a);
            box.extend(b);
        }
        if (box.isEmpty()) box.extend(Vec2::Zero());
        m_origin = box.min() - Vec2::Constant(pad);
        const Vec2 size = (box.max() - box.min()).array() + 2 * pad + 1e-9;
        m_cell = std::max({4 * pad, std::sqrt(size.x() * size.y() / std::max<double>(1, double(segs.size()))),
                           size.x() / 2048, size.y() / 2048, 1e-9});
        m_w = std::clamp(int(size.x() / m_cell) + 1, 1, 2049);
        m_h = std::clamp(int(size.y() / m_cell) + 1, 1, 2049);
        std::vector<int> count(size_t(m_w) * m_h + 1, 0);
        const auto each = [&](int id, auto &&fn) {
            const auto [x0, y0, x1, y1] = range(segs[size_t(id)].first, segs[size_t(id)].second);
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) fn(size_t(y) * m_w + x);
        };
        for (int id = 0; id < int(segs.size()); ++id) each(id, [&](size_t c) { ++count[c + 1]; });
        for (size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
        m_start = count;
        m_ids.resize(size_t(count.back()));
        for (int id = 0; id < int(segs.size()); ++id) each(id, [&](size_t c) { m_ids[size_t(count[c]++)] = id; });
    }
    /// Calls fn(id) for every segment id below `before` sharing a cell with the
    /// box of a–b grown by the pad (an id may come more than once).
    template <typename Fn> void visit(const Vec2 &a, const Vec2 &b, int before, Fn &&fn) const {
        const auto [x0, y0, x1, y1] = range(a, b);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const size_t c = size_t(y) * m_w + x;
                for (int k = m_start[c]; k < m_start[c + 1] && m_ids[size_t(k)] < before; ++k) fn(m_ids[size_t(k)]);
            }
    }

private:
    std::array<int, 4> range(const Vec2 &a, const Vec2 &b) const {
        const auto cx = [&](double v) { return std::clamp(int(std::floor((v - m_origin.x()) / m_cell)), 0, m_w - 1); };
        const auto cy = [&](double v) { return std::clamp(int(std::floor((v - m_origin.y()) / m_cell)), 0, m_h - 1); };
        return {cx(std::min(a.x(), b.x()) - m_pad), cy(std::min(a.y(), b.y()) - m_pad),
                cx(std::max(a.x(), b.x()) + m_pad), cy(std::max(a.y(), b.y()) + m_pad)};
    }
    double m_pad;
    Vec2 m_origin;
    double m_cell = 1;
    int m_w = 1, m_h = 1;
    std::vector<int> m_start, m_ids;
};

/// Point and width at arc length `s` along a stroke with cumulative lengths `cum`.
std::pair<Vec2, float> pointAtArc(const Stroke &st, const std::vector<double> &cum, double s) {
    const size_t n = st.points.size();
    size_t j = size_t(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin());
    j = std::clamp<size_t>(j, 1, n - 1) - 1; // segment j: points j, j+1
    const double len = cum[j + 1] - cum[j];
    const double t = len > 0 ? std::clamp((s - cum[j]) / len, 0.0, 1.0) : 0.0;
    const Vec2 p = (1 - t) * st.points[j] + t * st.points[j + 1];
    const float w = float((1 - t) * st.widths[j] + t * st.widths[j + 1]);
    return {p, w};
}

} // namespace

std::vector<Stroke> removeOverlaps(std::vector<Stroke> strokes, double tolerancePx, double minGapPx,
                                   double *removedPx) {
    if (!(tolerancePx > 0) || strokes.empty()) return strokes;
    for (Stroke &s : strokes)
        if (s.widths.size() != s.points.size()) s.widths.assign(s.points.size(), 1.0f);
    std::vector<std::pair<Vec2, Vec2>> segs;
    std::vector<int> firstSeg(strokes.size() + 1, 0);
    for (size_t i = 0; i < strokes.size(); ++i) {
        firstSeg[i] = int(segs.size());
        for (size_t j = 1; j < strokes[i].points.size(); ++j) segs.push_back({strokes[i].points[j - 1], strokes[i].points[j]});
    }
    firstSeg[strokes.size()] = int(segs.size());
    const SegmentGrid grid(segs, tolerancePx);
    const double sinMax = std::sin(kMaxOverlapAngleDeg * 3.14159265358979323846 / 180.0);

    // Kept parts of the segments processed so far, as t intervals: segment k's are keptAt[k]..keptAt[k+1].
    std::vector<std::pair<double, double>> kept;
    kept.reserve(segs.size() + 16);
    std::vector<int> keptAt(segs.size() + 1, 0);
    std::vector<int> stamp(segs.size(), -1);
    std::vector<std::pair<double, double>> covered;

    std::vector<Stroke> out;
    out.reserve(strokes.size());
    double removed = 0;
    for (size_t i = 0; i < strokes.size(); ++i) {
        Stroke &st = strokes[i];
        const int n = int(st.points.size());
        std::vector<double> cum(size_t(std::max(n, 1)), 0.0);
        for (int j = 1; j < n; ++j) cum[size_t(j)] = cum[size_t(j) - 1] + dist(st.points[size_t(j) - 1], st.points[size_t(j)]);
        // Kept ranges of this stroke in arc length, built segment by segment.
        std::vector<std::pair<double, double>> ranges;
        bool untouched = true;
        for (int j = 0; j + 1 < n; ++j) {
            const int c = firstSeg[i] + j;
            const Vec2 &P = segs[size_t(c)].first, &Q = segs[size_t(c)].second;
            const Vec2 u = Q - P;
            const double uLen = u.norm();
            covered.clear();
            if (uLen > 0) {
                grid.visit(P, Q, c, [&](int o) {
                    if (stamp[size_t(o)] == c) return;
                    stamp[size_t(o)] = c;
                    const Vec2 &A = segs[size_t(o)].first;
                    const Vec2 v = segs[size_t(o)].second - A;
                    const double vLen = v.norm();
                    if (!(vLen > 0) || std::abs(u.x() * v.y() - u.y() * v.x()) > sinMax * uLen * vLen) return;
                    const Vec2 e = v / vLen, nrm(-e.y(), e.x());
                    for (int k = keptAt[size_t(o)]; k < keptAt[size_t(o) + 1]; ++k) {
                        const auto [ka, kb] = kept[size_t(k)];
                        const Vec2 a = A + ka * v;
                        const double len = (kb - ka) * vLen;
                        const double d0 = nrm.dot(P - a), d1 = nrm.dot(Q - a);
                        const double s0 = e.dot(P - a), s1 = e.dot(Q - a);
                        const auto [t0, t1] = linearBand(d0, d1 - d0, -tolerancePx, tolerancePx);
                        const auto [r0, r1] = linearBand(s0, s1 - s0, 0.0, len);
                        const double lo = std::max(t0, r0), hi = std::min(t1, r1);
                        if ((hi - lo) * uLen > 1e-9) covered.push_back({lo, hi});
                    }
                });
            }
            std::sort(covered.begin(), covered.end());
            double at = 0; // kept = [0, 1] minus the union of covered
            for (const auto &[lo, hi] : covered) {
                if (lo > at) kept.push_back({at, lo});
                at = std::max(at, hi);
            }
            if (at < 1) kept.push_back({at, 1.0});
            keptAt[size_t(c) + 1] = int(kept.size());
            if (!covered.empty()) untouched = false;
            const double base = cum[size_t(j)], len = cum[size_t(j) + 1] - cum[size_t(j)];
            for (int k = keptAt[size_t(c)]; k < keptAt[size_t(c) + 1]; ++k) {
                const double a = base + kept[size_t(k)].first * len, b = base + kept[size_t(k)].second * len;
                if (!ranges.empty() && a - ranges.back().second <= 1e-12) ranges.back().second = b;
                else ranges.push_back({a, b});
            }
        }
        if (untouched || n < 2 || cum.back() <= 0) {
            out.push_back(std::move(st));
            continue;
        }
        // Rejoin across short interior overlaps, drop slivers.
        std::vector<std::pair<double, double>> joined;
        for (const auto &r : ranges) {
            if (!joined.empty() && r.first - joined.back().second < minGapPx) joined.back().second = r.second;
            else joined.push_back(r);
        }
        double keptLen = 0;
        for (const auto &[a, b] : joined) {
            if (b - a < tolerancePx) continue;
            keptLen += b - a;
            Stroke piece;
            piece.kind = st.kind;
            piece.family = st.family;
            piece.id = st.id;
            const auto [pa, wa] = pointAtArc(st, cum, a);
            piece.points.push_back(pa);
            piece.widths.push_back(wa);
            for (int k = 0; k < n; ++k)
                if (cum[size_t(k)] > a && cum[size_t(k)] < b) {
                    piece.points.push_back(st.points[size_t(k)]);
                    piece.widths.push_back(st.widths[size_t(k)]);
                }
            const auto [pb, wb] = pointAtArc(st, cum, b);
            piece.points.push_back(pb);
            piece.widths.push_back(wb);
            out.push_back(std::move(piece));
        }
        removed += cum.back() - keptLen;
    }
    if (removedPx) *removedPx += removed;
    return out;
}

std::vector<Stroke> mergeStrokes(std::vector<Stroke> strokes, double tolerancePx) {
    if (!(tolerancePx > 0) || strokes.size() < 2) return strokes;
    const int n = int(strokes.size());
    SparseEndGrid grid(strokes, tolerancePx);
    std::vector<char> used(n, 0);
    auto isFree = [&](int s) { return !used[s]; };
    auto pointOf = [&](int e) -> const Vec2 & {
        const Stroke &s = strokes[e / 2];
        return (e & 1) ? s.points.back() : s.points.front();
    };
    auto append = [](Stroke &dst, const Stroke &src) {
        const size_t skip = (dst.points.back() - src.points.front()).squaredNorm() <= 1e-18 ? 1 : 0;
        dst.points.insert(dst.points.end(), src.points.begin() + skip, src.points.end());
        dst.widths.insert(dst.widths.end(), src.widths.begin() + skip, src.widths.end());
    };

    std::vector<Stroke> out;
    out.reserve(strokes.size());
    for (int i = 0; i < n; ++i) {
        if (used[i]) continue;
        used[i] = 1;
        Stroke chain = std::move(strokes[i]);
        // Grow at the tail, then at the head (by growing the reversed chain's tail).
        for (int side = 0; side < 2; ++side) {
            for (;;) {
                const int e = grid.nearest(chain.points.back(), tolerancePx, isFree, pointOf);
                if (e < 0) break;
                used[e / 2] = 1;
                Stroke next = std::move(strokes[e / 2]);
                if (e & 1) reverseStroke(next);
                append(chain, next);
            }
            reverseStroke(chain);
        }
        out.push_back(std::move(chain));
    }
    return out;
}

double penUpLength(const std::vector<Stroke> &strokes) {
    Vec2 pen = Vec2::Zero();
    double total = 0;
    for (const Stroke &s : strokes) {
        if (s.points.empty()) continue;
        total += dist(pen, s.points.front());
        pen = s.points.back();
    }
    return total;
}

double penDownLength(const std::vector<Stroke> &strokes) {
    double total = 0;
    for (const Stroke &s : strokes)
        for (size_t i = 1; i < s.points.size(); ++i) total += dist(s.points[i - 1], s.points[i]);
    return total;
}

std::vector<Stroke> sortStrokes(std::vector<Stroke> strokes, const PlotterOptions &options) {
    const int n = int(strokes.size());
    if (n < 2) return strokes;

    // Greedy nearest end: from the pen, go to the closest free endpoint and draw
    // its stroke from there (reversing it if that endpoint is its end).
    std::vector<Vec2> ends(2 * size_t(n));
    for (int i = 0; i < n; ++i) {
        ends[2 * i] = strokes[i].points.front();
        ends[2 * i + 1] = strokes[i].points.back();
    }
    DenseEndGrid grid(ends);
    std::vector<int> alive(2 * size_t(n));
    for (int e = 0; e < 2 * n; ++e) alive[e] = e;
    grid.build(alive);
    std::vector<char> drawn(n, 0);
    std::vector<int> order;
    std::vector<char> rev;
    order.reserve(n);
    rev.reserve(n);
    Vec2 pen = Vec2::Zero();
    while (grid.count() > 0) {
        if (grid.sparse()) {
            alive.clear();
            for (int i = 0; i < n; ++i)
                if (!drawn[i]) {
                    alive.push_back(2 * i);
                    alive.push_back(2 * i + 1);
                }
            grid.build(alive);
        }
        const int e = grid.nearest(pen);
        ROSY_CHECK(e >= 0);
        const int s = e / 2;
        drawn[s] = 1;
        grid.remove(2 * s);
        grid.remove(2 * s + 1);
        order.push_back(s);
        rev.push_back(char(e & 1));
        pen = (e & 1) ? ends[2 * s] : ends[2 * s + 1];
    }

    // Windowed 2-opt on the open tour. Reversing positions i..j (and each stroke
    // in it) changes only the two travels at the run's borders:
    //   old: |E(i-1) S(i)| + |E(j) S(j+1)|    new: |E(i-1) E(j)| + |S(i) S(j+1)|
    std::vector<Vec2> S(n), E(n);
    for (int k = 0; k < n; ++k) {
        const int s = order[k];
        S[k] = rev[k] ? ends[2 * s + 1] : ends[2 * s];
        E[k] = rev[k] ? ends[2 * s] : ends[2 * s + 1];
    }
    const int window = std::max(1, options.twoOptWindow);
    for (int pass = 0; pass < options.twoOptMaxPasses; ++pass) {
        bool improved = false;
        for (int i = 0; i < n; ++i) {
            const int jEnd = std::min(n - 1, i + window - 1);
            for (int j = i; j <= jEnd; ++j) {
                const Vec2 prev = i > 0 ? E[i - 1] : Vec2::Zero();
                const bool hasNext = j + 1 < n;
                double before = dist(prev, S[i]);
                double after = dist(prev, E[j]);
                if (hasNext) {
                    before += dist(E[j], S[j + 1]);
                    after += dist(S[i], S[j + 1]);
                }
                if (after < before - 1e-9) {
                    std::reverse(order.begin() + i, order.begin() + j + 1);
                    std::reverse(rev.begin() + i, rev.begin() + j + 1);
                    std::reverse(S.begin() + i, S.begin() + j + 1);
                    std::reverse(E.begin() + i, E.begin() + j + 1);
                    for (int k = i; k <= j; ++k) {
                        rev[k] = char(!rev[k]);
                        std::swap(S[k], E[k]);
                    }
                    improved = true;
                }
            }
        }
        if (!improved) break;
    }

    std::vector<Stroke> out;
    out.reserve(n);
    for (int k = 0; k < n; ++k) {
        out.push_back(std::move(strokes[order[k]]));
        if (rev[k]) reverseStroke(out.back());
    }
    return out;
}

std::vector<Stroke> optimizeForPlotter(std::vector<Stroke> strokes, const PlotterOptions &options,
                                       PlotterReport *report) {
    if (report) report->penUpUnsortedPx += penUpLength(strokes);
    std::vector<Stroke> clean;
    clean.reserve(strokes.size());
    for (Stroke &s : strokes)
        if (removeDuplicatePoints(s)) clean.push_back(std::move(s));
    if (report) report->penDownInputPx += penDownLength(clean);

    clean = removeOverlaps(std::move(clean), options.overlapTolerancePx, options.overlapMinGapPx,
                           report ? &report->overlapRemovedPx : nullptr);
    clean = mergeStrokes(std::move(clean), options.mergeTolerancePx);
    // Strokes simplify independently, each writing only itself: thread-count independent.
    parallelFor(0, int64_t(clean.size()), [&](int64_t i) {
        simplifyStroke(clean[size_t(i)], options.simplifyTolerancePx);
    }, 64);
    if (options.sort) clean = sortStrokes(std::move(clean), options);

    if (report) {
        report->penUpPx += penUpLength(clean);
        report->penDownPx += penDownLength(clean);
        report->paths += int(clean.size());
    }
    return clean;
}

} // namespace rosy::renderer
