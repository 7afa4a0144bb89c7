#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and builds and runs tests/consumer against it.
set -euo pipefail
build="$1"; src="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
# The tree's compiler: a sanitizer build's library needs that compiler's sanitizer runtimes.
cxx="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")"
cmake -S "$src/tests/consumer" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" ${cxx:+-DCMAKE_CXX_COMPILER="$cxx"} >/dev/null
cmake --build "$work/build" >/dev/null
# The consumer is not one of our executables, which carry the leak suppressions built in
# (cmake/SanitizerOptions.cpp.in); without a sanitizer the variable is ignored.
LSAN_OPTIONS="suppressions=$src/tests/support/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
  LD_LIBRARY_PATH="$work/prefix/lib" "$work/build/consumer"
