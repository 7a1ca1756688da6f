"""Checks motion-blurred frames (animation.shutter) against what the motion
predicts: tests/cli/test_motion_blur.sh writes the frames and calls this.

  check_motion_blur.py line FITS   -- two stars moving at known velocities
  check_motion_blur.py pan FITS    -- a camera turning past a star
  check_motion_blur.py dome FITS   -- an observer moving past a star
  check_motion_blur.py same A B    -- two renders' planes are bit-identical

A streak is a segment of uniform brightness drawn with the deposit's
kernel; along it the brightness-weighted variance is L^2/12 plus the
kernel's own (CIC: 1/6 px^2 on average over sub-pixel offsets), so its
length is L = sqrt(12 (var - 1/6)). Its flux is the sum of its pixels
times their measure (the planes are surface brightness)."""
import math
import sys

import numpy as np
from astropy.io import fits

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def streak(img, rows, cols):
    """Flux (pixel sum), centroid and variance along x and y of the region."""
    sub = np.nan_to_num(img[rows, cols])
    y, x = np.mgrid[rows, cols]
    tot = sub.sum()
    cx, cy = (sub * x).sum() / tot, (sub * y).sum() / tot
    vx = (sub * (x - cx) ** 2).sum() / tot
    vy = (sub * (y - cy) ** 2).sum() / tot
    return tot, cx, cy, vx, vy


def length(var):
    return math.sqrt(max(12.0 * (var - 1.0 / 6.0), 0.0))


def line(path):
    # Orthographic, 10 units across 200 px (0.05 units a pixel, area
    # 0.0025); frame interval 0.1, shutter 0.5: a star moves v * 0.05.
    img = fits.getdata(path).astype(np.float64)
    area = (10.0 / 200) ** 2
    # Star A at (0.1, 0.2), vx = 12: 0.6 units = 12 px along x.
    fa, cx, cy, vx, vy = streak(img, slice(90, 120), slice(80, 130))
    check(abs(fa * area - 1) < 1e-5, "slow star's streak holds its flux: %.7f" % (fa * area))
    check(abs(length(vx) - 12) < 0.3, "slow star's streak is 12 px long: %.3f" % length(vx))
    check(abs(cx - (100 + 0.1 / 0.05 - 0.5)) < 0.05 and abs(cy - (100 + 0.2 / 0.05 - 0.5)) < 0.05,
          "slow star's streak is centred on its position at the frame's time: (%.3f, %.3f)" % (cx, cy))
    # Star B at (-3.3, -2.0), vy = 100: 5 units = 100 px along y.
    fb, cx, cy, vx, vy = streak(img, slice(0, 200), slice(25, 40))
    check(abs(fb * area - 1) < 1e-5, "fast star's streak holds its flux: %.7f" % (fb * area))
    check(abs(length(vy) - 100) < 0.5, "fast star's streak is 100 px long: %.3f" % length(vy))
    col = np.nan_to_num(img[:, 25:40]).sum(axis=1)
    lit = np.nonzero(col > 0)[0]
    inner = col[lit[0] + 2:lit[-1] - 1]
    check(lit[-1] - lit[0] + 1 == len(lit), "fast star's streak has no gap (rows %d to %d)" % (lit[0], lit[-1]))
    check(inner.min() > 0.9 * inner.mean() and inner.max() < 1.1 * inner.mean(),
          "fast star's streak is even: %.4f to %.4f of its mean" % (inner.min() / inner.mean(),
                                                                    inner.max() / inner.mean()))


def pan(path):
    # Perspective, 400 x 300, 60 degrees across: focal 200 / tan(30 deg) px.
    # The camera turns 30 degrees over 10 frame intervals, the shutter is
    # open for half of one: each star streaks 1.5 degrees, at the centre
    # 1.5 deg * focal px.
    img = fits.getdata(path).astype(np.float64)
    focal = 200 / math.tan(math.radians(30))
    expect = math.radians(1.5) * focal
    f, cx, cy, vx, vy = streak(img, slice(140, 160), slice(180, 220))
    check(abs(cx - 199.5) < 0.1 and abs(cy - 149.5) < 0.1, "the star's streak is centred: (%.3f, %.3f)" % (cx, cy))
    check(abs(length(vx) - expect) < 0.2, "turning camera streaks the star %.3f px (expected %.3f)"
          % (length(vx), expect))
    check(vy < 0.3, "... along the turn only (variance across %.3f px^2)" % vy)


def dome(path):
    # A 400 px dome master (180 degrees: 400 / pi px a radian); the
    # observer moves at v = 4 along x for 0.05 of simulation time (shutter
    # 0.5 of the frame interval 0.1): 0.2 units, past a star 10 units away
    # across its motion, which sweeps 0.02 rad.
    img = fits.getdata(path).astype(np.float64)
    expect = 0.2 / 10 * 400 / math.pi
    f, cx, cy, vx, vy = streak(img, slice(150, 250), slice(150, 250))  # (the reference is on the rim)
    check(abs(cx - 199.5) < 0.1 and abs(cy - 199.5) < 0.1, "the star's streak is at the zenith: (%.3f, %.3f)"
          % (cx, cy))
    along = max(vx, vy)
    check(abs(length(along) - expect) < 0.2, "the moving observer streaks the star %.3f px (expected %.3f)"
          % (length(along), expect))


def same(a, b):
    ha, hb = fits.open(a), fits.open(b)
    # The planes; not the SCENE text, which names each run's own overrides.
    check(all(np.array_equal(x.data, y.data, equal_nan=True) for x, y in zip(ha, hb)
              if x.data is not None and x.name != "SCENE"),
          "%s and %s hold the same planes bit for bit" % (a, b))


if __name__ == "__main__":
    {"line": line, "pan": pan, "dome": dome, "same": same}[sys.argv[1]](*sys.argv[2:])
    sys.exit(1 if failures else 0)
