#!/usr/bin/env python3
"""Stars that do not twinkle: 100 stars at random sub-pixel positions near
the zenith of a dome master and 50 about 70 degrees out, drawn with the
automatic PSF core (psf.fwhm_arcmin: auto). Each must keep its flux (pixels
times their solid angles, from the WCS) to 0.1 %, its centroid within 0.05
pixel of where the map puts it, and the share of its flux in its brightest
pixel may vary by at most 1.2x among them. With the core of 2 pixels that
Future Sky used before, the share varied by 1.39x.
usage: check_star_shimmer.py ORRERY WORKDIR"""
import math
import sys

import numpy as np

import sky_stars

orrery, work = sys.argv[1], sys.argv[2]
SIZE = 601
c = SIZE / 2.0
f = c / (math.pi / 2)  # pixels per radian of the hemisphere master


def direction(px, py):
    """The direction at image point (px, py) of this scene's dome: the
    zenith +z at the centre, +x (the reference, l = 0, the front) down,
    +y (l = 90) to the left."""
    u, w = px - c, py - c
    r = math.hypot(u, w)
    t = r / f
    return (math.sin(t) * w / r, -math.sin(t) * u / r, math.cos(t))


rng = np.random.default_rng(7)
truth = []
for k in range(100):  # near the zenith: a 10 x 10 grid 24 pixels apart
    truth.append((c + 24 * (k % 10 - 4.5), c + 24 * (k // 10 - 4.5)))
for k in range(50):  # about 70 degrees out, all round, 33 pixels apart
    a = 2 * math.pi * k / 50
    r = f * math.radians(70)
    truth.append((c + r * math.cos(a), c + r * math.sin(a)))
truth = [(x + o[0] - 0.5, y + o[1] - 0.5) for (x, y), o in zip(truth, rng.random((150, 2)))]
stars = [(direction(x, y), 1.0) for x, y in truth]
data, head = sky_stars.render(orrery, work, "shimmer", stars, "  projection: dome\n  dome_fov: 180\n  zenith: [0, 90]",
                              (SIZE, SIZE), "  kind: gaussian")
light = np.nan_to_num(data)
jj, ii = np.mgrid[0:SIZE, 0:SIZE]
failures = 0
for name, group in (("zenith", truth[:100]), ("70 degrees out", truth[100:])):
    flux, err, share = [], [], []
    for x, y in group:
        box = (np.abs(ii + 0.5 - x) < 9) & (np.abs(jj + 0.5 - y) < 9)  # the core's support, not a neighbour's
        w = np.where(box, light, 0.0)
        total = w.sum()
        flux.append(total)
        err.append(math.hypot((w * (ii + 0.5)).sum() / total - x, (w * (jj + 0.5)).sum() / total - y))
        share.append(w.max() / total)
    ratio = max(share) / min(share)
    print(f"{name}: core {head['PSFFWHM']:.3f} arcmin; flux {min(flux):.6f} to {max(flux):.6f}, "
          f"centroid within {max(err):.4f} px, peak share {min(share):.4f} to {max(share):.4f} ({ratio:.3f}x)")
    if max(abs(v - 1) for v in flux) > 1e-3 or max(err) > 0.05 or ratio > 1.2:
        print(f"FAIL {name}: a star twinkles, moves or loses light")
        failures += 1
expected = 3.2 / f * 180 / math.pi * 60
if abs(head["PSFFWHM"] - expected) > 1e-6 * expected:
    print(f"FAIL: PSFFWHM {head['PSFFWHM']}, expected the automatic {expected} arcmin (3.2 pixels)")
    failures += 1
sys.exit(1 if failures else 0)
