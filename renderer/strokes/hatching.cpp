#include "renderer/strokes/hatching.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/pixel_array.h"
#include "field/mesh/union_find.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>

namespace rosy::renderer {

namespace {

constexpr double kCos45 = 0.70710678118654752;
/// Band of angles between two lines of one layer, within one d_sep of each other,
/// that HatchReport::incoherentFraction counts: cos 20° and cos 50°.
constexpr double kIncoherentCosHi = 0.93969262078590838;
constexpr double kIncoherentCosLo = 0.64278760968653933;
/// The tracer treats lines within 55° as the same family, a margin over the 45° the
/// measurement uses: a sample's tangent is its incoming step while the measurement
/// takes central chords, which differ by up to half a step's turn (6°), and a line
/// ending near another may be judged from either side.
constexpr double kSameFamilyCos = 0.57357643635104609;
/// Largest turn of a stroke in one integration step (0.2 d_sep): 12°. Sharper turns
/// happen where the field swirls (singularities, label noise); stopping there keeps
/// strokes straight and keeps a sample's tangent within a few degrees of its chords.
constexpr double kMaxTurnCos = 0.97814760073380564;
/// d_test / d_sep (Jobard & Lefer 1997; keithfma and anvaka use the same ratio).
constexpr double kTestRatio = 0.5;
/// Integration step as a fraction of d_sep, and its bounds in style px (times
/// HatchStyle::pixelScale, so print mode keeps them on paper at any pitch): the upper
/// bound keeps steps short enough that the silhouette guard band cannot be jumped.
constexpr double kStepRatio = 0.2;
constexpr double kMinStepPx = 0.5;
constexpr double kMaxStepPx = 2.0;
/// Depth discontinuity: relative depth change over one pixel, alone or with a normal
/// change of more than 60° (a different sheet of surface close behind).
constexpr double kDepthJump = 0.03;
constexpr double kDepthJumpWithNormal = 0.01;
constexpr double kNormalJumpCos = 0.5;
/// Edge pixels are marked 1 (background, or a depth change with a normal turn: a
/// crease or a fold) or kDepthEdge (a pure depth jump: one surface hides another).
/// Stroke centres keep a guard band from every edge, except in the hole pass at a
/// depth jump, whose both sides are surface (ink over the edge stays on the object):
/// there a hole line may run up to the edge pixels themselves (print mode, whose band
/// is a distance, keeps it in every pass). Without
/// that, the band on both sides and the lines' d_test leave a strip 6–10 px wide
/// along an occluding edge inside dark tone, too narrow for a hole seed's
/// clearance, which reads as a light crack where no contour covers it.
constexpr uint8_t kDepthEdge = 2;
/// Bits of the blocked map (Hatcher::m_blocked): blocked for the line passes, for the
/// hole pass.
constexpr uint8_t kBlockLines = 1, kBlockHoles = 2, kBlockAll = kBlockLines | kBlockHoles;
/// A seed keeps this many d_sep from same-direction lines: slightly under one, so a
/// seed placed at exactly d_sep from its parent is not rejected by rounding; the hole
/// filling pass (Hatcher::fillHoles) accepts less room.
constexpr double kSeedClearance = 0.98;
constexpr double kFillClearance = 0.7;
/// The hole-filling pass keeps strokes from two d_sep on: a finger or a fold in
/// shadow has no room for longer ones, and left empty it reads as a light patch.
constexpr double kFillMinLengthRatio = 2.0;
/// Range of tone (target density) over which the ends of each family's strokes are
/// staggered, centred on its threshold (highlightDensity, crossDensity); the second
/// family's reaches half of it below crossDensity, where the first family's tone
/// rule still applies (its lines never cross there).
constexpr double kEndStagger[2] = {0.04, 0.08};
/// Which pass a stroke is traced in, passed down from the seed to the length rule:
/// Jobard–Lefer's passes of each family, or the hole pass (Hatcher::fillHoles),
/// whose seeds accept less room (kFillClearance) and whose strokes may be shorter
/// (kFillMinLengthRatio, the style's minLengthPx held only up to the stub length).
enum class Pass { Lines, Holes };
/// Tapered ends keep this fraction of the width, so a stroke does not end in nothing.
constexpr double kTaperFloor = 0.2;
/// Longest taper at each end of a stroke, in stroke widths.
constexpr double kMaxTaperWidths = 3.0;

float clampDensity(float d) { return d == d ? std::clamp(d, 0.f, 1.f) : 0.f; }

/// Line spacing at which parallel lines of the style's width give `coverage`.
double spacingOfCoverage(double coverage, const styles::HatchStyle &style) {
    const double lo = style.minSpacingPx, hi = std::max(style.minSpacingPx, style.maxSpacingPx);
    if (!(coverage > 0)) return hi;
    return std::clamp(style.spacingGain * style.strokeWidthPx / coverage, lo, hi);
}

/// splitmix64: a tiny, well-mixed hash for per-stroke random numbers.
uint64_t mix(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// Uniform in [0, 1) from (seed, id, k).
double random01(uint32_t seed, uint32_t id, uint32_t k) {
    const uint64_t h = mix(mix((uint64_t(seed) << 32) | id) ^ k);
    return double(h >> 11) * (1.0 / 9007199254740992.0);
}

Vec2 rotate(const Vec2 &v, double c, double s) { return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y()); }

/// The index of the pixel holding raster point p, clamped into the image.
size_t clampedPixel(const ScreenField &field, const Vec2 &p) {
    const int x = std::clamp(int(std::floor(p.x())), 0, field.width - 1);
    const int y = std::clamp(int(std::floor(p.y())), 0, field.height - 1);
    return size_t(field.index(x, y));
}

double pointSegmentDistance(const Vec2 &p, const Vec2 &a, const Vec2 &b) {
    const Vec2 ab = b - a;
    const double l2 = ab.squaredNorm();
    double t = l2 > 0 ? (p - a).dot(ab) / l2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return (p - (a + t * ab)).norm();
}

/// An accepted streamline sample, as Jobard–Lefer's distance grid stores it.
struct Sample {
    Vec2 p;
    Vec2 t;     // unit tangent
    double arc; // arc length along its stroke from the seed (negative backwards)
    int stroke;
    int family;
    double dTest; // d_test at the sample's own pixel
    int index;    // place in its stroke's trace order: the seed, forward samples, backward ones
    int crosses;  // an earlier first-family line crossing it, or -1 (Hatcher::relabelCrossings)
};

/// Uniform grid over the image holding the samples by cell. Samples are only appended
/// or removed from the back, so each cell's list stays in insertion order and a
/// rejected stroke is undone by popping its samples in reverse.
class SampleGrid {
public:
    SampleGrid(int width, int height, double cellPx)
        : m_cell(cellPx), m_nx(std::max(1, int(std::ceil(width / cellPx)))),
          m_ny(std::max(1, int(std::ceil(height / cellPx)))), m_cells(size_t(m_nx) * size_t(m_ny)),
          m_cellMaxR(m_cells.size(), 0.0), m_bnx((m_nx + kBlock - 1) / kBlock), m_bny((m_ny + kBlock - 1) / kBlock),
          m_blockMaxR(size_t(m_bnx) * size_t(m_bny), 0.0) {}

    void add(const Sample &s) {
        const size_t c = cellOf(s.p);
        m_cells[c].push_back(s);
        ++m_count[s.family != 0][c];
        m_order.push_back(uint32_t(c));
        // Maxima only grow: after a rejected stroke is popped they stay an upper
        // bound, which is all anyWithin() needs.
        m_cellMaxR[c] = std::max(m_cellMaxR[c], s.dTest);
        double &blockMax = m_blockMaxR[blockOf(c)];
        blockMax = std::max(blockMax, s.dTest);
        m_maxR = std::max(m_maxR, s.dTest);
    }
    void popBack() {
        --m_count[m_cells[m_order.back()].back().family != 0][m_order.back()];
        m_cells[m_order.back()].pop_back();
        m_order.pop_back();
    }

    /// Calls f(sample) for every sample that may lie within max(r, sample.dTest) of p,
    /// until f returns true; f must not depend on the order of the calls. Blocks of
    /// kBlock² cells, then cells, whose samples all have a small d_test are pruned by
    /// their distance, so a wide query radius (light tone somewhere in the image) only
    /// costs where large d_test exist: in dark tone a query reads a few cells, not the
    /// 9 × 9 that the lightest d_test spans.
    template <typename F> bool anyWithin(const Vec2 &p, double r, F &&f) const {
        const double big = std::max(r, m_maxR);
        const double blockPx = m_cell * kBlock, invBlock = 1.0 / blockPx, invCell = 1.0 / m_cell;
        const int bx0 = std::max(0, int(std::floor((p.x() - big) * invBlock)));
        const int bx1 = std::min(m_bnx - 1, int(std::floor((p.x() + big) * invBlock)));
        const int by0 = std::max(0, int(std::floor((p.y() - big) * invBlock)));
        const int by1 = std::min(m_bny - 1, int(std::floor((p.y() + big) * invBlock)));
        for (int by = by0; by <= by1; ++by) {
            const double dyb = gap(p.y(), by * blockPx, blockPx);
            const double *blockMax = &m_blockMaxR[size_t(by) * size_t(m_bnx)];
            for (int bx = bx0; bx <= bx1; ++bx) {
                const double reachB = std::max(r, blockMax[bx]);
                const double dxb = gap(p.x(), bx * blockPx, blockPx);
                if (dxb * dxb + dyb * dyb >= reachB * reachB) continue;
                // Cells of the block that overlap the square of half-side reachB around p.
                const int x0 = std::max(bx * kBlock, int(std::floor((p.x() - reachB) * invCell)));
                const int x1 = std::min({(bx + 1) * kBlock - 1, m_nx - 1, int(std::floor((p.x() + reachB) * invCell))});
                const int y0 = std::max(by * kBlock, int(std::floor((p.y() - reachB) * invCell)));
                const int y1 = std::min({(by + 1) * kBlock - 1, m_ny - 1, int(std::floor((p.y() + reachB) * invCell))});
                for (int cy = y0; cy <= y1; ++cy) {
                    const double dy = gap(p.y(), cy * m_cell, m_cell);
                    const size_t row = size_t(cy) * size_t(m_nx);
                    for (int cx = x0; cx <= x1; ++cx) {
                        // A cell that never held a sample has a zero bound: skipped without
                        // reading its list (m_cellMaxR is the smaller array).
                        const double cellMax = m_cellMaxR[row + size_t(cx)];
                        if (cellMax == 0.0) continue;
                        const double dx = gap(p.x(), cx * m_cell, m_cell);
                        const double reach = std::max(r, cellMax);
                        if (dx * dx + dy * dy >= reach * reach) continue;
                        for (const Sample &s : m_cells[row + size_t(cx)])
                            if (f(s)) return true;
                    }
                }
            }
        }
        return false;
    }
    size_t size() const { return m_order.size(); }

