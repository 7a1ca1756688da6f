# Stereo through the command line: every stereo.mode writes the files it
# should at the size it should (side-by-side twice as wide, over-under twice
# as tall, separate a file per eye); in an anaglyph of one bright particle
# nearer than the convergence distance the red (left-eye) blob lies right
# of the cyan one, and beyond it left; omni-directional stereo in an
# equirectangular over-under map turns a particle ahead by asin(r/d) in
# each eye; an orthographic camera is refused; configs/anaglyph-orbit.yaml
# renders.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# One particle on the view axis, 4 units from the camera: nearer than the
# convergence distance (10), and one 40 units away: farther.
printf 'x y z mass\n0 0 6 1\n' >near.txt
printf 'x y z mass\n0 0 -30 1\n' >far.txt
# scene NAME TABLE MODE [more lines...]
scene() {
  local name=$1 table=$2 mode=$3
  shift 3
  cat >"$name.yaml" <<EOT
input:
  file: $table
camera:
  projection: perspective
  position: [0, 0, 10]
  look_at: [0, 0, 0]
  up: [0, 1, 0]
  fov: 40
image:
  width: 80
  height: 60
output:
  dir: out
  name: $name
  colormap: grey
stereo:
  mode: $mode
  eye_separation: 0.5
EOT
  for line in "$@"; do printf '%s\n' "$line" >>"$name.yaml"; done
}
scene anaglyph near.txt anaglyph
scene far near.txt anaglyph "  anaglyph: colour"
sed -i 's/near.txt/far.txt/' far.yaml
scene grey near.txt anaglyph "  anaglyph: grey"
scene sbs near.txt side-by-side
scene ou near.txt over-under
scene sep near.txt separate
sed -i 's/^  name: sep$/  name: sep\n  exr: true/' sep.yaml
# Two particles, the brighter pixel in the left eye: with a linear stretch
# the right eye, graded with the left's white, peaks below full white.
printf 'x y z mass\n0 0 6 1\n0.35 0.3 2 1\n' >two.txt
scene white two.txt separate
scene whiteou two.txt over-under
sed -i 's/^  colormap: grey$/  colormap: grey\n  stretch: linear/' white.yaml whiteou.yaml
for s in anaglyph far grey sbs ou sep white whiteou; do
  "$ORRERY" render --quiet "$s.yaml" 2>err.txt || fail "render $s: $(cat err.txt)"
  grep -q "AddressSanitizer\|runtime error" err.txt && fail "render $s: sanitizer report: $(cat err.txt)"
done
for f in anaglyph.png anaglyph.fits sbs.png sbs.fits ou.png ou.fits sep-left.png sep-right.png sep-left.fits \
    sep-right.fits sep-left.exr sep-right.exr; do
  [ -s "out/$f" ] || fail "out/$f was not written"
done
[ -e out/sep.png ] && fail "separate mode wrote out/sep.png"

# An equirectangular over-under ODS map (the VR layout) of a particle 5
# units ahead, eye separation 1, and one inside the eye circle.
printf 'x y z mass\n5 0 0 1\n0.2 0.1 3 1\n' >ods.txt
cat >ods.yaml <<'EOT'
input:
  file: ods.txt
camera:
  projection: equirectangular
image:
  width: 360
  height: 180
deposit: ngp
output:
  dir: out
  name: ods
stereo:
  mode: over-under
  eye_separation: 1
EOT
"$ORRERY" render ods.yaml >ods.out 2>err.txt || fail "render ods: $(cat err.txt)"
grep -q "1 inside the stereo eye circle" ods.out || fail "ods: the skipped particle is not reported: $(cat ods.out)"

"$py" - <<'EOT' || fail "stereo pictures"
import math
import numpy as np
from astropy.io import fits
from PIL import Image

def rgb(name):
    return np.asarray(Image.open("out/" + name), dtype=float)

ok = True
def expect(cond, what):
    global ok
    if not cond:
        print("FAIL:", what)
        ok = False

sizes = {"anaglyph.png": (60, 80), "sbs.png": (60, 160), "ou.png": (120, 80),
         "sep-left.png": (60, 80), "sep-right.png": (60, 80), "ods.png": (360, 360)}
for name, shape in sizes.items():
    expect(rgb(name).shape[:2] == shape, f"{name} is {rgb(name).shape[:2]}, expected {shape}")

def centroid_x(plane):
    w = np.nan_to_num(plane)
    return (w.sum(axis=0) * (np.arange(w.shape[1]) + 0.5)).sum() / w.sum()

# Perspective: f = 40 / tan(20 deg) pixels; parallax f s (1/z - 1/C).
f = 40 / math.tan(math.radians(20))
near_parallax = f * 0.5 * (1 / 4 - 1 / 10)
far_parallax = f * 0.5 * (1 / 40 - 1 / 10)
for name, parallax in (("anaglyph", near_parallax), ("grey", near_parallax), ("far", far_parallax)):
    a = rgb(name + ".png")
    red, cyan = centroid_x(a[:, :, 0]), centroid_x(a[:, :, 1] + a[:, :, 2])
    expect((red - cyan) * parallax > 0, f"{name}: red at x = {red:.2f}, cyan at {cyan:.2f}")
    h = fits.open("out/" + name + ".fits")
    expect([x.name for x in h] == ["left.mass", "right.mass", "SCENE"], f"{name}.fits HDUs {[x.name for x in h]}")
    expect(h[0].header["STEREO"] == "anaglyph" and h[0].header["CONVERG"] == 10, f"{name}.fits cards")
    # The linear planes: the CIC centroids differ by the analytic parallax.
    got = centroid_x(h[0].data[::-1]) - centroid_x(h[1].data[::-1])
    expect(abs(got - parallax) < 0.05, f"{name}: parallax {got:.3f} px, expected {parallax:.3f}")
    expect(abs(centroid_x(h[0].data) + centroid_x(h[1].data) - 80) < 0.05, f"{name}: pair not centred")

