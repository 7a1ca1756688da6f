#!/usr/bin/env python3
"""Does the Sun wander more than stars like it? Over a run's snapshots
(orrery-nbody --snapshot-every K --snapshot-dir DIR), follows the disc stars
that start as the Sun does -- radius within --dr of the Sun's, height within
--dz of the plane, radial and vertical speeds below --dv km/s and a
rotation speed within --dv of the Sun's, so on near-circular orbits in the
plane -- and reports, for each, its largest
distance from its starting radius over all the snapshots, and the share of
them that stay within --band kpc of it (the issue's bar for the Sun: 8 +- 1
kpc). The Sun (particle id 3) is one draw from this spread; its own largest
excursion is printed with its rank among them (docs/nbody.md, "Why the Sun
wanders"). Radii and heights are about the disc stars' centre of mass, in
the plane normal to their total angular momentum, as the run's reports are.

usage: scripts/sun_like_stars.py [--dr KPC] [--dz KPC] [--dv KMS] [--band KPC] SNAPSHOT.hdf5...
"""
import argparse
import sys

import h5py
import numpy as np

import snapshot_disc  # scripts/snapshot_disc.py

SUN_TYPE, SUN_ID = 4, 3  # the model's Sun (docs/model.md)


def read(path):
    """(disc ids, positions, velocities, masses, Sun's position, velocity), disc sorted by id."""
    ids, x, v, m = snapshot_disc.disc_stars(path, "sun_like_stars")
    with h5py.File(path, "r") as f:
        sun = f.get(f"PartType{SUN_TYPE}")
        if sun is None:
            sys.exit(f"sun_like_stars: {path}: no Sun (PartType{SUN_TYPE})")
        k = np.nonzero(sun["ParticleIDs"][:] == SUN_ID)[0]
        if len(k) == 0:
            sys.exit(f"sun_like_stars: {path}: no particle with id {SUN_ID} (the Sun)")
        return ids, x, v, m, sun["Coordinates"][k[0]].astype(float), sun["Velocities"][k[0]].astype(float)


def disc_frame(x, v, m):
    """Centre of mass, its velocity and the unit normal of the disc (angular momentum)."""
    c, w = np.average(x, axis=0, weights=m), np.average(v, axis=0, weights=m)
    L = (m[:, None] * np.cross(x - c, v - w)).sum(axis=0)
    return c, w, L / np.linalg.norm(L)


def cylindrical(x, v, c, w, n):
    """(R, z, v_R, v_z, v_phi) about the centre c moving at w, the plane's normal n."""
    d, u = x - c, v - w
    z, vz = d @ n, u @ n
    p = d - np.outer(z, n)
    R = np.linalg.norm(p, axis=1)
    vR = np.einsum("ij,ij->i", p, u) / np.maximum(R, 1e-12)
    vphi = np.einsum("ij,ij->i", np.cross(n, p), u) / np.maximum(R, 1e-12)
    return R, z, vR, vz, vphi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dr", type=float, default=0.2, help="starting radius within this of the Sun's, kpc (0.2)")
    ap.add_argument("--dz", type=float, default=0.1, help="starting height below this, kpc (0.1)")
    ap.add_argument("--dv", type=float, default=15.0, help="starting |v_R|, |v_z| and |v_phi - the Sun's| below this, km/s (15)")
    ap.add_argument("--band", type=float, default=1.0, help="the bar: within this of the starting radius, kpc (1)")
    ap.add_argument("snapshots", nargs="+")
    a = ap.parse_args()
    ids0 = chosen = R0 = sunR0 = None
    excursion = sun_excursion = None
    for path in a.snapshots:
        ids, x, v, m, xs, vs = read(path)
        c, w, n = disc_frame(x, v, m)
        R, z, vR, vz, vphi = cylindrical(x, v, c, w, n)
        sun = cylindrical(xs[None, :], vs[None, :], c, w, n)
        sR = sun[0][0]
        if ids0 is None:
            ids0, sunR0 = ids, sR
            chosen = ((np.abs(R - sR) < a.dr) & (np.abs(z) < a.dz) & (np.abs(vR) < a.dv) & (np.abs(vz) < a.dv)
                      & (np.abs(vphi - sun[4][0]) < a.dv))
            if not chosen.any():
                sys.exit(f"sun_like_stars: {path}: no disc star starts like the Sun (loosen --dr, --dz, --dv)")
            R0 = R[chosen]
            excursion, sun_excursion = np.zeros(int(chosen.sum())), 0.0
        elif ids.shape != ids0.shape or np.any(ids != ids0):
            sys.exit(f"sun_like_stars: {path} holds other disc stars than {a.snapshots[0]} (ids differ)")
        excursion = np.maximum(excursion, np.abs(R[chosen] - R0))
        sun_excursion = max(sun_excursion, abs(sR - sunR0))
    stay = np.mean(excursion <= a.band)
    rank = np.mean(excursion < sun_excursion)
    print(f"{int(chosen.sum())} disc stars start like the Sun (R {sunR0:.2f} +- {a.dr:g} kpc, |z| < {a.dz:g} kpc, "
          f"|v_R|, |v_z|, |v_phi - Sun's| < {a.dv:g} km/s); over {len(a.snapshots)} snapshots:")
    print(f"  largest |R - R0|: median {np.median(excursion):.2f} kpc, 90th percentile {np.percentile(excursion, 90):.2f} kpc")
    print(f"  share within {a.band:g} kpc of R0 throughout: {stay:.3f}")
    print(f"  the Sun: largest |R - R0| {sun_excursion:.2f} kpc, more than {rank:.3f} of them")


if __name__ == "__main__":
    main()
