"""Agreement of orrery's all-sky SPH column density (equirectangular) with
SPLASH's -360 map, for bench/bench_scale.sh, in the pixels where both
sample the particles well.

  compare_sky.py ORRERY.fits SPLASH.pix SNAPSHOT OX OY OZ

ORRERY.fits: orrery's equirectangular map seen from (OX, OY, OZ) with no
orientation keys (l about world z from world x, growing to the left;
b toward world z; data[0] the bottom row, b = -90) and camera.dim, so a
pixel holds sum (m / r^2) x (kernel per steradian) = mass per area.
SPLASH.pix: `splash -360 -x 2 -y 3 -o ascii` from the same point (its
XORIGIN the observer's negative, docs/splash.md): phi = atan2(y, x) from
-180 to 180 along a line, theta = acos(z / r) from 0 (first line) to 180,
each pixel sum m F(q) / h^2 at its centre, q the chord at the particle's
distance over h: mass per area. So SPLASH's map turned by 180 degrees
(both axes reversed) is orrery's, in the same units; nothing is rescaled.
SNAPSHOT: the Gadget-1 file both read.

The particles around the observer, whose kernels hold it (r < h, a few),
are drawn differently by design: SPLASH adds m F(q) / h^2 (q, at most
2 r / h, the chord at the particle's distance over h), while orrery
spreads the weight m / max(r, 0.01)^2 (camera.dim_near; the pair's Sun is a
particle of 1e-10 at the observer) over the part of the cap inside
q < 2 r / h, normalised to the weight, i.e. times 1 / frac with
frac = 2 pi int_0^(2r/h) F(u) u du < 1 (for r > h the two are the same
sum). Each covers the whole sky, by up to 10 % of a pixel's value where
the sky is faint. That difference is computed here (cubic spline) and
taken off orrery's map before comparing ("corrected"); the figures without
it are printed too.

A pixel is *well sampled* when
  - no particle whose kernel is under 2 pixels (h / r under 2 pixel
    heights, pi / H each; along l a pixel spans less of the sky, so the
    kernel spans more pixels there) lies within 4 pixels of it, along l
    across the seam too;
  - at least 5 particles lie within those 4 pixels;
  - SPLASH's value is positive;
  - it is not in SPLASH's first or last row or column: SPLASH 3.6.0 treats
    theta as periodic too and draws a kernel whose range is the whole
    circle of longitude (a cap over a pole; every kernel holding the
    observer within 2h, whose range is the whole sky) over pixels 0 to
    n + 1, wrapped, so it adds those kernels twice to the seam's columns
    and the poles' rows (interpolate3D_proj_geom, iroll,
    coord_is_periodic).
Prints the share of the sky well sampled, the share of those pixels within
1 % of SPLASH, the median orrery / SPLASH ratio and the median / 99th
percentile / largest relative difference; last line
"agreement PASS|FAIL SHARE" for the script.
"""
import os
import sys

import numpy as np
from astropy.io import fits

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from compare_scale import MIN_HPIX, MIN_PARTICLES, REACH, TOL, gadget_pos_hsml  # noqa: E402
from compare_splash import read_pix  # noqa: E402

DIM_NEAR = 0.01  # camera.dim_near's default: orrery's weight is m / max(r, DIM_NEAR)^2


def gadget_mass(path, n):
    """The MASS block of bench_snapshot's layout (after POS VEL ID)."""
    off = 8 + 256 + 2 * (8 + 12 * n) + (8 + 4 * n) + 4
    return np.fromfile(path, dtype="<f4", count=n, offset=off).astype(np.float64)


def cubic_column(u):
    """F(u) h^2 of the M4 cubic spline (support 2h), the kernel integrated
    along the line of sight at impact parameter u h: Simpson's rule."""
    z = np.linspace(0.0, 2.0, 401)
    q = np.sqrt(np.asarray(u, dtype=np.float64)[..., None] ** 2 + z ** 2)
    w = np.where(q < 1, 1 - 1.5 * q ** 2 + 0.75 * q ** 3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0)) / np.pi
    c = np.ones(z.size)
    c[1:-1:2], c[2:-1:2] = 4, 2
    return 2 * (w * c).sum(-1) * (z[1] - z[0]) / 3


def sky_pixels(d, nx, ny):
    """Pixel column and row (orrery's orientation) of directions d."""
    r = np.sqrt((d ** 2).sum(1))
    lon = np.arctan2(d[:, 1], d[:, 0])
    lat = np.arcsin(np.clip(d[:, 2] / r, -1, 1))
    ix = np.clip(np.floor((np.pi - lon) * nx / (2 * np.pi)).astype(np.int64), 0, nx - 1)
    iy = np.clip(np.floor((lat + 0.5 * np.pi) * ny / np.pi).astype(np.int64), 0, ny - 1)
    return ix, iy, lon, lat, r


def window(a, op):
    """op (np.minimum or np.add) over the (2 REACH + 1)^2 window around each
    pixel: columns wrap round (the l = 180 seam), rows stop at the poles."""
    r = REACH
    pad = np.concatenate([a[:, -r:], a, a[:, :r]], axis=1)
    rows = pad[:, 0:a.shape[1]].copy()
    for k in range(1, 2 * r + 1):
        rows = op(rows, pad[:, k:a.shape[1] + k])
    out = rows.copy()
    for k in range(1, r + 1):
        out[k:] = op(out[k:], rows[:-k])
        out[:-k] = op(out[:-k], rows[k:])
    return out