# The particle nearer than convergence is all red in grey/colour modes and
# cyan only on the other side.
a = rgb("grey.png")
expect(a[:, :, 0].max() > 200 and a[:, :, 1].max() > 200, "grey anaglyph: blobs too faint")

# Side by side: the left half is the left eye (blob right of its centre);
# over-under: the top half is.
sbs, ou = rgb("sbs.png").sum(axis=2), rgb("ou.png").sum(axis=2)
l, r = centroid_x(sbs[:, :80]), centroid_x(sbs[:, 80:])
expect(abs((l - r) - near_parallax) < 0.6, f"side-by-side: left {l:.2f}, right {r:.2f}")
l, r = centroid_x(ou[:60]), centroid_x(ou[60:])
expect(abs((l - r) - near_parallax) < 0.6, f"over-under: top {l:.2f}, bottom {r:.2f}")
sl, sr = rgb("sep-left.png").sum(axis=2), rgb("sep-right.png").sum(axis=2)
expect(abs(centroid_x(sl) - l) < 1e-6 and abs(centroid_x(sr) - r) < 1e-6, "separate eyes differ from the pair")

# Both eyes graded with the left eye's white level.
peaks = [fits.getdata(f"out/white-{e}.fits").max() for e in ("left", "right")]
expect(peaks[0] > peaks[1], f"white test: left peak {peaks[0]} should be the brighter")
expected = 255 * peaks[1] / peaks[0]
got = rgb("white-right.png")[:, :, 0].max()
expect(rgb("white-left.png")[:, :, 0].max() == 255 and abs(got - expected) <= 1,
       f"separate right eye peaks at {got}, expected {expected:.1f} (the left eye's white)")
got = rgb("whiteou.png")[60:, :, 0].max()
expect(abs(got - expected) <= 1, f"over-under right eye peaks at {got}, expected {expected:.1f}")

# ODS: one degree per pixel; the left eye (top) sees the particle asin(0.5/5)
# to the right of the centre, the right eye as far to the left, both on the
# equator (rows 89 and 90 meet at the horizon).
h = fits.open("out/ods.fits")
expect([x.name for x in h] == ["left.mass", "right.mass", "SCENE"], f"ods.fits HDUs {[x.name for x in h]}")
turn = math.degrees(math.asin(0.5 / 5))
for k, sign in ((0, 1), (1, -1)):
    d = np.nan_to_num(h[k].data)
    # Mass per steradian: row j of the 360 x 180 map is the band of latitude
    # 90 - j to 89 - j degrees, 1 degree wide.
    top = np.radians(90.0 - np.arange(180))[:, None]
    omega = np.radians(1.0) * (np.sin(top) - np.sin(top - np.radians(1.0)))
    w = (d * omega).sum()
    expect(abs(w - 1) < 1e-6, f"ods eye {k}: weight {w}, expected 1 (the other is skipped)")
    j, i = np.unravel_index(np.argmax(d), d.shape)
    expect(i == 180 + int(math.floor(sign * turn)), f"ods eye {k}: column {i}, expected the {sign * turn:.2f} deg one")
    expect(j in (89, 90), f"ods eye {k}: row {j}")
sys_exit = 0 if ok else 1
raise SystemExit(sys_exit)
EOT

# No parallax without perspective: refused before anything is written.
scene ortho near.txt anaglyph
sed -i 's/projection: perspective/projection: orthographic\n  width: 10/; /look_at/d; /up:/d; /fov:/d' ortho.yaml
expect_fail 2 "stereo.mode.*orthographic" out_ortho -- render ortho.yaml --set output.dir=out_ortho

# The shipped anaglyph scene renders (smaller here: 4 frames of its orbit),
# the camera orbiting at a constant distance from the centre it converges on.
"$ORRERY" render --quiet "$SRC/configs/anaglyph-orbit.yaml" --set output.dir=orbit --set animation.frames=4 \
  --set input.model.particles=20000 --set image.width=192 --set image.height=108 2>err.txt ||
  fail "configs/anaglyph-orbit.yaml: $(cat err.txt)"
for f in 0 1 2 3; do
  [ -s orbit/anaglyph-orbit_000$f.png ] || fail "configs/anaglyph-orbit.yaml wrote no PNG for frame $f"
done
"$py" - <<'PY' || fail "orbit: camera distance or convergence wrong"
import math
from astropy.io import fits
xs = []
for f in range(4):
    h = fits.getheader(f"orbit/anaglyph-orbit_000{f}.fits")
    # the left eye's camera: half the eye separation from the centre camera
    d = math.dist((h["CAMPOSX"], h["CAMPOSY"], h["CAMPOSZ"]), (0, 0, 0))
    assert abs(d - math.hypot(86.0232526, 45)) < 0.05, (f, d)
    xs.append(h["CAMPOSX"])
assert len(set(round(x, 3) for x in xs)) == 4, xs
PY
finish
