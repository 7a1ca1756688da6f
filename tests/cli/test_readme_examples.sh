# The README's and the gallery's example commands, as written, at a tiny
# size (tests/cli/readme_examples.py adds the overrides): each runs, and
# each picture it writes is neither blank nor saturated: at least 1 % of
# its pixels lit (some channel at 16/255 or more) and at most 99 % white
# (every channel at 250 or more). (Not "at most 99 % lit": a full-sky
# equirectangular panorama has starlight in every pixel.) Run in a copy
# of configs/, examples/ and domes/, so out/ is this test's own.
source "$(dirname "$0")/lib.sh"
cp -r "$SRC/configs" "$SRC/examples" "$SRC/domes" .
mkdir -p build && ln -s "$ORRERY" build/orrery
"$py" "$SRC/tests/cli/readme_examples.py" "$SRC" >commands.txt || fail "reading the docs' commands"
[ "$(wc -l <commands.txt)" -ge 10 ] || fail "only $(wc -l <commands.txt) commands found in the docs"
n=0
while IFS=$'\t' read -r doc cmd; do
  n=$((n + 1))
  touch stamp$n
  before=$(date +%s%N)
  if ! eval "$cmd" >run$n.out 2>run$n.err; then
    fail "$doc: $cmd: $(tail -3 run$n.err)"
    continue
  fi
  echo "$doc ($((($(date +%s%N) - before) / 1000000)) ms): $cmd"
  case "$cmd" in *" ics "*) [ -s out/dark-universe-box.hdf5 ] || fail "$doc: $cmd: no box"; continue ;; esac
  # the pictures it wrote: PNGs newer than the stamp (a frame run names its own)
  pngs=$(find . \( -path ./configs -o -path ./examples -o -path ./domes \) -prune -o -name '*.png' -newer stamp$n -print)
  [ -n "$pngs" ] || { fail "$doc: $cmd: no picture written"; continue; }
  "$py" - $pngs <<'PY' || fail "$doc: $cmd: a blank or saturated picture"
import sys
import numpy as np
from PIL import Image
bad = 0
for p in sys.argv[1:]:
    a = np.asarray(Image.open(p).convert("RGB"))
    lit = float(np.mean(a.max(axis=2) >= 16))
    white = float(np.mean(a.min(axis=2) >= 250))
    print(f"  {p}: {a.shape[1]}x{a.shape[0]}, {100 * lit:.1f} % lit, {100 * white:.1f} % white")
    if lit < 0.01 or white > 0.99:
        print(f"{p}: {100 * lit:.2f} % of the pixels lit (at least 1 %), {100 * white:.2f} % white (at most 99 %)",
              file=sys.stderr)
        bad = 1
sys.exit(bad)
PY
done <commands.txt
finish
