/// \file sanitizer_canary_test.cpp
/// The canary of the sanitizer build (ROSY_SANITIZE / ROSY_FUZZ): each mode commits one
/// bug on purpose, and ctest passes only if the sanitizer's report for it appears
/// (tests/core/CMakeLists.txt). If the flags were silently lost, the bug goes unnoticed,
/// no report is printed and the canary test fails: an unsanitized "sanitizer" job cannot
/// pass. Not built in normal builds.
///
///   sanitizer_canary heap      reads one byte past a heap block  (AddressSanitizer)
///   sanitizer_canary overflow  overflows a signed int            (UndefinedBehaviorSanitizer)

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>

int main(int argc, char **argv) {
    const char *mode = argc > 1 ? argv[1] : "";
#ifndef ROSY_SANITIZED
    std::printf("built without ROSY_SANITIZED: the sanitizer flags are missing\n");
#endif
    if (std::strcmp(mode, "heap") == 0) {
        // volatile: the compiler may not prove the read out of bounds and drop it.
        char *volatile block = static_cast<char *>(std::malloc(16));
        std::memset(block, 1, 16);
        volatile int index = 16;
        const int value = block[index];
        std::free(block);
        std::printf("read %d past the end: no AddressSanitizer report\n", value);
        return 0;
    }
    if (std::strcmp(mode, "overflow") == 0) {
        volatile int big = INT_MAX;
        const int sum = big + 1;
        std::printf("INT_MAX + 1 = %d: no UndefinedBehaviorSanitizer report\n", sum);
        return 0;
    }
    std::fprintf(stderr, "usage: sanitizer_canary heap|overflow\n");
    return 2;
}
