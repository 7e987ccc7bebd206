#pragma once
/// \file pixel_array.h
/// PixelArray<T>: a fixed-size, zero-filled array for large per-pixel maps that are
/// read at random (the hatching tracer's spacing and cross-weight maps). Its memory
/// comes straight from the kernel: it starts zeroed without a serial fill pass, and it
/// is advised for transparent huge pages (the kernel here runs THP in `madvise` mode),
/// so an 8 MiB map is faulted in as four 2 MiB pages instead of 2048 small ones and the
/// tracer's scattered reads miss the TLB less. Where huge pages are not available the
/// advice is ignored and the memory is ordinary pages; values are never affected.

#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>

namespace rosy {

/// Asks for huge pages on the 2 MiB-aligned pages inside [data, data + bytes).
/// Advice only: never changes contents, ignores failure. (Also used for std::vector
/// buffers: renderer/output/large_buffer.h's assignLarge().)
void adviseHugePages(void *data, std::size_t bytes) noexcept;

/// Zeroed memory of at least `bytes` bytes, aligned to 2 MiB and advised for huge
/// pages; `mapped` receives what must be passed to releasePixelMemory(). Throws
/// std::bad_alloc when the memory cannot be had. bytes == 0 gives nullptr.
void *allocatePixelMemory(std::size_t bytes, std::size_t &mapped);
void releasePixelMemory(void *p, std::size_t mapped) noexcept;

template <typename T> class PixelArray {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                  "PixelArray holds plain values: it is zero-filled, never constructed");

public:
    PixelArray() = default;
    explicit PixelArray(std::size_t n) : m_size(n) {
        if (n > SIZE_MAX / sizeof(T)) throw std::bad_alloc();
        m_data = static_cast<T *>(allocatePixelMemory(n * sizeof(T), m_mapped));
    }
    PixelArray(PixelArray &&o) noexcept { swap(o); }
    PixelArray &operator=(PixelArray &&o) noexcept {
        PixelArray(std::move(o)).swap(*this);
        return *this;
    }
    PixelArray(const PixelArray &) = delete;
    PixelArray &operator=(const PixelArray &) = delete;
    ~PixelArray() { releasePixelMemory(m_data, m_mapped); }

    T &operator[](std::size_t i) { return m_data[i]; }
    const T &operator[](std::size_t i) const { return m_data[i]; }
    T *data() { return m_data; }
    const T *data() const { return m_data; }
    std::size_t size() const { return m_size; }
    bool empty() const { return m_size == 0; }

private:
    void swap(PixelArray &o) noexcept {
        std::swap(m_data, o.m_data);
        std::swap(m_size, o.m_size);
        std::swap(m_mapped, o.m_mapped);
    }
    T *m_data = nullptr;
    std::size_t m_size = 0;
    std::size_t m_mapped = 0;
};

} // namespace rosy