def well_sampled(ix, iy, hpix, nx, ny):
    pix = iy * nx + ix
    count = np.bincount(pix, minlength=nx * ny).reshape(ny, nx)
    hmin = np.full(nx * ny, np.inf)
    np.minimum.at(hmin, pix, hpix)
    return (window(hmin.reshape(ny, nx), np.minimum) >= MIN_HPIX) & (window(count, np.add) >= MIN_PARTICLES)


def near_difference(m, h, r, lon, lat, nx, ny):
    """orrery - SPLASH from the particles whose kernel holds the observer
    (r < h), at every pixel centre (see the module's docstring)."""
    lon_c = np.pi - (np.arange(nx) + 0.5) * 2 * np.pi / nx
    lat_c = -0.5 * np.pi + (np.arange(ny) + 0.5) * np.pi / ny
    dirs = np.stack(np.broadcast_arrays(np.cos(lat_c)[:, None] * np.cos(lon_c)[None, :],
                                        np.cos(lat_c)[:, None] * np.sin(lon_c)[None, :],
                                        np.sin(lat_c)[:, None]), axis=-1)
    u_grid = np.linspace(0, 2, 2001)
    f_grid = cubic_column(u_grid)
    # frac(x) = 2 pi int_0^x F(u) u du: trapezoids, and pi F(0) x^2 below the first step
    cum = 2 * np.pi * np.concatenate([[0], np.cumsum(0.5 * (f_grid[1:] * u_grid[1:] + f_grid[:-1] * u_grid[:-1])
                                                     * np.diff(u_grid))])
    diff = np.zeros((ny, nx))
    for k in np.flatnonzero(r < h):
        p = np.array([np.cos(lat[k]) * np.cos(lon[k]), np.cos(lat[k]) * np.sin(lon[k]), np.sin(lat[k])])
        chord = np.sqrt(np.maximum(((dirs - p) ** 2).sum(-1), 0))
        x = 2 * r[k] / h[k]
        frac = np.interp(x, u_grid, cum) if x >= u_grid[1] else np.pi * f_grid[0] * x * x
        dimming = r[k] ** 2 / max(r[k], DIM_NEAR) ** 2
        diff += m[k] * np.interp(chord * r[k] / h[k], u_grid, f_grid) / h[k] ** 2 * (dimming / frac - 1)
    return diff, int((r < h).sum())


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__.split("\n\n")[1])
    o_path, s_path, snap = sys.argv[1:4]
    obs = np.array([float(v) for v in sys.argv[4:7]])
    o = fits.getdata(o_path).astype(np.float64)
    ny, nx = o.shape
    s = read_pix(s_path)[::-1, ::-1]  # SPLASH's phi right, theta down -> orrery's l left, b up
    if s.shape != o.shape:
        sys.exit("%s is %d x %d, %s %d x %d" % (s_path, s.shape[1], s.shape[0], o_path, nx, ny))
    pos, hsml = gadget_pos_hsml(snap)
    h = 0.5 * np.asarray(hsml, dtype=np.float64)
    ix, iy, lon, lat, r = sky_pixels(np.asarray(pos, dtype=np.float64) - obs, nx, ny)
    ok = r > 0
    hpix = np.where(ok, h / np.where(ok, r, 1) / (np.pi / ny), 0.0)
    near, n_near = near_difference(gadget_mass(snap, h.size), h, r, lon, lat, nx, ny)
    mask = well_sampled(ix[ok], iy[ok], hpix[ok], nx, ny) & (s > 0)
    mask[[0, -1], :] = mask[:, [0, -1]] = False
    omega = 2 * np.pi / nx * (np.sin(-0.5 * np.pi + (np.arange(1, ny + 1)) * np.pi / ny)
                              - np.sin(-0.5 * np.pi + np.arange(ny) * np.pi / ny))
    print("sky totals (sum of pixel x solid angle): orrery %.7g, SPLASH -360 %.7g"
          % ((o * omega[:, None]).sum(), (s * omega[:, None]).sum()))
    print("particles holding the observer (r < h): %d; their difference is up to %.2g %% of a pixel (median %.2g %%)"
          % (n_near, 100 * np.max(np.abs(near) / np.where(s > 0, s, np.inf)),
             100 * np.median(np.abs(near[s > 0]) / s[s > 0])))
    if not mask.any():
        print("no well-sampled pixels")
        print("agreement FAIL 0")
        return 1
    corrected = o - near
    rel = np.abs(corrected[mask] - s[mask]) / s[mask]
    within = float(np.mean(rel < TOL))
    print("well sampled: %.1f %% of the pixels; corrected: within 1 %%: %.3f %% of those; "
          "orrery / SPLASH median %.6f; relative difference median %.1e, 99th pct %.1e, max %.1e"
          % (100 * mask.mean(), 100 * within, np.median(corrected[mask] / s[mask]),
             np.median(rel), np.percentile(rel, 99), rel.max()))
    raw = np.abs(o[mask] - s[mask]) / s[mask]
    print("  not corrected: within 1 %%: %.3f %%; orrery / SPLASH median %.6f; relative difference median %.1e"
          % (100 * np.mean(raw < TOL), np.median(o[mask] / s[mask]), np.median(raw)))
    nz = s > 0
    rel_all = np.abs(corrected[nz] - s[nz]) / s[nz]
    print("all pixels where SPLASH > 0 (%.1f %%), corrected: within 1 %%: %.1f %%; orrery / SPLASH median %.6f"
          % (100 * nz.mean(), 100 * np.mean(rel_all < TOL), np.median(corrected[nz] / s[nz])))
    print("agreement %s %.5f" % ("PASS" if within == 1.0 else "FAIL", within))
    return 0


if __name__ == "__main__":
    sys.exit(main())
