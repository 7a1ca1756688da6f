# Nightfall smoke test: configs/nightfall.yaml (the King cluster, colours
# from the CMD, 1/r^2 from the camera, the HST PSF, the inspiral) at a tiny
# size, 3 frames: every frame is written; the camera closes in on the
# centre; the brightest region (a 21-pixel box sum of the linear Y plane,
# single bright stars clipped at the 95th percentile) stays at the image
# centre; the centre outshines the border; star colours span blue
# horizontal-branch stars to red giants. Then the spikes over a black sky,
# a star's 1/r^2 as the camera passes, and the scene's error checks.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

mkdir -p out
if ! "$ORRERY" render "$SRC/configs/nightfall.yaml" -o out --set input.model.particles=200000 \
    --set animation.frames=3 --set image.width=96 --set image.height=64 >render.txt 2>&1; then
  fail "render: $(cat render.txt)"
fi
for f in 0 1 2; do
  [ -s "out/nightfall_000$f.png" ] || fail "frame $f: no PNG"
  [ -s "out/nightfall_000$f.fits" ] || fail "frame $f: no FITS"
done

"$py" - out <<'PY' || fail "structure of the frames"
import math, sys
import numpy as np
from astropy.io import fits
from PIL import Image

def box_sum(a, k):
    c = np.cumsum(np.cumsum(np.pad(a, ((1, 0), (1, 0))), 0), 1)
    return c[k:, k:] - c[:-k, k:] - c[k:, :-k] + c[:-k, :-k]

