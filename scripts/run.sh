#!/usr/bin/env bash
# Install what is missing, build, and run the main job.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/common.sh"
bsdeform_install_packages
bsdeform_build
exec "$BSDEFORM_BUILD/examples/bsdeform-core-demo" "$@"