    /// The nearest sample closer than r to p whose family is (same) or is not (!same)
    /// `family`; among equally near ones the first in any()'s order (row-major cells,
    /// each in insertion order). Cells are visited in square rings around p's, so the
    /// best is found early and the rings beyond its distance are not read (a scan seed
    /// of the second family looks up to 2 d_sep for a first-family line: about 80
    /// cells in row order); cells without such samples, or none as near as the best
    /// so far, are skipped. nullptr if none.
    const Sample *nearest(const Vec2 &p, double r, int family, bool same) const {
        const std::vector<uint32_t> &count = m_count[(family != 0) == same ? 1 : 0];
        const auto [x0, x1, y0, y1] = cellsAround(p, r);
        if (x0 > x1 || y0 > y1) return nullptr;
        const int px = std::clamp(int(std::floor(p.x() / m_cell)), x0, x1);
        const int py = std::clamp(int(std::floor(p.y() / m_cell)), y0, y1);
        const Sample *best = nullptr;
        size_t bestCell = 0;
        double bestD = r * r;
        auto visit = [&](int cx, int cy, double dy) {
            const size_t c = size_t(cy) * size_t(m_nx) + size_t(cx);
            if (count[c] == 0) return;
            const double dx = gap(p.x(), cx * m_cell, m_cell);
            if (dx * dx + dy * dy > bestD) return;
            for (const Sample &s : m_cells[c]) {
                if ((s.family == family) != same) continue;
                const double d2 = (s.p - p).squaredNorm();
                // Equally near: the earlier cell in row-major order wins, and in one
                // cell the earlier sample (any()'s order).
                if (d2 < bestD || (d2 == bestD && best && c < bestCell)) {
                    bestD = d2;
                    best = &s;
                    bestCell = c;
                }
            }
        };
        const int rings = std::max({px - x0, x1 - px, py - y0, y1 - py});
        for (int k = 0; k <= rings; ++k) {
            // Every cell of ring k is at least k − 1 cells from p's.
            const double reach = (k - 1) * m_cell;
            if (k >= 2 && reach * reach > bestD) break;
            for (int cy = std::max(y0, py - k); cy <= std::min(y1, py + k); ++cy) {
                const double dy = gap(p.y(), cy * m_cell, m_cell);
                if (dy * dy > bestD) continue;
                if (cy == py - k || cy == py + k) {
                    for (int cx = std::max(x0, px - k); cx <= std::min(x1, px + k); ++cx) visit(cx, cy, dy);
                } else {
                    if (px - k >= x0) visit(px - k, cy, dy);
                    if (px + k <= x1) visit(px + k, cy, dy);
                }
            }
        }
        return best;
    }

    /// any() for a predicate that holds only for samples of `family`: the cells
    /// holding none of that family (m_count) are not read. Where one family's lines
    /// are few (the second in a mostly single-tone image), a query among the other's
    /// samples then costs the cell counts alone.
    template <typename F> bool anyOfFamily(const Vec2 &p, double r, int family, F &&f) const {
        const std::vector<uint32_t> &count = m_count[family != 0];
        const auto [x0, x1, y0, y1] = cellsAround(p, r);
        for (int cy = y0; cy <= y1; ++cy)
            for (int cx = x0; cx <= x1; ++cx) {
                const size_t c = size_t(cy) * size_t(m_nx) + size_t(cx);
                if (count[c] == 0) continue;
                for (const Sample &s : m_cells[c])
                    if (f(s)) return true;
            }
        return false;
    }

    /// Calls f(sample) for samples in cells overlapping the disc (p, r) until f returns true.
    template <typename F> bool any(const Vec2 &p, double r, F &&f) const {
        const auto [x0, x1, y0, y1] = cellsAround(p, r);
        for (int cy = y0; cy <= y1; ++cy)
            for (int cx = x0; cx <= x1; ++cx)
                for (const Sample &s : m_cells[size_t(cy) * size_t(m_nx) + size_t(cx)])
                    if (f(s)) return true;
        return false;
    }

private:
    /// The cells [x0, x1] × [y0, y1] that overlap the square of half-side r around p,
    /// clipped to the grid (none when x0 > x1 or y0 > y1).
    struct CellRange {
        int x0, x1, y0, y1;
    };
    CellRange cellsAround(const Vec2 &p, double r) const {
        return {std::max(0, int(std::floor((p.x() - r) / m_cell))),
                std::min(m_nx - 1, int(std::floor((p.x() + r) / m_cell))),
                std::max(0, int(std::floor((p.y() - r) / m_cell))),
                std::min(m_ny - 1, int(std::floor((p.y() + r) / m_cell)))};
    }
    /// Distance from coordinate v to the interval [lo, lo + size] (0 inside).
    static double gap(double v, double lo, double size) { return std::max(0.0, std::max(lo - v, v - (lo + size))); }
    static constexpr int kBlock = 4; // cells per block side for anyWithin()'s first pruning
    size_t blockOf(size_t cell) const {
        const int cx = int(cell % size_t(m_nx)), cy = int(cell / size_t(m_nx));
        return size_t(cy / kBlock) * size_t(m_bnx) + size_t(cx / kBlock);
    }
    size_t cellOf(const Vec2 &p) const {
        const int cx = std::clamp(int(std::floor(p.x() / m_cell)), 0, m_nx - 1);
        const int cy = std::clamp(int(std::floor(p.y() / m_cell)), 0, m_ny - 1);
        return size_t(cy) * size_t(m_nx) + size_t(cx);
    }
    double m_cell;
    int m_nx, m_ny;
    std::vector<std::vector<Sample>> m_cells; // samples stored by cell: queries read them in order
    std::vector<double> m_cellMaxR; // upper bound of the samples' d_test per cell
    int m_bnx, m_bny;
    std::vector<double> m_blockMaxR; // the same per block of kBlock x kBlock cells
    double m_maxR = 0;
    std::vector<uint32_t> m_order; // cell of each sample, in insertion order (for popBack)
    std::vector<uint32_t> m_count[2] = {std::vector<uint32_t>(m_cells.size(), 0),
                                        std::vector<uint32_t>(m_cells.size(), 0)}; // per cell: family 0, other families
};

/// Print mode's guard band (HatchStyle::pixelScale != 1): per cell of a grid, the
/// Euclidean distance from it to the nearest `edge` cell (cells outside the grid
/// count as edge), in eighths of a cell, clamped at 255 (31.9 cells): two
/// passes, the distance along each row, then the lower envelope of parabolas down
/// each column (Felzenszwalb & Huttenlocher 2012, "Distance transforms of sampled
/// functions"). Read bilinearly (Hatcher::blockedAt) it gives the band a width in
/// fractions of a pixel, so the band keeps its size in mm at any pitch.
std::vector<uint8_t> edgeDistanceEighths(const std::vector<uint8_t> &edge, int w, int h) {
    constexpr int kFar = 255; // row distances are kept up to this many px
    std::vector<uint8_t> rowDist(edge.size());
    parallelFor(0, h, [&](int64_t y) {
        const uint8_t *e = &edge[size_t(y) * size_t(w)];
        uint8_t *o = &rowDist[size_t(y) * size_t(w)];
        int last = -1; // the border left of the image counts as edge
        for (int x = 0; x < w; ++x) {
            if (e[x]) last = x;
            o[x] = uint8_t(std::min(kFar, x - last));
        }
        last = w;
        for (int x = w - 1; x >= 0; --x) {
            if (e[x]) last = x;
            o[x] = uint8_t(std::min<int>(o[x], std::min(kFar, last - x)));
        }
    }, 8);
    std::vector<uint8_t> out(edge.size());
    parallelFor(0, w, [&](int64_t x) {
        // Sites: y = -1 and y = h (the border, f = 0) and each pixel of the column
        // (f = squared row distance; none within kFar counts as infinitely far).
        const int n = h + 2;
        std::vector<double> f(static_cast<size_t>(n)), z(static_cast<size_t>(n) + 1);
        std::vector<int> v(static_cast<size_t>(n));
        for (int k = 0; k < n; ++k) {
            const int y = k - 1;
            const int d = (y < 0 || y >= h) ? 0 : rowDist[size_t(y) * size_t(w) + size_t(x)];
            f[size_t(k)] = d >= kFar ? 1e30 : double(d) * d;
        }
        int k = 0;
        v[0] = 0;
        z[0] = -1e300;
        z[1] = 1e300;
        for (int q = 1; q < n; ++q) {
            if (f[size_t(q)] >= 1e30) continue; // no site here
            // Where q's parabola passes the envelope's last; z[0] = -inf stops the loop.
            auto meet = [&](int p) {
                return ((f[size_t(q)] + double(q) * q) - (f[size_t(p)] + double(p) * p)) / (2.0 * (q - p));
            };
            double s = meet(v[size_t(k)]);
            while (s <= z[size_t(k)]) s = meet(v[size_t(--k)]);
            ++k;
            v[size_t(k)] = q;
            z[size_t(k)] = s;
            z[size_t(k) + 1] = 1e300;
        }
        k = 0;
        for (int q = 1; q <= h; ++q) {
            while (z[size_t(k) + 1] < q) ++k;
            const int p = v[size_t(k)];
            const double d = std::sqrt(double(q - p) * (q - p) + f[size_t(p)]);
            out[size_t(q - 1) * size_t(w) + size_t(x)] = uint8_t(std::min(255.0, std::round(8.0 * d)));
        }
    }, 8);
    return out;
}

struct Disc {
    Vec2 centre;
    double radius;
};

/// Keep-away discs of the visible singularities: radius d_sep at the darkest tone
/// within d_sep of the singularity's own tone. `shrink` < 1 gives the measuring tolerance.
std::vector<Disc> singularityDiscs(const ScreenField &field, const std::vector<float> &density,
                                   const styles::HatchStyle &style, double shrink) {
    struct Candidate {
        Disc disc;
        double index;   // k / N
        bool crossTone; // the darkest tone within its disc is cross-hatched
    };
    std::vector<Candidate> cands;
    for (const ScreenSingularity &s : field.singularities) {
        if (!s.visible) continue;
        const int x = std::clamp(int(std::floor(s.pRaster.x())), 0, field.width - 1);
        const int y = std::clamp(int(std::floor(s.pRaster.y())), 0, field.height - 1);
        // d_sep at the singularity's own tone, unless darker tone lies within that
        // radius: a singularity on a light part beside a dark one (the tip of a horn
        // against a shadowed head) must not clear a light-tone disc out of the shadow.
        const double r0 = localSpacingPx(clampDensity(density[size_t(field.index(x, y))]), style);
        double darkest = 0.0;
        const int ri = int(std::ceil(r0));
        for (int yy = std::max(0, y - ri); yy <= std::min(field.height - 1, y + ri); ++yy)
            for (int xx = std::max(0, x - ri); xx <= std::min(field.width - 1, x + ri); ++xx) {
                const double dx = xx + 0.5 - s.pRaster.x(), dy = yy + 0.5 - s.pRaster.y();
                if (dx * dx + dy * dy <= r0 * r0)
                    darkest = std::max(darkest, double(clampDensity(density[size_t(field.index(xx, yy))])));
            }
        cands.push_back({{s.pRaster, localSpacingPx(darkest, style)}, s.index, darkest >= style.crossDensity});
    }
    // In cross-hatched tone, singularities whose discs overlap are one feature at the
    // drawing's scale: the two families hide the field's structure below a line
    // spacing. Such a group gets one disc at its mean position, and none when its
    // indices sum to zero (a +1/4, −1/4 pair leaves the field around it regular).
    // Scanned fists, lips and hooves carry dense clusters whose separate discs would
    // clear the whole small dark part of ink (seam_fraction). Where lines are sparse
    // every singularity shows and keeps its own disc.
    field::UnionFind groupOf(int(cands.size()));
    // Pairs by a sweep along x: scans carry thousands of singularities.
    std::vector<int> byX;
    double maxRadius = 0.0;
    for (size_t k = 0; k < cands.size(); ++k)
        if (cands[k].crossTone) {
            byX.push_back(int(k));
            maxRadius = std::max(maxRadius, cands[k].disc.radius);
        }
    auto discOf = [&](int k) -> const Disc & { return cands[size_t(k)].disc; };
    std::sort(byX.begin(), byX.end(), [&](int a, int b) { return discOf(a).centre.x() < discOf(b).centre.x(); });
    for (size_t i = 0; i < byX.size(); ++i)
        for (size_t j = i + 1; j < byX.size(); ++j) {
            const Disc &a = discOf(byX[i]), &b = discOf(byX[j]);
            if (b.centre.x() - a.centre.x() >= 2.0 * maxRadius) break;
            const double reach = a.radius + b.radius;
            if ((a.centre - b.centre).squaredNorm() < reach * reach) groupOf.unite(byX[i], byX[j]);
        }
    // Per group (indexed by its root): summed index, member count, centre sum, radius.
    struct Group {
        double net = 0.0;
        int members = 0;
        Vec2 centre = Vec2::Zero();
        double radius = 0.0;
    };
    std::vector<Group> groups(cands.size());
    for (size_t k = 0; k < cands.size(); ++k) {
        Group &g = groups[size_t(groupOf.find(int(k)))];
        g.net += cands[k].index;
        ++g.members;
        g.centre += cands[k].disc.centre;
        g.radius = std::max(g.radius, cands[k].disc.radius);
    }
    std::vector<Disc> kept;
    for (const Group &g : groups)
        if (g.members > 0 && std::abs(g.net) > 1e-6) kept.push_back({g.centre / double(g.members), shrink * g.radius});
    return kept;
}

/// The sequential Jobard–Lefer tracer for one image.
class Hatcher {
public:
    Hatcher(const ScreenField &field, const std::vector<float> &density, const GBuffer &gbuffer,
            const styles::HatchStyle &style, uint32_t seed)
        : m_field(field), m_density(density), m_style(style), m_seed(seed),
          m_grid(field.width, field.height, std::max(2.0, style.minSpacingPx)) {
        const double a = -style.angleOffsetDeg * M_PI / 180.0; // counter-clockwise on screen (y down)
        m_offCos = std::cos(a);
        m_offSin = std::sin(a);
        m_rotated = style.angleOffsetDeg != 0.0;
        buildBlocked(gbuffer);
        // Kernel memory in huge pages (PixelArray): no serial fill before the loop,
        // which writes every pixel, and fewer TLB misses in the tracer's reads.
        m_crossWeight = PixelArray<float>(field.nPixels());
        for (PixelArray<double> &sp : m_spacing) sp = PixelArray<double>(field.nPixels());
        parallelFor(0, int64_t(field.nPixels()), [&](int64_t ii) {
            const size_t i = size_t(ii);
            const double w = field.valid(i) ? crossWeight(field, i) : 0.0;
            m_crossWeight[i] = float(w);
            // Untoned pixels (paper, background) have no coverage: the sparsest spacing.
            if (hatchFamilies(densityAt(int(i)), style) == 0) {
                m_spacing[0][i] = m_spacing[1][i] = std::max(style.minSpacingPx, style.maxSpacingPx);
                return;
            }
            const std::array<double, 2> coverage = familyCoverage(densityAt(int(i)), style, w);
            for (int f = 0; f < 2; ++f) m_spacing[f][i] = spacingOfCoverage(coverage[size_t(f)], style);
        }, 4096);
        m_discs = singularityDiscs(field, density, style, 1.0);
        // Pixels a disc may reach, so the exact test runs only near singularities.
        m_nearDisc.assign(field.nPixels(), 0);
        for (const Disc &d : m_discs) {
            const int x0 = std::max(0, int(std::floor(d.centre.x() - d.radius)) - 1);
            const int x1 = std::min(field.width - 1, int(std::floor(d.centre.x() + d.radius)) + 1);
            const int y0 = std::max(0, int(std::floor(d.centre.y() - d.radius)) - 1);
            const int y1 = std::min(field.height - 1, int(std::floor(d.centre.y() + d.radius)) + 1);
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) m_nearDisc[size_t(field.index(x, y))] = 1;
        }
    }

