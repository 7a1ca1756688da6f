#!/usr/bin/env python3
"""A copy of an HDF5 snapshot without the particles of one type near the
observer, to measure how much of a frame's light they bring (render both,
scripts/frame_light.py on each; docs/sky.md, "The glow's flux").

usage: scripts/snapshot_without_near.py SNAPSHOT OUT --radius KPC [--type 2] [--observer-id 3]

Every group and dataset is copied as it is, but the particles of --type
(default 2, the disc stars) within --radius of the particle --observer-id
(default 3, the Sun) are left out of that type's datasets, and the
header's counts say so.
"""
import argparse
import os
import sys

import h5py
import numpy as np


def observer_position(f, observer_id):
    """The position of the particle with that id, in whichever group holds it."""
    for name, group in f.items():
        if name.startswith("PartType") and "ParticleIDs" in group:
            hits = np.flatnonzero(group["ParticleIDs"][:] == observer_id)
            if hits.size:
                return group["Coordinates"][hits[0]]
    sys.exit(f"snapshot_without_near: no particle has id {observer_id}")


def copy_without(f, g, group_name, keep, ptype):
    """f copied into g, but group_name's particles only where keep is set,
    and the header's counts of type ptype saying so."""
    for name in f:
        if name != group_name:
            f.copy(name, g)
    out = g.create_group(group_name)
    for key, value in f[group_name].attrs.items():
        out.attrs[key] = value
    for name, ds in f[group_name].items():
        out.create_dataset(name, data=ds[:][keep])
    for key in ("NumPart_ThisFile", "NumPart_Total"):
        counts = np.array(g["Header"].attrs[key])
        counts[ptype] = keep.sum()
        g["Header"].attrs[key] = counts


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("snapshot")
    ap.add_argument("out")
    ap.add_argument("--radius", type=float, required=True, help="kpc (the snapshot's length unit)")
    ap.add_argument("--type", type=int, default=2)
    ap.add_argument("--observer-id", type=int, default=3)
    a = ap.parse_args()
    if not a.radius > 0:
        sys.exit(f"snapshot_without_near: --radius {a.radius}: give a distance > 0")
    group_name = f"PartType{a.type}"
    with h5py.File(a.snapshot, "r") as f:
        if group_name not in f:
            sys.exit(f"snapshot_without_near: {a.snapshot} has no {group_name}")
        eye = observer_position(f, a.observer_id)
        keep = np.linalg.norm(f[group_name]["Coordinates"][:] - eye, axis=1) >= a.radius
        # Written beside OUT and renamed into place: a run that stops
        # half-way leaves no half-written snapshot under OUT's name.
        partial = f"{a.out}.partial"
        with h5py.File(partial, "w") as g:
            copy_without(f, g, group_name, keep, a.type)
    os.replace(partial, a.out)
    print(f"{a.out}: {int((~keep).sum())} of {keep.size} particles of type {a.type} within {a.radius} of "
          f"particle {a.observer_id} left out")


if __name__ == "__main__":
    main()
