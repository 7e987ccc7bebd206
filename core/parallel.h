#pragma once
/// \file parallel.h
/// The one way rosyhatch runs loops in parallel. Work items must be independent
/// and write only to their own outputs, so results are identical for any thread
/// count; reductions are done afterwards in index order by the caller.

#include <cstdint>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rosy {

/// Calls body(i) for every i in [begin, end), in parallel chunks of at least `grain`.
template <typename Body>
void parallelFor(int64_t begin, int64_t end, Body &&body, int64_t grain = 256) {
    if (end <= begin) return;
    if (end - begin <= grain) {
        for (int64_t i = begin; i < end; ++i) body(i);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<int64_t>(begin, end, grain),
                      [&](const tbb::blocked_range<int64_t> &r) {
                          for (int64_t i = r.begin(); i < r.end(); ++i) body(i);
                      });
}

/// Calls body(lo, hi) on disjoint chunks covering [begin, end).
template <typename Body>
void parallelForRange(int64_t begin, int64_t end, Body &&body, int64_t grain = 256) {
    if (end <= begin) return;
    tbb::parallel_for(tbb::blocked_range<int64_t>(begin, end, grain),
                      [&](const tbb::blocked_range<int64_t> &r) { body(r.begin(), r.end()); });
}

} // namespace rosy
