#!/usr/bin/env bash
# The main job on a fresh machine: install what is needed, build, and render
# Future Sky (configs/futuresky.yaml) from the built-in Milky Way-Andromeda
# model: a 3600x3600 dome master and a 4096x2048 Hammer-Aitoff panorama, each
# as FITS and PNG, in out/ (or $ORRERY_OUT).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
"$here/scripts/install-deps.sh"
"$here/scripts/build.sh" "$here/build"
"$here/build/orrery" render "$here/configs/futuresky.yaml" -o "${ORRERY_OUT:-out}"
