/// \file huge_pages.cpp
/// Compiled into every program that links `rosy_allocator` (cmake/Dependencies.cmake):
/// asks oneTBB's scalable allocator, which replaces malloc there, to back its large
/// blocks with transparent huge pages. The kernel here runs THP in `madvise` mode, so
/// without the request every field and pixel buffer is faulted in 4 KiB pages. Measured
/// with build/bench/field_bench, all benchmarks in one process (quiet machine,
/// 2026-12-01): curvature-aligned 4-RoSy 64 -> 38 ms, smoothest 137 -> 101 ms; the
/// same as TBB_MALLOC_USE_HUGE_PAGES=1 in the environment. Results are unchanged: only
/// where memory comes from changes, never a value.
#include <tbb/scalable_allocator.h>

namespace {
const int kHugePages = scalable_allocation_mode(TBBMALLOC_USE_HUGE_PAGES, 1);
} // namespace
