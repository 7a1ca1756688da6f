#!/usr/bin/env python3
"""The glow (glow.threshold, docs/sky.md#unresolved-starlight-as-a-glow):
faint stars crowded on the sky are drawn as kernels as wide as the angle to
their neighbours, bright or isolated ones as the PSF's core. On a
Hammer-Aitoff map from an observer:

- a cluster of 1000 faint stars in a cap 40 degrees across (smoothing.neighbours
  64) becomes smooth
  light (the pixel-to-pixel scatter inside it falls to under half of the
  points' own) with the same light in it;
- a bright star (flux above the threshold) and an isolated faint star (its
  neighbours farther than glow.max_arcmin) are drawn exactly as without
  the glow;
- the whole map holds the same flux as without the glow, and the same bits
  on one thread as on two.
usage: check_glow.py ORRERY WORKDIR"""
import math
import os
import subprocess
import sys

import numpy as np
from astropy.io import fits

import sky_stars
from solid_angle import unit

orrery, work = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


rng = np.random.default_rng(2)
centre = np.array(unit(40, 20))
# Uniform in a cap of 20 degrees radius about centre: the 32nd neighbour
# about 3.6 degrees away, a kernel wider than the PSF's core (1.6 degrees).
east = np.cross([0, 0, 1], centre)
east /= np.linalg.norm(east)
north = np.cross(centre, east)
stars = []
for _ in range(1000):
    t = math.acos(1 - rng.random() * (1 - math.cos(math.radians(20))))
    a = rng.uniform(0, 2 * math.pi)
    d = math.cos(t) * centre + math.sin(t) * (math.cos(a) * east + math.sin(a) * north)
    stars.append((tuple(d), 1e-3))
bright = (tuple(unit(-60, 0)), 1.0)
alone = (tuple(unit(-120, -30)), 1e-3)
stars += [bright, alone]
camera = "  projection: hammer-aitoff"
size = (720, 360)
psf = "  kind: gaussian"
glow = psf + "\nglow:\n  threshold: 0.5\n  max_arcmin: 600\nsmoothing:\n  neighbours: 64"
plain, head = sky_stars.render(orrery, work, "plain", stars, camera, size, psf)
glowing, _ = sky_stars.render(orrery, work, "glow", stars, camera, size, glow)
plain, glowing = np.nan_to_num(plain), np.nan_to_num(glowing)

total_p, total_g = plain.sum(), glowing.sum()
check(abs(total_g / total_p - 1) < 1e-5, f"the map's flux is kept: {total_g:.7f} with the glow, {total_p:.7f} without")

# Pixel directions (top row first, as sky_stars gives images).
from astropy.wcs import WCS
jj, ii = np.mgrid[0:size[1], 0:size[0]]
lon, lat = WCS(head).all_pix2world(ii, jj, 0)
pix = unit(lon, lat)[::-1]
cosang = np.nan_to_num(pix @ centre)
inner = cosang > math.cos(math.radians(12))
scatter_p = plain[inner].std() / plain[inner].mean()
scatter_g = glowing[inner].std() / glowing[inner].mean()
check(scatter_g < 0.5 * scatter_p, f"the cluster glows smoothly: pixel scatter {scatter_g:.3f} of the mean, "
      f"{scatter_p:.3f} as points")
cap = cosang > math.cos(math.radians(24))
check(abs(glowing[cap].sum() / plain[cap].sum() - 1) < 0.02,
      f"... with its light where it was: {glowing[cap].sum() / plain[cap].sum():.4f} of it within 24 degrees")
for name, (d, m) in (("bright star", bright), ("isolated faint star", alone)):
    near = np.nan_to_num(pix @ np.array(d)) > math.cos(math.radians(3))
    diff = np.abs(glowing[near] - plain[near]).max() / plain[near].max()
    check(diff < 1e-6, f"the {name} is drawn as without the glow (largest difference {diff:.2e} of its peak)")

env = dict(os.environ, OMP_NUM_THREADS="1")
subprocess.run([orrery, "render", "--quiet", "glow.yaml", "--set", "output.dir=one"], cwd=work, check=True, env=env)
a = fits.getdata(f"{work}/out/glow.fits")
b = fits.getdata(f"{work}/one/glow.fits")
check(np.array_equal(a, b, equal_nan=True), "one thread and two give the same bits")
sys.exit(1 if failures else 0)
