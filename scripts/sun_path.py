#!/usr/bin/env python3
"""The Sun's path through a run's snapshots (orrery-nbody --snapshot-every K
--snapshot-dir DIR), about the Milky Way: for each snapshot its time, the
Sun's distance from the Milky Way's axis (R) and height from its disc's
plane (z), the change of R from the snapshot before, the distance to
Andromeda's black hole (when there is one), and the surface density of the
disc stars (PartType2) about the Sun, within 1 and 4 kpc of it across the
Milky Way's plane (Msun/pc^2, the runs' units: 10^10 Msun, kpc), with the
change of the 4 kpc one from the snapshot before. The Milky Way: its stars (disc
and bulge, PartType2 and 3) within max(5 kpc, 2 x the Sun's distance) of
its black hole (id 1), centred twice on their centre of mass (as
orrery-nbody's --tracer-ring takes the Sun's galaxy, docs/nbody.md); its
plane normal to its disc stars' angular momentum there (as the runs'
reports take it). Then the largest |change of R| and |z| over the
snapshots given, and over those before Andromeda is within --near kpc,
with the largest change of the surface density within 4 kpc: the sky's
light follows it (docs/sky.md, "The glow's flux").

usage: scripts/sun_path.py [--near KPC] SNAPSHOT.hdf5...

Pass every 5th snapshot of examples/futuresky-short.sh (a snapshot every
5 block steps, a frame every 25; every 4th before 7 December 2026, when it
took global steps) for the frames' path. A snapshot that cannot
be read or lacks the Sun (PartType4, id 3), the Milky Way's black hole
(PartType5, id 1) or its stars is refused with a message naming the file
and what is missing, exit status 1. tests/cli/test_nbody_isolation.sh
checks it against the runs' reports.
"""
import argparse
import sys

import h5py
import numpy as np

GYR_PER_UNIT = 0.9778  # the time unit kpc / (km/s)
SUN_ID, MW_BH_ID, M31_BH_ID = 3, 1, 2


def one(f, path, ptype, pid, what, who="sun_path"):
    """Position of particle pid of type ptype, or an exit naming what is missing."""
    g = f.get(f"PartType{ptype}")
    k = np.nonzero(g["ParticleIDs"][:] == pid)[0] if g is not None else []
    if len(k) == 0:
        sys.exit(f"{who}: {path}: no {what} (PartType{ptype}, id {pid})")
    return g["Coordinates"][k[0]].astype(float)


def stars(f, path, who="sun_path"):
    """(positions, velocities, masses, is-disc) of the disc and bulge stars."""
    parts = [(f[f"PartType{t}"], t) for t in (2, 3) if f"PartType{t}" in f]
    if not parts:
        sys.exit(f"{who}: {path}: no stars (PartType2 or 3)")
    cat = lambda name: np.concatenate([g[name][:].astype(float) for g, _ in parts])
    disc = np.concatenate([np.full(len(g["Masses"]), t == 2) for g, t in parts])
    return cat("Coordinates"), cat("Velocities"), cat("Masses"), disc


def milky_way_frame(path, x, v, m, disc, hole, radius, who="sun_path"):
    """(centre, its velocity, the disc's unit normal) of the Milky Way: its
    stars within radius of the black hole, centred twice on their centre of
    mass; the normal along its disc stars' angular momentum there."""
    c = hole
    for _ in range(2):
        inside = np.linalg.norm(x - c, axis=1) <= radius
        if not inside.any():
            sys.exit(f"{who}: {path}: no stars within {radius:.1f} kpc of the Milky Way's black hole")
        w = m[inside] / m[inside].sum()
        c_next = w @ x[inside]
        vc = w @ v[inside]
        last, c = inside, c_next
    d = last & disc
    spin = (m[d, None] * np.cross(x[d] - c, v[d] - vc)).sum(axis=0)
    return c, vc, spin / np.linalg.norm(spin)


SIGMA_RADII = (1.0, 4.0)  # kpc
MSUN_PC2 = 1e10 / 1e6  # the runs' surface density unit, 10^10 Msun / kpc^2, in Msun / pc^2


def surface_densities(x, m, disc, sun, n):
    """The disc stars' surface density within each of SIGMA_RADII of the Sun
    across the plane of normal n (a cylinder through the disc), Msun/pc^2."""
    d = x[disc] - sun
    across = d - np.outer(d @ n, n)
    r2 = np.einsum("ij,ij->i", across, across)
    return [m[disc][r2 < a * a].sum() * MSUN_PC2 / (np.pi * a * a) for a in SIGMA_RADII]


def read(path):
    """(time, the Sun's R and z about the Milky Way, the distance between the
    black holes or nan, the disc's surface densities about the Sun)."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        sys.exit(f"sun_path: {path}: cannot read it as HDF5 ({e})")
    with f:
        sun = one(f, path, 4, SUN_ID, "Sun")
        hole = one(f, path, 5, MW_BH_ID, "Milky Way black hole")
        g5 = f["PartType5"]
        other = np.nonzero(g5["ParticleIDs"][:] == M31_BH_ID)[0]
        apart = np.linalg.norm(g5["Coordinates"][other[0]] - hole) if len(other) else np.nan
        x, v, m, disc = stars(f, path)
        time = float(f["Header"].attrs["Time"])
    c, _, n = milky_way_frame(path, x, v, m, disc, hole, max(5.0, 2.0 * np.linalg.norm(sun - hole)))
    z = (sun - c) @ n
    R = np.sqrt(max(0.0, np.sum((sun - c) ** 2) - z * z))
    return time, R, z, apart, surface_densities(x, m, disc, sun, n)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--near", type=float, default=100.0,
                    help="the summary's second part stops once the black holes are within this, kpc (100)")
    ap.add_argument("snapshots", nargs="+")
    a = ap.parse_args()
    print("snapshot  t (Gyr)  R (kpc)  z (kpc)  dR (kpc)  M31 (kpc)  Sigma1 Sigma4 (Msun/pc^2)  dSigma4 (%)")
    rows = []
    for path in a.snapshots:
        t, R, z, apart, (s1, s4) = read(path)
        dR = R - rows[-1][1] if rows else 0.0
        ds4 = 100.0 * (s4 / rows[-1][5] - 1.0) if rows and rows[-1][5] > 0 else 0.0
        rows.append((t, R, z, dR, apart, s4, ds4))
        print(f"{path}  {t * GYR_PER_UNIT:.3f}  {R:.3f}  {z:+.3f}  {dR:+.3f}  {apart:.1f}  {s1:.1f} {s4:.1f}  {ds4:+.1f}")
    before = []
    for row in rows:
        if row[4] < a.near:
            break
        before.append(row)
    for name, part in (("all", rows), (f"before M31 is within {a.near:g} kpc", before)):
        if part:
            print(f"{name}: {len(part)} snapshots, R {min(r[1] for r in part):.3f}-{max(r[1] for r in part):.3f} kpc, "
                  f"largest |dR| {max(abs(r[3]) for r in part):.3f} kpc, largest |z| {max(abs(r[2]) for r in part):.3f} kpc, "
                  f"largest |dSigma4| {max(abs(r[6]) for r in part):.1f} %")


if __name__ == "__main__":
    main()
