#pragma once
/// \file suggest.h
/// "Did you mean" for unknown names in scene files, style presets and --set keys:
/// the closest allowed name within a small edit distance, else the list of names.

#include <string>
#include <vector>

namespace rosy::scenes {

/// Edit distance between two strings (insertions, deletions, substitutions), for
/// did-you-mean suggestions. O(|a| |b|) time, O(|b|) memory.
int editDistance(const std::string &a, const std::string &b);

/// "did you mean 'x'?" for the candidate closest to `word` when it is within
/// max(2, |word| / 3) edits, else "expected one of: a, b, c". Ties go to the
/// first candidate in `candidates`' order.
std::string suggest(const std::string &word, const std::vector<std::string> &candidates);

/// The names separated by ", ".
std::string joinNames(const std::vector<std::string> &names);

} // namespace rosy::scenes
