#!/usr/bin/env python3
"""Checks an evolved box from `orrery ics --evolve` against its start and
linear theory, independently of orrery's code.

usage: scripts/box_stats.py START.hdf5 END.hdf5 [--kmax K] [--mesh M]

START is the Zel'dovich box at the run's first redshift (`orrery ics
--zeldovich --z 24`, the same --grid, --box and --seed), END the evolved one.

1. Growth: the matter power spectrum of each, from a cloud-in-cell deposit on
   an M³ mesh (default twice the particle grid) and numpy's FFT, divided by
   the CIC window squared, in shells of width k_f = 2π/box; for each shell
   below K (default 0.05 h/Mpc) the ratio P_end / P_start / [D(a_end) /
   D(a_start)]², D integrated here from the growth equation (scipy's
   solve_ivp), not taken from orrery. The same modes at both ends: sample
   variance cancels.
2. Non-Gaussianity: the skewness of the CIC density contrast on the
   particles' own grid (N³ cells), and the fraction of the mass in cells of
   the M³ mesh above 100 times the mean density, at both ends.
3. Momentum: |Σ u| / Σ |u| of the velocities; mass: the particle counts.

A file that is not such a box (unreadable, no Header attribute or
PartType1 dataset it needs, a particle count that is not a cube, or START
and END of different boxes) is refused with a message naming the file and
what is wrong, exit status 1. tests/cli/test_box_stats.sh runs it on
synthetic boxes with known answers (check_box_stats.py).
"""
import argparse
import sys

import h5py
import numpy as np
from scipy.integrate import solve_ivp


class BoxError(Exception):
    """A file that is not a box this script can measure."""


