#!/usr/bin/env python3
"""Checks scripts/collision_tails.py (docs/gallery.md) on synthetic
snapshots with known answers: 12 snapshots 0.05 Gyr apart of two bulges
(50 particles each, set symmetrically about their centres, so the
shrinking spheres find the centres exactly) whose distance runs
100 80 79 80 60 40 20 35 50 65 80 95 kpc: the dip to 79 rises by 1 kpc
only (a false minimum, as a jittering black hole makes), the first
pericentre is snapshot 6 (0.3 Gyr, 20 kpc). The disc's 100 stars sit by
the Milky Way's black hole except in snapshot 10 (0.2 Gyr after the
pericentre), where 37 of them are 200 kpc out: a share of 0.37 farther
than 50 kpc from both black holes, and 0 with --r 250. Then bad input: no
snapshots, a file that is not HDF5, a snapshot without its bulges or with
one black hole, each refused by name with exit status 1.

usage: check_collision_tails.py SOURCE_DIR WORK_DIR
"""
import contextlib
import io
import os
import subprocess
import sys

import h5py
import numpy as np

SRC, WORK = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SRC, "scripts"))
import collision_tails  # noqa: E402

SEPARATION = [100, 80, 79, 80, 60, 40, 20, 35, 50, 65, 80, 95]
DT_GYR = 0.05
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what, file=sys.stderr)


def bulge(centre, rng):
    """50 particles within 1 kpc of centre, in pairs on either side of it."""
    half = rng.uniform(-0.5, 0.5, (25, 3))
    return np.concatenate([centre + half, centre - half])


def write_snapshot(path, k, drop=(), bh_ids=(1, 2)):
    rng = np.random.default_rng(k)
    s = SEPARATION[k]
    mw, m31 = np.array([-s / 2, 0.0, 0.0]), np.array([s / 2, 0.0, 0.0])
    disc = mw + rng.uniform(-5, 5, (100, 3))
    if k == 10:
        disc[:37] = [0.0, 200.0, 0.0]
    parts = {
        "PartType5/ParticleIDs": np.array(bh_ids, np.int64),
        "PartType5/Coordinates": np.array([mw, m31])[: len(bh_ids)],
        "PartType3/ParticleIDs": np.concatenate([np.arange(1, 51), np.arange(1001, 1051)]),
        "PartType3/Coordinates": np.concatenate([bulge(mw, rng), bulge(m31, rng)]),
        "PartType2/Coordinates": disc,
    }
    with h5py.File(path, "w") as f:
        f.create_group("Header").attrs["Time"] = k * DT_GYR / collision_tails.GYR_PER_UNIT
        for name, data in parts.items():
            if name.split("/")[0] not in drop:
                f[name] = data


def run(*args):
    """collision_tails.main's output and exit (0, or the SystemExit's message)."""
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out):
            collision_tails.main(list(args))
        return 0, out.getvalue()
    except SystemExit as e:
        return e.code, out.getvalue()


def test_pericentre_and_tails():
    d = os.path.join(WORK, "collision")
    os.makedirs(d)
    for k in range(len(SEPARATION)):
        write_snapshot(os.path.join(d, f"snapshot_{k:04d}.hdf5"), k)
    rows, k, j = collision_tails.measure(d, after=0.2)
    check(k == 6 and abs(rows[k][1] - 0.3) < 1e-9, f"first pericentre at snapshot {k}, not 6 (0.3 Gyr)")
    check(all(abs(r[3] - s) < 1e-9 for r, s in zip(rows, SEPARATION)),
          f"bulge centres' distances {[round(r[3], 6) for r in rows]}, not {SEPARATION}")
    check(all(abs(r[2] - s) < 1e-9 for r, s in zip(rows, SEPARATION)), "black holes' distances")
    check(j == 10 and rows[j][4] == 0.37, f"0.2 Gyr after: snapshot {j}, share {rows[j][4] if j else None}, not 10, 0.37")
    check(all(r[4] == 0 for i, r in enumerate(rows) if i != 10), "disc stars far out where none were put")
    code, text = run("--after", "0.2", "--r", "250", d)
    check(code == 0 and "0.200 Gyr after it (t = 0.500): 0.000 of the disc stars are farther than 250 kpc" in text,
          f"--r 250: {text}")
    code, text = run(d)  # 0.5 Gyr after 0.3 is past the last snapshot (0.55): the nearest is the last
    check("first pericentre: t = 0.300 Gyr, bulge centres 20.0 kpc apart, black holes 20.0 kpc" in text and
          "(t = 0.550)" in text, f"default --after: {text}")
    print(text)
    # Without the rise after 20 kpc there is no pericentre.
    for k in range(7, len(SEPARATION)):
        os.remove(os.path.join(d, f"snapshot_{k:04d}.hdf5"))
    code, text = run(d)
    check(code == 0 and "no pericentre in these snapshots" in text, f"no rise, yet a pericentre: {text}")


def test_bad_input():
    d = os.path.join(WORK, "bad")
    os.makedirs(d)
    code, _ = run(d)
    check(isinstance(code, str) and "bad: no snapshot_*.hdf5" in code, f"an empty folder: {code!r}")
    cases = [("not HDF5", "cannot open as HDF5"), ("no bulges", "no PartType3/ParticleIDs dataset"),
             ("one black hole", "needs both galaxies (black holes with ids 1 and 2)")]
    for what, pattern in cases:
        path = os.path.join(d, "snapshot_0000.hdf5")
        if what == "not HDF5":
            open(path, "w").write("not a snapshot\n")
        else:
            write_snapshot(path, 0, drop=("PartType3",) if what == "no bulges" else (),
                           bh_ids=(1,) if what == "one black hole" else (1, 2))
        code, _ = run(d)
        check(isinstance(code, str) and code.startswith(path + ": ") and pattern in code, f"{what}: {code!r}")
    p = subprocess.run([sys.executable, os.path.join(SRC, "scripts", "collision_tails.py"), d],
                       capture_output=True, text=True)
    check(p.returncode == 1 and "needs both galaxies" in p.stderr and not p.stdout,
          f"as a program, one black hole: exit {p.returncode}, {p.stderr!r}")


for test in (test_pericentre_and_tails, test_bad_input):
    test()
sys.exit(1 if failures else 0)
