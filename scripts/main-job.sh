#!/usr/bin/env bash
# The main job on a fresh machine: install what is needed, build, and render
# the built-in Milky Way-Andromeda scene to out/ (FITS + PNG).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
"$here/scripts/install-deps.sh"
"$here/scripts/build.sh" "$here/build"
"$here/build/orrery" render "$here/configs/first-light.yaml" -o "${ORRERY_OUT:-out}"
