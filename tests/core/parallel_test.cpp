// core/parallel.h: every index exactly once, whatever the range, grain and thread count.

#include "core/parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

using namespace rosy;

TEST(ParallelFor, VisitsEveryIndexOnceForAnyRangeAndGrain) {
    for (const int threads : {1, 2, 4}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        for (const auto &range : std::vector<std::pair<int64_t, int64_t>>{{0, 1}, {0, 255}, {0, 256}, {0, 257}, {-300, 7000}, {5, 100000}})
            for (const int64_t grain : {1, 7, 256, 100000}) {
                const int64_t begin = range.first, end = range.second; // clang 14 cannot capture structured bindings
                std::vector<std::atomic<int>> hits(size_t(end - begin));
                parallelFor(begin, end, [&](int64_t i) { hits[size_t(i - begin)].fetch_add(1); }, grain);
                int wrong = 0;
                for (const auto &h : hits) wrong += h.load() != 1;
                EXPECT_EQ(wrong, 0) << "[" << begin << ", " << end << ") grain " << grain << ", " << threads << " threads";
            }
    }
}

TEST(ParallelFor, EmptyAndReversedRangesCallNothing) {
    int calls = 0;
    parallelFor(5, 5, [&](int64_t) { ++calls; });
    parallelFor(10, 3, [&](int64_t) { ++calls; });
    parallelForRange(7, 7, [&](int64_t, int64_t) { ++calls; });
    parallelForRange(7, -1, [&](int64_t, int64_t) { ++calls; });
    EXPECT_EQ(calls, 0);
}

TEST(ParallelForRange, ChunksAreDisjointAndCoverTheRange) {
    std::mutex m;
    std::vector<std::pair<int64_t, int64_t>> chunks;
    parallelForRange(-50, 10000, [&](int64_t lo, int64_t hi) {
        std::lock_guard<std::mutex> lock(m);
        chunks.emplace_back(lo, hi);
    }, 64);
    std::sort(chunks.begin(), chunks.end());
    ASSERT_FALSE(chunks.empty());
    EXPECT_EQ(chunks.front().first, -50);
    EXPECT_EQ(chunks.back().second, 10000);
    for (size_t k = 0; k < chunks.size(); ++k) {
        EXPECT_LT(chunks[k].first, chunks[k].second);
        if (k > 0) {
            EXPECT_EQ(chunks[k].first, chunks[k - 1].second) << "gap or overlap at chunk " << k;
        }
    }
}

TEST(StartWorkerThreads, ReturnsPromptlyForAnyParallelism) {
    for (const int threads : {1, 2, 8}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        const auto t0 = std::chrono::steady_clock::now();
        startWorkerThreads();
        // Each task waits at most 20 ms for the others: bounded even when workers cannot start.
        EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(2));
    }
}
