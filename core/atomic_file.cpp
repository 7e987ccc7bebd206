#include "core/atomic_file.h"

#include "core/error.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <vector>
#include <fcntl.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

namespace rosy {
namespace fs = std::filesystem;

namespace {

std::string errnoText(int err) { return std::strerror(err); }

// ---------------------------------------------------------------------------
// Names of temporary files currently on disk, for the signal handler. A fixed
// table of fixed-size slots: the handler may only read memory and call
// async-signal-safe functions (unlink, raise).
// ---------------------------------------------------------------------------

constexpr int kSlots = 64;
struct Slot {
    std::atomic<int> state{0}; ///< 0 free, 1 being filled, 2 holds a name to remove
    char path[4096];
};
Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots");

/// Registers `path` for removal on a fatal signal; -1 if the table is full (the
/// file is then still removed on every ordinary error, only not on a signal).
int registerTemporary(const std::string &path) {
    if (path.size() >= sizeof(Slot::path)) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expected = 0;
        if (g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) {
            std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
            g_slots[i].state.store(2, std::memory_order_release);
            return i;
        }
    }
    return -1;
}

void unregisterTemporary(int slot) {
    if (slot >= 0) g_slots[slot].state.store(0, std::memory_order_release);
}

void removeTemporariesAndReraise(int sig) {
    const int savedErrno = errno;
    for (Slot &s : g_slots)
        if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
    // SA_RESETHAND restored the default action; the signal is blocked while this
    // handler runs, so it takes effect (ends the process) as soon as we return.
    ::raise(sig);
    errno = savedErrno;
}

// ---------------------------------------------------------------------------
// Temporary files.
// ---------------------------------------------------------------------------

/// Ten random letters and digits (62^10 names) from the kernel's generator.
std::string randomName() {
    static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    unsigned char bytes[10];
    if (::getrandom(bytes, sizeof bytes, 0) != ssize_t(sizeof bytes)) {
        std::random_device device;
        for (unsigned char &b : bytes) b = static_cast<unsigned char>(device());
    }
    std::string name;
    for (unsigned char b : bytes) name += kAlphabet[b % 62];
    return name;
}

/// Whether writers can reach an open descriptor by path (/proc/self/fd/N).
bool haveProcFd() {
    static const bool have = ::access("/proc/self/fd", X_OK) == 0;
    return have;
}

/// The process's file creation mask, read without changing it where possible.
mode_t processUmask() {
    static const mode_t mask = [] {
        std::ifstream in("/proc/self/status");
        std::string line;
        while (std::getline(in, line))
            if (line.rfind("Umask:", 0) == 0) return mode_t(std::strtoul(line.c_str() + 6, nullptr, 8));
        const mode_t m = ::umask(022);
        ::umask(m);
        return m;
    }();
    return mask;
}

/// One temporary file: an open descriptor and, while it has one, its name.
struct TempFile {
    int fd = -1;
    std::string path; ///< empty once the name is gone (renamed or unlinked)
    int slot = -1;

    TempFile() = default;
    TempFile(const TempFile &) = delete;
    TempFile &operator=(const TempFile &) = delete;
    ~TempFile() { discard(); }

