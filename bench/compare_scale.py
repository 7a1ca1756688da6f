"""Agreement of orrery's SPH column density with SPLASH's exact rendering,
for bench/bench_scale.sh, in the pixels where the particles are well sampled.

  compare_scale.py ORRERY.fits SPLASH.pix SNAPSHOT WIDTH CX CY

ORRERY.fits: orrery's image (mass per area), orthographic, WIDTH across,
centred on (CX, CY), looking along -z. SPLASH.pix: SPLASH's `-o ascii` map
of the same view (column density, mass per area). SNAPSHOT: the Gadget-1
file both read (POS and HSML blocks; bench_snapshot's layout).

A pixel is *well sampled* when
  - no particle with h < 2 pixels lies within 4 pixels of it (in x and in
    y): such kernels (support 2h < 4 pixels) are the only ones that can reach
    it while being under-resolved, where SPLASH's centre sampling and
    orrery's pixel integrals legitimately differ by more than 1 %
    (docs/splash.md, "What differs");
  - at least 5 particles lie within those 4 pixels (not only the tails of a
    few distant kernels);
  - SPLASH's value is positive.
Prints the share of the image that is well sampled, the share of those
pixels within 1 % of SPLASH, and the median / 99th percentile / largest
relative difference; last line "agreement PASS|FAIL SHARE" for the script.
"""
import os
import sys

import numpy as np
from astropy.io import fits

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from compare_splash import read_pix  # noqa: E402

REACH = 4          # pixels: the support 2h of a kernel with h < 2 pixels
MIN_HPIX = 2.0     # pixels
MIN_PARTICLES = 5
TOL = 0.01


def gadget_pos_hsml(path):
    """POS and HSML of a Gadget-1 file of gas only, blocks POS VEL ID MASS U
    RHO HSML (32-bit ids, float), each in 4-byte record markers."""
    n = int(np.fromfile(path, dtype="<i4", count=2)[1])  # record marker, npart[0]
    rec = lambda nbytes: 8 + nbytes
    off_pos = rec(256) + 4
    off_hsml = rec(256) + 2 * rec(12 * n) + 4 * rec(4 * n) + 4  # after POS VEL ID MASS U RHO
    pos = np.memmap(path, dtype="<f4", mode="r", offset=off_pos, shape=(n, 3))
    hsml = np.memmap(path, dtype="<f4", mode="r", offset=off_hsml, shape=(n,))
    if os.path.getsize(path) != off_hsml + 4 * n + 4:
        sys.exit("%s: not the layout bench_snapshot writes" % path)
    return pos, hsml


def window(a, op):
    """op (np.minimum or np.add) over the (2 REACH + 1)^2 window around each
    pixel of a (padded by REACH on each side); result REACH smaller per side."""
    r = REACH
    rows = a[:, 0:a.shape[1] - 2 * r].copy()
    for k in range(1, 2 * r + 1):
        rows = op(rows, a[:, k:a.shape[1] - 2 * r + k])
    out = rows[0:a.shape[0] - 2 * r].copy()
    for k in range(1, 2 * r + 1):
        out = op(out, rows[k:a.shape[0] - 2 * r + k])
    return out


def well_sampled(pos, hsml, width, cx, cy, nx, ny):
    dx = width / nx
    r = REACH
    ix = np.floor((pos[:, 0] - (cx - 0.5 * width)) / dx).astype(np.int64) + r
    iy = np.floor((pos[:, 1] - (cy - 0.5 * dx * ny)) / dx).astype(np.int64) + r
    on = (ix >= 0) & (ix < nx + 2 * r) & (iy >= 0) & (iy < ny + 2 * r)
    pix = iy[on] * (nx + 2 * r) + ix[on]
    hpix = 0.5 * np.asarray(hsml[on], dtype=np.float64) / dx
    count = np.bincount(pix, minlength=(nx + 2 * r) * (ny + 2 * r)).reshape(ny + 2 * r, nx + 2 * r)
    order = np.lexsort((hpix, pix))
    first = np.unique(pix[order], return_index=True)
    hmin = np.full((ny + 2 * r) * (nx + 2 * r), np.inf)
    hmin[first[0]] = hpix[order][first[1]]
    hmin = hmin.reshape(ny + 2 * r, nx + 2 * r)
    return (window(hmin, np.minimum) >= MIN_HPIX) & (window(count, np.add) >= MIN_PARTICLES)


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__.split("\n\n")[1])
    o_path, s_path, snap = sys.argv[1:4]
    width, cx, cy = (float(v) for v in sys.argv[4:7])
    o = fits.getdata(o_path).astype(np.float64)
    ny, nx = o.shape
    o *= (width / nx) ** 2  # orrery's column density (mass per area) -> mass per pixel
    s = read_pix(s_path)
    if s.shape != o.shape:
        sys.exit("%s is %d x %d, %s %d x %d" % (s_path, s.shape[1], s.shape[0], o_path, nx, ny))
    s *= (width / nx) ** 2  # column density -> mass per pixel
    pos, hsml = gadget_pos_hsml(snap)
    mask = well_sampled(pos, hsml, width, cx, cy, nx, ny) & (s > 0)
    print("image sums: orrery %.7g, SPLASH exact %.7g" % (o.sum(), s.sum()))
    if not mask.any():
        print("no well-sampled pixels")
        print("agreement FAIL 0")
        return 1
    rel = np.abs(o[mask] - s[mask]) / s[mask]
    within = float(np.mean(rel < TOL))
    print("well sampled: %.1f %% of the image; within 1 %%: %.3f %% of those; "
          "relative difference median %.1e, 99th pct %.1e, max %.1e"
          % (100 * mask.mean(), 100 * within, np.median(rel), np.percentile(rel, 99), rel.max()))
    nz = s > 0
    rel_all = np.abs(o[nz] - s[nz]) / s[nz]
    print("all pixels where SPLASH > 0 (%.1f %%): within 1 %%: %.1f %%" % (100 * nz.mean(), 100 * np.mean(rel_all < TOL)))
    print("agreement %s %.5f" % ("PASS" if within == 1.0 else "FAIL", within))
    return 0


if __name__ == "__main__":
    sys.exit(main())