    void traceFamily(int family) {
        m_family = family;
        m_firstFamilyOnly = family == 0;
        // Scan seeds fill what propagation from accepted lines leaves empty; the scan
        // is row-major so the result is deterministic.
        const ScanPoints scan = scanPoints();
        for (int iy = 0; iy < scan.ny(); ++iy)
            for (int ix = 0; ix < scan.nx(); ++ix) {
                const Vec2 q = scan.at(ix, iy);
                m_threshold = baseThreshold();
                if (!eligible(q)) continue;
                Vec2 heading;
                if (!scanHeading(q, heading)) continue;
                if (trySeed(q, heading, Pass::Lines)) propagate(Pass::Lines);
            }
    }

    /// Last pass: holes in cross-hatched tone. Jobard–Lefer seeds need a full d_sep of
    /// room, so wedges between diverging lines narrower than 2 d_sep stay empty; in a
    /// dark region such a wedge reads as a light crack. Any point of cross tone with no
    /// line of either family within kFillClearance d_sep is seeded along both screen
    /// directions with that clearance (lines still keep d_test from their neighbours).
    /// Its lines may run up to a depth jump's edge pixels (kDepthEdge, kBlockHoles),
    /// into the strip the line passes' guard band leaves on each side of it.
    void fillHoles() {
        m_family = 0;
        m_firstFamilyOnly = false;
        m_blockMask = kBlockHoles; // lines may run up to depth jumps (kDepthEdge)
        // Whether scan point (x, y) is a hole now: dark enough, eligible, no line within
        // the clearance. Lines only come, never go (between strokes), so a point that is
        // no hole now never becomes one: the points are first tested all at once, in
        // parallel, and the sequential pass below tests again only those that were.
        auto hole = [&](const Vec2 &q, int i) {
            // Single tone is filled only where the tone is cross-hatching's but the
            // two screen directions have folded together: the first family carries
            // dark tone alone there, and a hole reads as a crack as in cross tone.
            if (i < 0 || (singleTone(i) && densityAt(i) < m_style.crossDensity)) return false;
            if (!eligible(q)) return false;
            const double r = kFillClearance * spacingAt(i);
            return !m_grid.any(q, r, [&](const Sample &s) { return (s.p - q).squaredNorm() < r * r; });
        };
        const ScanPoints scan = scanPoints();
        m_threshold = baseThreshold();
        std::vector<uint8_t> candidate(size_t(scan.nx()) * size_t(scan.ny()), 0);
        parallelFor(0, scan.ny(), [&](int64_t iy) {
            for (int ix = 0; ix < scan.nx(); ++ix) {
                const Vec2 q = scan.at(ix, int(iy));
                candidate[scan.index(ix, int(iy))] = hole(q, pixelIndex(q));
            }
        }, 4);
        for (int iy = 0; iy < scan.ny(); ++iy)
            for (int ix = 0; ix < scan.nx(); ++ix) {
                if (!candidate[scan.index(ix, iy)]) continue;
                const Vec2 q = scan.at(ix, iy);
                const int i = pixelIndex(q);
                m_threshold = baseThreshold();
                if (!hole(q, i)) continue;
                const Eigen::Vector2f &d0 = m_field.dir(0, size_t(i));
                Vec2 h(d0.x(), d0.y());
                if (m_rotated) h = rotate(h, m_offCos, m_offSin);
                if (trySeed(q, h, Pass::Holes) || trySeed(q, Vec2(-h.y(), h.x()), Pass::Holes))
                    propagate(Pass::Holes);
            }
    }

    /// Singularities left as holes in cross tone (HatchReport::singularityHoles: no line
    /// within kHoleRatio d_sep of the point). Every line keeps a disc of d_sep around a
    /// visible singularity free (its field turns too fast there to follow), and in dark
    /// tone where both families stop at it the disc reads as a white speck. The lines
    /// that stopped at such a disc (their blunt ends within it) are continued straight
    /// along their end tangent, in creation order, while inside the disc, on the surface
    /// and off the edges, and while no other line within 55° of their direction is
    /// closer than the walk's own d_test (blocks()' cross-tone rule, without its larger
    /// of both d_tests): the cross-hatching runs through the speck as an engraver fills
    /// it. Their samples join the grid, not Sample::crosses' count.
    void inkSingularityHoles() {
        m_blockMask = kBlockLines;
        // The stroke ends that stopped at a disc, in creation order: (stroke, 0 start / 1 end).
        std::vector<std::pair<size_t, int>> bluntEnds;
        for (size_t k = 0; k < m_strokes.size(); ++k)
            for (int end = 0; end < 2; ++end)
                if (m_blunt[k] & (end == 0 ? 1 : 2)) bluntEnds.emplace_back(k, end);
        for (const Disc &d : m_discs) {
            const int ic = pixelIndex(d.centre);
            if (ic < 0 || singleTone(ic)) continue; // cross tone only: a disc in single tone is the rule
            const double reach = kHoleRatio * m_spacing[0][size_t(ic)];
            if (m_grid.any(d.centre, reach,
                           [&](const Sample &s) { return (s.p - d.centre).squaredNorm() < reach * reach; }))
                continue;
            const double near = 1.25 * d.radius;
            for (const auto &[k, end] : bluntEnds) {
                std::vector<Vec2> &pts = m_strokes[k].points;
                const Vec2 p = end == 0 ? pts.front() : pts.back();
                if ((p - d.centre).squaredNorm() > near * near) continue;
                const Vec2 t = end == 0 ? Vec2(-m_tangents[k].front()) : Vec2(m_tangents[k].back());
                if (t.dot(d.centre - p) <= 0.0) continue; // heading away from the speck
                const std::vector<Vec2> added = continueStraight(p, t, int(k), d);
                if (added.empty()) continue;
                std::vector<Vec2> &tan = m_tangents[k];
                if (end == 1) {
                    pts.insert(pts.end(), added.begin(), added.end());
                    tan.insert(tan.end(), added.size(), t);
                } else {
                    pts.insert(pts.begin(), added.rbegin(), added.rend());
                    tan.insert(tan.begin(), added.size(), Vec2(-t));
                }
            }
        }
    }

