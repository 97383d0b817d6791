# The checking builds (tests/README.md, "Sanitizers and fuzzing"): options, not ad-hoc flags.
#   SWARMFORM_SANITIZE  every target (ours, the generated IDL code, the test programs) built with AddressSanitizer
#                       and UndefinedBehaviorSanitizer; any UB report aborts (-fno-sanitize-recover). -g1 gives
#                       the reports file:line without the cost of full debug info. -O1 (after the build type's
#                       -O3, so it wins) halves the compile time under the sanitizers (world_server/server.cpp:
#                       48 s at -O3, 21 s at -O1) for a small cost in the tests' run time; ASan's own docs
#                       recommend -O1. scripts/test builds it in build-asan/ with clang-14 (~30 % less CPU
#                       than gcc 12 under the sanitizers; tests/README.md "Sanitizers").
#   SWARMFORM_FUZZ      the libFuzzer targets of tests/fuzz/ (clang only: libFuzzer is clang's), each also built
#                       with ASan and UBSan; scripts/test builds them in build-fuzz/ with clang-14.
option(SWARMFORM_SANITIZE "Build everything with -fsanitize=address,undefined" OFF)
option(SWARMFORM_FUZZ "Build the libFuzzer targets of tests/fuzz (needs clang)" OFF)

set(SWARMFORM_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=undefined
                              -fno-omit-frame-pointer)

if(SWARMFORM_SANITIZE)
  add_compile_options(${SWARMFORM_SANITIZER_FLAGS} -g1 -O1)
  add_link_options(-fsanitize=address,undefined)
endif()

if(SWARMFORM_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "SWARMFORM_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++-14 "
                      "-DCMAKE_C_COMPILER=clang-14 (scripts/test does, in build-fuzz/)")
endif()
