# Every external dependency is found here, from Debian bookworm's packages.
# Nothing is downloaded at configure time.
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)
find_package(OpenMesh REQUIRED)
find_package(embree 3 REQUIRED)
find_package(OpenEXR REQUIRED)
find_package(OpenImageIO REQUIRED)
# 8-bit PNG without the OpenImageIO module (renderer/output/png_write.h).
find_package(PNG REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
# SuiteSparse 5 (CHOLMOD, UMFPACK) ships no CMake config on bookworm.
find_path(SUITESPARSE_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(UMFPACK_LIBRARY umfpack REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
add_library(rosy_suitesparse INTERFACE)
target_include_directories(rosy_suitesparse SYSTEM INTERFACE ${SUITESPARSE_INCLUDE_DIR})
target_link_libraries(rosy_suitesparse INTERFACE ${CHOLMOD_LIBRARY} ${UMFPACK_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})

# rosyhatch studio: Debian's cpp-httplib is a compiled library whose pkg-config file
# carries the feature macros it was built with (they change its classes' layout).
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
# The studio's request bodies, and the tests reading the JSON the programs write.
find_package(nlohmann_json 3 REQUIRED)

if(ROSY_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(ROSY_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

# Debian's OpenImageIO target lists /usr/include/opencv4, which does not exist
# unless OpenCV is installed; CMake then refuses to use the target. Drop it.
foreach(_oiio_target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  if(TARGET ${_oiio_target})
    get_target_property(_dirs ${_oiio_target} INTERFACE_INCLUDE_DIRECTORIES)
    if(_dirs)
      list(FILTER _dirs EXCLUDE REGEX "opencv4")
      set_target_properties(${_oiio_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_dirs}")
    endif()
  endif()
endforeach()

# The programs (CLI and benchmarks) replace malloc with oneTBB's scalable
# allocator. glibc returns freed multi-megabyte buffers to the kernel and the
# next stage faults every page in again; on bunny00 that made curvature 79 ms
# instead of 16 and the aligned field solve 216 ms instead of 97 (README,
# "Benchmarks"). Results are unchanged: the allocator never touches values.
# Not with the sanitizers (ASan brings its own allocator) and not in the test
# programs (valgrind and heaptrack then see glibc's malloc as usual).
add_library(rosy_allocator INTERFACE)
if(NOT (ROSY_SANITIZE OR ROSY_FUZZ))
  # --no-as-needed: the proxy is used through symbol interposition only.
  target_link_options(rosy_allocator INTERFACE "LINKER:--no-as-needed")
  target_link_libraries(rosy_allocator INTERFACE TBB::tbbmalloc_proxy TBB::tbbmalloc)
  # Huge pages for the allocator's large blocks (see the file).
  target_sources(rosy_allocator INTERFACE ${PROJECT_SOURCE_DIR}/core/huge_pages.cpp)
endif()
