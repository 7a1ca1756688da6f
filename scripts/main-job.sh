#!/usr/bin/env bash
# The main job on a fresh machine: install what is needed, build, and render
# Future Sky (configs/futuresky.yaml) from the built-in Milky Way-Andromeda
# model: a 3600x3600 dome master and a 4096x2048 Hammer-Aitoff panorama, each
# as FITS and PNG, in out/ (or $ORRERY_OUT).
#   ORRERY_BUILD=DIR  build (or bring up to date) and run DIR instead of
#                     build/: the test (tests/cli/test_main_job.sh) runs the
#                     job with the build it tests
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${ORRERY_BUILD:-$here/build}
"$here/scripts/install-deps.sh"
"$here/scripts/build.sh" "$build"
"$build/orrery" render "$here/configs/futuresky.yaml" -o "${ORRERY_OUT:-out}"
