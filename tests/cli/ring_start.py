"""The circular speed the particles give a tracer, from a snapshot alone
(h5py and numpy, independently of orrery-nbody's C): the pull of every
particle, Plummer-softened by the pair rule (eps_i^2 + eps_t^2) / 2 with the
tracer's eps_t = max(Eps, sqrt(2) x its 32nd heavier neighbour's distance),
summed directly at K points on the ring through the tracer about its
galaxy's axis; the mean inward part a_R gives v_c = sqrt(R a_R). The
galaxy: the stars within max(5, 2 x the tracer's distance) of the nearest
black hole, centred twice on their centre of mass, its axis the least
second moment of its disc particles, its velocity the stars' mean (those
of the second pass). (Its acceleration, which is not in a snapshot, does
not matter: turned back about the axis, a uniform pull has no radial
part.)

With --mirror (orrery-nbody's --tracer-mirror) every odd point is
reflected across the disc's plane, to the tracer's -z (the inward part of
its pull, across the axis, is the same reflected back or not).

usage: ring_start.py [--points K] [--mirror] SNAPSHOT_FILE...   (K = 32; the
files of one snapshot: one, or a --decompose run's one a rank) prints
"R z v_c v_phi v_R v_z" of the Sun (id 3), speeds about the galaxy (km/s),
v_phi signed along n x R.
"""
import sys

import h5py
import numpy as np

G = 43007.1


def load(paths):
    files = [h5py.File(p, "r") for p in paths]
    groups = [(f[k], int(k[-1])) for f in files for k in f if k.startswith("PartType")]
    cat = lambda name: np.concatenate([g[name][:].astype(float) for g, _ in groups])
    t = np.concatenate([np.full(len(g["Masses"]), k) for g, k in groups])
    ids = np.concatenate([g["ParticleIDs"][:] for g, _ in groups])
    run = files[0]["OrreryNbody"].attrs
    return cat("Coordinates"), cat("Velocities"), cat("Masses"), t, ids, run["Eps"], run["EpsHalo"]


def turn(n, phi, d):
    """d turned by phi about the unit axis n (Rodrigues)."""
    return d * np.cos(phi) + np.cross(n, d) * np.sin(phi) + n * (n @ d) * (1 - np.cos(phi))


def main():
    args = sys.argv[1:]
    K, mirror = 32, False
    while args[:1] in (["--points"], ["--mirror"]):
        if args[0] == "--mirror":
            mirror, args = True, args[1:]
        else:
            K, args = int(args[1]), args[2:]
    x, v, m, t, ids, eps, eps_halo = load(args)
    heavy = m >= 1e-3 * m.mean()
    sun = np.nonzero(ids == 3)[0][0]
    xs, vs = x[sun], v[sun]
    holes = x[t == 5]
    hole = holes[np.argmin(np.linalg.norm(holes - xs, axis=1))]
    radius = max(5.0, 2 * np.linalg.norm(xs - hole))
    star = heavy & ((t == 2) | (t == 3))
    centre = hole
    for _ in range(2):
        inside = star & (np.linalg.norm(x - centre, axis=1) <= radius)
        c = (m[inside, None] * x[inside]).sum(0) / m[inside].sum()
        v_host = (m[inside, None] * v[inside]).sum(0) / m[inside].sum()
        centre = c
    disc = (t == 2) & (np.linalg.norm(x - c, axis=1) <= radius)
    d = x[disc] - c
    n = np.linalg.eigh((m[disc, None, None] * d[:, :, None] * d[:, None, :]).sum(0))[1][:, 0]
    r32 = np.sort(np.linalg.norm(x[heavy] - xs, axis=1))[31]
    eps_t = max(eps, np.sqrt(2) * r32)
    e2 = 0.5 * (np.where(t == 1, eps_halo, eps)[heavy] ** 2 + eps_t**2)
    xh, mh = x[heavy], m[heavy]
    rel = xs - c
    z = rel @ n
    p = rel - z * n
    R = np.linalg.norm(p)
    inward = 0.0
    for k in range(K):
        phi = 2 * np.pi * k / K
        d = turn(n, phi, rel)
        if mirror and k % 2:
            d = d - 2 * (d @ n) * n
        pk = c + d
        dd = xh - pk
        r2 = (dd * dd).sum(1) + e2
        a = G * ((mh / (r2 * np.sqrt(r2)))[:, None] * dd).sum(0)
        inward -= a @ turn(n, phi, p) / R
    inward /= K
    u = vs - v_host
    tangent = np.cross(n, p) / R
    print(f"{R:.6f} {z:.6f} {np.sqrt(R * inward):.6f} {u @ tangent:.6f} {u @ p / R:.6f} {u @ n:.6f}")


if __name__ == "__main__":
    main()
