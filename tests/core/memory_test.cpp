// core/memory.h: the memory budget a render is checked against, and byte counts in
// messages. Expected strings are worked out by hand from the unit definitions.

#include "core/memory.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <sys/resource.h>

using namespace rosy;

TEST(FormatBytes, PicksTheLargestUnitBelowTheValue) {
    EXPECT_EQ(formatBytes(0), "0 KiB");
    EXPECT_EQ(formatBytes(2048), "2 KiB");
    EXPECT_EQ(formatBytes(300ULL * 1024 * 1024), "300 MiB");
    EXPECT_EQ(formatBytes(1024ULL * 1024 - 1024), "1023 KiB");           // just under 1 MiB
    EXPECT_EQ(formatBytes(1024ULL * 1024), "1 MiB");                      // exactly 1 MiB
    EXPECT_EQ(formatBytes(3ULL * 1024 * 1024 * 1024 / 2), "1.5 GiB");     // 1610612736 bytes
    EXPECT_EQ(formatBytes(4ULL * 1024 * 1024 * 1024), "4.0 GiB");
    EXPECT_EQ(formatBytes(7ULL * 1024 * 1024 * 1024 + 107374182), "7.1 GiB"); // 7.1 GiB = 7 GiB + 0.1 GiB
}

namespace {
/// This process's VmSize in bytes, read independently of the code under test.
long long vmSizeBytes() {
    std::ifstream in("/proc/self/status");
    std::string key;
    long long kb = -1;
    while (in >> key)
        if (key == "VmSize:") {
            in >> kb;
            break;
        }
    return kb * 1024;
}
} // namespace

TEST(AvailableMemory, AnAddressSpaceLimitDecidesWhenItIsTheSmallest) {
    const auto before = availableMemory();
    ASSERT_TRUE(before.has_value()); // /proc/meminfo exists on Linux
    EXPECT_GT(before->bytes, 0u);
    EXPECT_FALSE(before->source.empty());

#ifdef ROSY_SANITIZED
    GTEST_SKIP() << "ASan reserves terabytes of address space and must not meet an address space limit";
#endif
    struct rlimit old {};
    ASSERT_EQ(::getrlimit(RLIMIT_AS, &old), 0);
    const long long headroom = 64LL << 20; // 64 MiB above what the process maps now
    const long long limit = vmSizeBytes() + headroom;
    ASSERT_GT(limit, headroom);
    if (old.rlim_cur != RLIM_INFINITY && (long long)old.rlim_cur < limit) GTEST_SKIP() << "already limited below";
    struct rlimit tight = old;
    tight.rlim_cur = rlim_t(limit);
    ASSERT_EQ(::setrlimit(RLIMIT_AS, &tight), 0);
    const auto limited = availableMemory();
    ASSERT_EQ(::setrlimit(RLIMIT_AS, &old), 0);

    ASSERT_TRUE(limited.has_value());
    EXPECT_EQ(limited->source, "the address space limit (ulimit -v)");
    // The limit minus VmSize at the time of the call: the headroom, give or take the
    // few pages the call itself maps.
    EXPECT_LE(limited->bytes, uint64_t(headroom));
    EXPECT_GT(limited->bytes, uint64_t(headroom / 2));
}
