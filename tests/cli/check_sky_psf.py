#!/usr/bin/env python3
"""A sky map's PSF is drawn at an angular size, so stars keep their size in
degrees anywhere on a dome master, although its tangential pixel scale is
theta/sin(theta) times the radial one. Places stars at the zenith and at
30, 60 and 85 degrees from it, renders a 180-degree dome master with a
Gaussian PSF of 2 degrees FWHM, and measures each star's size in degrees,
radially and tangentially, from the image's second moments.
usage: check_sky_psf.py ORRERY WORKDIR"""
import math
import sys

import numpy as np

import sky_stars
from sky_stars import unit

orrery, work = sys.argv[1], sys.argv[2]
SIZE, FWHM_DEG = 721, 2.0
# The observer at the origin looks up +z (the dome's zenith: camera.zenith
# [0, 90] with observer.normal +z); the reference particle sets l = 0 along +x.
angles = [0.0, 30.0, 60.0, 85.0]  # degrees from the zenith
azimuth = 200.0                   # degrees, away from the reference direction
stars = [(unit(t, azimuth), 1.0) for t in angles]
camera = "  projection: dome\n  dome_fov: 180\n  zenith: [0, 90]"
data, _ = sky_stars.render(orrery, work, "psf", stars, camera, (SIZE, SIZE),
                           f"  kind: gaussian\n  fwhm_arcmin: {FWHM_DEG * 60}")
data = np.nan_to_num(data)
c = SIZE / 2.0
f_pix_per_rad = (SIZE / 2.0) / (math.pi / 2)  # 180-degree dome: the rim is 90 degrees out
jj, ii = np.mgrid[0:SIZE, 0:SIZE]
u, v = ii + 0.5 - c, jj + 0.5 - c
failures = 0
sizes = []
for t in angles:
    # The star's pixel position: the radius is f theta; find it as the
    # brightest pixel's neighbourhood instead of assuming the azimuth's sign.
    rad = f_pix_per_rad * math.radians(t)
    window = (np.hypot(u, v) - rad) ** 2 < (6 * FWHM_DEG / 2.355 * f_pix_per_rad * math.pi / 180 * 3) ** 2
    near = np.where(window, data, 0.0)
    j0, i0 = np.unravel_index(np.argmax(near), near.shape)
    box = (abs(ii - i0) < 40) & (abs(jj - j0) < 40)
    w = np.where(box, data, 0.0)
    m = w.sum()
    mu, mv = (w * u).sum() / m, (w * v).sum() / m
    r = math.hypot(mu, mv)
    er = (mu / r, mv / r) if r > 0 else (1.0, 0.0)
    et = (-er[1], er[0])
    du, dv = u - mu, v - mv
    var_r = (w * (du * er[0] + dv * er[1]) ** 2).sum() / m
    var_t = (w * (du * et[0] + dv * et[1]) ** 2).sum() / m
    theta = r / f_pix_per_rad
    # Radially a pixel is 1/f radians at every theta; tangentially
    # sin(theta) / (f theta) (1/f at the zenith).
    rad_deg = 2.3548 * math.sqrt(var_r) / f_pix_per_rad * 180 / math.pi
    stretch = math.sin(theta) / theta if theta > 1e-9 else 1.0
    tan_deg = 2.3548 * math.sqrt(var_t) / f_pix_per_rad * stretch * 180 / math.pi
    sizes.append((t, rad_deg, tan_deg))
    print(f"star {t:4.0f} deg from the zenith: FWHM {rad_deg:.3f} deg radially, {tan_deg:.3f} deg tangentially")
ref = sizes[0][1]
# The kernel's half-maximum width is the FWHM asked for; its second moment
# (what 2.3548 sigma measures) is a little narrower than a Gaussian's.
if abs(ref / FWHM_DEG - 1) > 0.10:
    print(f"FAIL: the zenith star's FWHM is {ref:.3f} deg, {FWHM_DEG} deg was asked for")
    failures += 1
for t, a, b in sizes:
    for name, val in (("radial", a), ("tangential", b)):
        if abs(val / ref - 1) > 0.10:
            print(f"FAIL: the star {t} deg out has {name} FWHM {val:.3f} deg, the zenith star {ref:.3f} deg")
            failures += 1
# The pixel-space FWHM at the rim must really differ (else the test proves nothing).
print("(the dome's tangential scale at 85 deg is %.2f times the radial one)" % (math.radians(85) / math.sin(math.radians(85))))
sys.exit(1 if failures else 0)
