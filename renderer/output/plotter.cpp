/// \file plotter.cpp
/// Merge, simplify and order strokes for a pen plotter (see plotter.h).

#include "renderer/output/plotter.h"

#include "core/error.h"
#include "core/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
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


/// Endpoints (and the pen's home, id ends.size()) in a static uniform grid of
/// about two points per cell, stored in cell order so a scan reads memory in
/// runs. Answers k-nearest and within-radius queries.
class TourGrid {
public:
    TourGrid(const std::vector<Vec2> &ends, const Vec2 &home) : m_nEnds(int(ends.size())) {
        m_pts = ends;
        m_pts.push_back(home);
        const int nPts = int(m_pts.size());
        Eigen::AlignedBox2d box;
        for (const Vec2 &p : m_pts) box.extend(p);
        m_min = box.min();
        const Vec2 size = (box.max() - box.min()).cwiseMax(1e-6);
        m_cell = std::max(std::sqrt(size.x() * size.y() / std::max(1.0, nPts / 2.0)), 1e-6);
        m_w = std::clamp(int(size.x() / m_cell) + 1, 1, 4096);
        m_h = std::clamp(int(size.y() / m_cell) + 1, 1, 4096);
        m_cell = std::max(size.x() / m_w, size.y() / m_h) * (1 + 1e-9) + 1e-12;
        m_start.assign(size_t(m_w) * m_h + 1, 0);
        m_ids.resize(size_t(nPts));
        for (const Vec2 &p : m_pts) ++m_start[cellIndex(p) + 1];
        for (size_t c = 1; c < m_start.size(); ++c) m_start[c] += m_start[c - 1];
        std::vector<int> fill(m_start.begin(), m_start.end() - 1);
        for (int i = 0; i < nPts; ++i) m_ids[size_t(fill[cellIndex(m_pts[size_t(i)])]++)] = i;
        m_cellPts.resize(size_t(nPts));
        for (int j = 0; j < nPts; ++j) m_cellPts[size_t(j)] = m_pts[size_t(m_ids[size_t(j)])];
    }

    int size() const { return int(m_pts.size()); }
    const Vec2 &point(int id) const { return m_pts[size_t(id)]; }

    /// The k nearest points to point q, nearest first (ties: lower id), leaving out
    /// q and the other end of q's stroke; fewer when there are fewer. Written to out[0..k).
    void nearest(int q, int k, int *out) const {
        const Vec2 &p = m_pts[size_t(q)];
        std::array<std::pair<double, int>, 64> best; // sorted (squared distance, id); no allocation
        int nBest = 0;
        const int cx = cellX(p.x()), cy = cellY(p.y());
        const int maxR = std::max(m_w, m_h);
        for (int r = 0; r <= maxR; ++r) {
            for (int y = std::max(cy - r, 0); y <= std::min(cy + r, m_h - 1); ++y) {
                const bool edgeRow = y == cy - r || y == cy + r;
                for (int x = cx - r; x <= cx + r; x += (edgeRow || r == 0) ? 1 : 2 * r) {
                    if (x < 0 || x >= m_w) continue;
                    const size_t c = size_t(y) * m_w + x;
                    for (int j = m_start[c]; j < m_start[c + 1]; ++j) {
                        const int e = m_ids[size_t(j)];
                        if (e == q || (q < m_nEnds && e < m_nEnds && e / 2 == q / 2)) continue;
                        const std::pair<double, int> cand{(m_cellPts[size_t(j)] - p).squaredNorm(), e};
                        if (nBest == k && !(cand < best[size_t(k - 1)])) continue;
                        int at = std::min(nBest, k - 1);
                        while (at > 0 && cand < best[size_t(at - 1)]) {
                            best[size_t(at)] = best[size_t(at - 1)];
                            --at;
                        }
                        best[size_t(at)] = cand;
                        nBest = std::min(nBest + 1, k);
                    }
                }
            }
            // Ring r+1 and beyond lie at least r cells away.
            if (nBest == k && best[size_t(k - 1)].first <= (r * m_cell) * (r * m_cell)) break;
        }
        for (int j = 0; j < k; ++j) out[j] = j < nBest ? best[size_t(j)].second : -1;
    }

