#pragma once
/// \file uninitialized.h
/// A std::vector whose resize() leaves new elements of trivially default-constructible
/// types uninitialized (internal to the mesh layer and the frames). For large arrays
/// that a parallel loop fills completely right after: value-initializing them first
/// would write every byte once more on one thread, and fault the pages in there.

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace rosy::field::detail {

template <typename T>
struct UninitializedAllocator : std::allocator<T> {
    template <typename U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <typename U>
    UninitializedAllocator(const UninitializedAllocator<U> &) noexcept {}
    /// Default-initialization: no value written for doubles, ints and Eigen vectors.
    template <typename U>
    void construct(U *p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void *>(p)) U;
    }
    template <typename U, typename... Args>
    void construct(U *p, Args &&...args) {
        ::new (static_cast<void *>(p)) U(std::forward<Args>(args)...);
    }
};

/// Every element must be written before it is read.
template <typename T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

} // namespace rosy::field::detail