    /// Layers by direction. In cross tone a first-family line may cross first-family
    /// lines traced before it (where two fronts of the cross field's labels meet); such
    /// a line is cross-hatching, so when most of its samples cross earlier first-family
    /// lines it moves to family 1. Creation order decides, so the result is deterministic.
    ///
    /// The tracer noted, for each first-family sample in cross tone, one earlier
    /// first-family line crossing it (Sample::crosses, as if no stroke had moved; see
    /// crossesEarlier()). Here, in creation order, a sample counts when that line has
    /// not moved, and only when it has is the sample searched again for one that has
    /// not: the same count as searching every sample here.
    void relabelCrossings() {
        const size_t n = m_strokes.size();
        std::vector<uint8_t> moved(n, 0);
        for (size_t k = 0; k < n; ++k) {
            if (m_strokes[k].family != 0) continue;
            const std::vector<Sample> &samples = m_samples[k];
            size_t crossing = 0;
            for (const Sample &v : samples) {
                if (v.crosses < 0) continue;
                if (!moved[size_t(v.crosses)] ||
                    m_grid.any(v.p, v.dTest, [&](const Sample &s) {
                        return crossesEarlier(s, int(k), v.p, v.t, v.dTest) && !moved[size_t(s.stroke)];
                    }))
                    ++crossing;
            }
            if (2 * crossing > samples.size()) {
                moved[k] = 1;
                m_strokes[k].family = 1;
            }
        }
    }

    std::vector<Stroke> takeStrokes() { return std::move(m_strokes); }
    const std::vector<uint8_t> &bluntEnds() const { return m_blunt; }

private:
    /// The scan seeds' points, row-major: one every minSpacingPx from half of it, the
    /// coordinates summed step by step (every pass scans exactly the same points).
    struct ScanPoints {
        std::vector<double> xs, ys;
        int nx() const { return int(xs.size()); }
        int ny() const { return int(ys.size()); }
        size_t index(int ix, int iy) const { return size_t(iy) * xs.size() + size_t(ix); }
        Vec2 at(int ix, int iy) const { return Vec2(xs[size_t(ix)], ys[size_t(iy)]); }
    };
    ScanPoints scanPoints() const {
        const double stride = std::max(1.0, m_style.minSpacingPx);
        ScanPoints s;
        for (double x = 0.5 * stride; x < m_field.width; x += stride) s.xs.push_back(x);
        for (double y = 0.5 * stride; y < m_field.height; y += stride) s.ys.push_back(y);
        return s;
    }

    int pixelIndex(const Vec2 &p) const {
        const int x = int(std::floor(p.x())), y = int(std::floor(p.y()));
        if (x < 0 || y < 0 || x >= m_field.width || y >= m_field.height) return -1;
        return m_field.index(x, y);
    }
    double densityAt(int i) const { return clampDensity(m_density[size_t(i)]); }
    double spacingAt(int i) const { return m_spacing[m_family][size_t(i)]; }

    bool inDisc(const Vec2 &q) const {
        const int i = pixelIndex(q);
        if (i < 0 || !m_nearDisc[size_t(i)]) return false;
        for (const Disc &d : m_discs)
            if ((q - d.centre).squaredNorm() < d.radius * d.radius) return true;
        return false;
    }

    /// Whether a stroke centre may not be at q (in pixel i): an edge or the guard band
    /// beside it. In print mode the band is a distance (m_guardBand px from the
    /// nearest edge pixel's square, read bilinearly from m_edgeDist at the pixel
    /// corners), not whole pixels.
    bool blockedAt(const Vec2 &q, int i) const {
        if (m_blocked[size_t(i)] & m_blockMask) return true;
        if (m_edgeDist.empty()) return false;
        const int w = m_field.width + 1, h = m_field.height + 1; // the corner grid
        const double fx = std::clamp(q.x(), 0.0, double(w - 1)), fy = std::clamp(q.y(), 0.0, double(h - 1));
        const int x0 = std::min(int(fx), w - 2), y0 = std::min(int(fy), h - 2);
        const double tx = fx - x0, ty = fy - y0;
        auto at = [&](int x, int y) { return double(m_edgeDist[size_t(y) * size_t(w) + size_t(x)]); };
        const double d = ((1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
                          ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1))) / 8.0;
        return d < m_guardBand;
    }

    /// The density from which the current family hatches: highlightDensity for the
    /// first, crossDensity for the second.
    double baseThreshold() const { return m_family == 0 ? m_style.highlightDensity : m_style.crossDensity; }

    /// A stroke's own threshold: the family's ± half kEndStagger at random, so
    /// the strokes that end at a tone edge end at different tones (Hertzmann & Zorin
    /// 2000 stagger them) instead of along one iso-line, which reads as a hard edge.
    void drawThreshold() {
        m_threshold = baseThreshold() + kEndStagger[m_family] * (random01(m_seed, m_attempts++, 0x5eedu) - 0.5);
    }

    /// A point a stroke of the current family may occupy (tone at least m_threshold).
    bool eligible(const Vec2 &q) const {
        const int i = pixelIndex(q);
        if (i < 0 || blockedAt(q, i)) return false;
        if (hatchFamilies(densityAt(i), m_style) <= m_family || densityAt(i) < m_threshold) return false;
        if (m_family == 1 && m_crossWeight[size_t(i)] <= 0.0f) return false;
        return !inDisc(q);
    }

    bool direction(const Vec2 &p, const Vec2 &heading, Vec2 &dir) const {
        if (!m_rotated) return m_field.lineNear(p, heading, dir);
        Vec2 d;
        if (!m_field.lineNear(p, rotate(heading, m_offCos, -m_offSin), d)) return false;
        dir = rotate(d, m_offCos, m_offSin);
        return true;
    }

    /// Would sample s keep a point q heading along t (own d_test r) away? Only a line of
    /// "the same family" does: tangent within 55° (mod π); where only one family is
    /// wanted, every family-0 sample counts for family 0, so mid-tones never cross.
    bool blocks(const Sample &s, const Vec2 &q, const Vec2 &t, double r, int stroke, double arc, bool singleTone) const {
        const bool sameDirection = std::abs(s.t.dot(t)) >= kSameFamilyCos;
        if (!sameDirection && !singleTone) return false; // cross tone: other directions never block
        // The larger of the two points' d_test: measureHatches() takes the smaller at
        // either end, so the tracer is never the more lenient where tone changes.
        const double rr = std::max(r, s.dTest);
        if ((s.p - q).squaredNorm() >= rr * rr) return false;
        const double selfSkip = 2.0 * rr;
        if (s.stroke == stroke && std::abs(s.arc - arc) < selfSkip) return false;
        return sameDirection || s.family == 0 || s.family == m_family;
    }

    /// Sample s belongs to a first-family line traced before `stroke` that crosses the
    /// point q heading along t: not within 55° of t, and closer than r (q's d_test).
    /// relabelCrossings() counts the first-family samples in cross tone that have one.
    static bool crossesEarlier(const Sample &s, int stroke, const Vec2 &q, const Vec2 &t, double r) {
        return s.stroke < stroke && s.family == 0 && std::abs(s.t.dot(t)) < kSameFamilyCos &&
               (s.p - q).squaredNorm() < r * r;
    }

    /// Whether a new sample at pixel i notes Sample::crosses (else -1): relabelCrossings()
    /// counts only the first family's samples in cross tone.
    bool notesCrossings(int i) const { return m_family == 0 && !singleTone(i); }

    /// Whether a seed (no stroke of its own) at q heading along t is too close to a
    /// line (blocks()). Seeds beside a parent line come in a row one step apart and are
    /// mostly rejected by the same neighbouring line, sample after sample along it; so the samples of the last two lines that rejected
    /// a seed, around the one that did, are tried first. The answer is the same (some
    /// sample blocks or none does): between strokes every sample in the grid belongs to
    /// an accepted stroke, whose samples m_samples holds and the grid never drops.
    bool seedTooClose(const Vec2 &q, const Vec2 &t, double r, bool singleTone) {
        auto blocking = [&](const Sample &s) { return blocks(s, q, t, r, -1, 0.0, singleTone); };
        for (int k = 0; k < 2; ++k)
            if (alongHint(m_blockers[k], 2, blocking)) {
                if (k == 1) std::swap(m_blockers[0], m_blockers[1]);
                return true;
            }
        const Sample *hit = nullptr;
        m_grid.anyWithin(q, r, [&](const Sample &s) {
            if (!blocking(s)) return false;
            hit = &s;
            return true;
        });
        if (!hit) return false;
        if (m_blockers[0].stroke != hit->stroke) m_blockers[1] = m_blockers[0];
        m_blockers[0] = hintAt(*hit);
        return true;
    }

    /// Where along which accepted line a query last found its answer (m_samples).
    struct LineHint {
        int stroke = -1, index = 0;
    };
    /// A hint to sample s, which must be in the grid between strokes: then it belongs
    /// to an accepted stroke, whose samples m_samples holds and the grid never drops.
    LineHint hintAt(const Sample &s) const {
        ROSY_CHECK_LT(size_t(s.stroke), m_samples.size());
        return {s.stroke, s.index};
    }
    /// Whether pred holds for one of the samples within `reach` places of the hint's
    /// along its line (nearest first); the hint moves to it.
    template <typename Pred> bool alongHint(LineHint &hint, int reach, Pred &&pred) const {
        if (hint.stroke < 0) return false;
        const std::vector<Sample> &line = m_samples[size_t(hint.stroke)];
        const int n = int(line.size());
        for (int d = 0; d <= reach; ++d)
            for (int v : {hint.index + d, hint.index - d}) {
                if (v < 0 || v >= n || !pred(line[size_t(v)])) continue;
                hint.index = v;
                return true;
            }
        return false;
    }

    /// Where the tone asks for one family, or the two screen directions have folded
    /// together (crossWeight 0), lines of the first family must not cross.
    bool singleTone(int i) const {
        return hatchFamilies(densityAt(i), m_style) < 2 || m_crossWeight[size_t(i)] <= 0.0f;
    }

    /// Whether a sample of `family` lies closer than r to q. Scan seeds one stride
    /// apart are mostly kept away by the same line: its samples around the one that
    /// answered last are tried first (m_scanHint); the answer is the same.
    bool anyNear(const Vec2 &q, double r, int family) {
        auto near = [&](const Sample &s) { return s.family == family && (s.p - q).squaredNorm() < r * r; };
        if (alongHint(m_scanHint, 6, near)) return true;
        const Sample *hit = nullptr;
        m_grid.anyOfFamily(q, r, family, [&](const Sample &s) {
            if (!near(s)) return false;
            hit = &s;
            return true;
        });
        if (hit) m_scanHint = hintAt(*hit);
        return hit != nullptr;
    }

