#!/usr/bin/env bash
# Regenerates the gallery's preview pictures (docs/gallery.md) in
# docs/images/gallery/: one frame of each case study rendered at small size,
# downscaled to PNGs of at most 150 KB. Needs a build (build/orrery, or
# $ORRERY) and /usr/bin/python3 with numpy and PIL.
#   scripts/gallery.sh              # a few minutes on two cores
#   scripts/gallery.sh --collision  # also Spiral Metamorphosis's encounter:
#                                   # the short in-situ N-body run, ~3 more minutes
#   scripts/gallery.sh --films [NAME...]  # the gallery of films instead: for each
#       of dark-universe, nightfall, spiral, futuresky (default all) its short run
#       at a small size, a strip of 6 frames across it (docs/images/gallery/
#       film-NAME.png) and a video made by `orrery video` (docs/videos/NAME.mp4,
#       at most 1.5 MB); prints each film's wall time. About 1.5 hours on two
#       shared cores, most of it the N-body runs of Spiral Metamorphosis and
#       Future Sky (docs/gallery.md). SPIRAL_RUN=DIR or FUTURESKY_RUN=DIR take
#       the frames of such a run made before (its output folder) instead.
#       spiral-full and futuresky-full make the strip and video of a
#       full-length run made before, named by SPIRAL_FULL_RUN=DIR or
#       FUTURESKY_FULL_RUN=DIR (those runs take an hour or more).
# Knobs, for a test that runs it (tests/cli/test_gallery.sh) without touching
# the source tree or taking minutes:
#   GALLERY_DEST=DIR     write the pictures (and the films' videos) into DIR,
#                        not docs/images/gallery (and docs/videos)
#   GALLERY_ONLY="NAME..."  only these of the pictures: futuresky, spiral,
#                        anaglyph, collision (also without --collision),
#                        dark-universe, nightfall (default: all but collision)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
orrery=${ORRERY:-$here/build/orrery}
py=/usr/bin/python3
[ -x "$py" ] || py=python3
[ -x "$orrery" ] || { echo "gallery.sh: no $orrery (build first: scripts/build.sh)" >&2; exit 1; }
dest=${GALLERY_DEST:-$here/docs/images/gallery}
videos=${GALLERY_DEST:-$here/docs/videos}
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
for colours in (256, 128, 64):  # starry pictures compress badly: fewer colours instead
    if os.path.getsize(dst) <= 150 * 1024:
        break
    im.quantize(colours, dither=Image.Dither.NONE).save(dst, optimize=True)
size = os.path.getsize(dst)
if size > 150 * 1024:
    os.remove(dst)
    sys.exit(f"{dst}: {size} bytes, over 150 KB")
print(f"wrote {dst} ({im.width}x{im.height}, {size // 1024} KB)")
PY
}

# side_by_side LEFT RIGHT OUT [HEIGHT]: two pictures of one height next to
# each other, downscaled to HEIGHT if given.
side_by_side() {
  "$py" - "$@" <<'PY'
import sys
from PIL import Image
a, b = (Image.open(p).convert("RGB") for p in sys.argv[1:3])
if len(sys.argv) > 4:
    h = int(sys.argv[4])
    a, b = (im.resize((round(im.width * h / im.height), h), Image.LANCZOS) for im in (a, b))
out = Image.new("RGB", (a.width + b.width, max(a.height, b.height)))
out.paste(a, (0, 0))
out.paste(b, (a.width, 0))
out.save(sys.argv[3])
PY
}

# downscaled SRC DST NAME N WIDTH: frames SRC/NAME_0000.png .. N-1 copied to
# DST at most WIDTH wide (a full-length run's frames, for a small video).
downscaled() {
  mkdir -p "$2"
  "$py" - "$@" <<'PY'
import sys
from PIL import Image
src, dst, name, n, width = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5])
for k in range(n):
    im = Image.open(f"{src}/{name}_{k:04d}.png").convert("RGB")
    if im.width > width:
        im = im.resize((width, round(im.height * width / im.width)), Image.LANCZOS)
    im.save(f"{dst}/{name}_{k:04d}.png")
PY
}

render() { "$orrery" render "$@" >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }; }

