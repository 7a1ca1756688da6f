#!/usr/bin/env python3
"""The Milky Way disc's vertical energy ez (docs/model.md, "Vertical energy
ez"): its distribution among the disc stars, and the thickness of the disc
that colour populations select by it with logistic weights
p = 1 / (1 + exp((ez - v0) / dv)) (docs/colour.md), beside what the model's
recipe predicts: ez = g^2 / 2 + |z| / h, g a unit Gaussian and |z| / h a
unit exponential (h = 0.3 kpc), so ez follows Gamma(3/2).

FIRST is a text table of `orrery model --galaxies mw` (the disc stars: type
2 within 50 kpc of the origin) or one of orrery-nbody's snapshots of the
Milky Way alone (PartType2). LATER snapshots of the same run show how well
ez, fixed at the start, still sorts the stars by thickness: the mean |z| of
each selection at that time, and the correlation of the carried ez with ez
recomputed from the star's v_z and z, sigma_z taken from FIRST's disc stars
in bins of R and |z|; and, for contrast, the thickness of the stars the same
weights select by their starting height alone.

usage: scripts/model_ez.py [--select V0,DV]... FIRST [LATER.hdf5 ...]
"""
import argparse
import sys

import numpy as np

H_KPC = 0.3  # the Milky Way disc's scale height (docs/model.md)
DISC_TYPE = 2
R_BINS = np.arange(0.0, 21.0, 1.0)                          # kpc; the last bin open-ended
Z_BINS = np.array([0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, np.inf])  # |z| / h


def read_text(path):
    """(ids, positions, v_z, ez) of the Milky Way's disc stars in a table of
    `orrery model`."""
    try:
        with open(path) as f:
            names = f.readline().split()
        table = np.loadtxt(path, skiprows=1, ndmin=2)
    except (OSError, ValueError) as e:
        sys.exit(f"model_ez: {path}: cannot read it as a text table ({e})")
    missing = [n for n in ("x", "y", "z", "type", "vz", "ez") if n not in names]
    if missing or table.shape[1] != len(names):
        sys.exit(f"model_ez: {path}: not a table of `orrery model` (no column {', '.join(missing) or 'count'} as named)")
    col = {n: table[:, names.index(n)] for n in names}
    disc = (col["type"] == DISC_TYPE) & (np.sqrt(col["x"] ** 2 + col["y"] ** 2 + col["z"] ** 2) < 50.0)
    ids = col["id"][disc].astype(np.int64) if "id" in col else np.arange(disc.sum())
    pos = np.stack([col["x"], col["y"], col["z"]], axis=1)[disc]
    return ids, pos, col["vz"][disc], col["ez"][disc]


def read_snapshot(path):
    import snapshot_disc  # scripts/snapshot_disc.py (h5py only when a snapshot is read)
    ids, (pos, vel, ez) = snapshot_disc.disc_datasets(path, "model_ez", ("Coordinates", "Velocities", "ez"))
    return ids.astype(np.int64), pos - pos.mean(axis=0), vel[:, 2] - vel[:, 2].mean(), ez


def read(path):
    """(ids, positions, v_z, ez) of the disc stars, from a snapshot (by its
    HDF5 signature) or a text table."""
    try:
        with open(path, "rb") as f:
            hdf5 = f.read(8) == b"\x89HDF\r\n\x1a\n"
    except OSError as e:
        sys.exit(f"model_ez: {path}: cannot read it ({e.strerror})")
    return read_snapshot(path) if hdf5 else read_text(path)


def weight(ez, v0, dv):
    return 1.0 / (1.0 + np.exp(np.clip((ez - v0) / dv, -700, 700)))


def predicted(v0, dv):
    """(kept fraction, mean |z| in kpc) the recipe predicts: the logistic
    weight averaged over g^2 / 2 + e, with g = sqrt(2) t, t >= 0 of density
    2 exp(-t^2) / sqrt(pi), and e of density exp(-e)."""
    t = (np.arange(600) + 0.5) * (6.0 / 600)
    e = (np.arange(2000) + 0.5) * (40.0 / 2000)
    pt = 2.0 / np.sqrt(np.pi) * np.exp(-t * t) * (6.0 / 600)
    pe = np.exp(-e) * (40.0 / 2000)
    w = weight(t[:, None] ** 2 + e[None, :], v0, dv) * pt[:, None] * pe[None, :]
    return w.sum(), H_KPC * (w * e[None, :]).sum() / w.sum()


