# Sanitizer and fuzzing builds (clang only). See tests/README.md, "Fuzzing and sanitizers".
#
#   ROSY_SANITIZE=ON  every target (libraries, tests, tools) with ASan + UBSan, aborting on
#                     the first report (-fno-sanitize-recover=all), at -O1 -gline-tables-only; defines
#                     ROSY_SANITIZED=1 so heavy tests can shrink and the canary can overflow.
#   ROSY_FUZZ=ON      builds the harnesses in tests/fuzz (linked with -fsanitize=fuzzer) and
#                     adds libFuzzer coverage instrumentation (-fsanitize=fuzzer-no-link) to
#                     the libraries they link (tests/fuzz/CMakeLists.txt), not to the test
#                     programs or the CLI. Implies the ASan + UBSan flags above.
# Both at once is one tree for CI: the test suite and the harnesses share the compiled libraries.
if(NOT (ROSY_SANITIZE OR ROSY_FUZZ))
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "ROSY_SANITIZE / ROSY_FUZZ need clang (libFuzzer and the sanitizer runtimes "
                      "come with libclang-rt-14-dev); configure with -DCMAKE_CXX_COMPILER=clang++-14")
endif()

set(ROSY_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
# Directory-level options come after CMAKE_CXX_FLAGS_<CONFIG>, so -O1 wins over Release's -O3.
# -O1 keeps the sanitized test suite fast enough; full -g would make the Eigen-heavy files
# much slower to compile and link, while line tables alone still give FILE:LINE in every
# sanitizer and libFuzzer stack trace.
add_compile_options(${ROSY_SANITIZER_FLAGS} -O1 -gline-tables-only)
add_link_options(-fsanitize=address,undefined)
add_compile_definitions(ROSY_SANITIZED=1)
message(STATUS "rosyhatch: ASan + UBSan build (ROSY_SANITIZE=${ROSY_SANITIZE}, ROSY_FUZZ=${ROSY_FUZZ})")
