#pragma once
/// \file memory.h
/// How much memory this process can still use, so that work which cannot fit is
/// refused before it starts (the render's estimate, cli/cmd_render.cpp) rather
/// than ending in std::bad_alloc or the kernel's OOM killer minutes later.

#include <cstdint>
#include <optional>
#include <string>

namespace rosy {

struct MemoryBudget {
    uint64_t bytes = 0;  ///< what can still be allocated
    std::string source;  ///< which limit decided, for messages ("available memory (MemAvailable + SwapFree)")
};

/// The smallest of: MemAvailable + SwapFree (/proc/meminfo); the cgroup's memory
/// limit minus its usage (v2 memory.max, v1 memory.limit_in_bytes); the address
/// space limit (ulimit -v, RLIMIT_AS) minus the current VmSize; the data segment
/// limit (RLIMIT_DATA) minus the current VmData. std::nullopt when none is known.
std::optional<MemoryBudget> availableMemory();

/// "1.5 GiB", "300 MiB": for messages.
std::string formatBytes(uint64_t bytes);

} // namespace rosy
