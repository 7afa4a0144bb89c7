#!/usr/bin/env bash
# Install what is missing, build, and run the main job: bsdeform-viewer on the default scene.
# Without a display, the default scene is stepped and rendered headlessly to build/default.png.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bsdeform_install_packages
bsdeform_build
if [ -n "${DISPLAY:-}" ] && [ -z "${CI:-}" ]; then
  exec "$BSDEFORM_BUILD/ui/bsdeform-viewer" "$@"
fi
echo "bsdeform: no display, rendering the default scene to $BSDEFORM_BUILD/default.png"
"$BSDEFORM_BUILD/examples/bsdeform-render" "$BSDEFORM_ROOT/scenes/region_load.iv" "$BSDEFORM_BUILD/default.png" 25
