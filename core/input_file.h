#pragma once
/// \file input_file.h
/// Reading a whole input file with a bound, so an endless stream (/dev/zero,
/// `yes | rosyhatch render /dev/stdin`, a link to a device) ends in a clear error
/// instead of filling memory.

#include <cstddef>
#include <string>

namespace rosy {

struct InputFileRules {
    /// Names the file in messages: "scene file", "style preset file", "mesh file".
    std::string what;
    /// Largest content accepted; more is an InputError (exit 2) naming the limit.
    size_t maxBytes = 0;
    /// Whether pipes and character devices (/dev/stdin) may be read; their size is
    /// unknown, so they are read through the same bound. When false they are an
    /// IoError (exit 3): readers that check header counts against the file size need
    /// a regular file.
    bool streams = false;
};

/// The checks readInputFile() makes before reading (links followed): that `path`
/// exists and is a regular file, or a stream when rules.streams.
/// \throws IoError: no such file, a folder, another kind of file than the rules allow.
void checkInputPath(const std::string &path, const InputFileRules &rules);

/// The whole content of `path` (links followed).
/// \throws IoError: no such file, a folder, another kind of file than the rules
///   allow, unreadable; InputError: more than rules.maxBytes.
std::string readInputFile(const std::string &path, const InputFileRules &rules);

} // namespace rosy