    /// Heading for a seed with no parent line: continue the look of nearby lines
    /// (family 1 crosses family 0), else the field's labelled direction.
    bool scanHeading(const Vec2 &q, Vec2 &heading) {
        const int i = pixelIndex(q);
        const double dSep = spacingAt(i);
        // A same-family line within d_sep would reject any seed here: skip the wider search.
        const double rNear = 0.98 * dSep;
        if (anyNear(q, rNear, m_family)) return false;
        // The nearest line of the same family within 2 d_sep gives the heading; else
        // the nearest of the other family (only looked for then).
        const double r = 2.0 * dSep;
        const Sample *best[2] = {m_grid.nearest(q, r, m_family, true), nullptr};
        if (!best[0]) best[1] = m_grid.nearest(q, r, m_family, false);
        const Eigen::Vector2f &d0 = m_field.dir(0, size_t(i)), &d1 = m_field.dir(1, size_t(i));
        Vec2 label = Vec2(m_family == 0 ? d0.x() : d1.x(), m_family == 0 ? d0.y() : d1.y());
        if (m_rotated) label = rotate(label, m_offCos, m_offSin);
        if (best[0]) {
            heading = best[0]->t;
        } else if (best[1]) {
            // Perpendicular (on screen) to the other family's line; direction() then
            // snaps to whichever field direction is closer to that.
            heading = Vec2(-best[1]->t.y(), best[1]->t.x());
        } else {
            heading = label;
        }
        Vec2 dir;
        if (!direction(q, heading, dir)) return false;
        heading = dir;
        return true;
    }

    bool trySeed(const Vec2 &q, const Vec2 &heading, Pass pass) {
        drawThreshold();
        if (!eligible(q)) return false;
        const int i = pixelIndex(q);
        // Slightly under d_sep: a seed placed at exactly d_sep from its parent must not
        // be rejected by its own parent through rounding.
        const double clearance = (pass == Pass::Holes ? kFillClearance : kSeedClearance) * spacingAt(i);
        const bool single = singleTone(i);
        // While only first-family lines exist, single tone blocks on every line near
        // whatever the seed's direction: test that before the field lookup, which most
        // seeds beside a parent line (rejected) would otherwise pay for.
        const bool directionFree = single && m_firstFamilyOnly;
        if (directionFree && seedTooClose(q, heading, clearance, true)) return false;
        Vec2 dir;
        if (!direction(q, heading, dir)) return false;
        if (!directionFree && seedTooClose(q, dir, clearance, single)) return false;
        return traceStroke(q, dir, pass);
    }

    /// Jobard–Lefer propagation: seeds at ±d_sep beside each accepted line, lines in
    /// creation order (FIFO), until no candidate is left.
    void propagate(Pass pass) {
        while (m_next < m_strokes.size()) {
            const size_t parent = m_next++;
            // By index, not by reference: trySeed() appends to m_strokes and m_tangents.
            const size_t nPoints = m_strokes[parent].points.size();
            for (size_t k = 0; k < nPoints; ++k) {
                const Vec2 point = m_strokes[parent].points[k], tangent = m_tangents[parent][k];
                const Vec2 nrm(-tangent.y(), tangent.x());
                const int ip = pixelIndex(point);
                if (ip < 0) continue;
                for (int side = -1; side <= 1; side += 2) {
                    double dist = spacingAt(ip);
                    if (m_style.spacingJitter != 0.0)
                        dist *= 1.0 + m_style.spacingJitter *
                                          (random01(m_seed, uint32_t(parent), uint32_t(2 * k + (side > 0))) - 0.5);
                    Vec2 q = point + side * dist * nrm;
                    // Toward lighter tone the seed's own d_sep is larger; place it there.
                    const int iq = pixelIndex(q);
                    if (iq >= 0 && m_style.spacingJitter == 0.0) {
                        const double dq = spacingAt(iq);
                        if (dq > dist) q = point + side * dq * nrm;
                    }
                    trySeed(q, tangent, pass);
                }
            }
        }
    }

    /// inkSingularityHoles()' walk: from stroke `stroke`'s end p along t in steps of
    /// kStepRatio d_sep while inside disc d, returning the points added (their samples
    /// are in the grid). Stops at the image's edge, an edge pixel or its guard band,
    /// paper, or a line of the same direction within d_test.
    std::vector<Vec2> continueStraight(Vec2 p, const Vec2 &t, int stroke, const Disc &d) {
        std::vector<Vec2> out;
        const int family = m_strokes[size_t(stroke)].family;
        double arc = 0.0;
        const double longest = 2.0 * d.radius;
        while (arc < longest) {
            const int ip = pixelIndex(p);
            if (ip < 0) break;
            const double step = std::clamp(kStepRatio * m_spacing[size_t(family)][size_t(ip)], m_minStep, m_maxStep);
            const Vec2 q = p + step * t;
            if ((q - d.centre).squaredNorm() >= d.radius * d.radius && (q - d.centre).dot(t) > 0.0) break; // leaving
            const int iq = pixelIndex(q);
            if (iq < 0 || blockedAt(q, iq) || hatchFamilies(densityAt(iq), m_style) == 0) break;
            const double r = kTestRatio * m_spacing[size_t(family)][size_t(iq)];
            if (m_grid.anyWithin(q, r, [&](const Sample &s) {
                    if (s.stroke == stroke) return false;
                    return std::abs(s.t.dot(t)) >= kSameFamilyCos && (s.p - q).squaredNorm() < r * r;
                }))
                break;
            arc += step;
            m_grid.add(Sample{q, t, arc, stroke, family, r, -1, -1});
            out.push_back(q);
            p = q;
        }
        return out;
    }

    /// Integrates from p along heading h (RK2 midpoint on the line field), appending
    /// samples with arc lengths sign * (distance from the seed) and indices from firstIndex.
    /// Returns whether the line stopped at a singularity's keep-away disc.
    bool extend(Vec2 p, Vec2 h, double sign, int stroke, int firstIndex, std::vector<Sample> &out) {
        const int maxSteps = int(4.0 * (m_field.width + m_field.height) / m_minStep);
        double arc = 0;
        for (int it = 0; it < maxSteps; ++it) {
            const int ip = pixelIndex(p);
            if (ip < 0) break;
            const double step = std::clamp(kStepRatio * spacingAt(ip), m_minStep, m_maxStep);
            Vec2 v1, v2;
            if (!direction(p, h, v1) || v1.dot(h) < kMaxTurnCos) break;
            const Vec2 pm = p + 0.5 * step * v1;
            const int im = pixelIndex(pm);
            if (im < 0 || blockedAt(pm, im)) break;
            if (!direction(pm, v1, v2) || v2.dot(h) < kMaxTurnCos) break; // sharp turn: near a singularity
            const Vec2 q = p + step * v2;
            if (!eligible(q)) return inDisc(q);
            const int iq = pixelIndex(q);
            const double r = kTestRatio * spacingAt(iq);
            // Too close to a line (blocks())? Noting on the way a crossing line for
            // relabelCrossings(): when nothing blocks, the walk has seen every sample within r.
            const bool single = singleTone(iq), note = notesCrossings(iq);
            const double qArc = sign * (arc + step);
            int crossed = -1;
            if (m_grid.anyWithin(q, r, [&](const Sample &s) {
                    if (blocks(s, q, v2, r, stroke, qArc, single)) return true;
                    if (note && crossed < 0 && crossesEarlier(s, stroke, q, v2, r)) crossed = s.stroke;
                    return false;
                }))
                break;
            arc += step;
            Sample s{q, v2, sign * arc, stroke, m_family, r, firstIndex + int(out.size()), crossed};
            m_grid.add(s);
            out.push_back(s);
            p = q;
            h = v2;
        }
        return false;
    }

    bool traceStroke(const Vec2 &seed, const Vec2 &dir, Pass pass) {
        const int id = int(m_strokes.size());
        const size_t before = m_grid.size();
        Sample s0{seed, dir, 0.0, id, m_family, kTestRatio * spacingAt(pixelIndex(seed)), 0, -1};
        if (notesCrossings(pixelIndex(seed)))
            m_grid.any(seed, s0.dTest, [&](const Sample &s) {
                if (!crossesEarlier(s, id, seed, dir, s0.dTest)) return false;
                s0.crosses = s.stroke;
                return true;
            });
        m_grid.add(s0);
        std::vector<Sample> fwd, bwd;
        const bool bluntEnd = extend(seed, dir, 1.0, id, 1, fwd);
        const bool bluntStart = extend(seed, -dir, -1.0, id, 1 + int(fwd.size()), bwd);
        const double length = (fwd.empty() ? 0.0 : fwd.back().arc) - (bwd.empty() ? 0.0 : bwd.back().arc);
        // Shortest stroke kept: the style's minLengthPx, and kStubLengthRatio times its
        // mean d_sep (as measureHatches() takes it), so no dash much shorter than the
        // spacing is wide stays; the room is left to seeds that make longer lines.
        double meanDTest = s0.dTest;
        for (const Sample &s : fwd) meanDTest += s.dTest;
        for (const Sample &s : bwd) meanDTest += s.dTest;
        meanDTest /= double(1 + fwd.size() + bwd.size());
        // The hole-filling pass holds the style's minLengthPx only up to the stub
        // length: a style asking for long lines (engraving: 40 px) would otherwise
        // leave every small dark part (an eye socket, a fold of the mouth) white.
        const double meanDSep = meanDTest / kTestRatio;
        const bool holes = pass == Pass::Holes;
        const double styleFloor = holes ? std::min(m_style.minLengthPx, kStubLengthRatio * meanDSep) : m_style.minLengthPx;
        const double minLength = std::max(styleFloor, (holes ? kFillMinLengthRatio : kStubLengthRatio) * meanDSep);
        if (length < std::max(minLength, 1e-9) || fwd.size() + bwd.size() < 1) {
            while (m_grid.size() > before) m_grid.popBack();
            return false;
        }
        Stroke stroke;
        stroke.kind = StrokeKind::Hatch;
        stroke.family = m_family;
        stroke.id = uint32_t(id);
        std::vector<Vec2> tangents;
        stroke.points.reserve(fwd.size() + bwd.size() + 1);
        for (auto it = bwd.rbegin(); it != bwd.rend(); ++it) {
            stroke.points.push_back(it->p);
            tangents.push_back(-it->t); // backward samples carry the reversed heading
        }
        stroke.points.push_back(seed);
        tangents.push_back(dir);
        for (const Sample &s : fwd) {
            stroke.points.push_back(s.p);
            tangents.push_back(s.t);
        }
        m_strokes.push_back(std::move(stroke));
        m_tangents.push_back(std::move(tangents));
        std::vector<Sample> samples;
        samples.reserve(1 + fwd.size() + bwd.size());
        samples.push_back(s0);
        samples.insert(samples.end(), fwd.begin(), fwd.end());
        samples.insert(samples.end(), bwd.begin(), bwd.end());
        m_samples.push_back(std::move(samples));
        m_blunt.push_back(uint8_t((bluntStart ? 1 : 0) | (bluntEnd ? 2 : 0)));
        return true;
    }

