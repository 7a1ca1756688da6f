#!/usr/bin/env python3
"""The Milky Way-Andromeda collision from orrery-nbody's snapshots
(--snapshot-every K --snapshot-dir DIR): the distance between the two black
holes (ids 1 and 2) and between the two bulges' density centres at every
snapshot, the first pericentre (the first minimum of the black holes'
distance), and, the snapshot nearest to AFTER Gyr (default 0.5) after it, the
share of disc stars farther than R kpc (default 50) from both black holes:
stars torn into tails and bridges (issue 21, docs/gallery.md).

usage: scripts/collision_tails.py [--after GYR] [--r KPC] DIR

A snapshot that cannot be read, or lacks the black holes (PartType5, ids 1
and 2), the bulges (PartType3) or the disc (PartType2), is refused with a
message naming the file and what is missing, exit status 1.
tests/cli/test_collision_tails.sh runs it on synthetic snapshots with known
answers (check_collision_tails.py).
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np

GYR_PER_UNIT = 0.9778  # the time unit kpc / (km/s)


def split_by_id(ids):
    """The two galaxies' particles of one type: the model numbers the Milky
    Way's first, so the largest gap between sorted ids separates them."""
    order = np.argsort(ids)
    gap = int(np.argmax(np.diff(ids[order])))
    return order[: gap + 1], order[gap + 1 :]


def density_centre(x):
    """Shrinking spheres (Power et al. 2003): the mean of the particles
    within a sphere cut by 20% each round about the last mean."""
    c, r = np.median(x, axis=0), 20.0
    while r > 0.3:
        inside = np.linalg.norm(x - c, axis=1) < r
        if inside.sum() < 30:
            break
        c, r = x[inside].mean(axis=0), 0.8 * r
    return c


def first_pericentre(sep):
    """The first snapshot where the bulges' distance turns from falling to
    rising for real: a minimum followed, within five snapshots, by a rise of
    at least 5 kpc and 20% of it. The bulges' density centres, not the
    black holes: a black hole is one particle, which in a small run jitters
    by a few kpc and makes false minima hundreds of kpc out (one at 279 kpc,
    0.8 Gyr before the true pericentre, in examples/futuresky-short.sh's run)."""
    for k in range(1, len(sep) - 1):
        later = sep[k + 1 : k + 6]
        if sep[k] < sep[k - 1] and sep[k] <= sep[k + 1] and later.max() >= sep[k] + max(5.0, 0.2 * sep[k]):
            return k
    return None


def snapshot(path):
    """Time, both black holes, both bulges' density centres and the disc's
    positions of one snapshot."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise SystemExit(f"{path}: cannot open as HDF5: {e}") from None
    with f:
        for name in ("PartType5/ParticleIDs", "PartType5/Coordinates", "PartType3/ParticleIDs",
                     "PartType3/Coordinates", "PartType2/Coordinates"):
            if name not in f:
                raise SystemExit(f"{path}: no {name} dataset (not an orrery-nbody snapshot of two galaxies)")
        if "Header" not in f or "Time" not in f["Header"].attrs:
            raise SystemExit(f"{path}: no Header attribute Time")
        t = float(f["Header"].attrs["Time"])
        bh_ids = f["PartType5/ParticleIDs"][:]
        bh = f["PartType5/Coordinates"][:]
        bh = {int(i): bh[k] for k, i in enumerate(bh_ids)}
        if 1 not in bh or 2 not in bh:
            raise SystemExit(f"{path}: needs both galaxies (black holes with ids 1 and 2)")
        bulge = f["PartType3/Coordinates"][:]
        mw_b, m31_b = split_by_id(f["PartType3/ParticleIDs"][:])
        disc = f["PartType2/Coordinates"][:]
    return t, bh[1], bh[2], density_centre(bulge[mw_b]), density_centre(bulge[m31_b]), disc


def measure(directory, after=0.5, rcut=50.0):
    """Per snapshot (path, t in Gyr, black holes' distance, bulge centres'
    distance, share of disc stars farther than rcut from both), the index
    of the first pericentre (None if none) and of the snapshot nearest to
    after Gyr past it."""
    paths = sorted(glob.glob(os.path.join(directory, "snapshot_*.hdf5")))
    if not paths:
        raise SystemExit(f"{directory}: no snapshot_*.hdf5")
    rows = []
    for p in paths:
        t, b1, b2, c1, c2, disc = snapshot(p)
        far = (np.linalg.norm(disc - b1, axis=1) > rcut) & (np.linalg.norm(disc - b2, axis=1) > rcut)
        rows.append((p, t * GYR_PER_UNIT, np.linalg.norm(b1 - b2), np.linalg.norm(c1 - c2), far.mean()))
    k = first_pericentre(np.array([r[3] for r in rows]))
    if k is None:
        return rows, None, None
    times = np.array([r[1] for r in rows])
    return rows, k, int(np.argmin(np.abs(times - (rows[k][1] + after))))


def main(argv):
    ap = argparse.ArgumentParser(description="First pericentre and tidal tails from orrery-nbody snapshots.")
    ap.add_argument("--after", type=float, default=0.5, help="Gyr after first pericentre")
    ap.add_argument("--r", type=float, default=50.0, help="kpc from both black holes")
    ap.add_argument("dir")
    args = ap.parse_args(argv)
    after, rcut = args.after, args.r
    rows, k, j = measure(args.dir, after, rcut)
    for p, t, bh, bulges, share in rows:
        print(f"{os.path.basename(p)}  t = {t:.3f} Gyr  black holes {bh:7.1f} kpc apart, "
              f"bulge centres {bulges:7.1f} kpc  disc stars > {rcut:g} kpc from both: {share:.3f}")
    if k is None:
        print("no pericentre in these snapshots")
        return
    print(f"first pericentre: t = {rows[k][1]:.3f} Gyr, bulge centres {rows[k][3]:.1f} kpc apart, black holes "
          f"{rows[k][2]:.1f} kpc (snapshot spacing {rows[1][1] - rows[0][1]:.3f} Gyr)")
    print(f"{rows[j][1] - rows[k][1]:.3f} Gyr after it (t = {rows[j][1]:.3f}): {rows[j][4]:.3f} of the disc stars are "
          f"farther than {rcut:g} kpc from both black holes")


if __name__ == "__main__":
    main(sys.argv[1:])
