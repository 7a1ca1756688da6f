"""Nightfall's spikes and black sky, from a frame's linear Y plane and its
PNG: python3 check_nightfall_spikes.py FRAME.fits [--min-spike C]
[--min-ratio R] [--max-sky S] [--expect-fail].

For the brightest stars (local maxima of Y at least ten core widths from
the edges; the core's FWHM is the FITS card PSFFWHM, in pixels), Y is
sampled (bilinearly) at three core widths from the star along the four
spike directions (45 + k 90 degrees counterclockwise from +x, y up) and
along the four directions between them. The spike contrast is the spikes'
mean over the local background, the median of Y in the box ten core widths
either side (the star and its spikes are a small part of it); the ratio is
the spikes' mean over the between-directions' mean (spikes, not rings). The
sky is the median of the PNG's luminance (0-255). Prints the figures;
exits 1 if none of the three brightest stars has both the contrast and the
ratio at their minimum, or the sky is above its maximum (with
--expect-fail: if all hold)."""
import argparse
import sys

import numpy as np
from astropy.io import fits
from PIL import Image
from scipy.ndimage import map_coordinates, maximum_filter

ap = argparse.ArgumentParser()
ap.add_argument("fits")
ap.add_argument("--min-spike", type=float, default=10)
ap.add_argument("--min-ratio", type=float, default=3)
ap.add_argument("--max-sky", type=float, default=3)
ap.add_argument("--angle", type=float, default=45)
ap.add_argument("--expect-fail", action="store_true")
a = ap.parse_args()

Y = fits.getdata(a.fits, "Y").astype(float)
core = float(fits.getheader(a.fits, "Y").get("PSFFWHM", 1.37))
sky = float(np.median(np.asarray(Image.open(a.fits[:-5] + ".png").convert("L"))))
h, w = Y.shape
half = int(np.ceil(10 * core))
peaks = (Y == maximum_filter(Y, 2 * half + 1)) & (Y > 0)
peaks[:half], peaks[h - half:], peaks[:, :half], peaks[:, w - half:] = False, False, False, False
js, is_ = np.nonzero(peaks)
order = np.argsort(Y[js, is_])[::-1][:3]


def ring(j, i, r, angles):
    rad = np.radians(angles)
    # pixel (i, j) covers [i, i+1) x [j, j+1); map_coordinates samples at centres
    return map_coordinates(Y, [j - r * np.sin(rad), i + r * np.cos(rad)], order=1)


figures = []
for n in order:
    j, i = js[n], is_[n]
    bg = np.median(Y[j - half:j + half + 1, i - half:i + half + 1])
    on = ring(j, i, 3 * core, a.angle + 90 * np.arange(4)).mean()
    off = ring(j, i, 3 * core, a.angle + 45 + 90 * np.arange(4)).mean()
    figures.append((on / bg, on / off))
    print(f"star at ({i}, {j}): peak {Y[j, i]:.4g}, background {bg:.4g}; at 3 core widths "
          f"({3 * core:.1f} pixels) spikes {on / bg:.1f} x the background, {on / off:.1f} x between them")
print(f"sky median {sky:.0f}/255")
spike, ratio = max(figures, key=lambda f: min(f[0] / a.min_spike, f[1] / a.min_ratio))
ok = spike >= a.min_spike and ratio >= a.min_ratio and sky <= a.max_sky
if ok == a.expect_fail:
    print(f"{'expected a failure' if a.expect_fail else 'failed'}: spike contrast {spike:.1f} (min {a.min_spike}), "
          f"spike/between {ratio:.1f} (min {a.min_ratio}), sky {sky:.0f} (max {a.max_sky})", file=sys.stderr)
    sys.exit(1)
