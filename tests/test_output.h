#pragma once
/// \file test_output.h
/// Where every test program writes its files: `<build>/test-output/...`, one helper
/// for all of them.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace rosy::test {

/// `<build>/test-output/NAME` (NAME may hold `/`), created. With perTest, a sub-folder
/// named after the running test; with fresh, emptied first.
inline std::filesystem::path testOutputDir(const std::string &name, bool perTest = false, bool fresh = false) {
    std::filesystem::path dir = std::filesystem::path(ROSY_BINARY_DIR) / "test-output" / name;
    if (perTest) dir /= ::testing::UnitTest::GetInstance()->current_test_info()->name();
    if (fresh) std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace rosy::test
