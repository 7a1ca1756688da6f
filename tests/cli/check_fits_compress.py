#!/usr/bin/env python3
"""output.fits_compress: gzip writes tile-compressed image extensions that
astropy reads back bit for bit equal to the uncompressed file's planes (NaN
off the dome included), with valid checksums, that fitsverify accepts and
CCDData.read takes with its unit and WCS; rice (lossy for floats) is
refused by the scene check.
usage: check_fits_compress.py ORRERY WORKDIR"""
import os
import subprocess
import warnings

import numpy as np
from astropy.io import fits
from astropy.nddata import CCDData

from check_lib import Checks, colour_dome_scene

check = Checks()
orrery, work = check.orrery, check.work

SCENE = colour_dome_scene(128, "  dir: out\n  png: false\n")
with open(f"{work}/c.yaml", "w") as f:
    f.write(SCENE)


def render(*sets, ok=True):
    args = [orrery, "render", "--quiet", "c.yaml"]
    for s in sets:
        args += ["--set", s]
    run = subprocess.run(args, cwd=work, capture_output=True, text=True)
    check((run.returncode == 0) == ok, f"render {sets}: exit {run.returncode}: {run.stderr.strip()}")
    return run.stderr


def bits(a):
    return np.ascontiguousarray(a, dtype="<f4").view("<u4")


render("output.name=plain")
render("output.name=gz", "output.fits_compress=gzip")
with warnings.catch_warnings():
    warnings.simplefilter("error")  # a checksum astropy cannot verify warns
    with fits.open(f"{work}/out/plain.fits") as plain, fits.open(f"{work}/out/gz.fits", checksum=True) as gz:
        check(isinstance(gz[1], fits.CompImageHDU), f"HDU 1 is {type(gz[1]).__name__}")
        check(gz[1]._header["ZCMPTYPE"] == "GZIP_2" and gz[1]._header["ZQUANTIZ"] == "NONE",
              "GZIP_2, not quantised")
        for k in ("X", "Y", "Z"):
            check(np.array_equal(bits(plain[k].data), bits(gz[k].data)), f"plane {k} differs")
            check(gz[k].header["BUNIT"] == plain[k].header["BUNIT"], f"{k} BUNIT")
            check(gz[k].header["CTYPE1"] == plain[k].header["CTYPE1"], f"{k} WCS")
        check(np.isnan(gz["Y"].data).any(), "NaN off the dome kept")
verify = subprocess.run(["fitsverify", "-q", f"{work}/out/gz.fits"], capture_output=True, text=True)
check(verify.stdout.strip().startswith("verification OK"), f"fitsverify: {verify.stdout.strip()}")
ccd = CCDData.read(f"{work}/out/gz.fits", hdu="Y")
check(str(ccd.unit) == "1 / sr" and ccd.wcs is not None, f"CCDData unit {ccd.unit}")
size_plain, size_gz = os.path.getsize(f"{work}/out/plain.fits"), os.path.getsize(f"{work}/out/gz.fits")
check(size_gz < size_plain / 2, f"gzip {size_gz} bytes against {size_plain}")
err = render("output.name=bad", "output.fits_compress=rice", ok=False)
check("output.fits_compress" in err and "none gzip" in err, f"rice refused: {err.strip()}")
check.finish("FITS compression checks")
