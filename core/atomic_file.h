#pragma once
/// \file atomic_file.h
/// How rosyhatch writes its output files, so a failed or interrupted run never
/// leaves a half-written file and never damages what the user already had.
///
/// What happens to an output path depends on what is there (resolveOutput()):
///  - nothing, or a regular file: the content goes to a temporary file in the
///    destination folder, named `.rosyhatch-XXXXXXXXXX.tmp` (ten random letters and
///    digits: short, so a destination name of up to NAME_MAX bytes still works) and
///    created with O_CREAT | O_EXCL | O_NOFOLLOW, so a link planted under that name is
///    never followed; writers reach it only through its open descriptor
///    (/proc/self/fd/N). When it is complete it is renamed over the destination. An
///    existing file keeps its permission bits and, where the system allows, its owner
///    and group. (A hard-linked destination is replaced, not written through: its
///    other names keep the old content.)
///  - a symbolic link: followed to its final target, which is then treated as
///    above (a regular target is replaced atomically, in the target's folder); a
///    link to nothing is refused;
///  - a character device or a FIFO (/dev/null, a named pipe), or a descriptor alias
///    (/dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N): written in place, never
///    replaced. The content is produced first in an anonymous temporary file in
///    $TMPDIR (or /tmp) and copied only once complete; a device that fails the copy
///    (/dev/full) is an IoError, but what was copied before the failure stays written;
///  - anything else (a folder, a block device, a socket): refused.
/// Every refusal and failure is an IoError naming the path (exit code 3). Temporary
/// files are removed on every error and, after installCleanupSignalHandlers(), on
/// SIGINT, SIGTERM, SIGHUP, SIGQUIT and SIGPIPE. A power cut is not covered: files are
/// not fsync()ed.

#include <functional>
#include <memory>
#include <string>

namespace rosy {

/// Checks before any work is done that `path` can be written as described above:
/// refused kinds, a missing or non-folder destination folder, a file name longer than
/// the file system allows, an existing file that is not writable. A temporary file
/// of the real naming scheme is created and removed where the output's temporary
/// will go (the destination folder, or $TMPDIR for in-place outputs), so read-only
/// mounts, full quotas and root's view of permissions are judged by the file system.
/// \throws IoError naming the path.
void checkWritable(const std::string &path);

/// Throws InputError (exit 2) if `output` names the same existing regular file as
/// `input` (also through links or another spelling of the path); `what` names the
/// input in the message ("input mesh"). Nothing happens when either does not exist or
/// is not a regular file (a device or pipe is not overwritten by writing to it).
void checkNotAnInput(const std::string &output, const std::string &input, const std::string &what);

/// Produces the file at `path` as described in the file comment: calls
/// write(tmpPath) to write the whole content to a temporary file (tmpPath opens
/// the safely created temporary; writers open it for writing and truncate it), then
/// moves it into place, or copies it for in-place outputs. Inside an OutputBatch the
/// move is deferred to OutputBatch::commit(). If `write` throws or anything fails,
/// the temporary is removed, `path` is left as it was and the error propagates
/// (file system failures as IoError).
void writeAtomically(const std::string &path, const std::function<void(const std::string &)> &write);

/// Writes `text` to `path` through writeAtomically().
/// \throws IoError naming the path if the file cannot be written (disk full).
void writeTextAtomically(const std::string &path, const std::string &text);

/// All outputs of one command, published together. While an OutputBatch is alive,
/// writeAtomically() writes each output to its temporary and keeps it; commit()
/// then writes the in-place outputs (devices, pipes) and renames every temporary
/// over its destination, in the order written. If anything fails before commit(),
/// or the batch is destroyed without commit(), every temporary is removed and no
/// destination is touched. The renames themselves are separate system calls: if one
/// fails (only when a folder changes under the running command), the outputs
/// renamed before it stay new and the rest stay old; an in-place output that fails
/// stops the commit before any rename. One batch at a time per process (nesting
/// defers to the outermost); not thread-safe.
class OutputBatch {
public:
    OutputBatch();
    ~OutputBatch();
    OutputBatch(const OutputBatch &) = delete;
    OutputBatch &operator=(const OutputBatch &) = delete;
    /// Publishes every output written so far. \throws IoError naming the output that failed.
    void commit();
    /// Outputs written and not yet published.
    size_t pending() const;

    struct Impl;

private:
    std::unique_ptr<Impl> m_impl;
};

/// Installs handlers that remove the temporary files of writes in progress on
/// SIGINT, SIGTERM, SIGHUP, SIGQUIT and SIGPIPE, then let the signal take its usual
/// effect (the process ends with that signal). Signals ignored when the program
/// started stay ignored. Call once, early in main().
void installCleanupSignalHandlers();

/// The prefix of every temporary output file name (for tests and documentation).
inline constexpr const char *kTemporaryPrefix = ".rosyhatch-";

} // namespace rosy
