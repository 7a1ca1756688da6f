# Fulldome sequences: frame names as planetariums take them (NAME.00001.png
# from 1: output.frame_start, output.frame_digits, output.frame_separator),
# resume markers that follow the names, orrery video finding them, and
# output.alpha_mask's RGBA PNG, transparent outside the dome's circle.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

printf 'x y z mass\n0 0 5 1\n1 1 4 2\n-2 1 6 1\n' >t.txt
cat >dome.yaml <<'EOT'
input:
  file: t.txt
camera:
  projection: dome
image:
  width: 48
  height: 48
animation:
  frames: 3
  fps: 30
output:
  dir: out
  name: show
  frame_start: 1
  frame_digits: 5
  frame_separator: .
  alpha_mask: true
  fits: false
EOT
"$ORRERY" render dome.yaml >run.out 2>run.err || fail "render: $(cat run.err)"
[ "$(ls out)" = "$(printf 'show.00001.png\nshow.00002.png\nshow.00003.png')" ] || fail "frame names: $(ls out)"
for f in 1 2 3; do
  [ -s out/.orrery-frames/show.0000$f.done ] || fail "no marker for show.0000$f: $(ls -A out/.orrery-frames)"
done

# The markers follow the names: a second run finds every frame complete,
# and a lost frame is redone under its own name.
rm out/show.00002.png
"$ORRERY" render dome.yaml >run.out 2>run.err || fail "resume: $(cat run.err)"
grep -q "rendered 1, skipped 2" run.out || fail "resume summary: $(cat run.out)"
[ -s out/show.00002.png ] || fail "lost frame not redone: $(ls out)"

# Alpha: 0 outside the circle (and black there), 255 inside, each rim
# pixel's coverage of the circle between (anti-aliased); RGBA 8-bit.
"$py" - <<'EOT' || fail "alpha mask"
import math
import numpy as np
from PIL import Image
im = Image.open("out/show.00001.png")
assert im.mode == "RGBA", im.mode
assert im.getpixel((0, 0)) == (0, 0, 0, 0), im.getpixel((0, 0))
assert im.getpixel((24, 24))[3] == 255, im.getpixel((24, 24))
assert im.getpixel((47, 0))[3] == 0
alpha = np.asarray(im)[:, :, 3] / 255.0
r = im.width / 2
assert ((alpha > 0) & (alpha < 1)).sum() > 4 * r, "no partial alpha on the rim"
assert abs(alpha.sum() / (math.pi * r * r) - 1) < 2e-3, alpha.sum() / (math.pi * r * r)
EOT

# The 16-bit TIFF of output.image carries the same alpha (read by OpenImageIO).
if "$py" -c 'import OpenImageIO' 2>/dev/null; then
  "$ORRERY" render dome.yaml --set output.image=tif --set output.png_bits=16 --set output.dir=tif \
    --set animation.frames=1 >run.out 2>run.err || fail "TIFF: $(cat run.err)"
  "$py" - <<'EOT' || fail "TIFF alpha"
import OpenImageIO as oiio
inp = oiio.ImageInput.open("tif/show.tif")
spec, px = inp.spec(), inp.read_image(oiio.FLOAT)
inp.close()
assert spec.channelnames == ("R", "G", "B", "A") and spec.alpha_channel == 3, spec.channelnames
assert str(spec.format) == "uint16", spec.format
assert list(px[0, 0]) == [0, 0, 0, 0] and px[24, 24][3] == 1, (px[0, 0], px[24, 24])
EOT
fi

# orrery video reads the same names (ffmpeg is a dependency).
if command -v ffmpeg >/dev/null; then
  "$ORRERY" video dome.yaml >video.out 2>video.err || fail "video: $(cat video.err)"
  [ -s out/show.mp4 ] || fail "no video: $(ls out) $(cat video.err)"
fi

# The default stays NAME_0000 from 0, without alpha.
sed -i '/frame_start\|frame_digits\|frame_separator\|alpha_mask/d; s/name: show/name: plain/' dome.yaml
"$ORRERY" render dome.yaml >run.out 2>run.err || fail "default names: $(cat run.err)"
[ -s out/plain_0000.png ] && [ -s out/plain_0002.png ] || fail "default names: $(ls out)"
"$py" -c 'from PIL import Image; import sys; sys.exit(Image.open("out/plain_0000.png").mode != "RGB")' ||
  fail "default PNG is not RGB"

# A marker's checksum of a large output (summed in 8 MiB pieces on every
# thread) is the file's CRC-32 as zlib computes it over the whole file.
"$ORRERY" render dome.yaml --set output.fits=true --set image.width=2000 --set image.height=2000 \
  --set animation.frames=2 --set output.name=big >run.out 2>run.err || fail "large frames: $(cat run.err)"
"$py" - <<'EOT' || fail "marker checksums of large outputs"
import zlib
lines = [l.split() for l in open("out/.orrery-frames/big_0001.done") if l.startswith("output ")]
assert any(int(size) > 8 << 20 for _, size, _, _ in lines), lines
for _, size, crc, name in lines:
    data = open("out/" + name, "rb").read()
    assert len(data) == int(size) and zlib.crc32(data) == int(crc, 16), (name, crc, hex(zlib.crc32(data)))
EOT

# Bad keys: named, exit 2, nothing written.
printf 'input:\n  file: t.txt\noutput:\n  dir: bad\n' >bad.yaml
expect_fail 2 "output.frame_separator: '/' may hold only" bad -- render bad.yaml --set "output.frame_separator=/"
expect_fail 2 "output.frame_digits" bad -- render bad.yaml --set output.frame_digits=0
expect_fail 2 "output.frame_start" bad -- render bad.yaml --set output.frame_start=-1
expect_fail 2 "output.alpha_mask: not with stereo.mode anaglyph" bad -- \
  render bad.yaml --set output.alpha_mask=true --set stereo.mode=anaglyph --set camera.projection=dome
finish