    /// Removes the name (if any) and closes the descriptor.
    void discard() {
        if (!path.empty()) ::unlink(path.c_str());
        forgetName();
        if (fd >= 0) ::close(fd);
        fd = -1;
    }
    /// The name now belongs to someone else (renamed into place) or is gone.
    void forgetName() {
        unregisterTemporary(slot);
        slot = -1;
        path.clear();
    }
    /// A path through which a writer can open this very file.
    std::string reopenPath() const {
        if (haveProcFd()) return "/proc/self/fd/" + std::to_string(fd);
        return path;
    }
};

/// Creates `dir/.rosyhatch-XXXXXXXXXX.tmp` with O_CREAT | O_EXCL | O_NOFOLLOW, mode
/// 0600 (the final mode is set before it is published). Null with `err` set on failure.
std::unique_ptr<TempFile> createTemporary(const fs::path &dirIn, int &err) {
    const fs::path dir = dirIn.empty() ? fs::path(".") : dirIn;
    for (int attempt = 0; attempt < 100; ++attempt) {
        auto t = std::make_unique<TempFile>();
        const std::string name = (dir / (std::string(kTemporaryPrefix) + randomName() + ".tmp")).string();
        // Registered before it exists: a signal right after open() must find it.
        t->slot = registerTemporary(name);
        t->fd = ::open(name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
        if (t->fd >= 0) {
            t->path = name;
            return t;
        }
        err = errno;
        t->forgetName(); // not ours: never remove it
        if (err != EEXIST) return nullptr;
    }
    return nullptr;
}

/// Where in-place outputs are staged.
fs::path stagingDir() {
    const char *tmp = std::getenv("TMPDIR");
    return tmp && *tmp ? fs::path(tmp) : fs::path("/tmp");
}

// ---------------------------------------------------------------------------
// What an output path is.
// ---------------------------------------------------------------------------

enum class OutputKind { Replace, InPlace, Refuse };

struct Resolved {
    OutputKind kind = OutputKind::Replace;
    std::string target;   ///< Replace: what to rename over; InPlace: what to open
    int fdAlias = -1;     ///< InPlace through one of our descriptors (/dev/stdout)
    bool exists = false;  ///< Replace: a regular file is there now
    struct stat st {};    ///< of that file
    std::string why;      ///< Refuse: the message
};

/// /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N -> N; else -1.
int descriptorAlias(const std::string &path) {
    if (path == "/dev/stdout") return 1;
    if (path == "/dev/stderr") return 2;
    for (const char *prefix : {"/dev/fd/", "/proc/self/fd/"}) {
        const std::string p(prefix);
        if (path.size() <= p.size() || path.compare(0, p.size(), p) != 0) continue;
        const std::string digits = path.substr(p.size());
        if (digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
            return -1;
        return std::stoi(digits);
    }
    return -1;
}

const char *kindName(mode_t mode) {
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISFIFO(mode)) return "a FIFO";
    return "not a regular file";
}

void classify(Resolved &r, const struct stat &st) {
    if (S_ISREG(st.st_mode)) {
        r.kind = OutputKind::Replace;
        r.exists = true;
        r.st = st;
    } else if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
        r.kind = OutputKind::InPlace;
    } else if (S_ISDIR(st.st_mode)) {
        r.kind = OutputKind::Refuse;
        r.why = "output path is a folder; give a file name";
    } else {
        r.kind = OutputKind::Refuse;
        r.why = std::string("output path is ") + kindName(st.st_mode) +
                "; rosyhatch writes regular files, character devices and pipes only";
    }
}

Resolved resolveOutput(const std::string &path) {
    Resolved r;
    r.target = path;
    if (const int fd = descriptorAlias(path); fd >= 0) {
        r.kind = OutputKind::InPlace;
        r.fdAlias = fd;
        const int flags = ::fcntl(fd, F_GETFL);
        if (flags < 0) {
            r.kind = OutputKind::Refuse;
            r.why = "descriptor " + std::to_string(fd) + " is not open";
        } else if ((flags & O_ACCMODE) == O_RDONLY) {
            r.kind = OutputKind::Refuse;
            r.why = "descriptor " + std::to_string(fd) + " is open only for reading";
        }
        return r;
    }
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) {
        const int err = errno;
        // A new file (or a name too long to exist): checkWritable() judges its folder and name.
        if (err == ENOENT || err == ENOTDIR || err == ENAMETOOLONG) return r;
        r.kind = OutputKind::Refuse;
        r.why = "cannot examine the output path: " + errnoText(err);
        return r;
    }
    if (S_ISLNK(st.st_mode)) {
        char *real = ::realpath(path.c_str(), nullptr);
        if (!real) {
            struct stat followed {};
            if (::stat(path.c_str(), &followed) == 0) { // a link the kernel resolves itself (a pipe of /proc)
                classify(r, followed);
                if (r.kind == OutputKind::Replace) { // no path to replace it by: write it where it is
                    r.kind = OutputKind::InPlace;
                    r.exists = false;
                }
                return r;
            }
            std::error_code ec;
            const std::string to = fs::read_symlink(path, ec).string();
            r.kind = OutputKind::Refuse;
            r.why = "output path is a link to '" + to + "', which does not exist; create the target or remove the link";
            return r;
        }
        r.target = real;
        std::free(real);
        if (::lstat(r.target.c_str(), &st) != 0) {
            r.kind = OutputKind::Refuse;
            r.why = "cannot examine the link's target '" + r.target + "': " + errnoText(errno);
            return r;
        }
    }
    classify(r, st);
    return r;
}

