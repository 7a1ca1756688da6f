#!/usr/bin/env bash
# Regenerates the gallery's preview pictures (docs/gallery.md) in
# docs/images/gallery/: one frame of each case study rendered at small size,
# downscaled to PNGs of at most 150 KB. Needs a build (build/orrery, or
# $ORRERY) and /usr/bin/python3 with numpy and PIL.
#   scripts/gallery.sh              # a few minutes on two cores
#   scripts/gallery.sh --collision  # also Spiral Metamorphosis's encounter:
#                                   # the short in-situ N-body run, ~3 more minutes
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
orrery=${ORRERY:-$here/build/orrery}
py=/usr/bin/python3
[ -x "$py" ] || py=python3
[ -x "$orrery" ] || { echo "gallery.sh: no $orrery (build first: scripts/build.sh)" >&2; exit 1; }
dest=$here/docs/images/gallery
work=$(mktemp -d /tmp/orrery-gallery-XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$dest"

# shrink IN OUT WIDTH: a downscaled copy, checked to be at most 150 KB.
shrink() {
  "$py" - "$1" "$2" "$3" <<'PY'
import os, sys
from PIL import Image
src, dst, width = sys.argv[1], sys.argv[2], int(sys.argv[3])
im = Image.open(src).convert("RGB")
if im.width > width:
    im = im.resize((width, round(im.height * width / im.width)), Image.LANCZOS)
im.save(dst, optimize=True)
if os.path.getsize(dst) > 150 * 1024:  # starry pictures compress badly: 256 colours instead
    im.quantize(256, dither=Image.Dither.NONE).save(dst, optimize=True)
size = os.path.getsize(dst)
if size > 150 * 1024:
    os.remove(dst)
    sys.exit(f"{dst}: {size} bytes, over 150 KB")
print(f"wrote {dst} ({im.width}x{im.height}, {size // 1024} KB)")
PY
}

# side_by_side LEFT RIGHT OUT: two pictures of one height next to each other.
side_by_side() {
  "$py" - "$1" "$2" "$3" <<'PY'
import sys
from PIL import Image
a, b = (Image.open(p).convert("RGB") for p in sys.argv[1:3])
out = Image.new("RGB", (a.width + b.width, max(a.height, b.height)))
out.paste(a, (0, 0))
out.paste(b, (a.width, 0))
out.save(sys.argv[3])
PY
}

render() { "$orrery" render "$@" >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }; }

echo "Future Sky (configs/futuresky.yaml), full size, downscaled, and a full-resolution detail of the dome"
render "$here/configs/futuresky.yaml" -o "$work/fs"
shrink "$work/fs/futuresky-panorama.png" "$dest/futuresky-panorama.png" 640
shrink "$work/fs/futuresky-dome.png" "$dest/futuresky-dome.png" 400
# Pixels 1040-1680 x 1260-1620 of the master, at its own scale: bright
# stars with spikes 20-35 degrees from the zenith, left of the Milky Way.
"$py" -c "import sys; from PIL import Image; Image.open(sys.argv[1]).crop((1040, 1260, 1680, 1620)).save(sys.argv[2])" \
  "$work/fs/futuresky-dome.png" "$work/fs/detail.png"
shrink "$work/fs/detail.png" "$dest/futuresky-dome-detail.png" 640

echo "Spiral Metamorphosis (configs/spiral-metamorphosis.yaml), the model today"
render "$here/configs/spiral-metamorphosis.yaml" -o "$work/sp" --set image.width=400 --set image.height=400
side_by_side "$work/sp/spiral-faceon.png" "$work/sp/spiral-edgeon.png" "$work/spiral.png"
shrink "$work/spiral.png" "$dest/spiral-metamorphosis.png" 640

echo "Spiral Metamorphosis anaglyph (configs/spiral-metamorphosis-anaglyph.yaml)"
render "$here/configs/spiral-metamorphosis-anaglyph.yaml" -o "$work/an" --set image.width=640 --set image.height=360
shrink "$work/an/spiral-anaglyph.png" "$dest/spiral-metamorphosis-anaglyph.png" 640

if [ "${1:-}" = "--collision" ]; then
  echo "Spiral Metamorphosis in-situ (orrery-nbody, 20000 particles, 240 steps), frame 27"
  nbody=$(dirname "$orrery")/examples/orrery-nbody
  "$nbody" --particles 20000 --steps 240 --dt 0.02 --render-every 8 --quiet \
    --scene "$here/configs/spiral-metamorphosis-insitu.yaml" --set output.dir="$work/run"
  side_by_side "$work/run/spiral-faceon_0027.png" "$work/run/spiral-edgeon_0027.png" "$work/collision.png"
  shrink "$work/collision.png" "$dest/spiral-metamorphosis-collision.png" 640
fi

echo "Dark Universe (configs/dark-universe.yaml): a 64^3 box, frame 150 of 600"
"$orrery" ics --zeldovich --grid 64 --box 100 --z 0 --truncate 1 --seed 1 -o "$work/box.hdf5" >"$work/log" 2>&1 ||
  { cat "$work/log" >&2; exit 1; }
render "$here/configs/dark-universe.yaml" -o "$work/du" --frames 150 --set input.file="$work/box.hdf5" \
  --set image.width=1024 --set image.height=540 --set psf.fwhm=1 --set colour.synthesis.white=90
shrink "$work/du/dark-universe_0150.png" "$dest/dark-universe.png" 480

echo "Nightfall (configs/nightfall.yaml): 300000 stars, frame 0 of 36"
render "$here/configs/nightfall.yaml" -o "$work/nf" --frames 0 --set input.model.particles=300000
shrink "$work/nf/nightfall_0000.png" "$dest/nightfall.png" 480
