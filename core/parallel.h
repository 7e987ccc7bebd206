#pragma once
/// \file parallel.h
/// The one way rosyhatch runs loops in parallel. Work items must be independent
/// and write only to their own outputs, so results are identical for any thread
/// count; reductions are done afterwards in index order by the caller.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

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

/// Makes oneTBB start its worker threads now rather than at the first parallel
/// loop: each of max-concurrency tasks waits (at most 20 ms) until all have begun,
/// which only happens once every worker is running. Call it before a long dlopen()
/// on another thread: the dynamic loader holds its lock for the whole load, and
/// pthread_create needs that lock, so a first parallel loop during the load would
/// wait for it to finish (rosyhatch's frames stage took 140 ms instead of 40).
inline void startWorkerThreads() {
    const int n = int(std::min<size_t>(size_t(tbb::this_task_arena::max_concurrency()),
                                       tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
    if (n <= 1) return;
    std::atomic<int> begun{0};
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, n, 1),
        [&](const tbb::blocked_range<int> &) {
            ++begun;
            while (begun.load() < n && std::chrono::steady_clock::now() < until) std::this_thread::yield();
        },
        tbb::simple_partitioner());
}

} // namespace rosy