fs::path folderOf(const std::string &target) {
    const fs::path dir = fs::path(target).parent_path();
    return dir.empty() ? fs::path(".") : dir;
}

/// "the output folder 'x'" or, for a link, "the folder 'x' of the link's target".
std::string folderText(const std::string &path, const Resolved &r) {
    const std::string dir = folderOf(r.target).string();
    if (r.target == path) return "output folder '" + dir + "'";
    return "folder '" + dir + "' of the link's target '" + r.target + "'";
}

/// Some writers do not report a failed write, so a file cut short by a full disk or
/// by the file size limit (ulimit -f) would be published. Both leave a trace: the
/// size reached the limit, or the file system has no free block left.
void checkNotCutShort(const std::string &path, const TempFile &tmp, const fs::path &dir) {
    struct stat st {};
    if (::fstat(tmp.fd, &st) != 0) throw IoError(path, "cannot examine the written file: " + errnoText(errno));
    struct rlimit limit {};
    if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
        uint64_t(st.st_size) >= uint64_t(limit.rlim_cur))
        throw IoError(path, "write failed: the file reached the file size limit (ulimit -f) of " +
                                std::to_string(uint64_t(limit.rlim_cur)) + " bytes");
    struct statvfs vfs {};
    if (::statvfs(dir.c_str(), &vfs) == 0 && vfs.f_blocks > 0 && vfs.f_bfree == 0)
        throw IoError(path, "write failed: the disk is full");
}