    /// Cells a within() query of this radius visits, at most.
    double cellsWithin(double radius) const { return std::pow(2 * radius / m_cell + 1, 2); }

    /// Calls fn(id) for every point strictly closer than `radius` to p, in cell order.
    template <typename Fn> void within(const Vec2 &p, double radius, Fn &&fn) const {
        const int x0 = cellX(p.x() - radius), x1 = cellX(p.x() + radius);
        const int y0 = cellY(p.y() - radius), y1 = cellY(p.y() + radius);
        const double r2 = radius * radius;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const size_t c = size_t(y) * m_w + x;
                for (int j = m_start[c]; j < m_start[c + 1]; ++j)
                    if ((m_cellPts[size_t(j)] - p).squaredNorm() < r2) fn(m_ids[size_t(j)]);
            }
    }

private:
    int cellX(double x) const { return std::clamp(int(std::floor((x - m_min.x()) / m_cell)), 0, m_w - 1); }
    int cellY(double y) const { return std::clamp(int(std::floor((y - m_min.y()) / m_cell)), 0, m_h - 1); }
    size_t cellIndex(const Vec2 &p) const { return size_t(cellY(p.y())) * m_w + cellX(p.x()); }
    int m_nEnds;
    std::vector<Vec2> m_pts, m_cellPts;
    Vec2 m_min = Vec2::Zero();
    double m_cell = 1;
    int m_w = 1, m_h = 1;
    std::vector<int> m_start, m_ids;
};

