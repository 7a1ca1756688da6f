# orrery compose re-grades a render from its raw planes: with the scene
# unchanged it reproduces the render's PNG bit for bit (PSF included, since
# the raw planes are taken before it), with another grading it differs, and
# without raw planes it says which file is missing.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

cat >flat.yaml <<'EOT'
input:
  model:
    name: mw-m31
    particles: 20000
  types: [2, 3]
camera:
  projection: orthographic
  width: 60
image:
  width: 120
  height: 90
psf:
  kind: gaussian
  fwhm: 2.5
output:
  dir: out
  name: flat
  raw: true
EOT
cp flat.yaml colour.yaml
sed -i 's/name: flat/name: colour/' colour.yaml
cat >>colour.yaml <<'EOT'
colour:
  populations:
    - name: bulge
      select: {types: [3]}
      colour: {temperature: 4000}
      luminance: {mass: 1}
    - name: disc
      select: {types: [2]}
      colour: {temperature: 9000}
      luminance: {mass: 1}
EOT
same_pixels() { "$py" -c "
import sys, numpy as np
from PIL import Image
a, b = (np.asarray(Image.open(p)) for p in sys.argv[1:3])
sys.exit(0 if a.shape == b.shape and (a == b).all() else 1)" "$1" "$2"; }

for s in flat colour; do
  "$ORRERY" render --quiet "$s.yaml" 2>err.txt || fail "render $s: $(cat err.txt)"
  [ -f "out/$s.raw.fits" ] || fail "$s: no raw planes written"
  cp "out/$s.png" "rendered-$s.png"
  "$ORRERY" compose --quiet "$s.yaml" 2>err.txt || fail "compose $s: $(cat err.txt)"
  same_pixels "rendered-$s.png" "out/$s.png" || fail "$s: compose with the same scene changed the PNG"
done
"$ORRERY" compose --quiet flat.yaml --set output.stretch=linear 2>err.txt || fail "compose flat linear: $(cat err.txt)"
same_pixels rendered-flat.png out/flat.png && fail "flat: compose with a linear stretch left the PNG unchanged"
"$ORRERY" compose --quiet colour.yaml --set colour.synthesis.stretch=gamma 2>err.txt ||
  fail "compose colour gamma: $(cat err.txt)"
same_pixels rendered-colour.png out/colour.png && fail "colour: compose with a gamma stretch left the PNG unchanged"

# Blending layers: single-channel raw renders of the bulge and of the disc,
# given their colours in compose, make the picture the populations render
# makes (same colours, luminance = mass) to within a level of rounding.
for part in bulge:3 disc:2; do
  "$ORRERY" render --quiet flat.yaml --set "output.name=${part%:*}" --set "input.types=[${part#*:}]" \
    --set psf.kind=none 2>err.txt || fail "render ${part%:*}: $(cat err.txt)"
done
"$ORRERY" render --quiet colour.yaml --set output.name=together --set psf.kind=none 2>err.txt ||
  fail "render together: $(cat err.txt)"
cp flat.yaml blend.yaml
sed -i 's/name: flat/name: blend/; s/kind: gaussian/kind: none/' blend.yaml
cat >>blend.yaml <<'EOT'
compose:
  layers:
    - file: out/bulge.raw.fits
      colour: {temperature: 4000}
    - file: out/disc.raw.fits
      colour: {temperature: 9000}
EOT
"$ORRERY" compose --quiet blend.yaml 2>err.txt || fail "compose blend: $(cat err.txt)"
"$py" -c "
import sys, numpy as np
from PIL import Image
a, b = (np.asarray(Image.open(p)).astype(int) for p in sys.argv[1:3])
d = np.abs(a - b).max()
print('blend vs populations: largest difference', d, 'levels')
sys.exit(0 if a.shape == b.shape and d <= 1 else 1)" out/blend.png out/together.png || fail "blended layers differ from the populations render"
# -o DIR: made when missing, as render makes it (the layers come from out/).
"$ORRERY" compose --quiet blend.yaml -o made/below 2>err.txt || fail "compose -o made/below: $(cat err.txt)"
[ -f made/below/blend.png ] || fail "compose -o did not make made/below and write blend.png there"
sed 's/      colour: {temperature: 4000}//' blend.yaml >blend-bad.yaml
expect_fail 2 "out/bulge.raw.fits: compose.layers: a single-plane layer needs a colour" none -- compose blend-bad.yaml

# Other formats: the linear planes as OpenEXR, the picture as TIFF (the
# PNG's pixels exactly, read back by Pillow).
"$ORRERY" render --quiet colour.yaml --set output.exr=true --set output.image=tif 2>err.txt ||
  fail "render colour exr/tif: $(cat err.txt)"
[ -s out/colour.exr ] || fail "no out/colour.exr"
head -c 4 out/colour.exr | od -An -tx1 | grep -q "76 2f 31 01" || fail "out/colour.exr is not OpenEXR"
same_pixels out/colour.png out/colour.tif || fail "the TIFF's pixels differ from the PNG's"
expect_fail 2 "output.image: a file extension such as tif" none -- render colour.yaml --set output.image=.tif
# output.exr and output.image: exr would both be NAME.exr, the picture over the planes.
expect_fail 2 "output.exr: true and output.image: exr both write NAME.exr" none -- \
  render colour.yaml --set output.exr=true --set output.image=exr

# A flat view's compose applies the PSF as set now (its raw planes are
# taken before the PSF) ...
"$ORRERY" compose --quiet flat.yaml 2>err.txt || fail "compose flat: $(cat err.txt)"
cp out/flat.png composed-flat.png
"$ORRERY" compose --quiet flat.yaml --set psf.fwhm=6 2>err.txt || fail "compose flat psf.fwhm=6: $(cat err.txt)"
same_pixels composed-flat.png out/flat.png && fail "flat: compose with another PSF left the PNG unchanged"
# ... but a sky map's PSF is drawn into its raw planes as it renders, so
# compose refuses to change it rather than ignore the key.
cat >dome.yaml <<'EOT'
input:
  model:
    name: mw-m31
    particles: 20000
  types: [2, 3]
camera:
  projection: dome
  position: [0, 0, 0]
image:
  width: 64
  height: 64
psf:
  kind: gaussian
  fwhm_arcmin: 60
output:
  dir: out
  name: dome
  raw: true
EOT
"$ORRERY" render --quiet dome.yaml 2>err.txt || fail "render dome: $(cat err.txt)"
"$ORRERY" compose --quiet dome.yaml 2>err.txt || fail "compose dome: $(cat err.txt)"
expect_fail 2 "^orrery: error: --set psf.fwhm_arcmin: the scene is a sky map, whose PSF is drawn into the raw planes .*render again" \
  none -- compose dome.yaml --set psf.fwhm_arcmin=120
expect_fail 2 "--set psf.kind: the scene is a sky map" none -- compose dome.yaml --set psf.kind=none

# A scene whose image size differs from the raw planes', and one never rendered.
expect_fail 1 "out/flat.raw.fits: holds 1 plane\(s\) of 120 x 90, but .*flat.yaml renders 1 of 64 x 90" none -- \
  compose flat.yaml --set image.width=64
sed 's/name: flat/name: never/' flat.yaml >never.yaml
expect_fail 1 "out/never.raw.fits: no such file: compose reads the raw planes that .orrery render. writes with output.raw: true" none -- compose never.yaml
finish