# strip [--middle FRACTION] OUT WIDTH ROWS... : frames side by side, each
# downscaled to WIDTH, each argument ROW a comma-separated list of PNGs
# (rows one above another); with --middle, only the middle FRACTION of each
# frame's width and height.
strip() {
  "$py" - "$@" <<'PY'
import sys
from PIL import Image
args = sys.argv[1:]
middle = 1.0
if args[0] == "--middle":
    middle, args = float(args[1]), args[2:]
out, width, rows = args[0], int(args[1]), [r.split(",") for r in args[2:]]


def cut(im):
    w, h = round(im.width * middle), round(im.height * middle)
    x, y = (im.width - w) // 2, (im.height - h) // 2
    return im.crop((x, y, x + w, y + h))


tiles = [[cut(Image.open(p).convert("RGB")) for p in row] for row in rows]
tiles = [[t.resize((width, round(t.height * width / t.width)), Image.LANCZOS) for t in row] for row in tiles]
heights = [max(t.height for t in row) for row in tiles]
im = Image.new("RGB", (width * max(len(r) for r in tiles) + 2 * (max(len(r) for r in tiles) - 1),
                       sum(heights) + 2 * (len(heights) - 1)))
y = 0
for row, h in zip(tiles, heights):
    for k, t in enumerate(row):
        im.paste(t, (k * (width + 2), y))
    y += h + 2
im.save(out)
PY
}

# frames_of DIR NAME N: 6 frames evenly across 0..N-1, as DIR/NAME_%04d.png, comma-separated.
frames_of() {
  local dir=$1 name=$2 n=$3 list="" k
  for k in 0 1 2 3 4 5; do list+="${list:+,}$dir/${name}_$(printf %04d $((k * (n - 1) / 5))).png"; done
  echo "$list"
}

# video SCENE DIR FRAMES VIEW OUT: `orrery video` of a view's frames to
# docs/videos/OUT.mp4, at --crf 30, or higher (lower quality) until it is
# at most 1.5 MB (star fields that move every frame compress badly).
video() {
  local scene=$1 dir=$2 frames=$3 view=$4 out=$videos/$5.mp4 crf size=0
  mkdir -p "$videos"
  for crf in 30 34 38 42; do
    local args=("$scene" -o "$dir" --frames "$frames" --set animation.frames="$frames" --crf "$crf" --force -q
                --out "$work/$5.mp4")
    [ -n "$view" ] && args+=(--view "$view")
    "$orrery" video "${args[@]}" >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
    size=$(stat -c %s "$work/$5.mp4")
    [ "$size" -gt $((1536 * 1024)) ] || break
  done
  [ "$size" -le $((1536 * 1024)) ] || { echo "gallery.sh: $out would be $size bytes, over 1.5 MB" >&2; exit 1; }
  mv "$work/$5.mp4" "$out"
  echo "wrote $out (--crf $crf, $((size / 1024)) KB)"
}

# The films: each its short run at a small size, a strip and a video.
film_dark_universe() {
  echo "Dark Universe: a 64^3 box evolved by the particle mesh, 48 frames at 384x202"
  "$orrery" ics --zeldovich --grid 64 --box 100 --evolve -o "$work/du-box.hdf5" >"$work/log" 2>&1 ||
    { cat "$work/log" >&2; exit 1; }
  render "$here/configs/dark-universe.yaml" -o "$work/du" --jobs 2 --set input.file="$work/du-box.hdf5" \
    --set animation.frames=48 --set image.width=384 --set image.height=202 --set psf.fwhm=1
  strip "$work/strip.png" 192 "$(frames_of "$work/du" dark-universe 48)"
  shrink "$work/strip.png" "$dest/film-dark-universe.png" 1160
  video "$here/configs/dark-universe.yaml" "$work/du" 48 "" dark-universe
}

film_nightfall() {
  echo "Nightfall: 36 frames at 960x540, 10^6 stars (the short run itself)"
  render "$here/configs/nightfall.yaml" -o "$work/nf" --jobs 2
  # the middle half of each frame at half size: a star field compresses
  # badly, and downscaled further the spikes would be lost
  strip --middle 0.5 "$work/strip.png" 240 "$(frames_of "$work/nf" nightfall 36)"
  shrink "$work/strip.png" "$dest/film-nightfall.png" 1450
  video "$here/configs/nightfall.yaml" "$work/nf" 36 "" nightfall
}

film_spiral() {
  echo "Spiral Metamorphosis in-situ: 200 000 particles, 2400 steps of 2 Myr, 31 frames of 240x240 views"
  local nbody scene=$here/configs/spiral-metamorphosis-insitu.yaml
  nbody=$(dirname "$orrery")/examples/orrery-nbody
  if [ -n "${SPIRAL_RUN:-}" ]; then
    ln -s "$(cd "$SPIRAL_RUN" && pwd)" "$work/sp"   # frames of that run, made before
  else
    "$nbody" --particles 200000 --steps 2400 --dt 0.002 --eps 0.3 --render-every 80 --quiet --scene "$scene" \
      --set output.dir="$work/sp" --set image.width=240 --set image.height=240 >"$work/log" 2>&1 ||
      { cat "$work/log" >&2; exit 1; }
  fi
  spiral_film "$work/sp" 31 spiral ""
}

