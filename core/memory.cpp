#include "core/memory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/resource.h>

namespace rosy {
namespace {

/// The value of `key:` (in kB) in a /proc status-style file, or -1.
long long kilobytesOf(const char *file, const std::string &key) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key + ":", 0) == 0) {
            long long kb = -1;
            std::istringstream(line.substr(key.size() + 1)) >> kb;
            return kb;
        }
    return -1;
}

/// One number from a cgroup file ("max" and absurd values mean no limit): -1 if none.
long long cgroupNumber(const std::string &file) {
    std::ifstream in(file);
    std::string word;
    if (!(in >> word) || word == "max") return -1;
    try {
        const long long v = std::stoll(word);
        return v <= 0 || v >= (1LL << 60) ? -1 : v;
    } catch (const std::exception &) {
        return -1;
    }
}

void consider(std::optional<MemoryBudget> &best, long long bytes, const std::string &source) {
    if (bytes < 0) return;
    if (!best || uint64_t(bytes) < best->bytes) best = MemoryBudget{uint64_t(bytes), source};
}

} // namespace

std::optional<MemoryBudget> availableMemory() {
    std::optional<MemoryBudget> best;
    const long long avail = kilobytesOf("/proc/meminfo", "MemAvailable");
    const long long swap = kilobytesOf("/proc/meminfo", "SwapFree");
    if (avail >= 0) consider(best, 1024 * (avail + std::max(0LL, swap)), "the available memory (MemAvailable + SwapFree)");

    // cgroup v2: this process's group from /proc/self/cgroup ("0::/path").
    std::ifstream cg("/proc/self/cgroup");
    std::string line;
    while (std::getline(cg, line))
        if (line.rfind("0::", 0) == 0) {
            const std::string dir = "/sys/fs/cgroup" + line.substr(3);
            const long long max = cgroupNumber(dir + "/memory.max"), used = cgroupNumber(dir + "/memory.current");
            if (max > 0) consider(best, std::max(0LL, max - std::max(0LL, used)), "the cgroup's memory limit");
        }
    // cgroup v1, as a container sees its own group.
    const long long max1 = cgroupNumber("/sys/fs/cgroup/memory/memory.limit_in_bytes");
    const long long used1 = cgroupNumber("/sys/fs/cgroup/memory/memory.usage_in_bytes");
    if (max1 > 0) consider(best, std::max(0LL, max1 - std::max(0LL, used1)), "the cgroup's memory limit");

    struct rlimit limit {};
    if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
        const long long used = 1024 * std::max(0LL, kilobytesOf("/proc/self/status", "VmSize"));
        consider(best, std::max(0LL, (long long)limit.rlim_cur - used), "the address space limit (ulimit -v)");
    }
    if (::getrlimit(RLIMIT_DATA, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
        const long long used = 1024 * std::max(0LL, kilobytesOf("/proc/self/status", "VmData"));
        consider(best, std::max(0LL, (long long)limit.rlim_cur - used), "the data size limit (ulimit -d)");
    }
    return best;
}

std::string formatBytes(uint64_t bytes) {
    char buf[32];
    const double b = double(bytes);
    if (b >= 1024.0 * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.1f GiB", b / (1024.0 * 1024 * 1024));
    else if (b >= 1024.0 * 1024) std::snprintf(buf, sizeof buf, "%.0f MiB", b / (1024.0 * 1024));
    else std::snprintf(buf, sizeof buf, "%.0f KiB", b / 1024.0);
    return buf;
}

} // namespace rosy
