"""The disc stars of one of orrery-nbody's snapshots (Gadget-layout HDF5,
--snapshot-every K --snapshot-dir DIR), as scripts/disc_churn.py,
scripts/sun_like_stars.py and scripts/model_ez.py read them: sorted by
particle id, so that two snapshots of one run line up star by star."""
import sys

import h5py
import numpy as np

DISC_TYPE = 2  # ORR_MODEL_TYPE_DISC, Gadget's PartType2 in the snapshots (docs/model.md)


def disc_datasets(path, tool, names):
    """(ids, [the datasets `names` as float]) of the disc stars, sorted by
    id. A file that cannot be read, holds no disc stars or lacks one of
    the datasets stops `tool` with a message naming it."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        sys.exit(f"{tool}: {path}: cannot read it as HDF5 ({e})")
    with f:
        group = f.get(f"PartType{DISC_TYPE}")
        if group is None:
            sys.exit(f"{tool}: {path}: no PartType{DISC_TYPE} (disc stars) in the snapshot")
        missing = [n for n in names if n not in group]
        if missing:
            sys.exit(f"{tool}: {path}: no PartType{DISC_TYPE}/{missing[0]} in the snapshot")
        ids = group["ParticleIDs"][:]
        data = [group[n][:].astype(float) for n in names]
    order = np.argsort(ids)
    return ids[order], [d[order] for d in data]


def disc_stars(path, tool):
    """(ids, positions, velocities, masses) of the disc stars, sorted by id."""
    ids, (pos, vel, mass) = disc_datasets(path, tool, ("Coordinates", "Velocities", "Masses"))
    return ids, pos, vel, mass
