#pragma once
/// \file plotter_reference.h
/// A textbook yardstick for the plotter pass's ordering (renderer/output/plotter.h),
/// shared by plotter_bench and tests/renderer/svg_test.cpp. It is what vpype's
/// `linesort --two-opt` documents (greedy nearest neighbour with flipping, then
/// 2-opt passes that reverse runs of lines, each line turned around), written
/// from that description and the textbook algorithm, not from vpype's code:
///  - greedy: from the pen, the nearest endpoint of any undrawn stroke, by brute
///    force (no grid), the stroke drawn from that end;
///  - 2-opt: every pair of boundaries, exhaustively, first improvement, until a
///    full pass finds nothing or `maxPasses` passes ran (vpype's default: 250).
/// O(n²) per pass: for a few thousand strokes. The pen starts at the origin, as
/// in the plotter pass; the travel is renderer::penUpLength().

#include "renderer/output/strokes.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace rosy::bench {

/// Strokes reordered and turned by greedy + exhaustive 2-opt; the passes run go to *passes.
inline std::vector<renderer::Stroke> referenceGreedyTwoOpt(std::vector<renderer::Stroke> strokes, int maxPasses = 250,
                                                           int *passes = nullptr) {
    using Vec2 = Eigen::Vector2d;
    const int n = int(strokes.size());
    if (n == 0) return strokes;
    std::vector<char> used(size_t(n), 0);
    std::vector<Vec2> S, E; // start and end of each position, as drawn
    std::vector<int> order;
    std::vector<char> flipped;
    Vec2 pen = Vec2::Zero();
    for (int step = 0; step < n; ++step) {
        double best = std::numeric_limits<double>::infinity();
        int bi = -1;
        bool bflip = false;
        for (int i = 0; i < n; ++i) {
            if (used[size_t(i)]) continue;
            const double d0 = (strokes[size_t(i)].points.front() - pen).norm();
            const double d1 = (strokes[size_t(i)].points.back() - pen).norm();
            if (d0 < best) best = d0, bi = i, bflip = false;
            if (d1 < best) best = d1, bi = i, bflip = true;
        }
        used[size_t(bi)] = 1;
        order.push_back(bi);
        flipped.push_back(char(bflip));
        const auto &pts = strokes[size_t(bi)].points;
        S.push_back(bflip ? pts.back() : pts.front());
        E.push_back(bflip ? pts.front() : pts.back());
        pen = E.back();
    }
    // Boundary b: travel from E[b-1] (the origin for b = 0) to S[b]; none after the last.
    const auto leftOf = [&](int b) { return b == 0 ? Vec2::Zero() : E[size_t(b - 1)]; };
    const auto cost = [&](int b) { return b >= n ? 0.0 : (leftOf(b) - S[size_t(b)]).norm(); };
    int pass = 0;
    for (; pass < maxPasses; ++pass) {
        bool improved = false;
        for (int b1 = 0; b1 < n; ++b1)
            for (int b2 = b1 + 1; b2 <= n; ++b2) {
                // Reversing positions b1..b2-1 (each stroke turned) replaces the
                // travels at b1 and b2 by E[b-1]→E[b2-1] and S[b1]→S[b2].
                const double after = (leftOf(b1) - E[size_t(b2 - 1)]).norm() +
                                     (b2 < n ? (S[size_t(b1)] - S[size_t(b2)]).norm() : 0.0);
                if (after < cost(b1) + cost(b2) - 1e-9) {
                    std::reverse(order.begin() + b1, order.begin() + b2);
                    std::reverse(flipped.begin() + b1, flipped.begin() + b2);
                    std::reverse(S.begin() + b1, S.begin() + b2);
                    std::reverse(E.begin() + b1, E.begin() + b2);
                    for (int p = b1; p < b2; ++p) {
                        flipped[size_t(p)] = char(!flipped[size_t(p)]);
                        std::swap(S[size_t(p)], E[size_t(p)]);
                    }
                    improved = true;
                }
            }
        if (!improved) break;
    }
    if (passes) *passes = pass;
    std::vector<renderer::Stroke> out;
    out.reserve(size_t(n));
    for (int p = 0; p < n; ++p) {
        out.push_back(std::move(strokes[size_t(order[size_t(p)])]));
        if (flipped[size_t(p)]) {
            std::reverse(out.back().points.begin(), out.back().points.end());
            std::reverse(out.back().widths.begin(), out.back().widths.end());
        }
    }
    return out;
}

} // namespace rosy::bench
