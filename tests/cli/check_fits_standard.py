#!/usr/bin/env python3
"""Reads orrery's FITS outputs with astropy, as an astronomer would: BUNIT is
a FITS unit astropy parses and CCDData.read accepts the file; every HDU's
CHECKSUM and DATASUM verify; a perspective frame's -TAN WCS and an
orthographic view's linear WCS put the camera's known points (particles, the
centre, a corner) where the camera draws them; a dome without an observer
does not claim galactic axes. usage: check_fits_standard.py ORRERY WORKDIR"""
import shutil
import subprocess
import warnings

import numpy as np
from astropy import units as u
from astropy.io import fits
from astropy.nddata import CCDData
from astropy.wcs import WCS

from check_lib import Checks

check = Checks()
orrery, work = check.orrery, check.work


def render(name, body, particles, output=""):
    rows = ["x y z mass id"] + ["%r %r %r %r %d" % (p[0], p[1], p[2], m, k + 1) for k, (p, m) in
                                 enumerate(particles)]
    with open(f"{work}/{name}.txt", "w") as f:
        f.write("\n".join(rows) + "\n")
    scene = (f"input:\n  file: {name}.txt\n{body}deposit: ngp\n"
             f"output:\n  dir: out\n  name: {name}\n  png: false\n{output}")
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(scene)
    subprocess.run([orrery, "render", "--quiet", f"{name}.yaml"], cwd=work, check=True)
    return f"{work}/out/{name}.fits"


