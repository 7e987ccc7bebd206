#include "core/pixel_array.h"

#include <cstdint>
#include <new>

#include <sys/mman.h>

namespace rosy {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
} // namespace

void adviseHugePages(void *data, std::size_t bytes) noexcept {
#ifdef MADV_HUGEPAGE
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(data) + kHugePage - 1) & ~(kHugePage - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHugePage - 1);
    if (end > begin) (void)madvise(reinterpret_cast<void *>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data;
    (void)bytes;
#endif
}

void *allocatePixelMemory(std::size_t bytes, std::size_t &mapped) {
    mapped = 0;
    if (bytes == 0) return nullptr;
    if (bytes > SIZE_MAX - 2 * kHugePage) throw std::bad_alloc();
    // Whole huge pages, placed on a 2 MiB boundary: map one page more, then give back
    // the unaligned head and the tail.
    const std::size_t size = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    const std::size_t over = size + kHugePage;
    void *raw = mmap(nullptr, over, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto base = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (base + kHugePage - 1) / kHugePage * kHugePage;
    if (aligned > base) munmap(raw, aligned - base);
    const std::uintptr_t end = base + over, used = aligned + size;
    if (end > used) munmap(reinterpret_cast<void *>(used), end - used);
    void *p = reinterpret_cast<void *>(aligned);
    adviseHugePages(p, size); // advice only: ordinary pages where THP is off
    mapped = size;
    return p;
}

void releasePixelMemory(void *p, std::size_t mapped) noexcept {
    if (p && mapped) munmap(p, mapped);
}

} // namespace rosy
