#!/usr/bin/env bash
# Renders every scene in configs/ at a small size with two orrery binaries
# and compares the FITS files they write: the data of every HDU bit for bit,
# and every header card except the ones that name the run (DATE, the
# checksums, orrery's version and timings). For a refactoring that must
# change no image (docs/architecture.md):
#
#   scripts/compare_builds.sh [--only NAME[,NAME...]] OLD_BUILD/orrery NEW_BUILD/orrery [WORK_DIR]
#
# --only renders just the named scenes (configs/NAME.yaml, from the list
# below). It prints one line per scene and exits 0 when every output is
# identical, 1 when any differs or a build fails to render, 2 on bad
# arguments. tests/cli/test_compare_builds.sh runs it on one small scene.
#
# The in-situ scenes (*-insitu.yaml) need a simulation and are left out; the
# snapshot-sequence scenes render from a small built-in model written as
# snapshots first.
set -euo pipefail
usage="usage: compare_builds.sh [--only NAME[,NAME...]] OLD_ORRERY NEW_ORRERY [WORK_DIR]"
only=
if [ "${1:-}" = --only ]; then
  only=${2:?$usage}
  shift 2
fi
[ $# -ge 2 ] && [ $# -le 3 ] || { echo "$usage" >&2; exit 2; }
old=$1 new=$2
here=$(cd "$(dirname "$0")/.." && pwd)
work=${3:-$(mktemp -d)}
mkdir -p "$work"
cd "$work"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

small="--set input.model.particles=20000"
declare -A extra=(
  [anaglyph-orbit]="$small --set image.width=160 --set image.height=90 --frames 3"
  [dark-universe]="--set input.file=$work/box.hdf5 --set image.width=128 --set image.height=72 --frames 2"
  [first-light]="--set image.width=128 --set image.height=128"
  [futuresky]="$small --set views.dome.image.width=128 --set views.dome.image.height=128 --set views.panorama.image.width=128 --set views.panorama.image.height=64"
  [nightfall]="--set image.width=120 --set image.height=68 --frames 2"
  [spiral-metamorphosis]="$small --set image.width=128 --set image.height=128"
  [spiral-metamorphosis-anaglyph]="$small --set image.width=160 --set image.height=90"
  [text-table-perspective]="--set image.width=128 --set image.height=96"
)
names=$(printf '%s\n' "${!extra[@]}" | sort | tr '\n' ' ')
if [ -n "$only" ]; then
  for name in ${only//,/ }; do
    [ -n "${extra[$name]+set}" ] || { echo "compare_builds.sh: --only: no scene '$name' (one of: $names)" >&2; exit 2; }
  done
  names=${only//,/ }
fi
# The dark-universe scene renders an evolved box, made once by the new build.
for name in $names; do
  if [ "$name" = dark-universe ]; then
    "$new" ics --zeldovich --grid 16 --box 100 --evolve --pm-steps 5 -o box.hdf5 >/dev/null
  fi
done
status=0
for name in $names; do
  scene=$here/configs/$name.yaml
  [ -f "$scene" ] || continue
  for side in old new; do
    bin=$old; [ $side = new ] && bin=$new
    rm -rf "$side-$name"
    # shellcheck disable=SC2086
    "$bin" render "$scene" -o "$side-$name" -q ${extra[$name]} 2>"$side-$name.err" ||
      { echo "$name: $side build failed: $(cat "$side-$name.err")"; status=1; continue 2; }
  done
  "$py" - "old-$name" "new-$name" <<'PY' || status=1
import glob, os, sys
import numpy as np
from astropy.io import fits
old, new = sys.argv[1:3]
IGNORE = {"DATE", "CHECKSUM", "DATASUM", "ORRVER", "CREATOR"}
files = sorted(os.path.relpath(p, old) for p in glob.glob(os.path.join(old, "**", "*.fits"), recursive=True))
bad = []
if not files:
    bad.append("no FITS files")
for f in files:
    b = os.path.join(new, f)
    if not os.path.exists(b):
        bad.append(f"{f}: missing from the new build's outputs")
        continue
    with fits.open(os.path.join(old, f)) as fa, fits.open(b) as fb:
        ha, hb = list(fa), list(fb)
        # The scene's text (docs/output.md#the-scene-in-the-file) is compared
        # when both builds write it; a build from before it has none.
        if (ha[-1].name == "SCENE") != (hb[-1].name == "SCENE"):
            ha, hb = [h for h in ha if h.name != "SCENE"], [h for h in hb if h.name != "SCENE"]
        if len(ha) != len(hb):
            bad.append(f"{f}: {len(ha)} HDUs against {len(hb)}")
            continue
        for i, (x, y) in enumerate(zip(ha, hb)):
            if x.data is not None or y.data is not None:
                if x.data is None or y.data is None or x.data.tobytes() != y.data.tobytes():
                    bad.append(f"{f}[{i}]: data differ")
            cx = {k: v for k, v in x.header.items() if k not in IGNORE}
            cy = {k: v for k, v in y.header.items() if k not in IGNORE}
            for k in sorted(set(cx) | set(cy)):
                if cx.get(k) != cy.get(k):
                    bad.append(f"{f}[{i}]: {k} = {cx.get(k)!r} against {cy.get(k)!r}")
name = os.path.basename(old)[4:]
print(f"{name}: {len(files)} FITS file(s), " + ("identical" if not bad else f"{len(bad)} difference(s)"))
for b in bad[:10]:
    print("   ", b)
sys.exit(1 if bad else 0)
PY
done
[ $status = 0 ] && echo "compare_builds: every configuration's FITS output is identical"
exit $status
