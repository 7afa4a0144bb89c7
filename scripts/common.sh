#!/usr/bin/env bash
# Shared by setup.sh / run.sh / test.sh: install missing Debian packages, configure and build.
set -euo pipefail

BSDEFORM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BSDEFORM_BUILD="${BSDEFORM_BUILD:-$BSDEFORM_ROOT/build}"
# The sanitizer + fuzzer build (clang) that scripts/test.sh runs the suite in a second time.
BSDEFORM_SAN_BUILD="${BSDEFORM_SAN_BUILD:-$BSDEFORM_BUILD-san}"

# Every package the project builds, tests or runs with (Debian bookworm names). clang,
# libclang-rt-14-dev (sanitizer runtimes, libFuzzer) and llvm (llvm-symbolizer for readable
# reports) are for the sanitizer build. python3-dev, python3-pivy, python3-numpy, pybind11-dev
# and swig build the Python package (docs/python.md), python3-matplotlib runs its examples,
# python3-distributed (Dask) runs bsdeform.sweep and its tests,
# dpkg-dev (dpkg-shlibdeps) lets CPack compute the Debian package's dependencies.
# libavformat-dev, libavcodec-dev and libswscale-dev (FFmpeg) write videos (MP4/H.264, WebM/VP9).
BSDEFORM_PACKAGES=(
  cmake g++ gcc make ccache pkg-config
  libeigen3-dev libembree-dev libtbb-dev libsuitesparse-dev libopenblas0-serial catch2 libbenchmark-dev
  libcoin-dev libmuparser-dev libgl-dev libegl-dev libpng-dev
  libavformat-dev libavcodec-dev libswscale-dev
  qtbase5-dev libqt5charts5-dev libqt5opengl5-dev fonts-dejavu-core
  libsoqt520-dev xvfb xauth
  clang libclang-rt-14-dev llvm
  locales
  python3-dev python3-pivy python3-numpy python3-matplotlib python3-distributed pybind11-dev swig dpkg-dev
)

# A locale with a decimal comma: the tests check that scene text does not depend on the
# process locale (SceneText_test.cpp). They say so and skip that check when it is missing.
BSDEFORM_TEST_LOCALE=de_DE.UTF-8

bsdeform_install_packages() {
  local missing=()
  local p
  for p in "${BSDEFORM_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -ne 0 ]; then
    echo "bsdeform: installing missing packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    if ! $(bsdeform_sudo) apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; then
      $(bsdeform_sudo) apt-get update -qq
      $(bsdeform_sudo) apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    fi
  fi
  bsdeform_install_test_locale
}

bsdeform_sudo() {
  if [ "$(id -u)" -ne 0 ]; then echo sudo; fi
}

# Generates $BSDEFORM_TEST_LOCALE (package locales) unless it exists; enabled in
# /etc/locale.gen too, so that a later locale-gen keeps it. Not fatal: the test that needs it
# skips with a message.
bsdeform_install_test_locale() {
  if locale -a 2>/dev/null | grep -qix "$(echo "$BSDEFORM_TEST_LOCALE" | sed 's/UTF-8/utf8/')"; then return 0; fi
  echo "bsdeform: generating the locale $BSDEFORM_TEST_LOCALE for the tests"
  if [ -f /etc/locale.gen ]; then
    $(bsdeform_sudo) sed -i "s/^# *\($BSDEFORM_TEST_LOCALE UTF-8\)/\1/" /etc/locale.gen || true
  fi
  $(bsdeform_sudo) localedef -i "${BSDEFORM_TEST_LOCALE%%.*}" -f UTF-8 "$BSDEFORM_TEST_LOCALE" ||
    echo "bsdeform: could not generate $BSDEFORM_TEST_LOCALE; the locale test will be skipped" >&2
}

bsdeform_build() {
  local jobs
  jobs="$(nproc 2>/dev/null || echo 2)"
  cmake -S "$BSDEFORM_ROOT" -B "$BSDEFORM_BUILD" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$BSDEFORM_BUILD" -j "$jobs"
}

# The whole tree with ASan + UBSan (float-cast-overflow included) and libFuzzer's coverage
# instrumentation, built by clang at -O1 with debug info; benchmarks and examples are left out
# (no test runs them).
bsdeform_build_sanitize() {
  local jobs
  jobs="$(nproc 2>/dev/null || echo 2)"
  cmake -S "$BSDEFORM_ROOT" -B "$BSDEFORM_SAN_BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DBSDEFORM_BUILD_FUZZ=ON \
    -DBSDEFORM_BUILD_TESTS=ON -DBSDEFORM_BUILD_BENCH=OFF -DBSDEFORM_BUILD_EXAMPLES=OFF "$@" >/dev/null
  cmake --build "$BSDEFORM_SAN_BUILD" -j "$jobs"
}
