#pragma once
/// \file test_support.h
/// Small things the renderer tests share: angle constants and a fresh output folder
/// (tests/test_output.h).

#include <filesystem>
#include <numbers>
#include <string>

#include "tests/test_output.h"

namespace rosy::test {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180.0;

/// An empty folder `<build>/test-output/<group>/<name>` (removed and made again).
inline std::filesystem::path freshDir(const std::string &group, const std::string &name) {
    return testOutputDir(group + "/" + name, /*perTest=*/false, /*fresh=*/true);
}

} // namespace rosy::test
