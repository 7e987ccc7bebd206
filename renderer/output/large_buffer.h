#pragma once
/// \file large_buffer.h
/// Filling a fresh multi-megabyte per-pixel buffer with the kernel's
/// transparent huge pages.
///
/// On the development VM every first touch of a 4 KiB page costs a trap into a
/// paravirtualised kernel; a 1024² render touches about 50,000 of them in its
/// per-pixel planes. This machine's THP mode is `madvise`: memory is backed by
/// 2 MiB pages only where the program asks. assignLarge() asks, for the whole
/// 2 MiB-aligned part of the buffer, between allocating it (reserve(): no page
/// touched yet) and filling it, so one fault maps 512 pages. Values are exactly
/// those of v.assign(n, value); elsewhere, or where the kernel declines, it is
/// just that.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <sys/mman.h>

namespace rosy::renderer {

/// Asks for huge pages on the 2 MiB-aligned pages inside [data, data + bytes).
/// Advice only: never changes contents, ignores failure.
inline void adviseHugePages(void *data, size_t bytes) {
#ifdef MADV_HUGEPAGE
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) (void)madvise(reinterpret_cast<void *>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data;
    (void)bytes;
#endif
}

/// v.assign(n, value) on freshly allocated memory advised for huge pages when the
/// buffer spans at least one whole huge page (see the file comment).
template <class T, class A>
void assignLarge(std::vector<T, A> &v, size_t n, const T &value) {
    constexpr size_t kWorthIt = size_t(4) << 20;
    if (n * sizeof(T) < kWorthIt) {
        v.assign(n, value);
        return;
    }
    std::vector<T, A>().swap(v); // drop the old storage: the new block is untouched
    v.reserve(n);
    adviseHugePages(v.data(), n * sizeof(T));
    v.assign(n, value);
}

} // namespace rosy::renderer
