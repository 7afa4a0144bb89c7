# SPDX-License-Identifier: MIT
# BSDEFORM_SANITIZE: the whole tree with AddressSanitizer (+ LeakSanitizer) and
# UndefinedBehaviorSanitizer, float-cast-overflow included (GCC's and clang's "undefined" group
# leaves it out or not depending on version, so it is named). Every report aborts the process
# (-fno-sanitize-recover=all), so a test with a finding fails. Frame pointers keep the reports'
# stacks complete. BSDEFORM_BUILD_FUZZ (clang only) builds the fuzz target in the same tree and
# gives the nodes library libFuzzer's coverage instrumentation (CMakeLists.txt), so one build
# serves the test suite and the fuzz target.

set(BSDEFORM_SANITIZER_COMPILE_FLAGS
  -fsanitize=address,undefined,float-cast-overflow
  -fno-sanitize-recover=all
  -fno-omit-frame-pointer -fno-optimize-sibling-calls)
set(BSDEFORM_SANITIZER_LINK_FLAGS -fsanitize=address,undefined)
if(BSDEFORM_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "BSDEFORM_BUILD_FUZZ needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++ "
                        "-DCMAKE_C_COMPILER=clang; this is ${CMAKE_CXX_COMPILER_ID}")
  endif()
endif()
add_compile_options(${BSDEFORM_SANITIZER_COMPILE_FLAGS})
add_link_options(${BSDEFORM_SANITIZER_LINK_FLAGS})

# The runtimes' default options, compiled into every executable of the tree (see
# bsdeform_add_sanitizer_options below), so that ctest, the programs the tests start and the fuzz
# target behave the same without any environment; ASAN_OPTIONS, UBSAN_OPTIONS and LSAN_OPTIONS
# still override them.
set(BSDEFORM_LSAN_SUPPRESSIONS ${PROJECT_SOURCE_DIR}/tests/support/lsan.supp)
configure_file(${CMAKE_CURRENT_LIST_DIR}/SanitizerOptions.cpp.in
               ${PROJECT_BINARY_DIR}/generated/SanitizerOptions.cpp @ONLY)

# Adds the options source to every executable defined in `dir` and below.
function(bsdeform_add_sanitizer_options dir)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    if(type STREQUAL "EXECUTABLE")
      target_sources(${t} PRIVATE ${PROJECT_BINARY_DIR}/generated/SanitizerOptions.cpp)
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(d IN LISTS subdirs)
    bsdeform_add_sanitizer_options(${d})
  endforeach()
endfunction()
