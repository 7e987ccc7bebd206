#pragma once
/// \file atomic_file.h
/// Output files are written to a temporary file in the destination folder and
/// renamed into place, so a failed render never leaves a half-written file and
/// never touches what the user already had.

#include <functional>
#include <string>

namespace rosy {

/// Checks before any work is done that `path` can be written: its folder exists,
/// is a folder and is writable, and `path` itself is not a folder.
/// Throws IoError naming the path otherwise.
/// Also creates and removes a probe file there, so read-only mounts and root's
/// view of permissions are judged by the file system itself.
void checkWritable(const std::string &path);

/// Throws InputError (exit 2) if `output` names the same existing file as `input`
/// (also through links or another spelling of the path); `what` names the input
/// in the message ("input mesh"). Nothing happens when either does not exist.
void checkNotAnInput(const std::string &output, const std::string &input, const std::string &what);

/// Calls write(tmpPath) to produce the file at a temporary path next to `path`,
/// then renames it over `path`. If write throws or the rename fails, the
/// temporary file is removed, `path` is left as it was, and the error propagates
/// (rename failures as IoError).
void writeAtomically(const std::string &path, const std::function<void(const std::string &)> &write);

/// Writes `text` to `path` through writeAtomically().
/// \throws IoError naming the path if the file cannot be opened or written (disk full).
void writeTextAtomically(const std::string &path, const std::string &text);

} // namespace rosy
