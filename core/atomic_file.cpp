#include "core/atomic_file.h"

#include "core/error.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
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
}

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
