#!/usr/bin/env bash
# scripts/main-job.sh, the README's main job, run as a reader runs it:
# install-deps.sh (nothing to install on a machine that runs the tests),
# build.sh on this test's own build (ORRERY_BUILD; up to date, so nothing is
# rebuilt), then Future Sky at full size into ORRERY_OUT, a temporary
# folder (never out/ in the source tree). The outputs are then read back:
# the two FITS files with astropy, the two PNGs with PIL.
#
# The job builds with scripts/build.sh's flags (RelWithDebInfo). In any
# other build (the sanitizer build is Debug) it would reconfigure and
# rebuild that build while its tests run, and the full-size render would
# take minutes under the sanitizers, so there the test skips (77): it runs
# in the release build only.
source "$(dirname "$0")/lib.sh"
build=$(dirname "$ORRERY")
cache=$build/CMakeCache.txt
if grep -q "ORRERY_SANITIZE:BOOL=ON" "$cache" || ! grep -q "^CMAKE_BUILD_TYPE:STRING=RelWithDebInfo$" "$cache"; then
  echo "main-job.sh builds with scripts/build.sh's flags (RelWithDebInfo, no sanitizers), not $build's: skipped here"
  exit 77
fi
source_out_before=$([ -e "$SRC/out" ] && echo yes || echo no)

ORRERY_BUILD=$build ORRERY_OUT=$WORK/job bash "$SRC/scripts/main-job.sh" >job.log 2>&1 ||
  { fail "main-job.sh failed: $(tail -20 job.log)"; finish; }
[ -e "$WORK/out" ] && fail "main-job.sh wrote out/ although ORRERY_OUT was set"
[ "$source_out_before" = no ] && [ -e "$SRC/out" ] && fail "main-job.sh left out/ in the source tree"

# The views of configs/futuresky.yaml: the dome master and the panorama,
# each its CIE X, Y, Z planes in FITS and its colour synthesis in PNG.
"$py" - "$WORK/job" <<'PY' || fail "main-job.sh's outputs: see above"
import sys
import numpy as np
from astropy.io import fits
from PIL import Image

out, bad = sys.argv[1], []
for view, (w, h) in (("dome", (3600, 3600)), ("panorama", (4096, 2048))):
    name = f"{out}/futuresky-{view}"
    with fits.open(name + ".fits") as f:
        data = f[0].data
        if data is None or data.shape[-2:] != (h, w):
            bad.append(f"{name}.fits: shape {None if data is None else data.shape}, expected ...x{h}x{w}")
        # NaN off the map (the dome's corners, outside the panorama's
        # ellipse: about 21 % of each); no infinity, nothing negative
        elif (np.isinf(data).any() or np.isfinite(data).mean() < 0.7 or np.nanmin(data) < 0
              or not np.nanmax(data) > 0):
            bad.append(f"{name}.fits: {np.isfinite(data).mean():.3f} of values finite, "
                       f"min {np.nanmin(data)}, max {np.nanmax(data)}")
    im = Image.open(name + ".png")
    pixels = np.asarray(im.convert("RGB"))
    if im.size != (w, h):
        bad.append(f"{name}.png: {im.size}, expected {(w, h)}")
    # a sky of stars: mostly dark, some light; neither black nor washed out
    elif not 0.5 < pixels.mean() < 128 or (pixels == 255).all(axis=2).mean() > 0.01:
        bad.append(f"{name}.png: mean {pixels.mean():.2f}, {(pixels == 255).all(axis=2).mean():.4f} of pixels white")
for b in bad:
    print(b, file=sys.stderr)
sys.exit(1 if bad else 0)
PY
finish