/// Local search on an open tour of reversible strokes that starts at the origin:
/// 2-opt (reversing a run of the order, each stroke in it turned around) and
/// Or-opt (moving one stroke, either way round, between two others), both over
/// candidate lists of nearby endpoints (Johnson & McGeoch, "The traveling
/// salesman problem: a case study in local optimization", 1997: neighbour lists).
/// Every move applied shortens the travel, so the result is never worse than the
/// greedy tour it starts from. Work is bounded: at most options.twoOptMaxPasses
/// looks per stroke, and a budget of moved entries proportional to n (the
/// reversals and shifts).
void improveTour(const std::vector<Vec2> &ends, std::vector<int> &order, std::vector<char> &rev,
                 const PlotterOptions &options) {
    const int n = int(order.size());
    if (n < 2) return;
    const int k = std::clamp(options.neighbours, 1, 32);
    const Vec2 home = options.homePx;
    const int origin = 2 * n;
    // Large layers (random dense strokes, 100k in the benchmark) get the light
    // search: neighbour lists only, single-stroke Or-opt, one round.
    const bool large = n > options.largeLayer;
    const auto pt = [&](int e) -> const Vec2 & { return e == origin ? home : ends[size_t(e)]; };
    const TourGrid grid(ends, home);
    std::vector<int> nbr(size_t(grid.size()) * size_t(k));
    // Queries are independent and each writes only its own row: thread-count independent.
    parallelFor(0, grid.size(), [&](int64_t q) { grid.nearest(int(q), k, &nbr[size_t(q) * size_t(k)]); }, 256);
    // Every endpoint closer to x than `radius`: from x's list when the list reaches
    // that far, else from the grid (a long travel: the list would miss partners, and
    // the 2-opt gain criterion needs them all). Order does not matter: callers keep the best.
    const auto candidates = [&](int x, double radius, auto &&fn) {
        const int last = nbr[size_t(x) * k + size_t(k - 1)];
        // Beyond kMaxRangeCells cells (a jump across much of a large layer) the
        // list alone bounds the work; exhaustive 2-opt covers small layers anyway.
        constexpr double kMaxRangeCells = 1024;
        if (large || last < 0 || dist(pt(x), pt(last)) >= radius || grid.cellsWithin(radius) > kMaxRangeCells) {
            for (int j = 0; j < k; ++j) {
                const int c = nbr[size_t(x) * k + size_t(j)];
                if (c < 0 || !(dist(pt(x), pt(c)) < radius)) break;
                fn(c);
            }
            return;
        }
        grid.within(pt(x), radius, [&](int c) {
            if (c != x && !(x < origin && c < origin && c / 2 == x / 2)) fn(c);
        });
    };
    std::vector<int> where(static_cast<size_t>(n));
    for (int p = 0; p < n; ++p) where[size_t(order[size_t(p)])] = p;


    // Endpoint ids of position p's start (where the pen lands) and end (where it lifts).
    const auto S = [&](int p) { return 2 * order[size_t(p)] + rev[size_t(p)]; };
    const auto E = [&](int p) { return 2 * order[size_t(p)] + 1 - rev[size_t(p)]; };
    // Boundary b (0..n) is the travel into position b: from E(b-1) (the origin at
    // b = 0) to S(b); boundary n, after the last stroke, costs nothing.
    const auto left = [&](int b) { return b == 0 ? origin : E(b - 1); };
    const auto cost = [&](int b) { return b >= n ? 0.0 : dist(pt(left(b)), pt(S(b))); };
    const auto isStart = [&](int e) { return (e & 1) == rev[size_t(where[size_t(e / 2)])]; };

    int64_t budget = std::max<int64_t>(int64_t(options.movesPerStroke) * n, 100000);
    const auto reverseRun = [&](int b1, int b2) { // positions b1..b2-1
        std::reverse(order.begin() + b1, order.begin() + b2);
        std::reverse(rev.begin() + b1, rev.begin() + b2);
        for (int p = b1; p < b2; ++p) {
            rev[size_t(p)] = char(!rev[size_t(p)]);
            where[size_t(order[size_t(p)])] = p;
        }
        budget -= b2 - b1;
    };
    const double eps = 1e-9;
    const int maxRun = std::max(options.maxRun, 1);

    // 2-opt at boundary b: the best reversal that gives b's left or right end a
    // nearer partner. Returns true if one was applied.
    const auto twoOpt = [&](int b, int &best1, int &best2) {
        const double cb = cost(b);
        if (!(cb > eps)) return false;
        double bestDelta = -eps;
        best1 = best2 = -1;
        const auto consider = [&](int b1, int b2) {
            if (b1 == b2) return;
            if (b1 > b2) std::swap(b1, b2);
            if (b2 - b1 > maxRun) return;
            const double delta = dist(pt(left(b1)), pt(E(b2 - 1))) + (b2 < n ? dist(pt(S(b1)), pt(S(b2))) : 0.0) -
                                 cost(b1) - cost(b2);
            if (delta < bestDelta) {
                bestDelta = delta;
                best1 = b1;
                best2 = b2;
            }
        };
        // New edge left(b)–E(q): the other boundary is q + 1 (the origin: boundary 0).
        candidates(left(b), cb, [&](int c) {
            if (c == origin) consider(b, 0);
            else if (!isStart(c)) consider(b, where[size_t(c / 2)] + 1);
        });
        // New edge S(b)–S(q): the other boundary is q.
        if (b < n)
            candidates(S(b), cb, [&](int c) {
                if (c != origin && isStart(c)) consider(b, where[size_t(c / 2)]);
            });
        if (best1 < 0) return false;
        reverseRun(best1, best2);
        return true;
    };

    // Or-opt of the run of `len` strokes at positions p..p+len-1 (Or 1976): moved,
    // either way round (a turned run is reversed and each stroke in it turned),
    // next to an endpoint near one of its two ends.
    const auto orOpt = [&](int p, int len) {
        const int last = p + len - 1;
        if (last >= n) return false;
        const double removeGain = cost(p) + cost(p + len) - (p + len < n ? dist(pt(left(p)), pt(S(p + len))) : 0.0);
        if (!(removeGain > eps)) return false;
        double bestDelta = -eps;
        int bestQ = -1;
        bool bestFlip = false;
        const auto consider = [&](int q, bool flip) { // insert at boundary q of the current order
            if ((q >= p && q <= p + len) || std::abs(q - p) > maxRun) return;
            const int a = flip ? E(last) : S(p), z = flip ? S(p) : E(last);
            const double add = dist(pt(left(q)), pt(a)) + (q < n ? dist(pt(z), pt(S(q))) : 0.0) - cost(q);
            const double delta = add - removeGain;
            if (delta < bestDelta) {
                bestDelta = delta;
                bestQ = q;
                bestFlip = flip;
            }
        };
        for (const bool flip : {false, true}) {
            // The run is entered at x, its new start (after an end E(q-1) or the
            // origin), and left from y, its new end (before a start S(q)).
            const int x = flip ? E(last) : S(p), y = flip ? S(p) : E(last);
            for (int j = 0; j < k; ++j) {
                const int c = nbr[size_t(x) * k + j];
                if (c < 0 || !(dist(pt(x), pt(c)) < removeGain)) break;
                if (c == origin) consider(0, flip);
                else if (!isStart(c)) consider(where[size_t(c / 2)] + 1, flip);
            }
            for (int j = 0; j < k; ++j) {
                const int c = nbr[size_t(y) * k + j];
                if (c < 0 || !(dist(pt(y), pt(c)) < removeGain)) break;
                if (c != origin && isStart(c)) consider(where[size_t(c / 2)], flip);
            }
        }
        if (bestQ < 0) return false;
        if (bestFlip) reverseRun(p, p + len);
        // Rotate the run from p to just before the stroke now at bestQ.
        const int lo = std::min(p, bestQ), hi = std::max(p + len, bestQ);
        if (bestQ > p) {
            std::rotate(order.begin() + p, order.begin() + p + len, order.begin() + bestQ);
            std::rotate(rev.begin() + p, rev.begin() + p + len, rev.begin() + bestQ);
        } else {
            std::rotate(order.begin() + bestQ, order.begin() + p, order.begin() + p + len);
            std::rotate(rev.begin() + bestQ, rev.begin() + p, rev.begin() + p + len);
        }
        for (int i = lo; i < hi; ++i) where[size_t(order[size_t(i)])] = i;
        budget -= hi - lo;
        return true;
    };

    // Don't-look bits (Bentley 1992) as a FIFO of strokes: a stroke is looked at
    // again only when a move changed a travel next to it.
    std::deque<int> queue;
    std::vector<char> queued(static_cast<size_t>(n), 0);
    const auto push = [&](int p) {
        if (p < 0 || p >= n) return;
        const int s = order[size_t(p)];
        if (!queued[size_t(s)]) {
            queued[size_t(s)] = 1;
            queue.push_back(s);
        }
    };
    int64_t looks = int64_t(std::max(options.twoOptMaxPasses, 0)) * n;
    // Rounds: every stroke queued in tour order, then the queue run dry; a move
    // elsewhere can open a new one at a stroke already passed over, so a round
    // that moved anything is followed by another (two rounds at most).
    const int rounds = large ? 1 : 2;
    for (int round = 0; round < rounds && budget > 0 && looks > 0; ++round) {
    for (int p = 0; p < n; ++p) push(p);
    int64_t moves = 0;
    while (!queue.empty() && budget > 0 && looks-- > 0) {
        const int s = queue.front();
        queue.pop_front();
        queued[size_t(s)] = 0;
        for (const int b : {where[size_t(s)], where[size_t(s)] + 1}) {
            int b1 = -1, b2 = -1;
            if (twoOpt(b, b1, b2)) {
                ++moves;
                for (const int p : {b1 - 1, b1, b2 - 1, b2}) push(p);
                break;
            }
        }
        if (queued[size_t(s)] || !options.orOpt) continue;
        // Runs of 1–3 strokes starting or ending at s.
        for (int len = 1; len <= (large ? 1 : 3); ++len) {
            bool moved = false;
            for (const int first : {where[size_t(s)], where[size_t(s)] - len + 1}) {
                if (first < 0 || first + len > n || (len == 1 && first != where[size_t(s)])) continue;
                const int before = first > 0 ? order[size_t(first - 1)] : -1;
                const int after = first + len < n ? order[size_t(first + len)] : -1;
                const int runFirst = order[size_t(first)], runLast = order[size_t(first + len - 1)];
                if (orOpt(first, len)) {
                    ++moves;
                    for (const int t : {before, after, runFirst, runLast})
                        if (t >= 0) {
                            const int q = where[size_t(t)];
                            push(q - 1);
                            push(q);
                            push(q + 1);
                        }
                    moved = true;
                    break;
                }
            }
            if (moved) break;
        }
    }
    if (moves == 0) break;
    }
}


