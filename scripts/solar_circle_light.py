#!/usr/bin/env python3
"""The sky's light seen by many Suns at once, through a run's snapshots: a
film's Sun is one draw, and this gives the odds of the others.

N observers (--observers, 64) stand evenly round the solar circle, radius
--radius (8 kpc) about the Milky Way's centre in its disc's plane, and ride
round with the disc from one snapshot to the next. For each snapshot: the
mean of the light they see and its spread round the circle (rms and the
extremes, over the mean), and the m = 2 Fourier amplitude of the Milky
Way's disc stars at 1-4 kpc from its centre (the bar) and at 6-10 kpc
(the spirals about the circle). For each step between snapshots: the change of
each observer's light, its rms over the observers, the largest, and the
share beyond --bar (0.15, issue 40's bar for a film's frames). Then, over
the steps before Andromeda's black hole is within --near kpc (100): the
largest change each observer saw, its median and 90th percentile over the
observers, and how many stayed within the bar at every step; and the rms
change over those steps and observers.

The light is sum m / (d^2 + s^2) over every star particle (disc and bulge,
PartType2 and 3, of both galaxies) at distance d: s (--soften, 0.25 kpc) is
about how far the renderer spreads a near particle's light (a disc
particle's glow takes its kernel's mean of 1/r^2, and its kernel reaches
about 0.4 kpc at the films' 5 x 10^5 particles; docs/sky.md). It is the
stars' mass, not their light: the films' populations weight young disc
stars 4.2 times the old per unit of mass. Yet it follows the frames: on
the shipped short run's frames 0 to 19, the Sun's own mass-light changes
by rms 14.3 % between frames and its panoramas' light
(scripts/frame_light.py) by 12.9 %, the two correlated 0.90
(docs/nbody.md).

The Milky Way's centre and plane are sun_path.py's: its stars within
max(5 kpc, 2 --radius) of its black hole (PartType5, id 1), centred twice;
the plane normal to the disc stars' angular momentum there. Azimuths start
from the direction of the snapshot's x axis in that plane. Between two
snapshots an observer turns by the disc's angular speed at the circle (the
median v_phi of the disc stars within 0.5 kpc of it over its radius, the
mean of the two snapshots') times the time between them.

usage: scripts/solar_circle_light.py [--radius KPC] [--observers N] [--soften KPC]
                                     [--bar FRACTION] [--near KPC] SNAPSHOT.hdf5...

A snapshot that cannot be read, or lacks the Milky Way's black hole, its
stars, or disc stars near the circle, is refused with a message naming the
file and what is missing, exit status 1. tests/cli/test_solar_circle_light.sh
checks it against the light of continuous rings and a rigidly turning disc.
"""
import argparse
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sun_like_stars import cylindrical  # noqa: E402
from sun_path import GYR_PER_UNIT, M31_BH_ID, MW_BH_ID, milky_way_frame, one, stars  # noqa: E402

WHO = "solar_circle_light"
# The Milky Way's disc rings whose m = 2 amplitude is printed: the bar's
# (1-4 kpc) and the spirals' about the solar circle (6-10 kpc).
M2_RINGS = ((1.0, 4.0), (6.0, 10.0))