/// Writes all of buf to fd (partial writes and EINTR handled); false with errno set.
bool writeAll(int fd, const char *buf, size_t n) {
    while (n > 0) {
        const ssize_t w = ::write(fd, buf, n);
        if (w < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        buf += w;
        n -= size_t(w);
    }
    return true;
}

/// Copies the staged content into a device, pipe or descriptor.
void copyInPlace(const std::string &path, const Resolved &r, int srcFd) {
    int out = r.fdAlias;
    if (out >= 0) {
        std::fflush(nullptr); // what the program printed comes first
    } else {
        out = ::open(r.target.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
        if (out < 0) throw IoError(path, "cannot open for writing: " + errnoText(errno));
    }
    std::vector<char> buffer(1 << 16);
    off_t offset = 0;
    int err = 0;
    for (;;) {
        const ssize_t n = ::pread(srcFd, buffer.data(), buffer.size(), offset);
        if (n < 0) {
            if (errno == EINTR) continue;
            err = errno;
            break;
        }
        if (n == 0) break;
        if (!writeAll(out, buffer.data(), size_t(n))) {
            err = errno;
            break;
        }
        offset += n;
    }
    if (r.fdAlias < 0 && ::close(out) != 0 && err == 0) err = errno;
    if (err) throw IoError(path, "write failed: " + errnoText(err));
}

} // namespace

// ---------------------------------------------------------------------------

struct OutputBatch::Impl {
    struct Item {
        std::string path;
        Resolved resolved;
        std::unique_ptr<TempFile> tmp;
    };
    std::vector<std::unique_ptr<Item>> items;
};

namespace {

OutputBatch *g_batch = nullptr;
OutputBatch::Impl *g_batchItems = nullptr;

using Item = OutputBatch::Impl::Item;

/// Writes the content to its temporary and makes it ready to publish.
std::unique_ptr<Item> prepare(const std::string &path, const std::function<void(const std::string &)> &write) {
    auto item = std::make_unique<Item>();
    item->path = path;
    item->resolved = resolveOutput(path);
    const Resolved &r = item->resolved;
    if (r.kind == OutputKind::Refuse) throw IoError(path, r.why);
    const fs::path dir = r.kind == OutputKind::Replace ? folderOf(r.target) : stagingDir();
    int err = 0;
    item->tmp = createTemporary(dir, err);
    if (!item->tmp)
        throw IoError(path, "cannot create a temporary file in '" + dir.string() + "': " + errnoText(err));
    TempFile &tmp = *item->tmp;
    // Staged in-place content needs no name once writers can reach the descriptor.
    if (r.kind == OutputKind::InPlace && haveProcFd()) {
        ::unlink(tmp.path.c_str());
        tmp.forgetName();
    }
    write(tmp.reopenPath()); // on an exception, ~Item removes the temporary
    checkNotCutShort(path, tmp, dir);
    if (r.kind == OutputKind::Replace) {
        // The existing file's permission bits and, where allowed, its owner and group;
        // a new file gets the usual 0666 minus the umask.
        if (r.exists) {
            if (::fchown(tmp.fd, r.st.st_uid, r.st.st_gid) != 0) (void)::fchown(tmp.fd, uid_t(-1), r.st.st_gid);
            if (::fchmod(tmp.fd, r.st.st_mode & 0777) != 0)
                throw IoError(path, "cannot give the new file the old one's permissions: " + errnoText(errno));
        } else if (::fchmod(tmp.fd, 0666 & ~processUmask()) != 0) {
            throw IoError(path, "cannot set the new file's permissions: " + errnoText(errno));
        }
        // The name must still be our file (a shared folder's other users could have
        // replaced it); otherwise the rename would publish their file.
        struct stat mine {}, named {};
        if (::fstat(tmp.fd, &mine) != 0 || ::lstat(tmp.path.c_str(), &named) != 0 || mine.st_dev != named.st_dev ||
            mine.st_ino != named.st_ino) {
            tmp.forgetName(); // whatever is there now is not ours to remove
            throw IoError(path, "the temporary file was replaced by another process; nothing was written");
        }
    }
    return item;
}

void publish(Item &item) {
    const Resolved &r = item.resolved;
    if (r.kind == OutputKind::InPlace) {
        copyInPlace(item.path, r, item.tmp->fd);
        item.tmp->discard();
        return;
    }
    if (::rename(item.tmp->path.c_str(), r.target.c_str()) != 0) {
        const int err = errno;
        throw IoError(item.path, "cannot move the finished file into place: " + errnoText(err));
    }
    item.tmp->forgetName();
    item.tmp->discard();
}

} // namespace

OutputBatch::OutputBatch() : m_impl(std::make_unique<Impl>()) {
    if (!g_batch) {
        g_batch = this;
        g_batchItems = m_impl.get();
    }
}

OutputBatch::~OutputBatch() {
    if (g_batch == this) {
        g_batch = nullptr;
        g_batchItems = nullptr;
    }
    // m_impl's items remove their temporaries.
}

size_t OutputBatch::pending() const { return m_impl->items.size(); }

void OutputBatch::commit() {
    if (g_batch != this) return; // nested: the outermost batch publishes
    std::vector<std::unique_ptr<Impl::Item>> items = std::move(m_impl->items);
    m_impl->items.clear();
    // Devices and pipes first: they cannot be taken back, and a failure there must
    // stop the run before any file is replaced.
    for (auto &item : items)
        if (item->resolved.kind == OutputKind::InPlace) publish(*item);
    for (auto &item : items)
        if (item->resolved.kind == OutputKind::Replace) publish(*item);
}

void writeAtomically(const std::string &path, const std::function<void(const std::string &)> &write) {
    std::unique_ptr<Item> item = prepare(path, write);
    if (g_batchItems) {
        g_batchItems->items.push_back(std::move(item));
        return;
    }
    publish(*item);
}

void writeTextAtomically(const std::string &path, const std::string &text) {
    writeAtomically(path, [&](const std::string &tmp) {
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
        if (fd < 0) throw IoError(path, "cannot open for writing: " + errnoText(errno));
        const bool ok = writeAll(fd, text.data(), text.size());
        const int err = errno;
        ::close(fd);
        if (!ok) throw IoError(path, "write failed: " + errnoText(err));
    });
}

void checkWritable(const std::string &path) {
    const Resolved r = resolveOutput(path);
    if (r.kind == OutputKind::Refuse) throw IoError(path, r.why);
    fs::path probeDir;
    if (r.kind == OutputKind::Replace) {
        const fs::path dir = folderOf(r.target);
        std::error_code ec;
        if (!fs::exists(dir, ec)) throw IoError(path, folderText(path, r) + " does not exist; create it first");
        if (!fs::is_directory(dir, ec)) throw IoError(path, "'" + dir.string() + "' is not a folder");
        const std::string name = fs::path(r.target).filename().string();
        const long nameMax = ::pathconf(dir.c_str(), _PC_NAME_MAX);
        if (nameMax > 0 && name.size() > size_t(nameMax))
            throw IoError(path, "the file name is " + std::to_string(name.size()) +
                                    " bytes long, more than the file system's limit of " + std::to_string(nameMax));
        if (::access(dir.c_str(), W_OK) != 0) throw IoError(path, folderText(path, r) + " is not writable");
        if (r.exists && ::access(r.target.c_str(), W_OK) != 0)
            throw IoError(path, "output file exists and is not writable");
        probeDir = dir;
    } else {
        if (r.fdAlias < 0 && ::access(r.target.c_str(), W_OK) != 0)
            throw IoError(path, std::string("cannot write to it: ") + errnoText(errno));
        probeDir = stagingDir();
    }
    // access() says yes to root everywhere and knows nothing of read-only mounts or
    // full quotas: create (and remove) a temporary named as the real one will be.
    int err = 0;
    std::unique_ptr<TempFile> probe = createTemporary(probeDir, err);
    if (!probe) {
        if (r.kind == OutputKind::Replace)
            throw IoError(path, "cannot create files in the " + folderText(path, r) + ": " + errnoText(err));
        throw IoError(path, "cannot create the temporary file for this output in '" + probeDir.string() +
                                "' (TMPDIR): " + errnoText(err));
    }
}

void checkNotAnInput(const std::string &output, const std::string &input, const std::string &what) {
    if (output.empty() || input.empty()) return;
    struct stat out {}, in {};
    if (::stat(output.c_str(), &out) != 0 || ::stat(input.c_str(), &in) != 0) return;
    if (!S_ISREG(out.st_mode) || !S_ISREG(in.st_mode)) return;
    if (out.st_dev == in.st_dev && out.st_ino == in.st_ino)
        throw InputError(FileLoc{output}, "the output would overwrite the " + what + " '" + input + "'",
                         "write the output to another file");
}

void installCleanupSignalHandlers() {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE}) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue; // keep "ignored"
        struct sigaction action {};
        action.sa_handler = removeTemporariesAndReraise;
        sigemptyset(&action.sa_mask);
        action.sa_flags = SA_RESETHAND;
        ::sigaction(sig, &action, nullptr);
    }
}

} // namespace rosy
