// core/diagnostics.h: warnings are counted per kind, captured by the innermost
// WarningCapture, printed as `where: warning: message` otherwise.

#include "core/diagnostics.h"

#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

using namespace rosy;

TEST(Warnings, CountedPerKindSortedAndReset) {
    resetWarningCounts();
    WarningCapture capture; // keep the test's output clean
    warn("b.off", "zeta", "one");
    warn("b.off", "alpha", "two");
    warn("c.off", "zeta", "three");
    const std::map<std::string, int> counts = warningCounts();
    ASSERT_EQ(counts.size(), 2u);
    EXPECT_EQ(counts.begin()->first, "alpha"); // sorted by kind, not by arrival
    EXPECT_EQ(counts.at("alpha"), 1);
    EXPECT_EQ(counts.at("zeta"), 2);
    resetWarningCounts();
    EXPECT_TRUE(warningCounts().empty());
}

TEST(Warnings, InnermostCaptureCollectsThenThePreviousOneAgain) {
    WarningCapture outer;
    warn("a", "k1", "first");
    {
        WarningCapture inner;
        warn("b", "k2", "second");
        ASSERT_EQ(inner.warnings().size(), 1u);
        EXPECT_EQ(inner.warnings()[0].where, "b");
        EXPECT_EQ(inner.warnings()[0].message, "second");
        EXPECT_TRUE(inner.has("k2"));
        EXPECT_FALSE(inner.has("k1"));
    }
    warn("c", "k3", "third");
    ASSERT_EQ(outer.warnings().size(), 2u);
    EXPECT_EQ(outer.warnings()[0].kind, "k1");
    EXPECT_EQ(outer.warnings()[1].kind, "k3");
    EXPECT_FALSE(outer.has("k2"));
}

TEST(Warnings, PrintedAsOneEscapedLineUnlessSilenced) {
    testing::internal::CaptureStderr();
    warn("m\x1b.off", "kind", "repaired 3 faces");
    setWarningsPrinted(false);
    warn("m.off", "kind", "not printed");
    setWarningsPrinted(true);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "m\\x1b.off: warning: repaired 3 faces\n");
}

TEST(Warnings, ConcurrentWarningsAreAllCounted) {
    resetWarningCounts();
    WarningCapture capture;
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([] {
            for (int i = 0; i < 1000; ++i) warn("x", "threaded", "m");
        });
    for (std::thread &t : threads) t.join();
    EXPECT_EQ(warningCounts().at("threaded"), 4000);
    EXPECT_EQ(capture.warnings().size(), 4000u);
    resetWarningCounts();
}
