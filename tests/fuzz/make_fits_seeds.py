#!/usr/bin/python3
"""Writes the seed corpus of fuzz_fits (tests/fuzz/corpus/fits/): small FITS
files of the kinds orrery reads, raw planes for `orrery compose` (float32
image HDUs with EXTNAME and BUNIT, the first in the primary HDU, as
src/encode/fits.c writes them) and PSF images, among them crops of the two
Hubble PSFs in shared/data/psf with their pixel scale. Each is a few KB.

usage: make_fits_seeds.py OUT_DIR [PSF_DIR]   (needs python3-astropy)"""
import os
import sys

import numpy as np
from astropy.io import fits

out = sys.argv[1]
psf_dir = sys.argv[2] if len(sys.argv) > 2 else None
os.makedirs(out, exist_ok=True)


def save(name, hdus):
    fits.HDUList(hdus).writeto(os.path.join(out, name), overwrite=True, output_verify="silentfix")


def plane(data, name, unit, primary):
    cls = fits.PrimaryHDU if primary else fits.ImageHDU
    h = cls(np.asarray(data))
    h.header["EXTNAME"] = name
    h.header["BUNIT"] = unit
    return h


yy, xx = np.mgrid[0:12, 0:16]
blob = np.exp(-((xx - 7.3) ** 2 + (yy - 5.6) ** 2) / 4.0).astype(np.float32)

# Raw planes as orrery writes them.
save("raw_weight_16x12.fits", [plane(blob, "weight", "mass/pixel", True)])
save("raw_xyz_16x12.fits", [plane(blob * k, n, "XYZ", i == 0) for i, (n, k) in
                            enumerate((("X", 0.9), ("Y", 1.0), ("Z", 1.2)))])
# Four planes (compose reads at most three) and planes of different sizes.
save("raw_4planes_8x4.fits", [plane(np.full((4, 8), i, np.float32), "P%d" % i, "", i == 0) for i in range(4)])
save("raw_mismatch.fits", [plane(blob, "X", "", True), plane(blob[:6, :6], "Y", "", False)])
# Other pixel types and scalings, non-finite values, a 1 x 1 image.
save("int16_bscale.fits", [fits.PrimaryHDU((blob * 1000).astype(np.int16))])
with fits.open(os.path.join(out, "int16_bscale.fits"), mode="update") as f:
    f[0].header["BSCALE"] = 0.001
    f[0].header["BZERO"] = 1.0
save("uint8.fits", [fits.PrimaryHDU((blob * 255).astype(np.uint8))])
save("float64_nan.fits", [fits.PrimaryHDU(np.where(blob > 0.5, np.nan, blob).astype(np.float64))])
save("one_pixel.fits", [fits.PrimaryHDU(np.ones((1, 1), np.float32))])
save("all_zero_9x9.fits", [fits.PrimaryHDU(np.zeros((9, 9), np.float32))])
save("negative_bg.fits", [fits.PrimaryHDU((blob - 0.1).astype(np.float32))])
# Not 2-D images: a cube, an empty primary with an image extension, a table.
save("cube_3d.fits", [fits.PrimaryHDU(np.ones((2, 3, 4), np.float32))])
save("empty_primary_ext.fits", [fits.PrimaryHDU(), fits.ImageHDU(blob, name="weight")])
save("table_ext.fits", [plane(blob, "X", "", True),
                        fits.BinTableHDU.from_columns([fits.Column(name="a", format="E", array=np.arange(3.0))])])

# (No tile-compressed image: fuzz_fits skips them, see mentions_zimage.)

# PSF images with a pixel scale, as Tiny Tim writes it.
psf = np.exp(-((xx[:, :12] - 5.5) ** 2 + (yy[:, :12] - 5.5) ** 2) / 2.0).astype(np.float32)
h = fits.PrimaryHDU(psf)
h.header["PIXSCALE"] = (0.025, "arcsec/pixel")
save("psf_pixscale.fits", [h])
h = fits.PrimaryHDU(psf)
h.header["PIXSCALE"] = 1e-30
save("psf_tiny_pixscale.fits", [h])

if psf_dir:
    # The empirical ACS stamp (19 x 19) with its header cut to a few cards.
    with fits.open(os.path.join(psf_dir, "acs_wfc_f814w_ngc5128_psf.fits")) as f:
        h = fits.PrimaryHDU(f[0].data.astype(np.float32))
        for k in ("INSTRUME", "DETECTOR", "FILTER1", "FILTER2"):
            if k in f[0].header:
                h.header[k] = f[0].header[k]
        save("psf_acs_wfc_19x19.fits", [h])
    # The Tiny Tim NICMOS PSF (528 x 528, 4x subsampled): 28 x 28 around the peak.
    with fits.open(os.path.join(psf_dir, "nic2_f160w_4xsub00.fits")) as f:
        d = f[0].data
        h = fits.PrimaryHDU(d[250:278, 250:278].astype(np.float32))
        for k in ("PIXSCALE", "INSTRUME", "FILTER", "X_PSF", "Y_PSF"):
            if k in f[0].header:
                h.header[k] = f[0].header[k]
        save("psf_nic2_4xsub_28x28.fits", [h])
        # The same rebinned 4x4 to detector pixels (as psf.file_subsample 4 would).
        b = d[248:280, 248:280].reshape(8, 4, 8, 4).sum(axis=(1, 3)).astype(np.float32)
        h = fits.PrimaryHDU(b)
        h.header["PIXSCALE"] = f[0].header.get("PIXSCALE", 0.0189) * 4
        save("psf_nic2_binned_8x8.fits", [h])
