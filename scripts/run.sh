#!/usr/bin/env bash
# Install what is missing, build, and run the main job: the core demo table, then the default
# scene stepped and rendered headlessly to build/default.png.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bsdeform_install_packages
bsdeform_build
"$BSDEFORM_BUILD/examples/bsdeform-core-demo" "$@"
"$BSDEFORM_BUILD/examples/bsdeform-render" "$BSDEFORM_ROOT/scenes/region_load.iv" "$BSDEFORM_BUILD/default.png" 25
