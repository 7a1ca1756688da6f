#!/usr/bin/env python3
"""Reads orrery's linear OpenEXR with OpenImageIO, as a compositor would: the
channels are R, G, B, A (no bare Z, which means depth) with the CIE planes in
the layer xyz; the chromaticities attribute says Rec. 709 / D65; alpha is
each pixel's coverage of the dome's circle (1 inside, 0 outside, where the
colour is 0, not NaN; on the rim the share inside, against an independent
count of sub-pixel points); and R, G, B are the linear sRGB of the X, Y, Z
the FITS file holds, premultiplied by alpha.
usage: check_exr_compositing.py ORRERY WORKDIR"""
import subprocess

import numpy as np
from astropy.io import fits

from check_lib import Checks, read_exr

check = Checks()
orrery, work = check.orrery, check.work


def render(name, scene):
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(scene)
    subprocess.run([orrery, "render", "--quiet", f"{name}.yaml"], cwd=work, check=True)


MODEL = ("input:\n  model:\n    name: mw-m31\n    particles: 20000\n  types: [2, 3]\n"
         "camera:\n  projection: dome\n  position: [-30, 0, 10]\n  look_at: [0, 0, 0]\n"
         "image:\n  width: 64\n  height: 64\n")
COLOUR = ("colour:\n  populations:\n    - name: bulge\n      select: {types: [3]}\n"
          "      colour: {temperature: 4000}\n      luminance: {mass: 1}\n"
          "    - name: disc\n      select: {types: [2]}\n      colour: {temperature: 9000}\n"
          "      luminance: {mass: 1}\n")
render("colour", MODEL + COLOUR + "output:\n  dir: out\n  name: colour\n  exr: true\n  png: false\n")
spec, ch = read_exr(f"{work}/out/colour.exr")
names = set(spec.channelnames)
check(names == {"R", "G", "B", "A", "xyz.X", "xyz.Y", "xyz.Z"}, f"colour channels {sorted(names)}")
chroma = spec.getattribute("chromaticities")
want = (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290)
check(chroma is not None and np.allclose(chroma, want, atol=1e-6), f"chromaticities {chroma}")
for name, plane in ch.items():
    check(np.isfinite(plane).all(), f"channel {name} has NaN or infinity")
a = ch["A"]
check(a[32, 32] == 1.0 and a[0, 0] == 0.0 and a[0, 63] == 0.0, "alpha: 1 at the centre, 0 in the corners")
# The circle of radius 32 pixels about the image's centre, 64 x 64 points a pixel.
k = 64
sub = (np.arange(64 * k) + 0.5) / k - 32.0
inside = (sub[:, None] ** 2 + sub[None, :] ** 2 <= 32.0**2).reshape(64, k, 64, k).mean(axis=(1, 3))
check(0 < a.min() + 1 and a.max() <= 1 and ((a > 0) & (a < 1)).sum() > 100, "alpha: partial on the rim")
check(np.abs(a - inside).max() < 1 / 16 + 1 / 64, f"alpha differs from the coverage by {np.abs(a - inside).max():g}")
check(abs(a.sum(dtype=np.float64) / (np.pi * 32**2) - 1) < 1e-3, f"alpha sums to {a.sum()}, not the circle's area")
outside = a == 0
check(all((ch[c][outside] == 0).all() for c in ("R", "G", "B")), "colour outside the circle is 0")
check(ch["R"].max() > 0 and ch["B"].max() > 0, "the galaxy is in R and B")
# The FITS planes hold the same X, Y, Z (rows bottom-up there), and R, G, B
# are their linear RGB in the primaries the file names: the matrix is built
# here from the chromaticities attribute (SMPTE RP 177), not taken from orrery.
with fits.open(f"{work}/out/colour.fits") as hdul:
    xyz = [np.nan_to_num(hdul[k].data[::-1]) for k in ("X", "Y", "Z")]
for k, c in enumerate(("xyz.X", "xyz.Y", "xyz.Z")):
    check(np.array_equal(ch[c], xyz[k].astype(np.float32)), f"{c} differs from the FITS plane")
xy = np.array(want, dtype=np.float64).reshape(4, 2)
cols = np.array([[x / y, 1.0, (1 - x - y) / y] for x, y in xy])  # XYZ of R, G, B, white (Y = 1)
primaries = cols[:3].T
rgb_to_xyz = primaries * np.linalg.solve(primaries, cols[3])
rgb = np.einsum("ij,jyx->iyx", np.linalg.inv(rgb_to_xyz), np.array(xyz, dtype=np.float64))
scale = max(np.abs(rgb).max(), 1e-30)
for k, c in enumerate("RGB"):
    err = np.abs(ch[c] - rgb[k] * a).max() / scale
    check(err < 1e-5, f"{c} differs from the linear RGB of X, Y, Z by {err:g} of the peak")

# A single weight: luminance Y and alpha, no colour channels to misread.
render("mono", MODEL + "output:\n  dir: out\n  name: mono\n  exr: true\n  png: false\n")
spec, ch = read_exr(f"{work}/out/mono.exr")
check(set(spec.channelnames) == {"Y", "A"}, f"mono channels {spec.channelnames}")
check(np.isfinite(ch["Y"]).all() and ch["A"][32, 32] == 1 and ch["A"][0, 0] == 0, "mono Y finite, alpha")
check.finish("EXR compositing checks")
