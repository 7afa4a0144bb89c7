#!/usr/bin/env bash
# Shared by setup.sh / run.sh / test.sh: install missing Debian packages, configure and build.
set -euo pipefail

BSDEFORM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BSDEFORM_BUILD="${BSDEFORM_BUILD:-$BSDEFORM_ROOT/build}"

# Every package the project builds, tests or runs with (Debian bookworm names).
BSDEFORM_PACKAGES=(
  cmake g++ gcc make ccache pkg-config
  libeigen3-dev libembree-dev catch2 libbenchmark-dev
  libcoin-dev libmuparser-dev libgl-dev libegl-dev libpng-dev
  qtbase5-dev libqt5charts5-dev libqt5opengl5-dev fonts-dejavu-core
  libsoqt520-dev xvfb xauth
)

bsdeform_install_packages() {
  local missing=()
  local p
  for p in "${BSDEFORM_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "bsdeform: installing missing packages: ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  if ! $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; then
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

bsdeform_build() {
  local jobs
  jobs="$(nproc 2>/dev/null || echo 2)"
  cmake -S "$BSDEFORM_ROOT" -B "$BSDEFORM_BUILD" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$BSDEFORM_BUILD" -j "$jobs"
}
