#!/usr/bin/env python3
"""Reads orrery's HEALPix maps with healpy, independent of orrery: a uniform
sky (a Fibonacci lattice of equal particles) gives a uniform map whose
pixels times their area sum to the mass; particles at known (l, b) around a
tilted observer frame land in the pixels healpy.ang2pix names, in RING and
NESTED order; the header says ordering, nside and the galactic COORDSYS;
the checksums verify. usage: check_healpix.py ORRERY WORKDIR"""
import shutil
import subprocess
import warnings

import healpy as hp
import numpy as np
from astropy.io import fits

from check_lib import Checks

check = Checks()
orrery, work = check.orrery, check.work


def render(name, table, body):
    with open(f"{work}/{name}.txt", "w") as f:
        f.write("\n".join(table) + "\n")
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(f"input:\n  file: {name}.txt\n{body}deposit: ngp\noutput:\n  dir: out\n  name: {name}\n")
    subprocess.run([orrery, "render", "--quiet", f"{name}.yaml"], cwd=work, check=True)
    return f"{work}/out/{name}.fits"


# A uniform sky: 200000 equal particles on a Fibonacci lattice around the camera.
n, nside = 200000, 8
k = np.arange(n) + 0.5
z = 1 - 2 * k / n
phi = np.pi * (1 + 5 ** 0.5) * k
rho = np.sqrt(1 - z * z)
rows = ["x y z mass"] + ["%r %r %r 0.5" % (10 * r * np.cos(p), 10 * r * np.sin(p), 10 * zz)
                         for r, p, zz in zip(rho, phi, z)]
path = render("uniform", rows, f"camera:\n  projection: healpix\n  healpix_nside: {nside}\n")
m, h = hp.read_map(path, h=True)
h = dict(h)
check(len(m) == 12 * nside * nside, f"{len(m)} pixels")
check(h.get("ORDERING") == "RING" and h.get("NSIDE") == nside and h.get("PIXTYPE") == "HEALPIX", f"header {h}")
check("COORDSYS" not in h, "a map without an observer claims a COORDSYS")
total = m.sum() * hp.nside2pixarea(nside)
check(abs(total - 0.5 * n) < 1e-6 * 0.5 * n, f"mass {total!r}, expected {0.5 * n}")
spread = np.abs(m / m.mean() - 1)
print(f"uniform sky: mass {total:.9g} of {0.5 * n:g}; pixels within {spread.max():.2%} of the mean, rms {spread.std():.2%}")
# About 260 lattice points a pixel: a point more or less is 0.4 %.
check(spread.max() < 0.05 and np.sqrt((spread ** 2).mean()) < 0.015, "the uniform sky is not uniform")
with warnings.catch_warnings():
    warnings.simplefilter("error")
    with fits.open(path, checksum=True) as hdul:
        check(all(hdu.verify_checksum() == 1 and hdu.verify_datasum() == 1 for hdu in hdul), "checksums")
if shutil.which("fitsverify"):
    out = subprocess.run(["fitsverify", "-q", path], capture_output=True, text=True).stdout
    check(out.startswith("verification OK"), f"fitsverify: {out.strip()}")

# Particles at known (l, b) in a tilted observer frame (tests/cli/check_wcs.py's).
obs = np.array([3.0, -2.0, 1.0])
ref = obs + np.array([7.0, 3.0, 2.0])
zax = np.array([0.1, -0.2, 1.0])
zax /= np.linalg.norm(zax)
d = ref - obs
xax = d - d.dot(zax) * zax
xax /= np.linalg.norm(xax)
yax = np.cross(zax, xax)
points = [(l + 0.37, b + 0.21) for l in range(-165, 180, 30) for b in (-70, -40, -15, 10, 35, 65)]
rows = ["x y z mass id", "%r %r %r 1000 1" % tuple(obs), "%r %r %r 0.5 2" % tuple(ref)]
for j, (l, b) in enumerate(points):
    lr, br = np.radians(l), np.radians(b)
    p = obs + 10 * (np.cos(br) * np.cos(lr) * xax + np.cos(br) * np.sin(lr) * yax + np.sin(br) * zax)
    rows.append("%r %r %r %d %d" % (p[0], p[1], p[2], j + 1, j + 3))
for order in ("ring", "nested"):
    path = render(f"sky-{order}", rows, "observer:\n  id: 1\n  reference_id: 2\n  normal: [0.1, -0.2, 1.0]\n"
                  f"  dim: false\ncamera:\n  projection: healpix\n  healpix_nside: 16\n  healpix_order: {order}\n")
    m, h = hp.read_map(path, h=True, nest=None)
    h = dict(h)
    nest = order == "nested"
    check(h.get("ORDERING") == ("NESTED" if nest else "RING") and h.get("COORDSYS") == "G", f"{order} header")
    area = hp.nside2pixarea(16)
    for j, (l, b) in enumerate(points):
        pix = hp.ang2pix(16, l, b, nest=nest, lonlat=True)
        got = m[pix] * area
        check(abs(got - (j + 1)) < 1e-4 * (j + 1), f"{order}: particle at l={l:g} b={b:g}: pixel {pix} holds {got}")
    check(abs(m.sum() * area - (sum(range(1, len(points) + 1)) + 0.5)) < 1e-3, f"{order}: total {m.sum() * area}")
check.finish("HEALPix checks")
