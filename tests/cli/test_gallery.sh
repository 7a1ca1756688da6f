#!/usr/bin/env bash
# scripts/gallery.sh, which makes the gallery's pictures (docs/gallery.md),
# run on one case study (GALLERY_ONLY=anaglyph: about 3 s, the others take
# 10 s to a minute) into a temporary folder (GALLERY_DEST), never the source
# tree. The picture is read back with PIL: at most 150 KB, the size of the
# one in docs/images/gallery, neither black nor washed out (a stale white
# level made Dark Universe's all white without any error).
source "$(dirname "$0")/lib.sh"
touch before
ORRERY=$ORRERY GALLERY_DEST=$WORK/gallery GALLERY_ONLY=anaglyph bash "$SRC/scripts/gallery.sh" >gallery.log 2>&1 ||
  fail "gallery.sh failed: $(cat gallery.log)"
made=$(ls "$WORK/gallery" 2>/dev/null | tr '\n' ' ')
[ "$made" = "spiral-metamorphosis-anaglyph.png " ] || fail "gallery.sh made '$made', expected spiral-metamorphosis-anaglyph.png only"
changed=$(find "$SRC/docs/images/gallery" "$SRC/docs/videos" -newer before 2>/dev/null)
[ -z "$changed" ] || fail "gallery.sh wrote into the source tree although GALLERY_DEST was set: $changed"

"$py" - "$WORK/gallery/spiral-metamorphosis-anaglyph.png" "$SRC/docs/images/gallery/spiral-metamorphosis-anaglyph.png" <<'PY' || fail "gallery.sh's picture: see above"
import os, sys
import numpy as np
from PIL import Image
made, shown = sys.argv[1:3]
im, pixels = Image.open(made), np.asarray(Image.open(made).convert("RGB"))
white = (pixels == 255).all(axis=2).mean()
bad = []
if os.path.getsize(made) > 150 * 1024:
    bad.append(f"{os.path.getsize(made)} bytes, over 150 KB")
if im.size != Image.open(shown).size:
    bad.append(f"{im.size}, docs/images/gallery's is {Image.open(shown).size}")
if not 0.5 < pixels.mean() < 128 or white > 0.01:
    bad.append(f"mean {pixels.mean():.2f}, {white:.4f} of pixels white")
for b in bad:
    print(f"{made}: {b}", file=sys.stderr)
sys.exit(1 if bad else 0)
PY
finish