def check_standard(path, unit):
    """BUNIT, CCDData, checksums and fitsverify for every HDU of path."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a failed checksum is only a warning in astropy
        with fits.open(path, checksum=True) as hdul:
            for hdu in hdul:
                check(hdu.verify_checksum() == 1 and hdu.verify_datasum() == 1,
                      f"{path}[{hdu.name}]: CHECKSUM/DATASUM do not verify")
                if hdu.name == "SCENE":  # the scene's text (tests/cli/check_fits_scene.py)
                    continue
                check(hdu.header.get("BUNIT") == unit,
                      f"{path}[{hdu.name}]: BUNIT {hdu.header.get('BUNIT')!r}, expected {unit!r}")
                u.Unit(hdu.header["BUNIT"], format="fits")  # raises if not a FITS unit
    ccd = CCDData.read(path)
    check(ccd.unit == u.Unit(unit, format="fits"), f"{path}: CCDData unit {ccd.unit}")
    if shutil.which("fitsverify"):
        out = subprocess.run(["fitsverify", "-q", path], capture_output=True, text=True).stdout
        check(out.startswith("verification OK"), f"{path}: fitsverify: {out.strip()}")


def image_point_to_fits(x, y, height):
    """Continuous image coordinates (row 0 at the top) to FITS 0-based pixel
    coordinates (rows stored bottom-up)."""
    return x - 0.5, height - y - 0.5


def lb(d):
    return np.degrees(np.arctan2(d[1], d[0])), np.degrees(np.arcsin(d[2] / np.linalg.norm(d)))


# A perspective frame: gnomonic, so -TAN, in the scene's own axes.
fwd = np.array([1.0, 0.3, 0.2])
fwd /= np.linalg.norm(fwd)
up = np.array([0.0, 0.0, 1.0])
right = np.cross(fwd, up)
right /= np.linalg.norm(right)
down = np.cross(fwd, right)
W, H, fov = 400, 300, 60.0
focal = 0.5 * max(W, H) / np.tan(np.radians(fov / 2))
offsets = [(0.013, 0.011), (0.3, -0.2), (-0.45, 0.3), (0.21, 0.33), (-0.1, -0.37)]
stars = [5.0 * (fwd + a * right + b * down) for a, b in offsets]
path = render("persp", f"camera:\n  projection: perspective\n  fov: {fov}\n  position: [0, 0, 0]\n"
              f"  direction: {list(fwd)}\n  up: [0, 0, 1]\nimage:\n  width: {W}\n  height: {H}\n",
              [(p, 1.0) for p in stars], "  bunit: solMass\n")
check_standard(path, "solMass sr-1")
with fits.open(path) as hdul:
    hdr, data = hdul[0].header, hdul[0].data
wcs = WCS(hdr)
check(hdr["CTYPE1"] == "WDLN-TAN" and hdr["CTYPE2"] == "WDLT-TAN", f"perspective CTYPE {hdr['CTYPE1']}")
for k, p in enumerate(stars):
    px, py = wcs.all_world2pix(*lb(p), 0)
    i, j = int(np.round(px)), int(np.round(py))
    check(0 <= i < W and 0 <= j < H and data[j, i] > 0, f"perspective star {k}: WCS pixel ({i}, {j}) is dark")
    # The camera's own projection, to 0.01 pixel.
    c = p.dot(right) / p.dot(fwd), p.dot(down) / p.dot(fwd)
    ex, ey = image_point_to_fits(W / 2 + focal * c[0], H / 2 + focal * c[1], H)
    check(abs(px - ex) < 0.01 and abs(py - ey) < 0.01, f"perspective star {k}: WCS ({px}, {py}) vs ({ex}, {ey})")
for x, y in [(W / 2, H / 2), (0, 0), (W, H)]:  # the centre and two corners
    d = fwd + (x - W / 2) / focal * right + (y - H / 2) / focal * down
    got = wcs.all_pix2world(*image_point_to_fits(x, y, H), 0)
    dl = (got[0] - lb(d)[0] + 180) % 360 - 180
    check(abs(dl) < 1e-6 and abs(got[1] - lb(d)[1]) < 1e-6, f"perspective point ({x}, {y}): {got} vs {lb(d)}")

# An orthographic view: linear axes in scene lengths along right and up.
path = render("ortho", "camera:\n  projection: orthographic\n  width: 10\n  position: [1, 2, 3]\n"
              "  direction: [0, 0, -1]\n  up: [0, 1, 0]\nimage:\n  width: 200\n  height: 100\n",
              [((3.013, 3.017, 0.0), 1.0), ((1.0 - 4.107, 2.0 - 2.213, 0.0), 1.0)],
              "  bunit: 10**10 solMass\n  length_unit: kpc\n")
check_standard(path, "10**10 solMass kpc-2")
with fits.open(path) as hdul:
    hdr, data = hdul[0].header, hdul[0].data
wcs = WCS(hdr)
check(hdr["CUNIT1"] == "kpc", "orthographic CUNIT1")
for off in [(2.013, 1.017), (-4.107, -2.213)]:  # off the pixels' edges
    px, py = wcs.all_world2pix(off[0], off[1], 0)
    i, j = int(np.round(px)), int(np.round(py))
    check(data[j, i] > 0, f"orthographic particle at {off}: WCS pixel ({i}, {j}) is dark")
corner = wcs.all_pix2world(*image_point_to_fits(0, 0, 100), 0)  # top left: left and up
check(np.allclose(corner, [-5.0, 2.5], atol=1e-9), f"orthographic top-left corner at {corner}")
centre = wcs.all_pix2world(*image_point_to_fits(100, 50, 100), 0)
check(np.allclose(centre, [0.0, 0.0], atol=1e-9), f"orthographic centre at {centre}")

# A dome without an observer: the scene's axes, not galactic ones; the
# weight's unit unknown, so the values are per steradian of pure numbers.
path = render("dome", "camera:\n  projection: dome\nimage:\n  width: 101\n  height: 101\n",
              [((0.0, 0.0, 5.0), 1.0)])
check_standard(path, "sr-1")
with fits.open(path) as hdul:
    hdr = hdul[0].header
check(hdr["CTYPE1"] == "WDLN-ARC" and hdr["CTYPE2"] == "WDLT-ARC", f"dome CTYPE {hdr['CTYPE1']}")
check.finish("FITS standard checks")
