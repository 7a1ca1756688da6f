#!/usr/bin/env python3
"""How far an isolated disc's stars migrate between two of orrery-nbody's
snapshots (--snapshot-every K --snapshot-dir DIR): the change of each disc
star's guiding radius R_g = L_z / v_c (its angular momentum about the disc's
centre of mass over the circular speed at the Sun), for the stars whose R_g
starts between --from and --to kpc (default 7-9: the Sun's neighbours), and
the m = 2 Fourier amplitude of the disc's density in three rings against its
noise level 1/sqrt(n), which tells spirals and bars grown from particle noise.

A star's radius alone swings with its epicycle (about sigma_R / kappa, 0.8
kpc near the Sun); its guiding radius changes only when spirals, a bar or
the graininess of the particles torque it. The Sun of the model, a tracer
on a circular orbit, drifts as its neighbours' guiding radii do
(docs/nbody.md, "Why the Sun wanders").

usage: scripts/disc_churn.py [--vc KMS] [--from KPC] [--to KPC] FIRST.hdf5 LATER.hdf5
"""
import argparse
import sys

import numpy as np

import snapshot_disc  # scripts/snapshot_disc.py


def disc_stars(path):
    """Ids, positions and velocities of the disc stars, sorted by id, about
    their centre of mass and its velocity."""
    ids, pos, vel, _ = snapshot_disc.disc_stars(path, "disc_churn")
    return ids, pos - pos.mean(axis=0), vel - vel.mean(axis=0)


def ring_m2(pos, rings=((0, 3), (3, 6), (6, 10))):
    """(ring, A2, noise) for each ring: |sum exp(2 i phi)| / n."""
    R = np.hypot(pos[:, 0], pos[:, 1])
    phi = np.arctan2(pos[:, 1], pos[:, 0])
    out = []
    for lo, hi in rings:
        inside = (R > lo) & (R < hi)
        n = int(inside.sum())
        a2 = abs(np.exp(2j * phi[inside]).sum()) / n if n else float("nan")
        out.append((f"{lo}-{hi} kpc", a2, 1 / np.sqrt(n) if n else float("nan")))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vc", type=float, default=239.0, help="circular speed, km/s (default 239: the model's at 8 kpc)")
    ap.add_argument("--from", dest="lo", type=float, default=7.0, help="inner guiding radius, kpc (default 7)")
    ap.add_argument("--to", dest="hi", type=float, default=9.0, help="outer guiding radius, kpc (default 9)")
    ap.add_argument("first")
    ap.add_argument("later")
    a = ap.parse_args()
    id0, x0, v0 = disc_stars(a.first)
    id1, x1, v1 = disc_stars(a.later)
    if id0.shape != id1.shape or np.any(id0 != id1):
        sys.exit(f"disc_churn: {a.first} and {a.later} hold different disc stars (ids differ)")
    lz0 = x0[:, 0] * v0[:, 1] - x0[:, 1] * v0[:, 0]
    lz1 = x1[:, 0] * v1[:, 1] - x1[:, 1] * v1[:, 0]
    rg0, drg = np.abs(lz0) / a.vc, (lz1 - lz0) / a.vc * np.sign(lz0)
    near = (rg0 > a.lo) & (rg0 < a.hi)
    if not near.any():
        sys.exit(f"disc_churn: no disc star has a guiding radius between {a.lo} and {a.hi} kpc")
    print(f"disc stars {len(id0)}, {int(near.sum())} with R_g {a.lo:g}-{a.hi:g} kpc: "
          f"rms change of R_g {np.sqrt(np.mean(drg[near] ** 2)):.3f} kpc, "
          f"{np.mean(np.abs(drg[near]) > 1):.3f} of them by more than 1 kpc")
    for name, path, pos in (("first", a.first, x0), ("later", a.later, x1)):
        rings = ", ".join(f"{r}: A2 {a2:.3f} (noise {n:.3f})" for r, a2, n in ring_m2(pos))
        print(f"{name} ({path}): {rings}")


if __name__ == "__main__":
    main()