def load(path):
    """Header attributes, positions and velocities of the box's PartType1."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise BoxError(f"{path}: cannot open as HDF5: {e}") from None
    with f:
        if "Header" not in f:
            raise BoxError(f"{path}: no Header group (not a Gadget/orrery HDF5 snapshot)")
        hdr = dict(f["Header"].attrs)
        for key in ("BoxSize", "Time", "Omega0", "OmegaLambda"):
            if key not in hdr:
                raise BoxError(f"{path}: Header has no {key} attribute")
        for name in ("PartType1/Coordinates", "PartType1/Velocities"):
            if name not in f:
                raise BoxError(f"{path}: no {name} dataset")
        x = f["PartType1/Coordinates"][:].astype(np.float64)
        v = f["PartType1/Velocities"][:].astype(np.float64)
    n = round(len(x) ** (1 / 3))
    if len(x) == 0 or n ** 3 != len(x) or x.shape != (n ** 3, 3) or v.shape != x.shape:
        raise BoxError(f"{path}: PartType1 holds {x.shape} positions and {v.shape} velocities, "
                       "not n^3 of each (a box from a particle grid)")
    return hdr, x, v


def cic(x, box, m):
    u = x * (m / box)
    i0 = np.floor(u).astype(np.int64)
    t = u - i0
    rho = np.zeros(m * m * m)
    for cx in (0, 1):
        for cy in (0, 1):
            for cz in (0, 1):
                w = (t[:, 0] if cx else 1 - t[:, 0]) * (t[:, 1] if cy else 1 - t[:, 1]) * \
                    (t[:, 2] if cz else 1 - t[:, 2])
                idx = (((i0[:, 0] + cx) % m) * m + (i0[:, 1] + cy) % m) * m + (i0[:, 2] + cz) % m
                rho += np.bincount(idx, weights=w, minlength=m ** 3)
    rho = rho.reshape(m, m, m)
    return rho / rho.mean() - 1


def power_shells(delta, box, nshell):
    m = delta.shape[0]
    dk = np.fft.rfftn(delta) / m ** 3
    n = np.fft.fftfreq(m) * m
    nz = np.arange(m // 2 + 1)
    nx, ny, nzz = np.meshgrid(n, n, nz, indexing="ij")
    s = np.pi * np.array([nx, ny, nzz]) / m
    window = np.prod(np.where(s == 0, 1.0, np.sin(s) / np.where(s == 0, 1, s)) ** 2, axis=0)
    p = np.abs(dk / window) ** 2 * box ** 3
    shell = np.floor(np.sqrt(nx ** 2 + ny ** 2 + nzz ** 2) + 0.5).astype(int)
    # rfft holds half of k-space: the kz = 0 plane twice over, which is fine for a shell mean
    out = []
    for i in range(1, nshell + 1):
        sel = shell == i
        out.append((i * 2 * np.pi / box, p[sel].mean(), sel.sum()))
    return out


def growth(om, ol, a):
    """D(a), unnormalised: dD/da = y / (a³E), dy/da = 1.5 Ω_m D / (a²E), from
    matter domination (D = a)."""
    def e(aa):
        return np.sqrt(om / aa ** 3 + (1 - om - ol) / aa ** 2 + ol)

    def rhs(aa, s):
        return [s[1] / (aa ** 3 * e(aa)), 1.5 * om * s[0] / (aa ** 2 * e(aa))]
    a0 = 1e-3
    sol = solve_ivp(rhs, (a0, a), [a0, a0 ** 3 * e(a0)], rtol=1e-10, atol=1e-14)
    return sol.y[0, -1]


def measure(start, end, kmax=0.05, mesh=None):
    """Every figure the script prints, as a dict (see the module's docstring)."""
    h0, x0, v0 = load(start)
    h1, x1, v1 = load(end)
    box = float(h0["BoxSize"])
    if float(h1["BoxSize"]) != box or len(x1) != len(x0):
        raise BoxError(f"{end}: box {float(h1['BoxSize']):g} with {len(x1)} particles, but {start} is box "
                       f"{box:g} with {len(x0)}: not the same run")
    n = round(len(x0) ** (1 / 3))
    m = mesh or 2 * n
    om, ol = float(h0["Omega0"]), float(h0["OmegaLambda"])
    a0, a1 = float(h0["Time"]), float(h1["Time"])
    expect = (growth(om, ol, a1) / growth(om, ol, a0)) ** 2
    nshell = max(1, int(kmax * box / (2 * np.pi) - 0.5))
    d0, d1 = cic(x0, box, m), cic(x1, box, m)
    shells = [(k, modes, p1 / p0 / expect)
              for (k, p0, modes), (_, p1, _) in zip(power_shells(d0, box, nshell), power_shells(d1, box, nshell))]
    ends = {}
    for name, x, v in (("start", x0, v0), ("end", x1, v1)):
        d = cic(x, box, n).ravel()
        fine = cic(x, box, m).ravel() + 1
        ends[name] = {"skewness": np.mean(d ** 3) / np.mean(d ** 2) ** 1.5, "max": d.max() + 1,
                      "mass_above_100": fine[fine > 100].sum() / fine.sum(),
                      "momentum": np.linalg.norm(v.sum(0)) / np.linalg.norm(v, axis=1).sum(), "particles": len(v)}
    return {"box": box, "n": n, "mesh": m, "a": (a0, a1), "growth2": expect, "kmax": kmax, "shells": shells,
            "worst": max(abs(r - 1) for _, _, r in shells), "ends": ends}


def main(argv):
    ap = argparse.ArgumentParser(description="An evolved box against its start and linear theory.")
    ap.add_argument("start", help="the Zel'dovich box at the run's first redshift")
    ap.add_argument("end", help="the evolved box")
    ap.add_argument("--kmax", type=float, default=0.05, help="largest k (h/Mpc) of the growth check")
    ap.add_argument("--mesh", type=int, help="CIC mesh per side (default twice the particle grid)")
    args = ap.parse_args(argv)
    if args.kmax <= 0 or (args.mesh is not None and args.mesh < 2):
        ap.error("--kmax must be positive and --mesh at least 2")
    try:
        r = measure(args.start, args.end, args.kmax, args.mesh)
    except BoxError as e:
        sys.exit(f"box_stats.py: {e}")
    n, m = r["n"], r["mesh"]
    print(f"box {r['box']:g} Mpc/h, {n}^3 particles, a {r['a'][0]:.4f} -> {r['a'][1]:.4f}, "
          f"[D1/D0]^2 = {r['growth2']:.2f}, mesh {m}^3")
    for k, modes, ratio in r["shells"]:
        print(f"  k = {k:.4f} h/Mpc ({modes} modes): P_end/P_start/[D1/D0]^2 = {ratio:.4f}")
    print(f"  largest deviation below k = {r['kmax']:g}: {100 * r['worst']:.1f} %")
    for name, e in r["ends"].items():
        print(f"  {name}: skewness of delta on {n}^3 cells {e['skewness']:.3f}, "
              f"max 1+delta {e['max']:.1f}; mass in {m}^3 cells above 100x mean {100 * e['mass_above_100']:.2f} %")
    for name, e in r["ends"].items():
        print(f"  {name}: |sum u| / sum |u| = {e['momentum']:.2e}, {e['particles']} particles")


if __name__ == "__main__":
    main(sys.argv[1:])
