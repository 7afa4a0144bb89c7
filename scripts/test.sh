#!/usr/bin/env bash
# Install what is missing, build, and run every test (CTest).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bsdeform_install_packages
bsdeform_build -DBSDEFORM_BUILD_TESTS=ON
cd "$BSDEFORM_BUILD"
# The soak test (label soak) runs for minutes: `cd build && ctest -L soak`.
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" -LE soak "$@"