# The full-length runs take hours: these take the frames of one made before
# (its output folder), with the commands of docs/gallery.md.
film_spiral_full() {
  [ -n "${SPIRAL_FULL_RUN:-}" ] || { echo "gallery.sh: spiral-full needs SPIRAL_FULL_RUN=DIR, the frames of the full-length run (docs/gallery.md)" >&2; exit 2; }
  echo "Spiral Metamorphosis in-situ, full length: the 121 frames of $SPIRAL_FULL_RUN"
  spiral_film "$SPIRAL_FULL_RUN" 121 spiral-full 240
}

film_futuresky_full() {
  [ -n "${FUTURESKY_FULL_RUN:-}" ] || { echo "gallery.sh: futuresky-full needs FUTURESKY_FULL_RUN=DIR, the frames of the full-length run (docs/gallery.md)" >&2; exit 2; }
  echo "Future Sky in-situ, full length: the 120 frames of $FUTURESKY_FULL_RUN"
  futuresky_film "$FUTURESKY_FULL_RUN" 120 futuresky-full 512
}

# spiral_film DIR N OUT HEIGHT: the strip docs/images/gallery/film-OUT.png
# and the video docs/videos/OUT.mp4 of a run's N frames of both views, the
# views side by side, as the paper shows them (downscaled to HEIGHT pixels
# high unless HEIGHT is empty):
# each frame's pair is pasted into one picture, under the face-on view's
# name in another folder, so `orrery video --view faceon` encodes the pairs.
spiral_film() {
  local dir=$1 n=$2 out=$3 height=$4 k
  local scene=$here/configs/spiral-metamorphosis-insitu.yaml
  strip "$work/strip.png" 160 "$(frames_of "$dir" spiral-faceon "$n")" "$(frames_of "$dir" spiral-edgeon "$n")"
  shrink "$work/strip.png" "$dest/film-$out.png" 970
  rm -rf "$work/side" && mkdir -p "$work/side"
  for k in $(seq 0 $((n - 1))); do
    side_by_side "$dir/spiral-faceon_$(printf %04d "$k").png" "$dir/spiral-edgeon_$(printf %04d "$k").png" \
      "$work/side/spiral-faceon_$(printf %04d "$k").png" ${height:+"$height"}
  done
  video "$scene" "$work/side" "$n" faceon "$out"
}

film_futuresky() {
  echo "Future Sky in-situ: examples/futuresky-short.sh's run (500 000 particles, 2450 steps of 2 Myr), 25 frames"
  echo "  of a 1024x512 panorama and a 1024x1024 dome master"
  if [ -n "${FUTURESKY_RUN:-}" ]; then
    ln -s "$(cd "$FUTURESKY_RUN" && pwd)" "$work/fs"   # frames of that run, made before
  else
    ORRERY_BUILD=$(dirname "$orrery") "$here/examples/futuresky-short.sh" "$work/fs" >"$work/log" 2>&1 ||
      { cat "$work/log" >&2; exit 1; }
  fi
  futuresky_film "$work/fs" 25 futuresky 1024
}

# futuresky_film DIR N OUT WIDTH: the strip docs/images/gallery/film-OUT.png
# of a run's N frames (panoramas above, dome masters below) and the videos
# docs/videos/OUT-panorama.mp4 and OUT-dome.mp4, of frames at most WIDTH
# pixels wide.
futuresky_film() {
  local dir=$1 n=$2 out=$3 width=$4 view
  local scene=$here/configs/futuresky-sequence.yaml
  strip "$work/strip.png" 160 "$(frames_of "$dir" futuresky-panorama "$n")" "$(frames_of "$dir" futuresky-dome "$n")"
  shrink "$work/strip.png" "$dest/film-$out.png" 970
  for view in panorama dome; do
    downscaled "$dir" "$work/fs-small" "futuresky-$view" "$n" "$width"
    video "$scene" "$work/fs-small" "$n" "$view" "$out-$view"
  done
}

if [ "${1:-}" = "--films" ]; then
  shift
  [ $# -gt 0 ] || set -- dark-universe nightfall spiral futuresky
  for f in "$@"; do
    start=$(date +%s)
    case "$f" in
      dark-universe) film_dark_universe ;; nightfall) film_nightfall ;;
      spiral) film_spiral ;; futuresky) film_futuresky ;;
      spiral-full) film_spiral_full ;; futuresky-full) film_futuresky_full ;;
      *) echo "gallery.sh: no film $f (dark-universe, nightfall, spiral, futuresky, spiral-full, futuresky-full)" >&2
         exit 2 ;;
    esac
    echo "$f: $(($(date +%s) - start)) s of wall-clock time"
  done
  exit 0