bad, xs = [], []
for f in range(3):
    path = f"{sys.argv[1]}/nightfall_{f:04d}.fits"
    X, Y, Z = (fits.getdata(path, n).astype(float) for n in "XYZ")
    hdr = fits.getheader(path)
    h, w = Y.shape
    if (w, h) != (96, 64):
        bad.append(f"frame {f}: {w}x{h}")
    png = Image.open(f"{sys.argv[1]}/nightfall_{f:04d}.png")
    if png.size != (96, 64):
        bad.append(f"frame {f}: PNG {png.size}")
    if not hdr.get("DIMMED"):
        bad.append(f"frame {f}: not dimmed from the camera")
    # The inspiral: exponential from 12 to 4 pc, eased in-out (u = 0, 1/2, 1).
    dist = math.sqrt(sum(hdr[k] ** 2 for k in ("CAMPOSX", "CAMPOSY", "CAMPOSZ")))
    want = 12 * (4 / 12) ** (f / 2)
    if abs(dist - want) > 1e-3 * want:
        bad.append(f"frame {f}: camera {dist:.4f} pc from the centre, expected {want:.4f}")
    k = 21
    s = box_sum(np.minimum(Y, np.percentile(Y, 95)), k)
    j, i = np.unravel_index(np.argmax(s), s.shape)
    dx, dy = i + k / 2 - w / 2, j + k / 2 - h / 2
    if abs(dx) > 6 or abs(dy) > 6:
        bad.append(f"frame {f}: brightest region off centre by ({dx}, {dy}) pixels")
    inner = Y[h // 2 - 10:h // 2 + 10, w // 2 - 10:w // 2 + 10].mean()
    border = np.concatenate([Y[:8].ravel(), Y[-8:].ravel(), Y[:, :8].ravel(), Y[:, -8:].ravel()]).mean()
    if not inner > 1.5 * border:
        bad.append(f"frame {f}: centre {inner:g} vs border {border:g}: no concentration")
    S = X + Y + Z
    lit = Y > np.percentile(Y, 90)
    xs.extend((X[lit] / S[lit]).tolist())
# CIE x: blue horizontal branch (~10 000 K, x 0.28) and red giants (~4000 K, x 0.38).
if not (min(xs) < 0.30 and max(xs) > 0.37):
    bad.append(f"chromaticity x spans only {min(xs):.3f} to {max(xs):.3f}")
for b in bad:
    print(b, file=sys.stderr)
sys.exit(1 if bad else 0)
PY

# Spikes over a black sky (docs/nightfall.md): at a small size with the
# production frame's crowding (about 1.9 stars a pixel: 111 000 stars on
# 320x180 as 10^6 on 960x540), one of the three brightest stars has spikes
# at least 10 times the local background and 6 times the light between
# them, 3 core widths out, and the PNG's sky median is at most 3/255, at
# the first and the last frame. Without the spike gain the same check
# fails: diffraction alone puts too little light in the spikes.
if ! "$ORRERY" render "$SRC/configs/nightfall.yaml" -o spikes --set input.model.particles=111000 \
    --set animation.frames=2 --set image.width=320 --set image.height=180 >render2.txt 2>&1; then
  fail "render at 320x180: $(cat render2.txt)"
fi
for f in 0 1; do
  "$py" "$SRC/tests/cli/check_nightfall_spikes.py" spikes/nightfall_000$f.fits --min-spike 10 --min-ratio 6 \
    --max-sky 3 >spikes$f.txt 2>&1 || fail "frame $f of 2: $(cat spikes$f.txt)"
done
if ! "$ORRERY" render "$SRC/configs/nightfall.yaml" -o nogain --set input.model.particles=111000 \
    --set animation.frames=2 --frames 0 --set image.width=320 --set image.height=180 \
    --set psf.spike_gain=1 >render3.txt 2>&1; then
  fail "render without the gain: $(cat render3.txt)"
fi
"$py" "$SRC/tests/cli/check_nightfall_spikes.py" nogain/nightfall_0000.fits --min-spike 10 --min-ratio 6 \
  --max-sky 3 --expect-fail >nogain.txt 2>&1 || fail "spikes without the gain: $(cat nogain.txt)"

# The stars drawn one by one give the same bits on one thread and three
# (the spike stars chosen in a fixed order, their stamps made row by row).
for t in 1 3; do
  OMP_NUM_THREADS=$t "$ORRERY" render "$SRC/configs/nightfall.yaml" -o threads$t -q --frames 0 \
    --set input.model.particles=30000 --set image.width=160 --set image.height=90 || fail "render on $t threads"
done
"$py" -c "import sys, numpy as np; from astropy.io import fits; \
a, b = (fits.open(p) for p in sys.argv[1:]); \
sys.exit(0 if all(np.array_equal(a[n].data, b[n].data) for n in 'XYZ') else 'X, Y or Z differ')" \
  threads1/nightfall_0000.fits threads3/nightfall_0000.fits || fail "thread count changed the picture"

# 1/r^2 as the camera passes a star: one star at the origin, the camera on
# a line 1 unit from it, looking at it, drawn with the Nightfall PSF (its
# core and, the only star, its whole PSF with the gain). Its flux, Y times
# each pixel's solid angle from the WCS (solid_angle.py), falls as 1/d^2,
# d the camera's distance in the header, to 1 % (the PSF's light beyond the
# frame's edge is all that is lost).
printf "x y z V BV\n0 0 0 0 0.9\n" >star.txt
cat >pass.yaml <<YAML
input: {file: star.txt}
camera:
  projection: perspective
  fov: 40
  dim: true
  dim_near: 0.01
  path: {kind: line, from: [-4, 1, 0], to: [4, 1, 0], look_at: [0, 0, 0], up: [0, 0, 1]}
animation: {frames: 5}
image: {width: 320, height: 180}
deposit: cic
psf: {kind: hst, fwhm: 1.5, spike_stars: 300, spike_gain: 40}
colour:
  populations:
    - {name: stars, colour: {bv_field: BV}, luminance: {magnitude_field: V}}
output: {name: pass}
YAML
"$ORRERY" render pass.yaml -o pass >render4.txt 2>&1 || fail "render of the passing star: $(cat render4.txt)"
"$py" - pass "$SRC/tests/cli" <<'PY' || fail "a passing star's flux against 1/d^2"
import math, sys
import numpy as np
from astropy.io import fits
sys.path.insert(0, sys.argv[2])
from solid_angle import solid_angles
bad, rows = [], []
for f in range(5):
    path = f"{sys.argv[1]}/pass_{f:04d}.fits"
    Y, hdr = fits.getdata(path, "Y").astype(float), fits.getheader(path, "Y")
    flux = float(np.sum(Y * solid_angles(hdr)))
    d2 = sum(hdr[k] ** 2 for k in ("CAMPOSX", "CAMPOSY", "CAMPOSZ"))
    rows.append((f, d2, flux, flux * d2))
ref = rows[2][3]
for f, d2, flux, fd2 in rows:
    print(f"frame {f}: d^2 {d2:.3f}, flux {flux:.6g}, flux d^2 / frame 2's {fd2 / ref:.4f}")
    if abs(fd2 / ref - 1) > 0.01:
        bad.append(f"frame {f}: flux times d^2 is {fd2 / ref:.4f} of frame 2's")
for b in bad:
    print(b, file=sys.stderr)
sys.exit(1 if bad else 0)
PY

# The king model's keys are checked and named.
expect_fail 2 "input.model.w0" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 --set input.model.w0=40
expect_fail 2 "input.model.separation.*king" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 \
  --set input.model.separation=100
expect_fail 2 "camera.dim_near" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 --set camera.dim=false
# The PSF's keys: the gain and the vanes are the generated Hubble PSF's;
# compose cannot change a PSF drawn star by star into the raw planes.
expect_fail 2 "psf.spike_gain is used only with psf.kind: hst" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 \
  --set psf.kind=gaussian
expect_fail 2 "psf.vane_width is used only with psf.kind: hst" out2 -- render "$SRC/configs/text-table-perspective.yaml" \
  -o out2 --set psf.vane_width=0.05
expect_fail 2 "psf.spike_gain" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 --set psf.spike_gain=0.5
expect_fail 2 "draws its stars one by one" out2 -- compose "$SRC/configs/nightfall.yaml" -o out2 --set psf.spike_gain=2
finish
