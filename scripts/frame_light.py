#!/usr/bin/env python3
"""The light of each frame of a run, how much it changes, and the level an
automatic white would take: the curve a producer grades a film by.

usage: scripts/frame_light.py [--max-change FRACTION] [--percentile P] FRAME.fits...

A frame's light is the sum over its pixels of the value (orrery's pixels
hold surface brightness: weight per steradian or per area, docs/output.md)
times what the pixel covers, worked out here independently of orrery's own
orr_pixel_measure: for perspective frames the exact solid angle of a flat
pixel seen by a pinhole camera whose field of view (FITS key FOV) spans the
wider axis; for sky maps the solid angle from the FITS WCS
(tests/cli/solid_angle.py); for orthographic frames the area
(ORTHOWID / width)^2. With colour the first plane is X; the percentile is
of the Y plane when there is one. Prints each frame's light, its change
from the frame before and the P-th percentile of its positive pixels
(default 99.9, colour.synthesis.white_percentile's default: what
`white: auto` would take), then the largest change and the percentiles'
median, a steady fixed white for the run; with --max-change, exits 1 when
the largest change is larger than FRACTION (0.05: 5 %). Used by
tests/cli/test_dark_universe.sh, docs/dark-universe.md and docs/animation.md.
"""
import os
import sys

import numpy as np
from astropy.io import fits

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from solid_angle import solid_angles as sky_solid_angles  # noqa: E402


def solid_angles(width, height, fov_deg):
    """Each pixel's solid angle: the pinhole integral over its rectangle,
    F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1) with
    F(x, y) = atan(x y / (f sqrt(f^2 + x^2 + y^2))), f the focal length in
    pixels."""
    f = 0.5 * max(width, height) / np.tan(np.radians(fov_deg) / 2)
    x, y = np.meshgrid(np.arange(width + 1) - 0.5 * width, np.arange(height + 1) - 0.5 * height)
    corner = np.arctan(x * y / (f * np.sqrt(f * f + x * x + y * y)))
    return corner[1:, 1:] - corner[1:, :-1] - corner[:-1, 1:] + corner[:-1, :-1]


def pixel_measures(header):
    """What each pixel covers, in the FITS array's order."""
    kind = header.get("PROJTYPE", "perspective")
    width, height = header["NAXIS1"], header["NAXIS2"]
    if kind == "perspective":
        return solid_angles(width, height, header["FOV"])
    if kind == "orthographic":
        return np.full((height, width), (header["ORTHOWID"] / width) ** 2)
    return sky_solid_angles(header)


def frame_light(path, percentile):
    """The light of the first plane of a FITS frame, and the percentile of
    its luminance (the Y plane with colour)."""
    with fits.open(path) as hdul:
        # The first plane: the primary's, or with an empty primary (a colour
        # frame's X, Y, Z planes as extensions) the first extension's.
        first = next((h for h in hdul if h.is_image and h.data is not None), None)
        if first is None:
            sys.exit(f"frame_light: {path}: no image plane")
        header = first.header
        data = np.nan_to_num(first.data.astype(np.float64))
        light = float((data * pixel_measures(header)).sum())
        y = next((np.nan_to_num(h.data) for h in hdul if h.name == "Y"), data)
        lit = y[y > 0]
        return light, float(np.percentile(lit, percentile)) if lit.size else 0.0


def main(argv):
    max_change, percentile = None, 99.9
    while len(argv) >= 2 and argv[0] in ("--max-change", "--percentile"):
        if argv[0] == "--max-change":
            max_change = float(argv[1])
        else:
            percentile = float(argv[1])
        argv = argv[2:]
    if len(argv) < 2:
        sys.exit(__doc__)
    frames = [frame_light(p, percentile) for p in argv]
    lights = [light for light, _ in frames]
    changes = [b / a - 1 if a > 0 else float("inf") for a, b in zip(lights, lights[1:])]
    for k, (path, (light, level)) in enumerate(zip(argv, frames)):
        change = f"  {100 * changes[k - 1]:+8.2f} %" if k else " " * 12
        print(f"{path}: light {light:.6g}{change}   {percentile:g}th percentile {level:.4g}")
    worst = max(range(len(changes)), key=lambda k: abs(changes[k]))
    print(f"{len(lights)} frames, light {min(lights):.4g} to {max(lights):.4g}; largest change between frames "
          f"{100 * changes[worst]:+.2f} % (frames {worst} to {worst + 1}); median {percentile:g}th percentile "
          f"{np.median([level for _, level in frames]):.4g} (a steady white for the run)")
    if min(lights) <= 0:
        print("a frame has no light")
        return 1
    return 1 if max_change is not None and abs(changes[worst]) > max_change else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