fi

# The pictures: one function each.
picture_futuresky() {
  echo "Future Sky (configs/futuresky.yaml), full size, downscaled, and a full-resolution detail of the dome"
  render "$here/configs/futuresky.yaml" -o "$work/fs"
  shrink "$work/fs/futuresky-panorama.png" "$dest/futuresky-panorama.png" 640
  shrink "$work/fs/futuresky-dome.png" "$dest/futuresky-dome.png" 400
  # Pixels 2594-3234 x 1681-2041 of the master, at its own scale: the
  # brightest star of the shipped sky (seed 3: V = -0.4, l = 85, b = 56) with
  # its spikes, 56 degrees from the zenith, among the naked-eye stars.
  "$py" -c "import sys; from PIL import Image; Image.open(sys.argv[1]).crop((2594, 1681, 3234, 2041)).save(sys.argv[2])" \
    "$work/fs/futuresky-dome.png" "$work/fs/detail.png"
  shrink "$work/fs/detail.png" "$dest/futuresky-dome-detail.png" 640
}

picture_spiral() {
  echo "Spiral Metamorphosis (configs/spiral-metamorphosis.yaml), the model today"
  render "$here/configs/spiral-metamorphosis.yaml" -o "$work/sp" --set image.width=400 --set image.height=400
  side_by_side "$work/sp/spiral-faceon.png" "$work/sp/spiral-edgeon.png" "$work/spiral.png"
  shrink "$work/spiral.png" "$dest/spiral-metamorphosis.png" 640
}

picture_anaglyph() {
  echo "Spiral Metamorphosis anaglyph (configs/spiral-metamorphosis-anaglyph.yaml)"
  render "$here/configs/spiral-metamorphosis-anaglyph.yaml" -o "$work/an" --set image.width=640 --set image.height=360
  shrink "$work/an/spiral-anaglyph.png" "$dest/spiral-metamorphosis-anaglyph.png" 640
}

picture_collision() {
  echo "Spiral Metamorphosis in-situ (orrery-nbody, 20000 particles, 240 steps), frame 27"
  nbody=$(dirname "$orrery")/examples/orrery-nbody
  "$nbody" --particles 20000 --steps 240 --dt 0.02 --render-every 8 --quiet \
    --scene "$here/configs/spiral-metamorphosis-insitu.yaml" --set output.dir="$work/run"
  side_by_side "$work/run/spiral-faceon_0027.png" "$work/run/spiral-edgeon_0027.png" "$work/collision.png"
  shrink "$work/collision.png" "$dest/spiral-metamorphosis-collision.png" 640
}

picture_dark_universe() {
  echo "Dark Universe (configs/dark-universe.yaml): a 64^3 box, frame 150 of 600"
  "$orrery" ics --zeldovich --grid 64 --box 100 --z 0 --truncate 1 --seed 1 -o "$work/box.hdf5" >"$work/log" 2>&1 ||
    { cat "$work/log" >&2; exit 1; }
  render "$here/configs/dark-universe.yaml" -o "$work/du" --frames 150 --set input.file="$work/box.hdf5" \
    --set image.width=1024 --set image.height=540 --set psf.fwhm=1
  shrink "$work/du/dark-universe_0150.png" "$dest/dark-universe.png" 480
}

picture_nightfall() {
  echo "Nightfall (configs/nightfall.yaml): frame 0 of 36"
  render "$here/configs/nightfall.yaml" -o "$work/nf" --frames 0
  shrink "$work/nf/nightfall_0000.png" "$dest/nightfall.png" 480
}

pictures="futuresky spiral anaglyph dark-universe nightfall"
if [ "${1:-}" = "--collision" ]; then pictures="futuresky spiral anaglyph collision dark-universe nightfall"; fi
pictures=${GALLERY_ONLY:-$pictures}
for p in $pictures; do
  case "$p" in
    futuresky) picture_futuresky ;; spiral) picture_spiral ;; anaglyph) picture_anaglyph ;;
    collision) picture_collision ;; dark-universe) picture_dark_universe ;; nightfall) picture_nightfall ;;
    *) echo "gallery.sh: no picture $p in GALLERY_ONLY (futuresky, spiral, anaglyph, collision, dark-universe, nightfall)" >&2
       exit 2 ;;
  esac
done