def bins(pos):
    """Each star's bin of R and |z| / h (the last of each open-ended), and
    its |z| / h."""
    R, az = np.hypot(pos[:, 0], pos[:, 1]), np.abs(pos[:, 2]) / H_KPC
    i = np.clip(np.digitize(R, R_BINS) - 1, 0, len(R_BINS) - 2)
    j = np.clip(np.digitize(az, Z_BINS) - 1, 0, len(Z_BINS) - 2)
    return i * (len(Z_BINS) - 1) + j, az


def sigma_z2_bins(pos, vz):
    """<v_z^2> in each bin of R and |z| / h; where a bin holds fewer than
    30 stars, the disc's mean."""
    b, _ = bins(pos)
    n = np.bincount(b, minlength=(len(R_BINS) - 1) * (len(Z_BINS) - 1))
    s = np.bincount(b, weights=vz * vz, minlength=n.size)
    return np.where(n >= 30, s / np.maximum(n, 1), np.mean(vz * vz))


def recomputed(pos, vz, s2):
    """v_z^2 / (2 sigma_z^2) + |z| / h, sigma_z^2 from the bins s2."""
    b, az = bins(pos)
    return vz * vz / (2.0 * s2[b]) + az


def ranks(a):
    r = np.empty(a.size)
    r[np.argsort(a, kind="stable")] = np.arange(a.size)
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--select", action="append", metavar="V0,DV",
                    help="a logistic selection (default: 1.5,0.4 and 0.7,0.25)")
    ap.add_argument("first")
    ap.add_argument("later", nargs="*")
    a = ap.parse_args()
    try:
        sels = [tuple(float(v) for v in s.split(",")) for s in (a.select or ["1.5,0.4", "0.7,0.25"])]
    except ValueError:
        sels = [()]
    if any(len(s) != 2 or s[1] == 0 or not np.all(np.isfinite(s)) for s in sels):
        sys.exit(f"model_ez: --select {a.select}: expected V0,DV, two finite numbers, DV not 0")

    ids, pos, vz, ez = read(a.first)
    if ids.size == 0:
        sys.exit(f"model_ez: {a.first}: no Milky Way disc stars")
    az = np.abs(pos[:, 2])
    print(f"{ids.size} disc stars: ez mean {ez.mean():.3f}, median {np.median(ez):.3f} "
          f"(Gamma(3/2): 1.500, 1.183); mean |z| {az.mean():.3f} kpc (h = {H_KPC})")
    for v0, dv in sels:
        w = weight(ez, v0, dv)
        keep, z_pred = predicted(v0, dv)
        print(f"logistic v0 {v0:g} dv {dv:g}: keeps {w.mean():.3f}, mean |z| {(w * az).sum() / w.sum():.3f} kpc "
              f"(the recipe: {keep:.3f}, {z_pred:.3f})")
    if not a.later:
        return
    # The control: the same weights on the starting height alone (|z| / h
    # + 1/2, the mean of g^2 / 2 added), which the stars' oscillations mix.
    by_height = az / H_KPC + 0.5
    for v0, dv in sels:
        wh = weight(by_height, v0, dv)
        print(f"by height alone, v0 {v0:g} dv {dv:g}: keeps {wh.mean():.3f}, mean |z| {(wh * az).sum() / wh.sum():.3f} kpc")
    s2 = sigma_z2_bins(pos, vz)
    ez_re = recomputed(pos, vz, s2)
    print(f"{a.first}: carried ez against ez recomputed: correlation {np.corrcoef(ez, ez_re)[0, 1]:.3f} "
          f"(ranks {np.corrcoef(ranks(ez), ranks(ez_re))[0, 1]:.3f})")
    for path in a.later:
        ids1, pos1, vz1, ez1 = read(path)
        if ids1.shape != ids.shape or np.any(ids1 != ids) or np.any(ez1 != ez):
            sys.exit(f"model_ez: {a.first} and {path} hold other disc stars or other ez (not one run)")
        az1 = np.abs(pos1[:, 2])
        ez_re = recomputed(pos1, vz1, s2)
        line = [f"{path}: mean |z| {az1.mean():.3f} kpc"]
        for v0, dv in sels:
            w, wh = weight(ez, v0, dv), weight(by_height, v0, dv)
            line.append(f"v0 {v0:g} dv {dv:g}: {(w * az1).sum() / w.sum():.3f} "
                        f"(by height {(wh * az1).sum() / wh.sum():.3f})")
        line.append(f"carried ez against recomputed: correlation {np.corrcoef(ez, ez_re)[0, 1]:.3f} "
                    f"(ranks {np.corrcoef(ranks(ez), ranks(ez_re))[0, 1]:.3f})")
        print("; ".join(line))


if __name__ == "__main__":
    main()