    void buildBlocked(const GBuffer &g) {
        const int w = m_field.width, h = m_field.height;
        // Edge pixels: 1 for the background (or no field) and for both pixels of a
        // crease, kDepthEdge for both pixels of a depth jump; a pixel on both kinds
        // keeps 1 (its band).
        auto jump = [&](size_t a, size_t b) -> uint8_t {
            if (g.faceId[a] < 0 || g.faceId[b] < 0) return 0;
            const double da = g.depth[a], db = g.depth[b];
            const double rel = std::abs(da - db) / std::max(1e-12, std::min(std::abs(da), std::abs(db)));
            // Per traced pixel: print mode's pixels are 1 / pixelScale style pixels, over
            // which a smooth surface changes depth 1 / pixelScale times as much.
            if (rel > kDepthJump * m_jumpScale) return kDepthEdge;
            return rel > kDepthJumpWithNormal * m_jumpScale && g.normal(a).dot(g.normal(b)) < kNormalJumpCos ? 1 : 0;
        };
        // Each pair of neighbours once: right[i] is the jump between pixel i and the one
        // to its right, down[i] the one below; then each pixel gathers its four.
        std::vector<uint8_t> right(size_t(w) * size_t(h)), down(size_t(w) * size_t(h));
        parallelFor(0, h, [&](int64_t y) {
            const size_t row = size_t(y) * size_t(w);
            for (int x = 0; x + 1 < w; ++x) right[row + size_t(x)] = jump(row + size_t(x), row + size_t(x) + 1);
            if (y + 1 < h)
                for (int x = 0; x < w; ++x) down[row + size_t(x)] = jump(row + size_t(x), row + size_t(x) + size_t(w));
        }, 8);
        std::vector<uint8_t> edge(size_t(w) * size_t(h));
        parallelFor(0, h, [&](int64_t y) {
            for (int x = 0; x < w; ++x) {
                const size_t i = size_t(y) * size_t(w) + size_t(x);
                if (g.faceId[i] < 0 || !m_field.valid(i)) {
                    edge[i] = 1;
                    continue;
                }
                const uint8_t j[4] = {x > 0 ? right[i - 1] : uint8_t(0), x + 1 < w ? right[i] : uint8_t(0),
                                      y > 0 ? down[i - size_t(w)] : uint8_t(0), y + 1 < h ? down[i] : uint8_t(0)};
                uint8_t e = 0;
                for (uint8_t v : j)
                    if (v == 1 || (v != 0 && e == 0)) e = v;
                edge[i] = e;
            }
        }, 8);
        if (m_style.pixelScale != 1.0) {
            // Print mode: a band of one style pixel (pixelScale px, any fraction),
            // measured from the edge pixels (blockedAt()); no step can jump it, as
            // steps are at most two style pixels and their midpoints are tested.
            // Distances are taken at pixel corners, a corner being on the edge when
            // any pixel around it is, so that read bilinearly at a point they give its
            // distance to the nearest edge pixel's square.
            std::vector<uint8_t> corners(size_t(w + 1) * size_t(h + 1), 0);
            parallelFor(0, h + 1, [&](int64_t y) {
                uint8_t *row = &corners[size_t(y) * size_t(w + 1)];
                if (y == 0 || y == h) { // beside the image border
                    std::fill(row, row + w + 1, uint8_t(1));
                    return;
                }
                const uint8_t *above = &edge[size_t(y - 1) * size_t(w)], *below = &edge[size_t(y) * size_t(w)];
                row[0] = row[w] = 1;
                for (int x = 1; x < w; ++x) row[x] = (above[x - 1] | above[x] | below[x - 1] | below[x]) != 0;
            }, 8);
            m_blocked.resize(edge.size());
            for (size_t i = 0; i < edge.size(); ++i) m_blocked[i] = edge[i] != 0 ? kBlockAll : 0;
            m_edgeDist = edgeDistanceEighths(corners, w + 1, h + 1);
            return;
        }
        // A guard band of m_guardPx pixels (one style pixel, at least one; square
        // neighbourhood) keeps stroke centres away from the background, so a stroke's
        // width stays on the object. Separable: a horizontal then a vertical
        // (2 m_guardPx + 1)-tap maximum; the image border counts as edge.
        const int r = m_guardPx;
        // Bit kBlockLines: any edge within the band. Bit kBlockHoles: the edge pixels
        // themselves, and the band only from the background and creases (see kDepthEdge).
        std::vector<uint8_t> rows(edge.size(), 0);
        parallelFor(0, h, [&](int64_t y) {
            const uint8_t *e = &edge[size_t(y) * size_t(w)];
            uint8_t *o = &rows[size_t(y) * size_t(w)];
            for (int x = 0; x < w; ++x) {
                uint8_t v = 0;
                for (int d = -r; d <= r && v != kBlockAll; ++d) {
                    const uint8_t ed = (x + d < 0 || x + d >= w) ? 1 : e[x + d];
                    v |= ed == 0 ? 0 : ed == kDepthEdge ? kBlockLines : kBlockAll;
                }
                o[x] = v;
            }
        }, 8);
        m_blocked.assign(edge.size(), 0);
        parallelFor(0, h, [&](int64_t y) {
            uint8_t *o = &m_blocked[size_t(y) * size_t(w)];
            for (int x = 0; x < w; ++x) {
                uint8_t v = edge[size_t(y) * size_t(w) + size_t(x)] != 0 ? kBlockAll : 0;
                for (int d = -r; d <= r && v != kBlockAll; ++d)
                    v |= (y + d < 0 || y + d >= h) ? kBlockAll : rows[size_t(y + d) * size_t(w) + size_t(x)];
                o[x] = v;
            }
        }, 8);
    }

    const ScreenField &m_field;
    const std::vector<float> &m_density;
    const styles::HatchStyle &m_style;
    uint32_t m_seed;
    SampleGrid m_grid;
    std::vector<uint8_t> m_blocked;  // kBlockLines / kBlockHoles per pixel
    uint8_t m_blockMask = kBlockLines; // the bit the current pass tests
    PixelArray<float> m_crossWeight;  // crossWeight() per pixel
    PixelArray<double> m_spacing[2]; // familySpacingPx() per family and pixel (double, as measured)
    std::vector<Disc> m_discs;
    std::vector<uint8_t> m_nearDisc;
    double m_offCos = 1, m_offSin = 0;
    bool m_rotated = false;
    // Print mode's pixel scale (HatchStyle::pixelScale): the integration step's bounds
    // and the guard band, in px of this image. The band is at least one pixel and
    // never narrower than half the longest step, so a step cannot jump it.
    double m_minStep = kMinStepPx * std::max(m_style.pixelScale, 1e-3);
    double m_maxStep = std::max(kMaxStepPx * m_style.pixelScale, m_minStep);
    int m_guardPx = std::max(1, int(std::ceil(0.5 * m_maxStep - 1e-9)));
    // Print mode (pixelScale != 1): the guard band in px of this image, the distance
    // to the edges it is read from (edgeDistanceEighths), and the depth-jump scale.
    double m_guardBand = std::max(m_style.pixelScale, 1e-3);
    std::vector<uint8_t> m_edgeDist;
    double m_jumpScale = 1.0 / std::max(m_style.pixelScale, 1e-3);
    int m_family = 0;
    bool m_firstFamilyOnly = true; // no line of the second family traced yet
    LineHint m_blockers[2]; // the lines that last rejected a seed, latest first (seedTooClose)
    LineHint m_scanHint;    // the line that last kept a scan seed away (scanHeading)
    double m_threshold = 0.0;  // tone from which the stroke being traced may hatch
    uint32_t m_attempts = 0;   // seeds tried: the stagger's random stream
    std::vector<Stroke> m_strokes;
    std::vector<std::vector<Vec2>> m_tangents;
    std::vector<std::vector<Sample>> m_samples; // per stroke, its grid samples by Sample::index
    std::vector<uint8_t> m_blunt; // per stroke: bit 0 its start, bit 1 its end stopped at a disc (untapered)
    size_t m_next = 0;
};

} // namespace

// A taper thins the last three widths before a singularity's disc, so the light hole
// read larger than the disc the rule clears (in cross tone, where many lines stop
// around it, enough to count as a seam): `blunt` ends keep their full width.
void finishStroke(Stroke &stroke, const styles::HatchStyle &style, uint32_t seed, uint8_t blunt) {
    const size_t n = stroke.points.size();
    std::vector<double> arc(n, 0.0);
    for (size_t k = 1; k < n; ++k) arc[k] = arc[k - 1] + (stroke.points[k] - stroke.points[k - 1]).norm();
    const double length = arc.back();
    // The taper is a share of the stroke's length, but never longer than
    // kMaxTaperWidths line widths: where many long strokes end together (along a
    // silhouette, a tone edge, a fold) long thin ends would add up to a light band.
    const double taperFrac = length > 0 ? std::min(std::clamp(style.taper, 0.0, 0.5),
                                                   kMaxTaperWidths * style.strokeWidthPx / length)
                                        : 0.0;
    const double taperLen = taperFrac * length;
    const double ph[4] = {2 * M_PI * random01(seed, stroke.id, 0), 2 * M_PI * random01(seed, stroke.id, 1),
                          2 * M_PI * random01(seed, stroke.id, 2), 2 * M_PI * random01(seed, stroke.id, 3)};
    // Two incommensurate sines: smooth, never periodic over a stroke, bounded by 1.
    auto noise = [&](double s, double l1, double l2, double a, double b) {
        return 0.6 * std::sin(2 * M_PI * s / l1 + a) + 0.4 * std::sin(2 * M_PI * s / l2 + b);
    };
    // The tapered ends thin the stroke: over each tapered end of length taperLen the
    // smoothstep profile averages kTaperFloor + (1 − kTaperFloor) / 2, so with both
    // ends tapered the stroke averages 1 − taper (1 − kTaperFloor) of its peak (half
    // that loss with one). Dividing by that keeps the mean width at strokeWidthPx,
    // the width the spacing formula assumes.
    const bool taperStart = !(blunt & 1), taperEnd = !(blunt & 2);
    const double meanProfile = 1.0 - 0.5 * (int(taperStart) + int(taperEnd)) * taperFrac * (1.0 - kTaperFloor);
    stroke.widths.resize(n);
    for (size_t k = 0; k < n; ++k) {
        double profile = 1.0;
        if (taperLen > 0) {
            const double fromEnd = std::min(taperStart ? arc[k] : 1e300, taperEnd ? length - arc[k] : 1e300);
            const double e = std::clamp(fromEnd / taperLen, 0.0, 1.0);
            profile = (kTaperFloor + (1 - kTaperFloor) * e * e * (3 - 2 * e)) / meanProfile;
        }
        const double pressure =
            1.0 + style.pressureVariation * noise(arc[k], 61.0 * style.pixelScale, 23.0 * style.pixelScale, ph[0], ph[1]);
        stroke.widths[k] = float(std::max(0.0, style.strokeWidthPx * profile * pressure));
    }
    if (style.jitterPx != 0.0 && n >= 2) {
        std::vector<Vec2> moved(n);
        for (size_t k = 0; k < n; ++k) {
            const Vec2 t = stroke.points[std::min(k + 1, n - 1)] - stroke.points[k > 0 ? k - 1 : 0];
            const double tl = t.norm();
            const Vec2 nrm = tl > 0 ? Vec2(-t.y() / tl, t.x() / tl) : Vec2::Zero();
            const double wobble = noise(arc[k], 41.0 * style.pixelScale, 15.0 * style.pixelScale, ph[2], ph[3]);
            moved[k] = stroke.points[k] + style.jitterPx * wobble * nrm;
        }
        stroke.points = std::move(moved);
    }
}

