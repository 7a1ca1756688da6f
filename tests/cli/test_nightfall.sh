# Nightfall smoke test: configs/nightfall.yaml (the King cluster, colours
# from the CMD, 1/r^2 from the camera, the HST PSF, the inspiral) at a tiny
# size, 3 frames: every frame is written; the camera closes in on the
# centre; the brightest region (a 21-pixel box sum of the linear Y plane,
# single bright stars clipped at the 95th percentile) stays at the image
# centre; the centre outshines the border; star colours span blue
# horizontal-branch stars to red giants. Then the scene's error checks.
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

# The king model's keys are checked and named.
expect_fail 2 "input.model.w0" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 --set input.model.w0=40
expect_fail 2 "input.model.separation.*king" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 \
  --set input.model.separation=100
expect_fail 2 "camera.dim_near" out2 -- render "$SRC/configs/nightfall.yaml" -o out2 --set camera.dim=false
finish
