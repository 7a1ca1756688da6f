#!/usr/bin/env python3
"""The Hubble-like PSF on sky maps (psf.kind: hst, docs/psf.md): bright stars
get the whole PSF drawn in angle, faint ones only its core, and every star
keeps its flux.

Dome master (180 degrees, 1001 pixels): two equal bright stars, one at the
zenith and one 60 degrees from it, and a faint one (1e-4 of their flux).
Measured against this script's own model of the azimuthal-equidistant map
(r = f theta) and of the convention (north towards the top of the master,
east to the image's right at the centre, the PSF's angle counterclockwise
from east):
  - the total flux is the stars' to 1e-4;
  - around each bright star, the light 1.5-6 degrees out, binned in
    position angle from the local north, peaks at 45 + k 90 degrees (the
    spikes of psf.angle 45) at least 3 times above the light at k 90;
  - the spikes have the same angular length: the light in the spike wedges
    per ring of angle agrees between the two stars to 15 %, although the
    map's tangential scale at 60 degrees is 1.21 times the radial one;
  - the faint star (below psf.spike_min_flux) has no light beyond 1 degree.
Hammer-Aitoff panorama (1024x512): a bright star 1 degree from the l = 180
seam and one near the pole; the flux is conserved to 1e-4 and the star's
spikes reach both edges of the map.
psf.kind: file (Tiny Tim's NICMOS 2 PSF from the shared data, when there):
a star on a dome master keeps its flux to 1e-4 and has wings beyond 1 degree.
usage: check_sky_spikes.py ORRERY WORKDIR"""
import math
import os
import sys

import numpy as np

import sky_stars
from sky_stars import unit

orrery, work = sys.argv[1], sys.argv[2]
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures += 1


# The PSF's size and the spikes' flux threshold for every star field below,
# after its psf.kind.
PSF_SIZE = "  fwhm_arcmin: 12\n  spike_min_flux: 0.001"


def render(name, stars, camera, size, psf="  kind: hst"):
    return sky_stars.render(orrery, work, name, stars, camera, size, psf + "\n" + PSF_SIZE)


def flux_conserved(data, total, what):
    got = np.nansum(data)
    check(abs(got - total) <= 1e-4 * total, f"{what}: flux {got:.7g}, the stars' {total:.7g}")
    lo = np.nanmin(data)
    check(lo >= -1e-6 * np.nanmax(data), f"{what}: no negative light (min {lo:.3g})")


# ---- dome master ----
SIZE = 1001
bright_at = [0.0, 60.0]
stars = [(unit(t, 200.0), 1.0) for t in bright_at] + [(unit(30.0, 20.0), 1e-4)]
dome_camera = "  projection: dome\n  dome_fov: 180\n  zenith: [0, 90]"
data, head = render("dome", stars, dome_camera, (SIZE, SIZE))
flux_conserved(data, 2.0001, "dome")
check(head["PSFSTARS"] == 2, f"dome: {head['PSFSTARS']} stars drawn with spikes, expected the 2 bright ones")
light = np.nan_to_num(data)

# Each pixel's direction on this script's model of the map: image up is
# the direction (0, 1, 0), right (1, 0, 0) at the centre, the zenith (0, 0, 1).
c = SIZE / 2.0
f = (SIZE / 2.0) / (math.pi / 2)
jj, ii = np.mgrid[0:SIZE, 0:SIZE]
u, v = ii + 0.5 - c, c - (jj + 0.5)
theta, psi = np.hypot(u, v) / f, np.arctan2(v, u)
dirs = np.stack([np.sin(theta) * np.cos(psi), np.sin(theta) * np.sin(psi), np.cos(theta)], axis=-1)


def star_direction(theta_deg):
    """The light-weighted mean direction of the brightest pixel near theta."""
    near = np.where(np.abs(np.degrees(theta) - theta_deg) < 2.0, light, 0.0)
    j0, i0 = np.unravel_index(np.argmax(near), near.shape)
    box = (abs(ii - i0) <= 2) & (abs(jj - j0) <= 2)
    s = (dirs * np.where(box, light, 0.0)[..., None]).sum(axis=(0, 1))
    return s / np.linalg.norm(s)


def tangent_coords(s):
    """Angle from the star (degrees) and position angle from east towards
    north (degrees) of every pixel, in the star's tangent plane."""
    up = np.array([0.0, 1.0, 0.0])
    north = up - s * (s @ up)
    north /= np.linalg.norm(north)
    east = np.cross(north, s)  # image right at the centre (this model's y is up)
    cosr = dirs @ s
    rho = np.degrees(np.arccos(np.clip(cosr, -1, 1)))
    t = dirs / cosr[..., None] - s
    pa = np.degrees(np.arctan2(t @ north, t @ east)) % 360.0
    return rho, pa


