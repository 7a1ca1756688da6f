#!/usr/bin/env python3
"""Checks scripts/box_stats.py (docs/dark-universe.md) on synthetic boxes
with known answers:

- [D(a1)/D(a0)]^2 in an Einstein-de Sitter universe is (a1/a0)^2, and in
  flat LCDM it is the Heath (1977) integral's, D(a) ~ E(a) * int_0^a
  da' / (a' E(a'))^3 (computed here by quadrature, not by the script's ODE);
- a 16^3 grid displaced by one Zel'dovich plane wave of the box's
  fundamental mode, its amplitude grown by D(a1)/D(a0) from start to end:
  the power ratio in the first shell is 1 (the exact Zel'dovich density's
  first harmonic is short of linear by A^2/8 in amplitude, 3e-4 here); the
  same wave grown 10 % too much gives 1.21;
- every particle in one cell of the N^3 grid: 1 + delta = N^3 there, the
  skewness (N^3 - 2) / sqrt(N^3 - 1) and all the mass above 100 x mean;
- velocities all equal: |sum u| / sum |u| = 1; the wave's: 0;
- bad input (a missing file, a Header without Omega0, a particle count
  that is not a cube, START and END of different boxes) refused with the
  file named and exit 1.

usage: check_box_stats.py SOURCE_DIR WORK_DIR
"""
import contextlib
import io
import os
import subprocess
import sys

import h5py
import numpy as np
from scipy.integrate import quad

SRC, WORK = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SRC, "scripts"))
import box_stats  # noqa: E402

N, BOX = 16, 100.0
K = 2 * np.pi / BOX
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what, file=sys.stderr)


def write_box(name, x, v, a, om=1.0, ol=0.0, box=BOX, drop=()):
    """A Gadget-style HDF5 box as orrery ics writes it (PartType1 only)."""
    path = os.path.join(WORK, name)
    with h5py.File(path, "w") as f:
        h = f.create_group("Header")
        for key, value in (("BoxSize", box), ("Time", a), ("Omega0", om), ("OmegaLambda", ol)):
            if key not in drop:
                h.attrs[key] = value
        f["PartType1/Coordinates"] = np.asarray(x, np.float32)
        f["PartType1/Velocities"] = np.asarray(v, np.float32)
    return path


def grid():
    i = (np.arange(N) + 0.5) * BOX / N
    return np.stack(np.meshgrid(i, i, i, indexing="ij"), -1).reshape(-1, 3)


def wave(amplitude):
    """The grid displaced by x += (A/k) sin(k q_x): delta = -A cos(k q_x) to first order."""
    q = grid()
    x = q.copy()
    x[:, 0] = (q[:, 0] + amplitude / K * np.sin(K * q[:, 0])) % BOX
    v = np.zeros_like(q)
    v[:, 0] = np.sin(K * q[:, 0])
    return x, v


def heath_growth(om, ol, a):
    e = lambda aa: np.sqrt(om / aa ** 3 + (1 - om - ol) / aa ** 2 + ol)  # noqa: E731
    return e(a) * quad(lambda aa: 1 / (aa * e(aa)) ** 3, 0, a, epsabs=0, epsrel=1e-12)[0]


def test_growth_of_a_wave():
    a0, a1, amp = 0.04, 1.0, 0.002
    start = write_box("start.hdf5", *wave(amp), a0)
    end = write_box("end.hdf5", *wave(amp * a1 / a0), a1)
    r = box_stats.measure(start, end)
    check(abs(r["growth2"] / 625 - 1) < 1e-6, f"EdS [D1/D0]^2 = {r['growth2']}, not (1/0.04)^2 = 625")
    (k, modes, ratio), = r["shells"]
    check(abs(k - K) < 1e-12, f"first shell at k = {k}, not 2 pi / box = {K}")
    check(abs(ratio - 1) < 1e-3, f"a wave grown as D: P_end/P_start/[D1/D0]^2 = {ratio}, not 1")
    check(r["ends"]["end"]["momentum"] < 1e-6, f"the wave's momentum ratio {r['ends']['end']['momentum']}, not 0")
    check(r["ends"]["end"]["mass_above_100"] == 0, "mass above 100 x mean in a 5 % wave")
    too_much = write_box("end_fast.hdf5", *wave(1.1 * amp * a1 / a0), a1)
    r = box_stats.measure(start, too_much)
    check(abs(r["shells"][0][2] - 1.21) < 2e-3 and abs(r["worst"] - 0.21) < 2e-3,
          f"a wave grown 10 % too much: ratio {r['shells'][0][2]}, not 1.21")
    print(f"wave: growth^2 625 -> {r['growth2']:.6f}; ratio {ratio:.5f}; 10 % too fast {r['shells'][0][2]:.5f}")


