#!/bin/bash
# A uniform sky stays uniform through the glow's coarse maps
# (pass/coarse_glow.c, docs/sky.md#stars-from-particles): 3 000 equal
# stars spread evenly over the sky at 1 kpc, every one a glow tens of
# degrees wide (stars.limit -30: none drawn as a point), on a 512^2 dome
# master and a 512 x 256 Hammer-Aitoff panorama. Against the truth, the
# light over 4 pi: the interior's mean brightness within 3 %, and the rim
# rings (the outermost 2 % of the dome's radius and of the ellipse)
# within 25 % of the interior, averaged over four skies. (Before the coarse
# maps' linear map with its edge extension, the dome's outermost ring was
# at 0.63.)
. "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
cat >sky.yaml <<'Y'
input:
  file: pts.txt
  types: [2]
observer: {id: 1, reference_id: 2, normal: [0, 0, 1], dim: false}
colour:
  populations:
    - {name: all, select: {types: [2]}, colour: {bv: 0.65}, luminance: {mass: 1}}
psf: {kind: gaussian}
glow: {threshold: 1.0e30, max_arcmin: 5000}
stars: {limit: -30, types: [2], spread: 0.00001, glow_max: 90}
views:
  dome: {camera: {projection: dome}, image: {width: 512, height: 512}}
  pano: {camera: {projection: hammer-aitoff}, image: {width: 512, height: 256}}
output: {name: uni}
Y
for seed in 1 2 3 4; do
  "$py" - "$seed" <<'PY' || fail "writing the sky $seed"
import sys
import numpy as np
rng = np.random.default_rng(int(sys.argv[1]))
v = rng.normal(size=(3000, 3))
v /= np.linalg.norm(v, axis=1)[:, None]
with open("pts.txt", "w") as f:
    f.write("x y z mass id type\n0 0 0 0 1 1\n1 0 0 0 2 1\n")
    for i, (x, y, z) in enumerate(v):
        f.write(f"{x:.7f} {y:.7f} {z:.7f} 1 {i + 3} 2\n")
PY
  "$ORRERY" render sky.yaml -o "sky$seed" -q || fail "render of sky $seed"
done
"$py" - <<'PY' || fail "a uniform sky is not uniform"
import math
import numpy as np
from astropy.io import fits
truth = 3000 / (4 * math.pi)  # light per steradian
bad = []
for kind in ("dome", "pano"):
    inner, rings = [], []
    for seed in (1, 2, 3, 4):
        y = fits.getdata(f"sky{seed}/uni-{kind}.fits", "Y").astype(float)
        h, w = y.shape
        yy, xx = np.mgrid[:h, :w]
        u, v = (xx + 0.5 - w / 2) / (w / 2), (yy + 0.5 - h / 2) / (h / 2)
        r = np.hypot(u, v)
        ok = np.isfinite(y) & (r < 1)
        mean = y[ok & (r < 0.9)].mean()
        inner.append(mean)
        rings.append([y[ok & (r >= lo) & (r < hi)].mean() / mean for lo, hi in ((0.98, 0.99), (0.99, 1.0))])
    inner, rings = np.mean(inner), np.mean(rings, axis=0)
    print(f"{kind}: interior {inner:.2f} (truth {truth:.2f}); rim rings / interior {rings[0]:.3f} {rings[1]:.3f}")
    if abs(inner / truth - 1) > 0.03:
        bad.append(f"{kind}: interior {inner:.2f}, truth {truth:.2f}")
    if not np.all(np.abs(rings - 1) <= 0.25):
        bad.append(f"{kind}: rim rings {rings}")
print("\n".join(bad) or "ok")
raise SystemExit(1 if bad else 0)
PY
