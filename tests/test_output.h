#pragma once
/// \file test_output.h
/// Where every test program writes its files, `<build>/test-output/...`, and the
/// whole-file reads and writes the tests make there: one helper each for all of them.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
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

/// The whole content of a file, bytes as stored ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path &p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Writes `text` to p, bytes as given.
inline void put(const std::filesystem::path &p, const std::string &text) {
    std::ofstream(p, std::ios::binary) << text;
}

} // namespace rosy::test
