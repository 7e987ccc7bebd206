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
/// just that. Maps that a parallel loop writes in full can skip the fill as well:
/// core/pixel_array.h's PixelArray.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/pixel_array.h" // adviseHugePages()

namespace rosy::renderer {

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
    rosy::adviseHugePages(v.data(), n * sizeof(T));
    v.assign(n, value);
}

} // namespace rosy::renderer
