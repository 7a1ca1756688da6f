#!/usr/bin/env python3
"""deposit: sph on a HEALPix map, against truth computed here with healpy
and numpy alone: each pixel holds the integral of the particle's kernel
over its area (the M4 cubic spline's column kernel F(chord / theta),
theta = h / r, integrated over each pixel by its 4^5 sub-pixels of nside
32 nside, normalised to the particle's mass); the mass on the map is the
mass to 1e-6; a uniform sky stays uniform; a broad kernel's profile matches
the analytic kernel at the pixel centres; 1 and 2 threads give the same map
bit for bit. usage: check_healpix_kernels.py ORRERY WORKDIR"""
import os
import subprocess

import healpy as hp
import numpy as np

from check_lib import Checks

check = Checks()
orrery, work = check.orrery, check.work


def column_kernel():
    """F(q) of the M4 cubic spline (support 2h): the 3-D kernel integrated
    along the line of sight, tabulated, shape only (every use normalises)."""
    q = np.linspace(0.0, 2.0, 4001)
    z = np.linspace(0.0, 2.0, 4001)
    r = np.sqrt(q[:, None] ** 2 + z[None, :] ** 2)
    w = np.where(r < 1, 1 - 1.5 * r ** 2 + 0.75 * r ** 3, np.where(r < 2, 0.25 * (2 - r) ** 3, 0.0))
    return q, 2 * np.trapz(w, z, axis=1)


Q, F = column_kernel()


def kernel(chord, theta):
    return np.interp(chord / theta, Q, F, right=0.0)


def render(name, rows, nside, order="ring", threads=None, deposit="sph"):
    with open(f"{work}/{name}.txt", "w") as f:
        f.write("\n".join(["x y z mass h"] + rows) + "\n")
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(f"input:\n  file: {name}.txt\ncamera:\n  projection: healpix\n  healpix_nside: {nside}\n"
                f"  healpix_order: {order}\ndeposit: {deposit}\nsmoothing:\n  lengths: file\n"
                f"output:\n  dir: out\n  name: {name}\n")
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    subprocess.run([orrery, "render", "--quiet", f"{name}.yaml"], cwd=work, check=True, env=env)
    return f"{work}/out/{name}.fits"


def camera_position(lon, lat, r):
    """The scene position at longitude lon, latitude lat (deg) and distance
    r from the camera at the origin: without an observer the map's axes are
    the scene's own (z the pole, x toward phi = 0; docs/sky.md)."""
    lo, la = np.radians(lon), np.radians(lat)
    return r * np.array([np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)])


def truth(nside, vec, theta, mass, sub=32):
    """Each pixel's integral of the normalised kernel (nested order), from
    the centres of its sub-pixels at nside * sub."""
    fine = nside * sub
    radius = 2 * np.arcsin(min(theta, 1.0))
    pix = hp.query_disc(fine, vec, radius, nest=True, inclusive=False)
    centres = np.array(hp.pix2vec(fine, pix, nest=True)).T
    wt = kernel(np.linalg.norm(centres - vec, axis=1), theta)
    out = np.zeros(hp.nside2npix(nside))
    np.add.at(out, pix // (sub * sub), wt)
    return mass * out / wt.sum()


def one_particle(name, nside, lon, lat, theta, order):
    r = 10.0
    p = camera_position(lon, lat, r)
    path = render(name, ["%r %r %r 2.0 %r" % (p[0], p[1], p[2], theta * r)], nside, order)
    m = hp.read_map(path, nest=(order == "nested"))  # healpy reorders to what we ask
    return m * hp.nside2pixarea(nside), hp.ang2vec(lon, lat, lonlat=True)


# A broad kernel (theta = 0.25 rad, 14 pixels of nside 32), and one of about
# a pixel (0.6 of nside 16's 3.7 degrees), in both orders.
for name, nside, theta, order in [("broad", 32, 0.25, "nested"), ("pixel", 16, 0.039, "ring"),
                                  ("pixel-nest", 16, 0.039, "nested")]:
    got, vec = one_particle(name, nside, 37.3, 23.1, theta, order)
    want = truth(nside, vec, theta, 2.0)
    if order == "ring":
        want = want[hp.ring2nest(nside, np.arange(hp.nside2npix(nside)))]
    err = np.abs(got - want).max() / want.max()
    print(f"{name}: nside {nside}, theta {theta} rad: mass {got.sum():.9g} of 2; "
          f"largest pixel error {err:.2e} of the peak pixel, {np.count_nonzero(got)} pixels")
    check(abs(got.sum() - 2.0) < 2e-6, f"{name}: mass {got.sum()!r}")
    check(err < 2e-3, f"{name}: pixel integrals off by {err:.2e} of the peak")
    if name == "broad":
        # The analytic kernel at the pixel centres, normalised over the sphere.
        psi = np.linspace(0, 2 * np.arcsin(theta), 200001)
        norm = 2 * np.pi * np.trapz(kernel(2 * np.sin(psi / 2), theta) * np.sin(psi), psi)
        centres = np.array(hp.pix2vec(nside, np.arange(len(got)), nest=True)).T
        analytic = 2.0 * kernel(np.linalg.norm(centres - vec, axis=1), theta) / norm
        sb = got / hp.nside2pixarea(nside)
        inner = analytic > 0.01 * analytic.max()
        prof = np.abs(sb[inner] - analytic[inner]).max() / analytic.max()
        print(f"broad: surface brightness at pixel centres within {prof:.2e} of the analytic kernel's peak")
        check(prof < 5e-3, f"broad kernel's profile off by {prof:.2e} of its peak")

# A uniform sky: 20000 equal particles on a Fibonacci lattice, kernels of
# 0.1 rad (about 4 lattice spacings), nside 16; and 1 against 2 threads.
n, nside = 20000, 16
k = np.arange(n) + 0.5
z = 1 - 2 * k / n
phi = np.pi * (1 + 5 ** 0.5) * k
rho = np.sqrt(1 - z * z)
rows = ["%r %r %r 0.5 1.0" % (10 * a * np.cos(b), 10 * a * np.sin(b), 10 * c) for a, b, c in zip(rho, phi, z)]
one = render("uniform-1", rows, nside, threads=1)
two = render("uniform-2", rows, nside, threads=2)
m1, m2 = hp.read_map(one), hp.read_map(two)
total = m1.sum() * hp.nside2pixarea(nside)
spread = np.abs(m1 / m1.mean() - 1)
print(f"uniform sky: mass {total:.9g} of {0.5 * n:g}; pixels within {spread.max():.3%} of the mean")
check(abs(total - 0.5 * n) < 1e-6 * 0.5 * n, f"uniform sky: mass {total!r}")
print(f"uniform sky: rms {spread.std():.4%}; away from the poles (|b| < 60 deg) within "
      f"{spread[np.abs(hp.pix2ang(nside, np.arange(len(m1)), lonlat=True)[1]) < 60].max():.4%}")
check(spread.max() < 0.005, f"uniform sky: a pixel {spread.max():.3%} off the mean")
check(spread.std() < 5e-4, f"uniform sky: rms {spread.std():.3%} off the mean")
check(np.array_equal(m1, m2), "1 and 2 threads give different maps")  # exactly equal floats
check.finish("HEALPix kernel checks")
