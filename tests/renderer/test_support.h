#pragma once
/// \file test_support.h
/// Small things the renderer tests share: angle constants and a fresh output folder.

#include <filesystem>
#include <numbers>
#include <string>

namespace rosy::test {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180.0;

/// An empty folder `<build>/test-output/<group>/<name>` (removed and made again).
inline std::filesystem::path freshDir(const std::string &group, const std::string &name) {
    const std::filesystem::path dir = std::filesystem::path(ROSY_BINARY_DIR) / "test-output" / group / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace rosy::test
