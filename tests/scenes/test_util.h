#pragma once
/// \file test_util.h
/// Message checks shared by the scene tests.

#include <gtest/gtest.h>

#include <string>

namespace rosy::test {

/// Success when `s` begins with `prefix`; the failure message shows both.
inline ::testing::AssertionResult startsWith(const std::string &s, const std::string &prefix) {
    if (s.rfind(prefix, 0) == 0) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "'" << s << "' does not start with '" << prefix << "'";
}

inline bool contains(const std::string &s, const std::string &part) { return s.find(part) != std::string::npos; }

} // namespace rosy::test
