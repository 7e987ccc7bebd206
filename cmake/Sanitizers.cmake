# Sanitizer and fuzzing builds (clang only). See tests/README.md, "Fuzzing and sanitizers".
#
#   ROSY_SANITIZE=ON  every target (libraries, tests, tools) with ASan + UBSan, aborting on
#                     the first report (-fno-sanitize-recover=all), at -O1 -g; defines
#                     ROSY_SANITIZED=1 so heavy tests can shrink and the canary can overflow.
#   ROSY_FUZZ=ON      adds libFuzzer coverage instrumentation (-fsanitize=fuzzer-no-link) to
#                     every target and builds the harnesses in tests/fuzz (linked with
#                     -fsanitize=fuzzer). Implies the ASan + UBSan flags above.
# Both at once is one tree for CI: the test suite and the harnesses share the compiled libraries.
if(NOT (ROSY_SANITIZE OR ROSY_FUZZ))
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "ROSY_SANITIZE / ROSY_FUZZ need clang (libFuzzer and the sanitizer runtimes "
                      "come with libclang-rt-14-dev); configure with -DCMAKE_CXX_COMPILER=clang++-14")
endif()

set(ROSY_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
if(ROSY_FUZZ)
  list(APPEND ROSY_SANITIZER_FLAGS -fsanitize=fuzzer-no-link)
endif()
# Directory-level options come after CMAKE_CXX_FLAGS_<CONFIG>, so -O1 wins over Release's -O3:
# fast enough for the test suite, still precise stack traces.
add_compile_options(${ROSY_SANITIZER_FLAGS} -O1 -g)
add_link_options(-fsanitize=address,undefined)
add_compile_definitions(ROSY_SANITIZED=1)
message(STATUS "rosyhatch: ASan + UBSan build (ROSY_SANITIZE=${ROSY_SANITIZE}, ROSY_FUZZ=${ROSY_FUZZ})")