def test_lcdm_growth():
    a0, a1 = 1 / 25, 1.0
    start = write_box("lcdm0.hdf5", *wave(0.002), a0, 0.3, 0.7)
    end = write_box("lcdm1.hdf5", *wave(0.002), a1, 0.3, 0.7)
    expect = (heath_growth(0.3, 0.7, a1) / heath_growth(0.3, 0.7, a0)) ** 2
    got = box_stats.measure(start, end)["growth2"]
    check(abs(got / expect - 1) < 1e-5, f"LCDM [D1/D0]^2 = {got}, Heath's integral gives {expect}")
    print(f"LCDM (0.3, 0.7), a 0.04 -> 1: [D1/D0]^2 {got:.4f}, Heath {expect:.4f}")


def test_one_cell():
    n3 = N ** 3
    x = np.tile(np.array([3, 5, 7]) * BOX / N, (n3, 1))  # on a node of the N^3 mesh: all of it in one cell
    start = write_box("equal_v.hdf5", wave(0.002)[0], np.tile([3.0, 4.0, 0.0], (n3, 1)), 0.04)
    end = write_box("one_cell.hdf5", x, wave(0.002)[1], 1.0)
    e = box_stats.measure(start, end)["ends"]
    skew = (n3 - 2) / np.sqrt(n3 - 1)
    check(abs(e["end"]["max"] - n3) < 1e-6 * n3, f"all in one cell: max 1+delta {e['end']['max']}, not {n3}")
    check(abs(e["end"]["skewness"] / skew - 1) < 1e-9, f"one cell's skewness {e['end']['skewness']}, not {skew}")
    check(e["end"]["mass_above_100"] == 1.0, f"one cell's mass above 100 x mean {e['end']['mass_above_100']}")
    check(abs(e["start"]["momentum"] - 1) < 1e-12, f"equal velocities: momentum ratio {e['start']['momentum']}")
    check(e["start"]["particles"] == n3 and e["end"]["particles"] == n3, "particle counts")


def refused(args, pattern):
    """box_stats.main's exit: status 1 with a message matching pattern."""
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out):
            box_stats.main(args)
        code = 0
    except SystemExit as e:
        code = e.code
    check(isinstance(code, str) and pattern in code, f"box_stats.py {args}: exit {code!r}, expected {pattern!r}")


def test_bad_input():
    x, v = wave(0.002)
    start = write_box("start.hdf5", x, v, 0.04)
    refused([os.path.join(WORK, "none.hdf5"), start], "none.hdf5: cannot open as HDF5")
    refused([write_box("no_om.hdf5", x, v, 1.0, drop=("Omega0",)), start], "no_om.hdf5: Header has no Omega0")
    refused([start, write_box("odd.hdf5", x[:-1], v[:-1], 1.0)], "odd.hdf5: PartType1 holds (4095, 3) positions")
    refused([start, write_box("big.hdf5", x, v, 1.0, box=200.0)], "big.hdf5: box 200 with 4096 particles, but")
    # As a program: the message on stderr, exit status 1, nothing on stdout.
    p = subprocess.run([sys.executable, os.path.join(SRC, "scripts", "box_stats.py"), start,
                        os.path.join(WORK, "none.hdf5")], capture_output=True, text=True)
    check(p.returncode == 1 and "none.hdf5: cannot open as HDF5" in p.stderr and not p.stdout,
          f"box_stats.py on a missing file: exit {p.returncode}, {p.stderr!r}")


for test in (test_growth_of_a_wave, test_lcdm_growth, test_one_cell, test_bad_input):
    test()
sys.exit(1 if failures else 0)