def in_plane_axes(n):
    """Two unit vectors spanning the plane normal to n: the first along the
    x axis's shadow on it (the y axis's when x is nearly along n)."""
    for axis in (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        e1 = axis - (axis @ n) * n
        if np.linalg.norm(e1) > 0.1:
            e1 /= np.linalg.norm(e1)
            return e1, np.cross(n, e1)
    raise AssertionError("a unit normal has a shadow on x or y")


def read(path, radius):
    """The snapshot's time, stars (positions, masses), the Milky Way's
    centre and in-plane axes, the disc's angular speed at radius, and the
    distance between the black holes (nan without Andromeda's)."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        sys.exit(f"{WHO}: {path}: cannot read it as HDF5 ({e})")
    with f:
        hole = one(f, path, 5, MW_BH_ID, "Milky Way black hole", WHO)
        g5 = f["PartType5"]
        other = np.nonzero(g5["ParticleIDs"][:] == M31_BH_ID)[0]
        apart = np.linalg.norm(g5["Coordinates"][other[0]] - hole) if len(other) else np.nan
        x, v, m, disc = stars(f, path, WHO)
        if "Header" not in f or "Time" not in f["Header"].attrs:
            sys.exit(f"{WHO}: {path}: no Header/Time attribute (the snapshot's time)")
        time = float(f["Header"].attrs["Time"])
    c, vc, n = milky_way_frame(path, x, v, m, disc, hole, max(5.0, 2.0 * radius), WHO)
    e1, e2 = in_plane_axes(n)
    R, _, _, _, v_phi = cylindrical(x, v, c, vc, n)
    near = disc & (np.abs(R - radius) < 0.5)
    if not near.any():
        sys.exit(f"{WHO}: {path}: no disc stars within 0.5 kpc of the circle of radius {radius:g} kpc")
    r = x - c
    own = disc & (np.linalg.norm(r, axis=1) <= max(5.0, 2.0 * radius))
    phi = np.arctan2(r[own] @ e2, r[own] @ e1)
    m2 = [two_arm_amplitude(m[own], R[own], phi, lo, hi) for lo, hi in M2_RINGS]
    return time, x, m, (c, e1, e2), float(np.median(v_phi[near])) / radius, apart, m2


def two_arm_amplitude(m, R, phi, lo, hi):
    """The m = 2 Fourier amplitude of the mass between radii lo and hi,
    |sum m exp(2 i phi)| / sum m: 0 for a round disc, about 1/sqrt(n) for
    n stars placed at random, the bar's or the spirals' strength else."""
    ring = (R >= lo) & (R < hi)
    if not ring.any():
        return 0.0
    return float(np.abs(np.sum(m[ring] * np.exp(2j * phi[ring]))) / np.sum(m[ring]))


def light(x, m, frame, radius, azimuths, soften):
    """Each observer's sum of m / (d^2 + soften^2)."""
    c, e1, e2 = frame
    out = np.empty(len(azimuths))
    for k, a in enumerate(azimuths):
        eye = c + radius * (np.cos(a) * e1 + np.sin(a) * e2)
        d2 = np.sum((x - eye) ** 2, axis=1)
        out[k] = np.sum(m / (d2 + soften * soften))
    return out


def percent(x):
    return 100.0 * x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--radius", type=float, default=8.0, help="the solar circle's radius, kpc (8)")
    ap.add_argument("--observers", type=int, default=64, help="observers round it (64)")
    ap.add_argument("--soften", type=float, default=0.25, help="s in m / (d^2 + s^2), kpc (0.25)")
    ap.add_argument("--bar", type=float, default=0.15, help="the largest change asked of a step (0.15)")
    ap.add_argument("--near", type=float, default=100.0,
                    help="the summary stops once the black holes are within this, kpc (100)")
    ap.add_argument("snapshots", nargs="+")
    a = ap.parse_args()
    for name, value in (("--radius", a.radius), ("--soften", a.soften), ("--bar", a.bar), ("--near", a.near)):
        if not (np.isfinite(value) and value > 0):
            sys.exit(f"{WHO}: {name} {value:g}: expected a number above 0")
    if a.observers < 1:
        sys.exit(f"{WHO}: --observers {a.observers}: expected at least 1")

    azimuths = 2.0 * np.pi * np.arange(a.observers) / a.observers
    print("snapshot  t (Gyr)  light: mean  rms %  min  max  disc m=2: 1-4 kpc  6-10 kpc"
          "  |  change: rms %  largest %  beyond bar %")
    largest = np.zeros(a.observers)
    squares = 0.0
    steps = 0
    approached = False  # Andromeda within --near: the summary ends there
    before = None
    for path in a.snapshots:
        time, x, m, frame, omega, apart, m2 = read(path, a.radius)
        if before is not None:
            t0, omega0, seen0 = before
            azimuths = azimuths + 0.5 * (omega + omega0) * (time - t0)
        seen = light(x, m, frame, a.radius, azimuths, a.soften)
        mean = seen.mean()
        line = (f"{path}  {time * GYR_PER_UNIT:.3f}  {mean:.6g}  {percent(seen.std() / mean):.1f}"
                f"  {seen.min() / mean:.2f}  {seen.max() / mean:.2f}  {m2[0]:.3f}  {m2[1]:.3f}")
        if before is not None:
            change = np.abs(seen / seen0 - 1.0)
            line += (f"  |  {percent(np.sqrt(np.mean(change ** 2))):.1f}  {percent(change.max()):.1f}"
                     f"  {percent(np.mean(change > a.bar)):.1f}")
            approached = approached or apart < a.near
            if not approached:
                largest = np.maximum(largest, change)
                squares += np.sum(change ** 2)
                steps += 1
        print(line)
        before = (time, omega, seen)
    if steps:
        within = int(np.sum(largest <= a.bar))
        rms = np.sqrt(squares / (steps * a.observers))
        print(f"{a.observers} observers, {steps} steps before Andromeda is within {a.near:g} kpc: "
              f"rms change {percent(rms):.1f} %; largest change median {percent(np.median(largest)):.1f} %, "
              f"90th percentile {percent(np.percentile(largest, 90)):.1f} %; "
              f"{within} of {a.observers} within {percent(a.bar):g} % at every step")


if __name__ == "__main__":
    main()
