#!/usr/bin/env python3
"""Particles for, and the comparison behind, tests/cli/test_splash.sh: orrery's
SPH column-density image against SPLASH's rendering of the same particles.

  compare_splash.py particles OUT.txt [--n N] [--seed S]
      A Plummer sphere (80 % of the mass, a = 1, cut at r = 3.5) and a denser
      Plummer clump (20 %, a = 0.25, at (1.2, 0.7, 0.4)), equal masses summing
      to 1, h = 1.2 (m / rho)^(1/3) with rho the model's density (about 58
      neighbours in 2h, what SPH codes aim for). One table read by both
      programs: '# x y z mass h rho' (orrery's text reader takes mass and h,
      SPLASH's ascii reader recognises all six columns by name).

  compare_splash.py compare --orrery FITS --splash PIX [--fine PIX]
          --particles TXT --width W [--min-kernels 5] [--min-hpix 3] [--tol 0.01]
      FITS: orrery's image (mass per area). PIX: SPLASH's pixel map ('-o
      ascii': column density, mass per area, one image row per line from the
      bottom) of the same view at the same size. FINE: SPLASH's map at k
      times the resolution; summed over k x k blocks it is a k x k midpoint
      rule for the pixel average, and (k^2 FINE - PIX) / (k^2 - 1) removes
      the leading error of SPLASH's centre sampling (Richardson), giving the
      pixel average that orrery computes.
      Pixels compared ("more than a few particles per kernel"): at least
      --min-kernels particles within h of the pixel centre (projected), i.e.
      inside the core of several kernels, not only in their tails. Checks
      that the largest |orrery - SPLASH| / SPLASH stays below --tol (exit 1
      otherwise) in those pixels (1) at the same resolution where the
      kernels are resolved, the smallest h reaching the pixel (within 2h)
      being at least --min-hpix pixels, since SPLASH samples each kernel at
      pixel centres, an error that grows as 1/h^2 (docs/splash.md); (2)
      against the extrapolated pixel averages, whatever h. Other lines are
      printed for information.
"""
import argparse
import sys

import numpy as np
from astropy.io import fits


def plummer(rng, n, a, rmax):
    """n positions of a Plummer sphere of scale a, cut at radius rmax."""
    fmax = rmax**3 / (rmax**2 + a**2) ** 1.5  # enclosed mass fraction at rmax
    u = rng.uniform(0.0, fmax, n)
    r = a / np.sqrt(u ** (-2.0 / 3.0) - 1.0)
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    return r[:, None] * v


def plummer_density(p, centre, mass, a):
    r2 = ((p - centre) ** 2).sum(axis=1)
    return 3.0 * mass / (4.0 * np.pi * a**3) * (1.0 + r2 / a**2) ** -2.5


def make_particles(args):
    rng = np.random.default_rng(args.seed)
    n1 = int(0.8 * args.n)
    n2 = args.n - n1
    clump = np.array([1.2, 0.7, 0.4])
    p = np.vstack([plummer(rng, n1, 1.0, 3.5), clump + plummer(rng, n2, 0.25, 2.0)])
    m = np.full(args.n, 1.0 / args.n)
    # Density of the (uncut) model, each component carrying its share of the mass.
    rho = plummer_density(p, 0.0, 0.8, 1.0) + plummer_density(p, clump, 0.2, 0.25)
    h = 1.2 * (m / rho) ** (1.0 / 3.0)
    with open(args.out, "w") as f:
        f.write("# x y z mass h rho\n")
        np.savetxt(f, np.column_stack([p, m, h, rho]), fmt="%.9g")
    print("%d particles, h from %.4g to %.4g (median %.4g)" % (args.n, h.min(), h.max(), np.median(h)))


def read_pix(path):
    """SPLASH's ascii pixel map: '#' header lines, the last one 'nx ny', then
    ny rows of nx values (a row may wrap over several lines)."""
    with open(path) as f:
        lines = f.read().split("\n")
    head = [l for l in lines if l.startswith("#")]
    nx, ny = (int(v) for v in head[-1][1:].split())
    vals = np.array(" ".join(l for l in lines if not l.startswith("#")).split(), dtype=float)
    if vals.size != nx * ny:
        sys.exit("%s: %d values, expected %d x %d" % (path, vals.size, nx, ny))
    return vals.reshape(ny, nx)


