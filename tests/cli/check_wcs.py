#!/usr/bin/env python3
"""Places particles at known (l, b) around an observer, renders Hammer-Aitoff,
equirectangular and dome maps with orrery, and checks with astropy's WCS
(wcslib, an independent implementation) that each particle landed in the
pixel the FITS header says. usage: check_wcs.py ORRERY WORKDIR"""
import subprocess
import sys

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS

from solid_angle import pixel_solid_angle

orrery, work = sys.argv[1], sys.argv[2]

# An observer off the origin, a tilted disc normal: nothing lines up with the axes.
obs = np.array([3.0, -2.0, 1.0])
ref = obs + np.array([7.0, 3.0, 2.0])
n0 = np.array([0.1, -0.2, 1.0])
z = n0 / np.linalg.norm(n0)
d = ref - obs
x = d - d.dot(z) * z
x /= np.linalg.norm(x)
y = np.cross(z, x)


def direction(l_deg, b_deg):
    l, b = np.radians(l_deg), np.radians(b_deg)
    return np.cos(b) * np.cos(l) * x + np.cos(b) * np.sin(l) * y + np.sin(b) * z


# Off the half-degree grid, so that no particle sits on a pixel boundary
# where rounding would pick either neighbour.
points = [(l + 0.37, b + 0.21) for l in range(-165, 180, 30) for b in (-70, -40, -15, 10, 35, 65)]
rows = ["x y z mass id", "%r %r %r 1000 1" % tuple(obs), "%r %r %r 0.5 2" % tuple(ref)]
for k, (l, b) in enumerate(points):
    p = obs + 10.0 * direction(l, b)
    rows.append("%r %r %r %d %d" % (p[0], p[1], p[2], k + 1, k + 3))
with open(f"{work}/sky.txt", "w") as f:
    f.write("\n".join(rows) + "\n")

views = {
    "hammer-aitoff": "  projection: hammer-aitoff\nimage:\n  width: 720\n  height: 360\n",
    "equirectangular": "  projection: equirectangular\nimage:\n  width: 720\n  height: 360\n",
    "dome": "  projection: dome\n  zenith: [40, 50]\n  front: [200, 10]\nimage:\n  width: 601\n  height: 601\n",
}


failures = 0
for name, camera in views.items():
    scene = (f"input:\n  file: sky.txt\nobserver:\n  id: 1\n  reference_id: 2\n  normal: [0.1, -0.2, 1.0]\n"
             f"  dim: false\ncamera:\n{camera}deposit: ngp\noutput:\n  dir: out\n  name: {name}\n  png: false\n")
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(scene)
    subprocess.run([orrery, "render", "--quiet", f"{name}.yaml"], cwd=work, check=True)
    with fits.open(f"{work}/out/{name}.fits") as hdul:
        data = hdul[0].data
        wcs = WCS(hdul[0].header)
    zenith = direction(40, 50)
    checked = 0
    for k, (l, b) in enumerate(points):
        if name == "dome" and np.degrees(np.arccos(np.clip(direction(l, b).dot(zenith), -1, 1))) > 85:
            continue  # below the dome's horizon
        px, py = wcs.all_world2pix(l, b, 0)
        i, j = int(np.round(px)), int(np.round(py))
        got = data[j, i] if 0 <= j < data.shape[0] and 0 <= i < data.shape[1] else None
        # A pixel holds mass per steradian: times its solid angle, the mass.
        got = got * pixel_solid_angle(wcs, i, j) if got is not None else None
        if got is None or abs(got - (k + 1)) > 1e-3 * (k + 1):
            print(f"{name}: particle at l={l:g} b={b:g} (mass {k + 1}): WCS pixel ({i}, {j}) holds {got}")
            failures += 1
        checked += 1
    # The total is every drawn particle's mass: nothing was lost or doubled.
    lit = np.argwhere(np.nan_to_num(data) != 0)
    total = sum(data[j, i] * pixel_solid_angle(wcs, i, j) for j, i in lit)
    print(f"{name}: {checked} particles checked against the WCS, image total {total:g}")
    if name != "dome":
        expected = sum(k + 1 for k in range(len(points))) + 0.5
        if abs(total - expected) > 1e-3 * expected:
            print(f"{name}: image total {total} != {expected}")
            failures += 1
    if name == "hammer-aitoff" and not np.isnan(data[0, 0]):
        print(f"{name}: the corner outside the ellipse is not blank (NaN)")
        failures += 1
sys.exit(1 if failures else 0)
