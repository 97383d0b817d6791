# Precompiled headers (SWARMFORM_PCH, on by default with clang, below): two headers, each compiled once per build by an owner
# target of one empty source, and reused (REUSE_FROM) by every target of its kind:
#   swarmform_pch_tests  the GoogleTest programs (and libraries) of tests/: gtest, nlohmann/json, the standard headers
#   swarmform_pch_code   our other C++ targets (libraries, programs, benchmarks): nlohmann/json, the standard headers
# Why: CI's two builds are most of its CPU (tests/README.md "Time budget"), and every translation unit parses
# the same standard, gtest and json headers again. The figures, clean builds before/after, are in that section.
# What is left without it, on purpose:
#   - the behaviour API (swarmform_behaviour, installed and exported to plug-ins), the registry beside it, and the
#     example plug-ins and their tests: a user's plug-in builds against those headers with no forced includes,
#     so they are compiled as the user compiles them (a header missing an #include fails here, not at the user's);
#   - position-independent targets (a PCH is valid for one code model), C sources (the generated IDL code), a
#     target of another C++ standard (the viewer's web server), and the fuzz targets (-fsanitize=fuzzer).
# The owners carry no definitions of their own: GCC refuses a PCH made with a macro (or a C++ standard) its user
# lacks, while a user's extra macros (SWARMFORM_REPO_DIR, DDS_NDEBUG...) are fine for both compilers as long as
# the headers below do not read them. CMake passes GCC -Winvalid-pch, which -Werror turns into an error: a target
# that stops matching its owner fails the build rather than silently parsing the headers again.
# On by default with clang only. Measured per translation unit with scripts/compile-cpu (same files, a clean build
# before and after, 2026-12-07): clang-14 under the sanitizers (scripts/test's build-asan/) spent ~35 % less CPU
# per file using it; GCC 12 at -O3 (the Release build) gained nothing on the test files (-12 %, as much as files
# without a PCH moved between the two builds) and lost 17 % on the others: loading its ~100 MB .gch costs a small
# file more than parsing the few headers it needs. tests/README.md "Time budget" has the figures.
if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  set(_sf_pch_default ON)
else()
  set(_sf_pch_default OFF)
endif()
option(SWARMFORM_PCH "Compile the common headers once (precompiled headers) for our non-exported targets"
       ${_sf_pch_default})

set(SWARMFORM_PCH_STD_HEADERS
    <algorithm> <array> <chrono> <cmath> <cstddef> <cstdint> <cstdio> <cstring> <filesystem> <fstream>
    <functional> <iostream> <limits> <map> <memory> <numbers> <optional> <random> <set> <span> <sstream>
    <stdexcept> <string> <string_view> <unordered_map> <utility> <vector>)

# The CMake targets defined in <dir> and the folders under it.
function(_swarmform_targets_under dir out)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    _swarmform_targets_under("${sub}" more)
    list(APPEND targets ${more})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

# swarmform_apply_pch(<folder>...): called once, after every folder is added; each C++ target of those folders
# that is neither position-independent nor of C sources reuses the tests' header if it links GoogleTest, else
# the code's.
function(swarmform_apply_pch)
  if(NOT SWARMFORM_PCH)
    return()
  endif()
  set(_anchor ${SWARMFORM_ROOT}/cmake/pch/anchor.cpp)
  add_library(swarmform_pch_code STATIC EXCLUDE_FROM_ALL ${_anchor})
  target_link_libraries(swarmform_pch_code PRIVATE nlohmann_json::nlohmann_json)
  target_precompile_headers(swarmform_pch_code PRIVATE ${SWARMFORM_PCH_STD_HEADERS} <nlohmann/json.hpp>)
  swarmform_target_warnings(swarmform_pch_code)
  if(TARGET GTest::gtest)  # not found without SWARMFORM_BUILD_TESTS (the fuzz build)
    add_library(swarmform_pch_tests STATIC EXCLUDE_FROM_ALL ${_anchor})
    target_link_libraries(swarmform_pch_tests PRIVATE GTest::gtest nlohmann_json::nlohmann_json)
    target_precompile_headers(swarmform_pch_tests PRIVATE ${SWARMFORM_PCH_STD_HEADERS} <nlohmann/json.hpp>
                                                          <gtest/gtest.h>)
    swarmform_target_warnings(swarmform_pch_tests)
  endif()

  set(_targets)
  foreach(dir IN LISTS ARGN)
    _swarmform_targets_under("${dir}" more)
    list(APPEND _targets ${more})
  endforeach()
  foreach(t IN LISTS _targets)
    get_target_property(type ${t} TYPE)
    if(NOT type MATCHES "^(EXECUTABLE|STATIC_LIBRARY)$" OR t MATCHES "^swarmform_pch_")
      continue()
    endif()
    get_target_property(pic ${t} POSITION_INDEPENDENT_CODE)
    get_target_property(sources ${t} SOURCES)
    list(FILTER sources INCLUDE REGEX "\\.(cpp|cc)$")
    get_target_property(srcdir ${t} SOURCE_DIR)
    if(srcdir MATCHES "^${SWARMFORM_ROOT}/examples/" OR sources MATCHES "${SWARMFORM_ROOT}/examples/")
      continue()  # an example is compiled as its user compiles it (examples/ci's test, added from tests/)
    endif()
    get_target_property(std ${t} CXX_STANDARD)
    if(pic OR NOT sources OR (std AND NOT std EQUAL CMAKE_CXX_STANDARD))
      continue()  # (the viewer's web server is C++17: websocketpp)
    endif()
    get_target_property(libs ${t} LINK_LIBRARIES)
    if(libs MATCHES "GTest::" AND TARGET swarmform_pch_tests)
      target_precompile_headers(${t} REUSE_FROM swarmform_pch_tests)
    else()
      target_precompile_headers(${t} REUSE_FROM swarmform_pch_code)
    endif()
  endforeach()
endfunction()