/// Pen-up travel of a tour given as stroke order and turned flags (see sortStrokes).
double tourLength(const std::vector<Vec2> &ends, const std::vector<int> &order, const std::vector<char> &rev,
                  const Vec2 &home) {
    Vec2 pen = home;
    double total = 0;
    for (size_t p = 0; p < order.size(); ++p) {
        total += dist(pen, ends[2 * size_t(order[p]) + size_t(rev[p])]);
        pen = ends[2 * size_t(order[p]) + 1 - size_t(rev[p])];
    }
    return total;
}

/// Exhaustive 2-opt, first improvement, in sweeps over every pair of boundaries
/// (at most maxPasses sweeps): O(n²) per sweep, for small tours only.
void exhaustiveTwoOpt(const std::vector<Vec2> &ends, std::vector<int> &order, std::vector<char> &rev,
                      const Vec2 &home, int maxPasses) {
    const int n = int(order.size());
    const auto S = [&](int p) -> const Vec2 & { return ends[2 * size_t(order[size_t(p)]) + size_t(rev[size_t(p)])]; };
    const auto E = [&](int p) -> const Vec2 & { return ends[2 * size_t(order[size_t(p)]) + 1 - size_t(rev[size_t(p)])]; };
    const auto left = [&](int b) -> const Vec2 & { return b == 0 ? home : E(b - 1); };
    for (int pass = 0; pass < maxPasses; ++pass) {
        bool improved = false;
        for (int b1 = 0; b1 < n; ++b1)
            for (int b2 = b1 + 1; b2 <= n; ++b2) {
                const double before = dist(left(b1), S(b1)) + (b2 < n ? dist(E(b2 - 1), S(b2)) : 0.0);
                const double after = dist(left(b1), E(b2 - 1)) + (b2 < n ? dist(S(b1), S(b2)) : 0.0);
                if (after < before - 1e-9) {
                    std::reverse(order.begin() + b1, order.begin() + b2);
                    std::reverse(rev.begin() + b1, rev.begin() + b2);
                    for (int p = b1; p < b2; ++p) rev[size_t(p)] = char(!rev[size_t(p)]);
                    improved = true;
                }
            }
        if (!improved) break;
    }
}

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

