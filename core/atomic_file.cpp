#include "core/atomic_file.h"

#include "core/error.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

namespace rosy {
namespace fs = std::filesystem;

void checkWritable(const std::string &path) {
    fs::path p(path);
    fs::path dir = p.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::exists(dir, ec))
        throw IoError(path, "output folder '" + dir.string() + "' does not exist; create it first");
    if (!fs::is_directory(dir, ec))
        throw IoError(path, "'" + dir.string() + "' is not a folder");
    if (fs::is_directory(p, ec)) throw IoError(path, "output path is a folder; give a file name");
    if (access(dir.c_str(), W_OK) != 0)
        throw IoError(path, "output folder '" + dir.string() + "' is not writable");
    if (fs::exists(p, ec) && access(p.c_str(), W_OK) != 0)
        throw IoError(path, "output file exists and is not writable");
    // access() says yes to root everywhere and knows nothing of read-only mounts
    // or full quotas: create (and remove) a probe file where the output will go.
    std::ostringstream probeName;
    probeName << ".rosyhatch-probe-" << getpid() << "-" << std::hash<std::string>{}(path);
    const fs::path probe = dir / probeName.str();
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) {
        const int err = errno;
        if (err != EEXIST)
            throw IoError(path, "cannot create files in the output folder '" + dir.string() +
                                    "': " + std::strerror(err));
    } else {
        ::close(fd);
        ::unlink(probe.c_str());
    }
}

void checkNotAnInput(const std::string &output, const std::string &input, const std::string &what) {
    std::error_code ec;
    if (output.empty() || input.empty() || !fs::exists(output, ec) || !fs::exists(input, ec)) return;
    if (fs::equivalent(output, input, ec) && !ec)
        throw InputError(FileLoc{output},
                         "the output would overwrite the " + what + " '" + input + "'",
                         "write the output to another file");
}

namespace {

/// Some writers (OpenImageIO's PNG among them) do not report a failed write, so
/// a file cut short by a full disk or by the file size limit (ulimit -f) would
/// be renamed into place. Both leave a trace: the size equals the limit, or the
/// file system has no free block left.
void checkNotCutShort(const std::string &path, const fs::path &tmp) {
    struct stat st {};
    if (::stat(tmp.c_str(), &st) != 0) throw IoError(path, "the written file vanished before it was moved into place");
    struct rlimit limit {};
    if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
        uint64_t(st.st_size) >= uint64_t(limit.rlim_cur))
        throw IoError(path, "write failed: the file reached the file size limit (ulimit -f) of " +
                                std::to_string(uint64_t(limit.rlim_cur)) + " bytes");
    struct statvfs vfs {};
    const fs::path dir = tmp.parent_path().empty() ? fs::path(".") : tmp.parent_path();
    if (::statvfs(dir.c_str(), &vfs) == 0 && vfs.f_blocks > 0 && vfs.f_bfree == 0)
        throw IoError(path, "write failed: the disk is full");
}

} // namespace

void writeAtomically(const std::string &path, const std::function<void(const std::string &)> &write) {
    static std::atomic<int> counter{0};
    fs::path p(path);
    // Keep the extension last: image writers choose the format from it. (A stream,
    // not an operator+ chain: GCC 12 reports a false -Wrestrict on the latter.)
    std::ostringstream tmpName;
    tmpName << "." << p.stem().string() << ".tmp" << getpid() << "-" << counter++ << p.extension().string();
    fs::path tmp = p.parent_path() / tmpName.str();
    try {
        write(tmp.string());
        checkNotCutShort(path, tmp);
    } catch (...) {
        std::error_code ec;
        fs::remove(tmp, ec);
        throw;
    }
    if (std::rename(tmp.c_str(), p.c_str()) != 0) {
        int err = errno;
        std::error_code ec;
        fs::remove(tmp, ec);
        throw IoError(path, std::string("cannot move the finished file into place: ") + std::strerror(err));
    }
}

void writeTextAtomically(const std::string &path, const std::string &text) {
    writeAtomically(path, [&](const std::string &tmp) {
        std::ofstream os(tmp, std::ios::binary);
        if (!os) throw IoError(path, "cannot open for writing");
        os << text;
        if (!os.flush()) throw IoError(path, "write failed (disk full?)");
    });
}

} // namespace rosy
