// core/pixel_array.h: large per-pixel maps straight from the kernel, zeroed, 2 MiB
// aligned and advised for transparent huge pages.

#include "core/pixel_array.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <new>
#include <sstream>
#include <string>

using namespace rosy;

TEST(PixelArray, StartsZeroedAlignedAndKeepsWhatIsWritten) {
    const size_t n = 1024 * 1024 + 3; // 8 MiB of doubles and a bit: five huge pages
    PixelArray<double> a(n);
    ASSERT_EQ(a.size(), n);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data()) % (2u << 20), 0u);
    for (size_t i = 0; i < n; i += 4093) EXPECT_EQ(a[i], 0.0) << i;
    EXPECT_EQ(a[n - 1], 0.0);
    for (size_t i = 0; i < n; ++i) a[i] = double(i) * 0.5;
    double sum = 0;
    for (size_t i = 0; i < n; ++i) sum += a[i];
    EXPECT_DOUBLE_EQ(sum, 0.5 * double(n) * double(n - 1) / 2.0);
}

TEST(PixelArray, MovesOwnershipAndHandlesEmpty) {
    PixelArray<float> e;
    EXPECT_TRUE(e.empty());
    EXPECT_EQ(e.data(), nullptr);
    PixelArray<float> z(0);
    EXPECT_TRUE(z.empty());
    PixelArray<float> a(100);
    a[99] = 7.f;
    float *p = a.data();
    PixelArray<float> b(std::move(a));
    EXPECT_EQ(b.data(), p);
    EXPECT_EQ(b[99], 7.f);
    EXPECT_EQ(a.data(), nullptr); // NOLINT(bugprone-use-after-move): moved-from is empty
    PixelArray<float> c(10);
    c = std::move(b);
    EXPECT_EQ(c.data(), p);
    EXPECT_EQ(c.size(), 100u);
}

TEST(PixelArray, AnImpossibleSizeThrowsBadAlloc) {
    EXPECT_THROW(PixelArray<double>(SIZE_MAX / 16), std::bad_alloc);
    EXPECT_THROW(PixelArray<uint8_t>(SIZE_MAX - 10), std::bad_alloc);
}

namespace {
/// The "THPeligible:" flag of the mapping holding `p` in /proc/self/smaps; -1 when
/// the kernel does not report it.
int thpEligible(const void *p) {
    const auto addr = reinterpret_cast<std::uintptr_t>(p);
    std::ifstream in("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(in, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = addr >= lo && addr < hi;
            continue;
        }
        if (inside && line.rfind("THPeligible:", 0) == 0) return std::stoi(line.substr(12));
    }
    return -1;
}
} // namespace

TEST(PixelArray, IsAdvisedForHugePagesWhereTheKernelOffersThem) {
    std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(thp, mode);
    if (mode.empty() || mode.find("[never]") != std::string::npos) GTEST_SKIP() << "no transparent huge pages here";
    PixelArray<double> a(1 << 20);
    const int eligible = thpEligible(a.data());
    if (eligible < 0) GTEST_SKIP() << "this kernel's smaps has no THPeligible";
    EXPECT_EQ(eligible, 1) << "THP mode: " << mode;
}
