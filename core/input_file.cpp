#include "core/input_file.h"

#include "core/error.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace rosy {

namespace {

const char *kindOf(mode_t mode) {
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISFIFO(mode)) return "a pipe";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

/// Closes the descriptor on every path out.
struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

} // namespace

/// stat() of `path` with checkInputPath()'s rules applied.
static struct stat statInput(const std::string &path, const InputFileRules &rules) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        const int err = errno;
        if (err == ENOENT) throw IoError(path, "no such file");
        throw IoError(path, "cannot open the " + rules.what + ": " + std::strerror(err));
    }
    if (S_ISDIR(st.st_mode)) throw IoError(path, "is a folder, not a " + rules.what);
    const bool regular = S_ISREG(st.st_mode);
    const bool stream = S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode);
    if (!regular && !(stream && rules.streams))
        throw IoError(path, std::string("is ") + kindOf(st.st_mode) + ", not a regular file; the " + rules.what +
                                " must be a file on disk");
    return st;
}

void checkInputPath(const std::string &path, const InputFileRules &rules) { statInput(path, rules); }

std::string readInputFile(const std::string &path, const InputFileRules &rules) {
    const struct stat st = statInput(path, rules);
    const bool regular = S_ISREG(st.st_mode);
    auto tooLarge = [&] {
        return InputError(FileLoc{path},
                          "the " + rules.what + " is larger than the limit of " + std::to_string(rules.maxBytes) +
                              " bytes" + (regular ? "" : " (is it an endless stream such as /dev/zero?)"),
                          "give a " + rules.what + " of at most " + std::to_string(rules.maxBytes) + " bytes");
    };
    if (regular && uint64_t(st.st_size) > uint64_t(rules.maxBytes)) throw tooLarge();
    Fd in{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY)};
    if (in.fd < 0) throw IoError(path, "cannot open the " + rules.what + " for reading: " + std::strerror(errno));
    std::string text;
    if (regular) text.reserve(size_t(st.st_size));
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(in.fd, buffer, sizeof buffer);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw IoError(path, "error while reading the " + rules.what + ": " + std::strerror(errno));
        }
        if (n == 0) break;
        // Also for regular files: one may grow while it is read.
        if (text.size() + size_t(n) > rules.maxBytes) throw tooLarge();
        text.append(buffer, size_t(n));
    }
    return text;
}

} // namespace rosy
