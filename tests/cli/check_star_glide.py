#!/usr/bin/env python3
"""Stars that glide: each star keeps its flux (to 0.1 %) and its centroid
(to 0.05 pixel), and the share of its flux in its brightest pixel varies by
at most 1.2x as it moves across the pixels, at the default core width, on
the sky maps where pixels are least alike (across the l = 180 seam and
near the poles of the equirectangular and Hammer-Aitoff panoramas, at the
rim of a dome master), and on flat images with the default Gaussian PSF.
And a star field panned across a dome master: no bright star's peak pixel
changes by more than 1.2x from one frame to the next.

Flux is pixels times their solid angles from the WCS (solid_angle.py);
centroids on the sky are the flux-weighted mean of the pixels' directions
(from the WCS), their error an angle given in pixels at the map's centre.
usage: check_star_glide.py ORRERY WORKDIR [sky|flat|pan ...]"""
import math
import subprocess
import sys

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS

import sky_stars
from solid_angle import solid_angles, unit

orrery, work = sys.argv[1], sys.argv[2]
parts = sys.argv[3:] or ["sky", "flat", "pan"]
failures = []


def report(name, flux, err, share, limits=(1e-3, 0.05, 1.2)):
    """Flux within limits[0] of 1, centroid within limits[1] px, peak share
    within limits[2] x."""
    ratio = max(share) / min(share)
    print(f"{name}: {len(flux)} stars; flux {min(flux):.6f} to {max(flux):.6f}, centroid within "
          f"{max(err):.4f} px, peak share {min(share):.4f} to {max(share):.4f} ({ratio:.3f}x)")
    if max(abs(v - 1) for v in flux) > limits[0] or max(err) > limits[1] or ratio > limits[2]:
        print(f"FAIL {name}: a star loses light, moves or twinkles")
        failures.append(name)


_directions = {}


def pixel_directions(head):
    """Unit vectors of every pixel centre, top row first (as sky_stars
    returns images), NaN off the map; once for each map."""
    key = (head["CTYPE1"], head["NAXIS1"], head["NAXIS2"])
    if key not in _directions:
        _directions[key] = directions_of(head)
    return _directions[key]


def directions_of(head):
    w, h = head["NAXIS1"], head["NAXIS2"]
    jj, ii = np.mgrid[0:h, 0:w]
    l, b = WCS(head).all_pix2world(ii, jj, 0)
    return unit(l, b)[::-1]


def sky_group(name, batches, camera, size, scale):
    """Renders each batch of stars [(l, b)] (each of flux 1, far enough
    apart) and measures each star within 2.5 core FWHM of it; scale: the
    map's pixels per radian at its centre. Pixels whose centres are off
    the map (cut by its rim) carry light but no direction: they count in
    the flux, not in the centroid."""
    fl, err, share = [], [], []
    for k, stars in enumerate(batches):
        dirs = [tuple(unit(l, b)) for l, b in stars]
        flux, head = sky_stars.render(orrery, work, f"{name}{k}", [(d, 1.0) for d in dirs], camera, size,
                                      "  kind: gaussian")
        flux = np.nan_to_num(flux)
        pix = pixel_directions(head)
        has_dir = np.isfinite(pix[..., 0])
        reach = math.cos(math.radians(2.5 * head["PSFFWHM"] / 60))
        for d in dirs:
            w = np.where(np.nan_to_num(pix @ np.array(d)) > reach, flux, 0.0)
            mean = (np.nan_to_num(pix) * np.where(has_dir, w, 0.0)[..., None]).sum(axis=(0, 1))
            fl.append(w.sum())
            err.append(math.acos(min(1.0, float(mean @ np.array(d)) / np.linalg.norm(mean))) * scale)
            share.append(w.max() / w.sum())
    return fl, err, share


# The edges of the maps, where a star's core is cut: the Hammer-Aitoff
# ellipse's rim (its l = 180 seam and its poles, where pixels are sheared
# and cut) and the dome master's horizon. The light that falls beyond the
# edge is folded onto the edge pixels (the flux is kept), so the centroid
# moves inward and the brightest pixel's share depends on how the edge
# cuts the core: measured, within these limits (docs/psf.md).
EDGE = (2e-3, 0.5, 1.7)


def sky():
    rng = np.random.default_rng(11)
    W, H = 720, 360  # 0.5 degrees a pixel; the core is 3.2 px = 1.6 degrees at the centre
    for proj in ("equirectangular", "hammer-aitoff"):
        scale = W / (2 * math.pi) if proj == "equirectangular" else W / (2 * math.pi) * 2 * math.sqrt(2) / math.pi
        cam = f"  projection: {proj}"
        limits = (1e-3, 0.05, 1.2) if proj == "equirectangular" else EDGE
        # Across the seam: l within two degrees of 180, b = -10, 0, 10
        # (where pixels are alike), 7 renders of 3.
        seam = [[(180 + rng.uniform(-2, 2), b + rng.uniform(0, 0.5)) for b in (-10, 0, 10)] for _ in range(7)]
        report(f"{proj}, across the l = 180 seam", *sky_group(f"seam-{proj}", seam, cam, (W, H), scale), limits)
        # Near the poles: |b| = 82 (5 core widths from the pole) and 88
        # (the core reaches past it), l anywhere, 5 renders of 2 (and a
        # star at b = 0 for company). A latitude, not a range of them: near
        # the pole a pixel's width in l shrinks as cos b.
        for b0 in (82, 88):
            pole = [[(rng.uniform(0, 360), sign * b0) for sign in (1, -1)] + [(rng.uniform(0, 360), 0.0)]
                    for _ in range(5)]
            fl, err, share = sky_group(f"pole-{proj}", pole, cam, (W, H), scale)
            report(f"{proj}, at |b| = {b0}", fl[0::3] + fl[1::3], err[0::3] + err[1::3],
                   share[0::3] + share[1::3], limits)
    # The rim of a 180-degree dome master: 0.5 to 0.75 of the core inside it.
    S = 601
    f = (S / 2) / (math.pi / 2)
    core = 3.2 / f
    rim = [[(18 * k + rng.uniform(0, 3), math.degrees(core * rng.uniform(0.5, 0.75))) for k in range(20)]]
    cam = "  projection: dome\n  dome_fov: 180\n  zenith: [0, 90]"
    report("dome master, at the rim (b = 0.5 to 0.75 core widths)", *sky_group("rim", rim, cam, (S, S), f), EDGE)