double penUpLength(const std::vector<Stroke> &strokes, const Eigen::Vector2d &homePx) {
    Vec2 pen = homePx;
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
    Vec2 pen = options.homePx;
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

    if (options.twoOptMaxPasses > 0) {
        // Small layers (contours: tens of long paths, where one bad placement
        // costs a lot) also try a second local optimum: exhaustive first-improvement
        // 2-opt sweeps from the greedy tour, then the same local search; the shorter wins.
        std::vector<int> order2 = order;
        std::vector<char> rev2 = rev;
        improveTour(ends, order, rev, options);
        if (n <= options.exhaustiveTwoOptMax) {
            exhaustiveTwoOpt(ends, order2, rev2, options.homePx, options.twoOptMaxPasses);
            improveTour(ends, order2, rev2, options);
            if (tourLength(ends, order2, rev2, options.homePx) < tourLength(ends, order, rev, options.homePx)) {
                order = std::move(order2);
                rev = std::move(rev2);
            }
        }
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
    if (report) report->penUpUnsortedPx += penUpLength(strokes, options.homePx);
    std::vector<Stroke> clean;
    clean.reserve(strokes.size());
    for (Stroke &s : strokes)
        if (removeDuplicatePoints(s)) clean.push_back(std::move(s));
    if (report) report->penDownInputPx += penDownLength(clean);

    clean = mergeStrokes(std::move(clean), options.mergeTolerancePx);
    // Strokes simplify independently, each writing only itself: thread-count independent.
    parallelFor(0, int64_t(clean.size()), [&](int64_t i) {
        simplifyStroke(clean[size_t(i)], options.simplifyTolerancePx);
    }, 64);
    // Overlaps after simplification: the segment test then sees the few points
    // a path keeps, not every traced one (on the 4096² bunny it was ~90 % of the
    // pass before simplification).
    clean = removeOverlaps(std::move(clean), options.overlapTolerancePx, options.overlapMinGapPx,
                           report ? &report->overlapRemovedPx : nullptr);
    if (options.sort) clean = sortStrokes(std::move(clean), options);

    if (report) {
        report->penUpPx += penUpLength(clean, options.homePx);
        report->penDownPx += penDownLength(clean);
        report->paths += int(clean.size());
    }
    return clean;
}

} // namespace rosy::renderer