def coverage(parts, width, nx, ny):
    """Per pixel: how many particles have the pixel centre within h of them
    (projected on the image plane), and the smallest h whose support (2h)
    reaches the pixel centre. The image spans [-W/2, W/2] in x, centred."""
    dx = width / nx
    x0, y0 = -0.5 * width, -0.5 * dx * ny
    xc = x0 + (np.arange(nx) + 0.5) * dx
    yc = y0 + (np.arange(ny) + 0.5) * dx
    core = np.zeros((ny, nx), dtype=np.int32)
    hmin = np.full((ny, nx), np.inf)
    for xi, yi, hi in zip(parts[:, 0], parts[:, 1], parts[:, 4]):
        r = 2.0 * hi
        i0, i1 = max(int(np.floor((xi - r - x0) / dx)), 0), min(int(np.ceil((xi + r - x0) / dx)), nx)
        j0, j1 = max(int(np.floor((yi - r - y0) / dx)), 0), min(int(np.ceil((yi + r - y0) / dx)), ny)
        if i0 >= i1 or j0 >= j1:
            continue
        d2 = (xc[None, i0:i1] - xi) ** 2 + (yc[j0:j1, None] - yi) ** 2
        core[j0:j1, i0:i1] += d2 < hi * hi
        sub = hmin[j0:j1, i0:i1]
        np.minimum(sub, np.where(d2 < r * r, hi, np.inf), out=sub)
    return core, hmin / dx


def stats(name, o, ref, mask, tol):
    rel = np.abs(o - ref) / np.where(ref > 0, ref, np.nan)
    m = mask & (ref > 0)
    if not m.any():
        print("%-42s no pixels compared" % name)
        return False
    r = rel[m]
    j, i = np.unravel_index(np.argmax(np.where(m, rel, -1.0)), rel.shape)
    print(
        "%-42s %5.1f %% of pixels: median %.1e, 99th pct %.1e, max %.1e at pixel (%d, %d)%s"
        % (name, 100.0 * m.mean(), np.median(r), np.percentile(r, 99), r.max(), i, j,
           "" if tol is None else (" [limit %.0e]" % tol))
    )
    return tol is None or r.max() < tol


def compare(args):
    o = fits.getdata(args.orrery).astype(np.float64)
    ny, nx = o.shape
    dx = args.width / nx
    o *= dx * dx  # orrery's column density (mass per area) -> mass per pixel, compared below
    s = read_pix(args.splash)
    if s.shape != o.shape:
        sys.exit("SPLASH map %s is %d x %d, orrery's %d x %d" % (args.splash, s.shape[1], s.shape[0], nx, ny))
    s *= dx * dx  # column density -> mass per pixel
    parts = np.loadtxt(args.particles)
    core, hpix = coverage(parts, args.width, nx, ny)
    many = core >= args.min_kernels
    resolved = many & (hpix >= args.min_hpix)
    print("image sums: orrery %.7g, SPLASH %.7g" % (o.sum(), s.sum()))
    ok = stats("same size, >= %d kernels, h >= %g px" % (args.min_kernels, args.min_hpix), o, s, resolved, args.tol)
    stats("same size, >= %d kernels, h >= 2 px" % args.min_kernels, o, s, many & (hpix >= 2), None)
    stats("same size, >= %d kernels, any h" % args.min_kernels, o, s, many, None)
    stats("same size, all pixels", o, s, np.ones_like(many), None)
    if args.fine:
        f = read_pix(args.fine)
        k = f.shape[1] // nx
        if k < 2 or f.shape != (k * ny, k * nx):
            sys.exit("fine SPLASH map %s is not a multiple of %d x %d" % (args.fine, nx, ny))
        fb = f.reshape(ny, k, nx, k).sum(axis=(1, 3)) * (dx / k) ** 2
        stats("SPLASH %dx%d-sampled, >= %d kernels, any h" % (k, k, args.min_kernels), o, fb, many, None)
        # Centre sampling errs by c / k^2 with k x k samples a pixel (the
        # midpoint rule), so (k^2 fb - s) / (k^2 - 1) is SPLASH's pixel average.
        ex = (k * k * fb - s) / (k * k - 1)
        ok &= stats("SPLASH extrapolated, >= %d kernels, any h" % args.min_kernels, o, ex, many, args.tol)
        stats("SPLASH extrapolated, all pixels", o, ex, np.ones_like(many), None)
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("particles")
    p.add_argument("out")
    p.add_argument("--n", type=int, default=20000)
    p.add_argument("--seed", type=int, default=20240611)
    c = sub.add_parser("compare")
    c.add_argument("--orrery", required=True)
    c.add_argument("--splash", required=True)
    c.add_argument("--fine")
    c.add_argument("--particles", required=True)
    c.add_argument("--width", type=float, required=True)
    c.add_argument("--min-kernels", type=int, default=5)
    c.add_argument("--min-hpix", type=float, default=3.0)
    c.add_argument("--tol", type=float, default=0.01)
    args = ap.parse_args()
    if args.cmd == "particles":
        make_particles(args)
        return 0
    return compare(args)


if __name__ == "__main__":
    sys.exit(main())
