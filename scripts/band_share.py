#!/usr/bin/env python3
"""The Milky Way band's share of the sky's light, frame by frame: for each
panorama (a sky map FITS with a Y plane and a WCS, e.g. Future Sky's
futuresky-panorama_NNNN.fits), the light within |b| < B degrees (default 15)
over all the light, light being Y times each pixel's solid angle (from the
WCS alone, tests/cli/solid_angle.py; orrery's pixels hold flux per
steradian), and the band's half-light latitude: the |b| within which half
the light lies. The share counts the bulge's glow around l = 0 as band, so
a disc heated into a thick glow can keep it; the half-light latitude grows
as the band thickens (4 deg for the thin disc of Future Sky's frame 0).
Prints one line per frame and, with --hold FRACTION, the first frame whose
share falls below FRACTION of frame 0's (docs/gallery.md).

usage: scripts/band_share.py [--b DEG] [--hold FRACTION] PANORAMA.fits...
"""
import argparse
import os
import sys

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "cli"))
from solid_angle import solid_angles  # noqa: E402


def y_plane(path):
    """The Y plane and the header whose WCS maps it (NaN off the map -> 0)."""
    with fits.open(path) as h:
        for u in h:
            if u.name.upper() == "Y":
                return np.nan_to_num(np.asarray(u.data, dtype=float)), u.header
    raise SystemExit(f"{path}: no Y plane")


_geometry = {}


def latitudes_and_areas(head):
    """|b| of every pixel centre and every pixel's solid angle, once per map size."""
    key = (head["CTYPE1"], head["NAXIS1"], head["NAXIS2"])
    if key not in _geometry:
        w, h = head["NAXIS1"], head["NAXIS2"]
        jj, ii = np.mgrid[0:h, 0:w]
        _, b = WCS(head).all_pix2world(ii, jj, 0)
        _geometry[key] = (np.abs(np.nan_to_num(b, nan=90.0)), solid_angles(head))
    return _geometry[key]


def share_and_half_light(path, bmax):
    """(light within |b| < bmax over all, the |b| holding half the light)."""
    y, head = y_plane(path)
    absb, area = latitudes_and_areas(head)
    light = (y * area).ravel()
    total = light.sum()
    if not total > 0:
        return float("nan"), float("nan")
    order = np.argsort(absb.ravel(), kind="stable")
    cumulative = np.cumsum(light[order]) / total
    half = absb.ravel()[order][np.searchsorted(cumulative, 0.5)]
    return light[absb.ravel() < bmax].sum() / total, float(half)


def main(argv):
    ap = argparse.ArgumentParser(description="The Milky Way band's share of each panorama's light.")
    ap.add_argument("--b", type=float, default=15.0, help="half-width of the band in degrees of latitude")
    ap.add_argument("--hold", type=float, help="report the first frame whose share falls below this fraction of frame 0's")
    ap.add_argument("panoramas", nargs="+")
    args = ap.parse_args(argv)
    measured = [share_and_half_light(p, args.b) for p in args.panoramas]
    shares = [s for s, _ in measured]
    for k, (p, (s, half)) in enumerate(zip(args.panoramas, measured)):
        print(f"{k:3d}  {os.path.basename(p)}  share(|b| < {args.b:g}) = {s:.3f}  ({s / shares[0]:.2f} of frame 0)"
              f"  half-light |b| = {half:.1f} deg")
    if args.hold is not None:
        below = [k for k, s in enumerate(shares) if s < args.hold * shares[0]]
        print(f"first frame below {args.hold:g} of frame 0's share: {below[0] if below else 'none'}")

if __name__ == "__main__":
    main(sys.argv[1:])