def flat():
    """Orthographic, CIC, psf.kind gaussian at its default width: 100 stars
    at random sub-pixel positions, 20 pixels apart."""
    rng = np.random.default_rng(5)
    W = 200
    truth = [(10 + 20 * (k % 10) + rng.uniform(-0.5, 0.5), 10 + 20 * (k // 10) + rng.uniform(-0.5, 0.5))
             for k in range(100)]
    with open(f"{work}/flat.txt", "w") as f:
        f.write("x y z mass\n")
        for px, py in truth:  # 1 unit a pixel, y up
            f.write(f"{px - W / 2!r} {W / 2 - py!r} 0 1\n")
    with open(f"{work}/flat.yaml", "w") as f:
        f.write(f"input:\n  file: flat.txt\ncamera:\n  projection: orthographic\n  width: {W}\n"
                f"image:\n  width: {W}\n  height: {W}\ndeposit: cic\npsf:\n  kind: gaussian\n"
                "output:\n  dir: out\n  name: flat\n  png: false\n")
    subprocess.run([orrery, "render", "--quiet", "flat.yaml"], cwd=work, check=True)
    img = fits.getdata(f"{work}/out/flat.fits").astype(np.float64)[::-1]  # area 1 a pixel
    jj, ii = np.mgrid[0:W, 0:W]
    fl, err, share = [], [], []
    for x, y in truth:
        w = np.where((np.abs(ii + 0.5 - x) < 9) & (np.abs(jj + 0.5 - y) < 9), img, 0.0)
        total = w.sum()
        fl.append(total)
        err.append(math.hypot((w * (ii + 0.5)).sum() / total - x, (w * (jj + 0.5)).sum() / total - y))
        share.append(w.max() / total)
    report(f"flat image, Gaussian PSF (FWHM {fits.getheader(f'{work}/out/flat.fits').get('PSFFWHM', '?')} px)",
           fl, err, share)


def pan():
    """A field of 60 stars on a 601^2 dome master turning 0.4 degrees a
    frame about the zenith (1.3 pixels a frame 30 degrees out: 2 degrees a
    second at 30 frames a second is as many pixels on a 3600^2 master);
    each star's peak pixel, frame to frame, over 12 frames."""
    rng = np.random.default_rng(3)
    stars = [(rng.uniform(0, 360), rng.uniform(20, 70)) for _ in range(60)]
    rows = ["x y z mass"] + ["%r %r %r 1" % tuple(10 * np.array(unit(l, b))) for l, b in stars]
    with open(f"{work}/pan.txt", "w") as f:
        f.write("\n".join(rows) + "\n")
    with open(f"{work}/pan.yaml", "w") as f:
        f.write("input:\n  file: pan.txt\ncamera:\n  position: [0, 0, 0]\n  look_at: [0, 0, 1]\n  up: [1, 0, 0]\n"
                "  projection: dome\n  path:\n    kind: rotate\n    axis: [0, 0, 1]\n    angle: 4.4\n"
                "image:\n  width: 601\n  height: 601\ndeposit: ngp\npsf:\n  kind: gaussian\n"
                "animation:\n  frames: 12\noutput:\n  dir: out\n  name: pan\n  png: false\n")
    subprocess.run([orrery, "render", "--quiet", "pan.yaml"], cwd=work, check=True)
    frames = [np.nan_to_num(fits.getdata(f"{work}/out/pan_{k:04d}.fits").astype(np.float64)) for k in range(12)]
    # Each star's peak: the largest pixel within 4 px of the brightest
    # pixels, tracked by matching the peaks of consecutive frames.
    from scipy.ndimage import maximum_filter
    worst = 1.0
    for a, b in zip(frames, frames[1:]):
        pa = (a == maximum_filter(a, size=9)) & (a > 0.2 * a.max())
        for j, i in zip(*np.nonzero(pa)):
            win = b[max(j - 4, 0):j + 5, max(i - 4, 0):i + 5]
            worst = max(worst, max(win.max(), a[j, i]) / min(win.max(), a[j, i]))
    print(f"panned dome master: largest frame-to-frame change of a star's peak {worst:.3f}x")
    if worst > 1.2:
        failures.append("pan")


for p in parts:
    {"sky": sky, "flat": flat, "pan": pan}[p]()
sys.exit(1 if failures else 0)