int hatchFamilies(double density, const styles::HatchStyle &style) {
    if (!(density >= style.highlightDensity) || !(density > 0)) return 0;
    return density >= style.crossDensity ? 2 : 1;
}

double hatchSpacingPx(double density, int nFamilies, const styles::HatchStyle &style) {
    const double lo = style.minSpacingPx, hi = std::max(style.minSpacingPx, style.maxSpacingPx);
    if (!(density > 0)) return hi;
    const double rho = std::min(density, 1.0);
    // One family covers w/s; two crossing families cover 1 − (1 − w/s)².
    const double perFamily = nFamilies >= 2 ? 1.0 - std::sqrt(1.0 - rho) : rho;
    if (!(perFamily > 0)) return hi;
    return std::clamp(style.spacingGain * style.strokeWidthPx / perFamily, lo, hi);
}

double maxHatchDensity(const styles::HatchStyle &style) {
    if (!(style.strokeWidthPx > 0) || !(style.minSpacingPx > 0)) return 0.0;
    const double perFamily = std::min(1.0, style.strokeWidthPx / style.minSpacingPx);
    const bool cross = style.crossDensity <= 1.0;
    return cross ? 1.0 - (1.0 - perFamily) * (1.0 - perFamily) : perFamily;
}

double crossWeight(const ScreenField &field, size_t pixel) {
    static const double c0 = std::cos(kCrossCollapseDeg * M_PI / 180.0),
                        c1 = std::cos((kCrossCollapseDeg + kCrossCollapseBandDeg) * M_PI / 180.0);
    const Eigen::Vector2f &d0 = field.dir(0, pixel), &d1 = field.dir(1, pixel);
    const double c = std::abs(double(d0.dot(d1)));
    const double t = std::clamp((c0 - c) / (c0 - c1), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

std::array<double, 2> familyCoverage(double density, const styles::HatchStyle &style, double crossWeight) {
    const int families = hatchFamilies(density, style);
    if (families == 0) return {0.0, 0.0};
    const double rho = std::min(density, 1.0);
    if (families == 1 || !(crossWeight > 0)) return {rho, 0.0};
    const double t = std::clamp((rho - style.crossDensity) / kCrossFeatherBand, 0.0, 1.0);
    const double b = std::min(crossWeight, 1.0) * t * t * (3.0 - 2.0 * t) * (1.0 - std::sqrt(1.0 - rho));
    return {1.0 - (1.0 - rho) / (1.0 - b), b};
}

double familySpacingPx(double density, int family, const styles::HatchStyle &style, double crossWeight) {
    return spacingOfCoverage(familyCoverage(density, style, crossWeight)[family == 0 ? 0 : 1], style);
}

double localSpacingPx(double density, const styles::HatchStyle &style) {
    return familySpacingPx(density, 0, style);
}

double toneInkPx(const ScreenField &field, const std::vector<float> &targetDensity, const styles::HatchStyle &style,
                 double *atMinSpacingPx) {
    ROSY_CHECK_EQ(targetDensity.size(), field.nPixels());
    // Per row, then summed in row order: the same totals for any thread count.
    std::vector<std::array<double, 2>> rows(size_t(std::max(0, field.height)), {0.0, 0.0});
    parallelFor(0, field.height, [&](int64_t y) {
        double sum = 0, atMin = 0;
        for (int x = 0; x < field.width; ++x) {
            const size_t i = size_t(field.index(x, int(y)));
            const double rho = clampDensity(targetDensity[i]);
            if (!field.valid(i) || hatchFamilies(rho, style) == 0) continue;
            const double w = crossWeight(field, i);
            const std::array<double, 2> c = familyCoverage(rho, style, w);
            for (int f = 0; f < 2; ++f) {
                if (!(c[size_t(f)] > 0)) continue;
                const double ink = 1.0 / spacingOfCoverage(c[size_t(f)], style);
                sum += ink;
                // Asked at or below the densest spacing (before the clamp; the tone
                // saturates at maxHatchDensity(), exactly there up to rounding).
                if (style.spacingGain * style.strokeWidthPx / c[size_t(f)] <= style.minSpacingPx * (1.0 + 1e-6))
                    atMin += ink;
            }
        }
        rows[size_t(y)] = {sum, atMin};
    }, 16);
    double total = 0, totalAtMin = 0;
    for (const auto &r : rows) {
        total += r[0];
        totalAtMin += r[1];
    }
    if (atMinSpacingPx) *atMinSpacingPx = totalAtMin;
    return total;
}

double hatchInkPx(const StrokeList &strokes) {
    double ink = 0;
    for (const Stroke &s : strokes.strokes)
        if (s.kind == StrokeKind::Hatch)
            for (size_t k = 1; k < s.points.size(); ++k) ink += (s.points[k] - s.points[k - 1]).norm();
    return ink;
}

StrokeList traceHatches(const ScreenField &field, const std::vector<float> &targetDensity,
                        const GBuffer &gbuffer, const styles::HatchStyle &style, uint32_t seed,
                        HatchReport *report, const std::function<void()> &whileTracing) {
    ROSY_CHECK_EQ(field.width, gbuffer.width);
    ROSY_CHECK_EQ(field.height, gbuffer.height);
    ROSY_CHECK_EQ(targetDensity.size(), field.nPixels());
    ROSY_CHECK(style.strokeWidthPx > 0 && style.minSpacingPx > 0);
    StrokeList out;
    out.width = field.width;
    out.height = field.height;
    if (field.nPixels() > 0) {
        Hatcher hatcher(field, targetDensity, gbuffer, style, seed);
        if (whileTracing) whileTracing();
        hatcher.traceFamily(0);
        hatcher.traceFamily(1);
        hatcher.fillHoles();
        hatcher.inkSingularityHoles();
        hatcher.relabelCrossings();
        const std::vector<uint8_t> blunt = hatcher.bluntEnds();
        out.strokes = hatcher.takeStrokes();
        // Each stroke's finish depends only on itself and (seed, id): safe in parallel.
        parallelFor(0, int64_t(out.strokes.size()),
                    [&](int64_t k) { finishStroke(out.strokes[size_t(k)], style, seed, blunt[size_t(k)]); }, 64);
    } else if (whileTracing) {
        whileTracing();
    }
    if (report) *report = measureHatches(out, field, targetDensity, style);
    return out;
}

namespace {

/// The hatch strokes of `list` that measureHatches() looks at (kind Hatch, at least two
/// points), by index.
std::vector<int> measuredStrokes(const StrokeList &list) {
    std::vector<int> hatch;
    for (size_t k = 0; k < list.strokes.size(); ++k)
        if (list.strokes[k].kind == StrokeKind::Hatch && list.strokes[k].points.size() >= 2) hatch.push_back(int(k));
    return hatch;
}

/// measureHatches()'s spacing at p: family 0's d_sep, the densest hatching the tone
/// asks for (strokes carry a family label for their layer, but a line can change layer
/// after tracing, relabelled crossings, so the measure does not depend on which family
/// traced it); family 1's for the second family's own d_test.
double measuredSpacingAt(const ScreenField &field, const std::vector<float> &targetDensity,
                         const styles::HatchStyle &style, const Vec2 &p, int family) {
    const size_t i = clampedPixel(field, p);
    const double w = field.valid(i) ? crossWeight(field, i) : 0.0;
    return familySpacingPx(clampDensity(targetDensity[i]), family, style, w);
}

/// Whether the tone at p asks for both families and the two screen directions there
/// have not folded together: where a singularity's disc left empty reads as a hole.
bool inCrossTone(const ScreenField &field, const std::vector<float> &targetDensity, const styles::HatchStyle &style,
                 const Vec2 &p) {
    const size_t i = clampedPixel(field, p);
    return hatchFamilies(clampDensity(targetDensity[i]), style) >= 2 && field.valid(i) && crossWeight(field, i) > 0.0;
}

/// HatchReport::singularityHoles over the hatch strokes `hatch` of `list`.
int countSingularityHoles(const StrokeList &list, const std::vector<int> &hatch, const ScreenField &field,
                          const std::vector<float> &targetDensity, const styles::HatchStyle &style) {
    int holes = 0;
    std::vector<std::array<Vec2, 2>> box; // each stroke's bounding box, computed on the first use
    for (const ScreenSingularity &s : field.singularities) {
        if (!s.visible) continue;
        if (!inCrossTone(field, targetDensity, style, s.pRaster)) continue;
        const double reach = kHoleRatio * measuredSpacingAt(field, targetDensity, style, s.pRaster, 0);
        if (box.empty())
            for (int k : hatch) {
                const auto &pts = list.strokes[size_t(k)].points;
                std::array<Vec2, 2> b{pts[0], pts[0]};
                for (const Vec2 &p : pts) b = {b[0].cwiseMin(p), b[1].cwiseMax(p)};
                box.push_back(b);
            }
        bool inked = false;
        for (size_t h = 0; h < hatch.size() && !inked; ++h) {
            if ((s.pRaster.array() < box[h][0].array() - reach).any() ||
                (s.pRaster.array() > box[h][1].array() + reach).any())
                continue;
            const auto &pts = list.strokes[size_t(hatch[h])].points;
            for (size_t k = 0; k + 1 < pts.size() && !inked; ++k)
                inked = pointSegmentDistance(s.pRaster, pts[k], pts[k + 1]) <= reach;
        }
        holes += !inked;
    }
    return holes;
}

} // namespace

HatchReport countHatches(const StrokeList &list, const ScreenField &field, const std::vector<float> &targetDensity,
                         const styles::HatchStyle &style, double tolerance) {
    ROSY_CHECK_EQ(targetDensity.size(), field.nPixels());
    HatchReport r;
    const std::vector<int> hatch = measuredStrokes(list);
    for (int k : hatch) {
        const Stroke &s = list.strokes[size_t(k)];
        ++r.strokes;
        (s.family == 1 ? r.strokesFamily1 : r.strokesFamily0)++;
        for (size_t i = 1; i < s.points.size(); ++i) r.inkLengthPx += (s.points[i] - s.points[i - 1]).norm();
    }
    if (hatch.empty() || field.nPixels() == 0) return r;
    // The discs the tracer keeps free: those outside cross tone (in cross tone a disc
    // that would be a white speck is inked afterwards, Hatcher::inkSingularityHoles()).
    std::vector<Disc> discs;
    for (const Disc &d : singularityDiscs(field, targetDensity, style, 1.0 - tolerance))
        if (!inCrossTone(field, targetDensity, style, d.centre)) discs.push_back(d);
    std::vector<uint8_t> isStub(hatch.size(), 0), nearSing(hatch.size(), 0);
    parallelFor(0, int64_t(hatch.size()), [&](int64_t h) {
        const auto &pts = list.strokes[size_t(hatch[size_t(h)])].points;
        // Stubs: strokes shorter than kStubLengthRatio times their mean local spacing.
        double arc = 0.0, spacingSum = 0.0;
        for (size_t i = 0; i < pts.size(); ++i) {
            if (i > 0) arc += (pts[i] - pts[i - 1]).norm();
            spacingSum += measuredSpacingAt(field, targetDensity, style, pts[i], 0);
        }
        isStub[size_t(h)] = arc < kStubLengthRatio * (spacingSum / double(pts.size()));
        for (const Disc &d : discs)
            for (size_t i = 0; i + 1 < pts.size() && !nearSing[size_t(h)]; ++i)
                if (pointSegmentDistance(d.centre, pts[i], pts[i + 1]) < d.radius) nearSing[size_t(h)] = 1;
    }, 64);
    for (size_t h = 0; h < hatch.size(); ++h) {
        r.strokesNearSingularities += nearSing[h];
        r.stubs += isStub[h];
    }
    r.stubFraction = double(r.stubs) / double(hatch.size());
    r.singularityHoles = countSingularityHoles(list, hatch, field, targetDensity, style);
    return r;
}

HatchReport measureHatches(const StrokeList &list, const ScreenField &field,
                           const std::vector<float> &targetDensity,
                           const styles::HatchStyle &style, double tolerance) {
    HatchReport r = countHatches(list, field, targetDensity, style, tolerance);
    const std::vector<int> hatch = measuredStrokes(list);
    if (hatch.empty() || field.nPixels() == 0) return r;

    auto spacingAt = [&](const Vec2 &p) { return measuredSpacingAt(field, targetDensity, style, p, 0); };
    auto dTestAt = [&](const Vec2 &p) { return kTestRatio * spacingAt(p); };
    // The second family's own d_test: its lines are traced at that spacing, so only
    // first-family lines that were relabelled (relabelCrossings) can lie closer.
    auto dTest1At = [&](const Vec2 &p) { return kTestRatio * measuredSpacingAt(field, targetDensity, style, p, 1); };

    // Segment grid, independent of the tracer's sample grid: every segment is entered
    // in each cell its bounding box touches.
    const double cell = std::max(2.0, style.minSpacingPx);
    const int nx = std::max(1, int(std::ceil(field.width / cell))), ny = std::max(1, int(std::ceil(field.height / cell)));
    std::vector<std::vector<std::pair<int, int>>> cells(size_t(nx) * size_t(ny)); // (stroke, segment)
    auto cellRange = [&](double lo, double hi, int n) {
        return std::make_pair(std::clamp(int(std::floor(lo / cell)), 0, n - 1), std::clamp(int(std::floor(hi / cell)), 0, n - 1));
    };
    for (int k : hatch) {
        const auto &pts = list.strokes[size_t(k)].points;
        for (size_t i = 0; i + 1 < pts.size(); ++i) {
            auto [x0, x1] = cellRange(std::min(pts[i].x(), pts[i + 1].x()), std::max(pts[i].x(), pts[i + 1].x()), nx);
            auto [y0, y1] = cellRange(std::min(pts[i].y(), pts[i + 1].y()), std::max(pts[i].y(), pts[i + 1].y()), ny);
            for (int cy = y0; cy <= y1; ++cy)
                for (int cx = x0; cx <= x1; ++cx) cells[size_t(cy) * size_t(nx) + size_t(cx)].push_back({k, int(i)});
        }
    }

    // Per stroke: the partners it violates spacing with.
    std::vector<std::vector<int>> partners(hatch.size());
    std::vector<double> crossLength(hatch.size(), 0.0), overdenseLength(hatch.size(), 0.0),
        squeezedLength(hatch.size(), 0.0), incoherentLength(hatch.size(), 0.0);
    parallelFor(0, int64_t(hatch.size()), [&](int64_t h) {
        const int k = hatch[size_t(h)];
        const Stroke &a = list.strokes[size_t(k)];
        const auto &pts = a.points;
        std::vector<int> &mine = partners[size_t(h)];
        // One pass over the points: each point's central-chord tangent and local d_sep
        // serve the spacing test and the squeezed runs.
        double runStart = -1.0, runEnd = 0.0, arc = 0.0;
        for (size_t i = 0; i < pts.size(); ++i) {
            if (i > 0) arc += (pts[i] - pts[i - 1]).norm();
            const Vec2 ta = (pts[std::min(i + 1, pts.size() - 1)] - pts[i > 0 ? i - 1 : 0]).normalized();
            const double dSep = spacingAt(pts[i]);
            const double rA = kTestRatio * dSep; // dTestAt(pts[i])
            const double r1A = a.family == 1 ? dTest1At(pts[i]) : 0.0;
            const double reach = std::max(rA, r1A);
            const double weight = 0.5 * ((i > 0 ? (pts[i] - pts[i - 1]).norm() : 0.0) +
                                         (i + 1 < pts.size() ? (pts[i + 1] - pts[i]).norm() : 0.0));
            if (a.family == 1) crossLength[size_t(h)] += weight;
            bool overdense = false;
            {
                auto [x0, x1] = cellRange(pts[i].x() - reach, pts[i].x() + reach, nx);
                auto [y0, y1] = cellRange(pts[i].y() - reach, pts[i].y() + reach, ny);
                for (int cy = y0; cy <= y1; ++cy)
                    for (int cx = x0; cx <= x1; ++cx)
                        for (const auto &[kb, j] : cells[size_t(cy) * size_t(nx) + size_t(cx)]) {
                            if (kb == k) continue;
                            const Stroke &b = list.strokes[size_t(kb)];
                            if (b.family != a.family) continue;
                            const Vec2 &b0 = b.points[size_t(j)], &b1 = b.points[size_t(j) + 1];
                            const Vec2 tb = (b1 - b0).normalized();
                            if (std::abs(ta.dot(tb)) < kCos45) continue;
                            const double dist = pointSegmentDistance(pts[i], b0, b1);
                            // Closer than d_test wherever it is evaluated (tone may differ
                            // between the two points), less the polyline chord tolerance.
                            const double r = (1.0 - tolerance) * std::min(rA, dTestAt(0.5 * (b0 + b1)));
                            if (dist < r) mine.push_back(kb);
                            if (a.family == 1 && !overdense &&
                                dist < (1.0 - tolerance) * std::min(r1A, dTest1At(0.5 * (b0 + b1))))
                                overdense = true;
                        }
            }
            if (overdense) overdenseLength[size_t(h)] += weight;
            // Incoherent directions: a line of the same layer within one d_sep runs at
            // 20°–50° to this one. Neighbours of one family follow the field's smooth
            // turn and differ by a few degrees over a spacing; lines of one direction
            // never cross (the tracer keeps 55° apart lines at d_test), and crossings
            // of two fronts (55° and more) are cross_overdense_fraction's.
            bool incoherent = false;
            {
                auto [x0, x1] = cellRange(pts[i].x() - dSep, pts[i].x() + dSep, nx);
                auto [y0, y1] = cellRange(pts[i].y() - dSep, pts[i].y() + dSep, ny);
                for (int cy = y0; cy <= y1 && !incoherent; ++cy)
                    for (int cx = x0; cx <= x1 && !incoherent; ++cx)
                        for (const auto &[kb, j] : cells[size_t(cy) * size_t(nx) + size_t(cx)]) {
                            if (kb == k) continue;
                            const Stroke &b = list.strokes[size_t(kb)];
                            if (b.family != a.family) continue;
                            const Vec2 &b0 = b.points[size_t(j)], &b1 = b.points[size_t(j) + 1];
                            const double c = std::abs(ta.dot((b1 - b0).normalized()));
                            if (c <= kIncoherentCosLo || c >= kIncoherentCosHi) continue;
                            if (pointSegmentDistance(pts[i], b0, b1) >= dSep) continue;
                            incoherent = true;
                            break;
                        }
            }
            if (incoherent) incoherentLength[size_t(h)] += weight;
            // Squeezed runs: stretches of at least one local d_sep along which a line of
            // the same direction (within 45°, any layer) lies on each side closer than
            // kSqueezeRatio d_sep: two fronts interleaved at half the spacing.
            const double R = kSqueezeRatio * dSep;
            bool left = false, right = false;
            auto [x0, x1] = cellRange(pts[i].x() - R, pts[i].x() + R, nx);
            auto [y0, y1] = cellRange(pts[i].y() - R, pts[i].y() + R, ny);
            for (int cy = y0; cy <= y1 && !(left && right); ++cy)
                for (int cx = x0; cx <= x1 && !(left && right); ++cx)
                    for (const auto &[kb, j] : cells[size_t(cy) * size_t(nx) + size_t(cx)]) {
                        if (kb == k) continue;
                        const Stroke &b = list.strokes[size_t(kb)];
                        const Vec2 &b0 = b.points[size_t(j)], &b1 = b.points[size_t(j) + 1];
                        if (std::abs(ta.dot((b1 - b0).normalized())) < kCos45) continue;
                        if (pointSegmentDistance(pts[i], b0, b1) >= R) continue;
                        const Vec2 d = 0.5 * (b0 + b1) - pts[i];
                        (ta.x() * d.y() - ta.y() * d.x() > 0 ? left : right) = true;
                    }
            const bool squeezedHere = left && right;
            if (squeezedHere) {
                if (runStart < 0) runStart = arc;
                runEnd = arc;
            }
            if (runStart >= 0 && (!squeezedHere || i + 1 == pts.size())) {
                if (runEnd - runStart >= dSep) squeezedLength[size_t(h)] += runEnd - runStart;
                runStart = -1.0;
            }
        }
    }, 16);

    std::vector<std::pair<int, int>> pairs;
    for (size_t h = 0; h < hatch.size(); ++h) {
        const int k = hatch[h];
        for (int kb : partners[h]) pairs.emplace_back(std::min(k, kb), std::max(k, kb));
    }
    double cross = 0.0, over = 0.0, squeezed = 0.0, incoherent = 0.0;
    for (size_t h = 0; h < hatch.size(); ++h) {
        cross += crossLength[h];
        over += overdenseLength[h];
        squeezed += squeezedLength[h];
        incoherent += incoherentLength[h];
    }
    r.crossOverdenseFraction = cross > 0.0 ? over / cross : 0.0;
    r.squeezedFraction = r.inkLengthPx > 0.0 ? squeezed / r.inkLengthPx : 0.0;
    r.incoherentFraction = r.inkLengthPx > 0.0 ? incoherent / r.inkLengthPx : 0.0;
    std::sort(pairs.begin(), pairs.end());
    r.minSpacingViolations = int(std::unique(pairs.begin(), pairs.end()) - pairs.begin());
    return r;
}

} // namespace rosy::renderer
