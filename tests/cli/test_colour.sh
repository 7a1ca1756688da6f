# Colour through the command line: a scene with populations writes X, Y, Z
# planes to FITS and a colour PNG; rendering two populations separately and
# adding their planes gives the planes rendered together (additivity), and a
# population's random draws do not depend on which others are present.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# scene NAME POPULATION-BLOCKS...: the built-in model face-on, with colour.
scene() {
  local name=$1
  shift
  cat >"$name.yaml" <<EOT
input:
  model:
    name: mw-m31
    particles: 20000
  types: [2, 3]
camera:
  projection: orthographic
  width: 60
image:
  width: 96
  height: 96
output:
  dir: out
  name: $name
colour:
  populations:
EOT
  for block in "$@"; do printf '%s\n' "$block" >>"$name.yaml"; done
}
bulge='    - name: bulge
      select: {types: [3]}
      colour: {temperature: 4000}
      luminance: {mass: 1}'
old='    - name: old-disc
      select:
        types: [2]
        random: {field: r, law: logistic, v0: 6, dv: 2}
      colour: {bv: 1.2}
      luminance: {mass: 1}'
young='    - name: young-disc
      select: {types: [2]}
      colour: {srgb: [0.6, 0.7, 1.0]}
      luminance: {mass: 1}'
scene all "$bulge" "$old" "$young"
for pop in bulge old young; do
  scene "$pop" "$bulge" "$old" "$young"
  printf '  only: %s\n' "$([ $pop = bulge ] && echo bulge || echo $pop-disc)" >>"$pop.yaml"
done
for s in all bulge old young; do
  "$ORRERY" render --quiet "$s.yaml" 2>err.txt || fail "render $s: $(cat err.txt)"
done
"$py" - <<'EOT' || fail "colour planes"
import sys
import numpy as np
from astropy.io import fits
from PIL import Image

def planes(name):
    with fits.open(f"out/{name}.fits") as h:
        names = [hdu.header.get("EXTNAME") for hdu in h]
        assert names == ["X", "Y", "Z", "SCENE"], names  # the planes, then the scene's text
        return np.array([hdu.data.astype(np.float64) for hdu in h[:3]])

a = planes("all")
parts = planes("bulge") + planes("old") + planes("young")
err = np.abs(a - parts).max() / a.max()
print(f"additivity: max |all - (bulge + old + young)| = {err:.2e} of the peak")
ok = err < 1e-6
# The bulge is redder than the young disc: x chromaticity of their sums.
def x_chroma(p):
    s = p.sum(axis=(1, 2))
    return s[0] / s.sum()
xb, xy = x_chroma(planes("bulge")), x_chroma(planes("young"))
print(f"chromaticity x: bulge {xb:.3f}, young disc {xy:.3f}")
ok &= xb > xy + 0.05
img = Image.open("out/all.png")
ok &= img.mode == "RGB" and img.size == (96, 96)
sys.exit(0 if ok else 1)
EOT
# A single-channel map tinted along a path of temperatures: blue at t = 0,
# red at t = 1 (a hue across a run); the linear transfer curve leaves
# mid-tones darker than sRGB's.
tint() {
  "$ORRERY" render --quiet "$SRC/configs/first-light.yaml" -o tint --set "output.name=$1" \
    --set "colour.tint.path=[20000,6500,2500]" --set image.width=128 --set image.height=128 "${@:2}" 2>err.txt ||
    fail "tint $1: $(cat err.txt)"
}
tint blue --set colour.tint.t=0
tint red --set colour.tint.t=1
tint red-linear --set colour.tint.t=1 --set output.png_transfer=linear
"$py" - <<'EOT' || fail "tinted maps"
import sys
import numpy as np
from PIL import Image
def mean_rgb(name):
    a = np.asarray(Image.open(f"tint/{name}.png")).reshape(-1, 3).astype(float)
    return a[a.sum(axis=1) > 30].mean(axis=0)
b, r, rl = mean_rgb("blue"), mean_rgb("red"), mean_rgb("red-linear")
print("mean RGB: t=0", b.round(1), "t=1", r.round(1), "t=1 linear", rl.round(1))
sys.exit(0 if b[2] > b[0] and r[0] > r[2] and rl.sum() < r.sum() else 1)
EOT
expect_fail 2 "colour.tint is for single-channel maps" none -- render all.yaml --set "colour.tint.path=[3000]"

# Errors name the population and the key.
scene bad '    - name: hot
      colour: {temperature: -5}'
expect_fail 2 "colour.populations\[0\].*hot.*temperature" out2 -- render bad.yaml -o out2
scene bad2 '    - name: a
      colour: {kelvin: 5000}'
expect_fail 2 "bad2.yaml:[0-9]+: colour.populations\[0\].colour: unknown key 'kelvin'" out2 -- render bad2.yaml -o out2
finish
