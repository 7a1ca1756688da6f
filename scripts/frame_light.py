#!/usr/bin/env python3
"""The light of each frame of a perspective run, and how much it changes.

usage: scripts/frame_light.py [--max-change FRACTION] FRAME.fits...

A frame's light is the sum over its pixels of the value (orrery's pixels
hold surface brightness: weight per steradian, docs/output.md) times the
pixel's solid angle, here the exact solid angle of a flat pixel seen by a
pinhole camera whose field of view (FITS key FOV) spans the wider axis:
independent of orrery's own orr_pixel_measure. Prints each frame's light
and its change from the frame before, then the largest change; with
--max-change, exits 1 when that is larger than FRACTION (0.05: 5 %).
Used by tests/cli/test_dark_universe.sh and docs/dark-universe.md.
"""
import sys

import numpy as np
from astropy.io import fits


def solid_angles(width, height, fov_deg):
    """Each pixel's solid angle: the pinhole integral over its rectangle,
    F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1) with
    F(x, y) = atan(x y / (f sqrt(f^2 + x^2 + y^2))), f the focal length in
    pixels."""
    f = 0.5 * max(width, height) / np.tan(np.radians(fov_deg) / 2)
    x, y = np.meshgrid(np.arange(width + 1) - 0.5 * width, np.arange(height + 1) - 0.5 * height)
    corner = np.arctan(x * y / (f * np.sqrt(f * f + x * x + y * y)))
    return corner[1:, 1:] - corner[1:, :-1] - corner[:-1, 1:] + corner[:-1, :-1]


def frame_light(path):
    """The light of the first plane of a FITS frame."""
    with fits.open(path) as hdul:
        header = hdul[0].header
        if header.get("PROJTYPE", "perspective") != "perspective":
            sys.exit(f"{path}: PROJTYPE is {header['PROJTYPE']}; this measures perspective frames")
        omega = solid_angles(header["NAXIS1"], header["NAXIS2"], header["FOV"])
        return float((hdul[0].data.astype(np.float64) * omega).sum())


def main(argv):
    max_change = None
    if len(argv) >= 2 and argv[0] == "--max-change":
        max_change = float(argv[1])
        argv = argv[2:]
    if len(argv) < 2:
        sys.exit(__doc__)
    lights = [frame_light(p) for p in argv]
    changes = [b / a - 1 for a, b in zip(lights, lights[1:])]
    for k, (path, light) in enumerate(zip(argv, lights)):
        change = f"  {100 * changes[k - 1]:+.2f} %" if k else ""
        print(f"{path}: light {light:.6g}{change}")
    worst = max(range(len(changes)), key=lambda k: abs(changes[k]))
    print(f"{len(lights)} frames, light {min(lights):.4g} to {max(lights):.4g}; largest change between frames "
          f"{100 * changes[worst]:+.2f} % (frames {worst} to {worst + 1})")
    if min(lights) <= 0:
        print("a frame has no light")
        return 1
    return 1 if max_change is not None and abs(changes[worst]) > max_change else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
