#include "field/rosy.h"

#include <gtest/gtest.h>
#include <cmath>
#include <vector>
#include <cstdint>
#include <random>
#include <cstring>

using namespace rosy::field;

TEST(Representation, MemberChoiceDoesNotMatter) {
    for (int n = 1; n <= 6; ++n)
        for (double theta : {0.0, 0.3, 1.7, -2.2})
            for (int k = 1; k < n; ++k) {
                Complex a = representation(theta, n), b = representation(theta + 2 * M_PI * k / n, n);
                EXPECT_NEAR(std::abs(a - b), 0.0, 1e-12) << "N=" << n << " k=" << k;
            }
}

TEST(Representation, OrthogonalLineFieldsCancel) {
    // {±x} + {±y} as 2-RoSys: representation vectors 1 and e^{iπ} sum to zero.
    Complex sum = representation(0.0, 2) + representation(M_PI / 2, 2);
    EXPECT_NEAR(std::abs(sum), 0.0, 1e-15);
    // As 4-RoSys, x and y are the same cross: the sum doubles.
    EXPECT_NEAR(std::abs(representation(0.0, 4) + representation(M_PI / 2, 4)), 2.0, 1e-12);
}

TEST(Representation, InverseGivesAllMembers) {
    const int n = 3;
    Complex u = representation(0.4, n, 2.5);
    EXPECT_NEAR(std::abs(u), 2.5, 1e-12);
    std::vector<double> m = memberAngles(u, n);
    ASSERT_EQ(int(m.size()), 3);
    EXPECT_NEAR(m[0], 0.4, 1e-12);
    EXPECT_NEAR(m[1], 0.4 + 2 * M_PI / 3, 1e-12);
    EXPECT_NEAR(m[2], 0.4 + 4 * M_PI / 3, 1e-12);
}

TEST(Representation, ScalarMultipleAndSumFollowEq3) {
    // 2 s1 + s2 with s1 = s2 (same 4-RoSy, different member chosen) is 3 s1.
    Complex s1 = representation(0.2, 4), s2 = representation(0.2 + M_PI / 2, 4);
    EXPECT_NEAR(std::abs(2.0 * s1 + s2 - 3.0 * s1), 0.0, 1e-12);
}

TEST(WrapAngle, IntoHalfOpenInterval) {
    EXPECT_NEAR(wrapAngle(3 * M_PI), M_PI, 1e-12);
    EXPECT_NEAR(wrapAngle(-M_PI), M_PI, 1e-12);
    EXPECT_NEAR(wrapAngle(0.5 + 4 * M_PI), 0.5, 1e-12);
}

TEST(WrapAngle, RemainderAndFmodOfTwoPiAreTheLibrarysBitForBit) {
    // The shortcuts must give exactly what std::remainder and std::fmod give: at and
    // next to every multiple of π up to 8π (ties included), spread values, tiny,
    // huge, signed zeros, infinities and NaN.
    std::vector<double> xs = {0.0, -0.0, 1e-310, -1e-310, 1e300, -1e300, HUGE_VAL, -HUGE_VAL, std::nan("")};
    for (int k = -8; k <= 8; ++k)
        for (double base : {k * M_PI, k * (2.0 * M_PI) / 2.0, M_PI + k * (2.0 * M_PI), double(k) * 2.0 * M_PI})
            for (double x = std::nextafter(std::nextafter(base, -HUGE_VAL), -HUGE_VAL), n = 0; n < 5;
                 ++n, x = std::nextafter(x, HUGE_VAL))
                xs.push_back(x);
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> spread(-30.0, 30.0);
    for (int i = 0; i < 200000; ++i) xs.push_back(spread(rng));
    auto bits = [](double v) {
        uint64_t b;
        std::memcpy(&b, &v, sizeof b);
        return std::isnan(v) ? uint64_t(1) : b; // any NaN is a NaN
    };
    for (double x : xs) {
        ASSERT_EQ(bits(remainderTwoPi(x)), bits(std::remainder(x, 2.0 * M_PI))) << x;
        ASSERT_EQ(bits(fmodTwoPi(x)), bits(std::fmod(x, 2.0 * M_PI))) << x;
    }
}