def wedge_light(rho, pa, centres, r0, r1, half=5.0):
    """Light in the wedges within +-half degrees of the given angles,
    r0 <= rho < r1."""
    diff = np.min([np.abs((pa - a + 180.0) % 360.0 - 180.0) for a in centres], axis=0)
    return light[(rho >= r0) & (rho < r1) & (diff <= half)].sum()


SPIKES, BETWEEN = [45, 135, 225, 315], [0, 90, 180, 270]
rings = [(1.5, 2.5), (2.5, 3.5), (3.5, 4.5), (4.5, 5.5)]
profiles = []
for t in bright_at:
    s = star_direction(t)
    rho, pa = tangent_coords(s)
    on, off = wedge_light(rho, pa, SPIKES, 1.5, 6.0, 3.0), wedge_light(rho, pa, BETWEEN, 1.5, 6.0, 3.0)
    check(on > 3.0 * off, f"dome, star at {t:g} deg: spikes at 45 + k 90 deg from east ({on:.3g} vs {off:.3g} between)")
    # Where, folded by 90 degrees, the spikes' light lies: its mean angle
    # within 10 degrees of 45 (a map's 1.21 stretch drawn in pixels would
    # turn the spikes by 5 degrees).
    fold = pa % 90.0
    near = (rho >= 1.5) & (rho < 6.0) & (np.abs(fold - 45.0) <= 10.0)
    mean = (fold[near] * light[near]).sum() / light[near].sum()
    check(abs(mean - 45.0) <= 1.5, f"dome, star at {t:g} deg: the spikes' angle {mean:.2f} deg (expected 45)")
    profiles.append([wedge_light(rho, pa, SPIKES, r0, r1, 10.0) for r0, r1 in rings])
for k, (r0, r1) in enumerate(rings):
    a, b = profiles[0][k], profiles[1][k]
    check(a > 0 and abs(b / a - 1.0) < 0.10,
          f"dome: spike light {r0:g}-{r1:g} deg out, zenith {a:.4g} vs 60 deg {b:.4g} (same angular length)")
s = star_direction(30.0)
rho, _ = tangent_coords(s)
faint_wings = light[(rho >= 1.0) & (rho < 6.0)].sum()
check(faint_wings < 1e-3 * 1e-4, f"dome: the faint star has no spikes (light 1-6 deg out: {faint_wings:.3g})")

# ---- Hammer-Aitoff panorama ----
def lb(l_deg, b_deg):
    lr, br = math.radians(l_deg), math.radians(b_deg)
    return (math.cos(br) * math.cos(lr), math.cos(br) * math.sin(lr), math.sin(br))


data, head = render("panorama", [(lb(179.0, 10.0), 1.0), (lb(40.0, 80.0), 1.0)],
                    "  projection: hammer-aitoff", (1024, 512))
flux_conserved(data, 2.0, "panorama")
light = np.nan_to_num(data)
# The seam star's light on both sides: the map's left and right quarters.
rows = slice(200, 312)
left, right = light[rows, :256].sum(), light[rows, 768:].sum()
check(left > 0.01 and right > 0.01, f"panorama: the star at the seam lights both edges ({left:.3g}, {right:.3g})")

# ---- a PSF from a FITS file ----
shared = os.environ.get("ORRERY_SHARED_DATA", "")
tinytim = os.path.join(shared, "psf", "nic2_f160w_4xsub00.fits")
if shared and os.path.exists(tinytim):
    data, head = render("file", [(unit(40.0, 100.0), 1.0)], dome_camera, (401, 401),
                        f"  kind: file\n  file: {tinytim}\n  file_subsample: 4")
    flux_conserved(data, 1.0, "psf.kind file")
    light = np.nan_to_num(data)
    f = (401 / 2.0) / (math.pi / 2)  # pixels per radian
    jj, ii = np.mgrid[0:401, 0:401]
    j0, i0 = np.unravel_index(np.argmax(light), light.shape)
    far = np.hypot(ii - i0, jj - j0) > f * math.radians(1.0)
    check(head["PSFSTARS"] == 1 and light[far].sum() > 0.01,
          f"psf.kind file: the star drawn with its wings ({light[far].sum():.3g} of its light beyond 1 deg)")
else:
    print("skip psf.kind file: no shared data (ORRERY_SHARED_DATA)")
sys.exit(1 if failures else 0)
