#!/usr/bin/env python3
"""Every FITS file says how it was made: its last HDU, SCENE, holds the
scene as YAML (the file with the --set overrides applied and the view's
keys merged in). astropy reads it back with its checksums, PyYAML parses
it, fitsverify finds no warning, and `orrery render` of that text alone
draws the same planes bit for bit (NaN off the map included): a view of a
two-view scene, its raw planes, a HEALPix map and a tile-compressed file.
`orrery compose` still reads raw planes that carry the SCENE HDU.
usage: check_fits_scene.py ORRERY WORKDIR"""
import os
import subprocess
import warnings

import numpy as np
import yaml
from astropy.io import fits

from check_lib import Checks

check = Checks()
orrery, work = check.orrery, check.work

SCENE = """\
input:
  model: {name: mw-m31, particles: 20000}
  types: [2, 3]
camera:
  position: [-32, 46, 0]
output:
  dir: out
  png: false
  bunit: 10**10 solMass
views:
  dome:
    camera: {projection: dome}
    image: {width: 96, height: 96}
    output: {raw: true}
  sky:
    camera: {projection: healpix, healpix_nside: 8}
    deposit: ngp
"""


def render(folder, scene, *sets):
    args = [orrery, "render", "--quiet", scene]
    for s in sets:
        args += ["--set", s]
    run = subprocess.run(args, cwd=folder, capture_output=True, text=True)
    check(run.returncode == 0, f"render {scene} {sets} in {folder}: exit {run.returncode}: {run.stderr.strip()}")


def planes(path):
    """Every HDU's data but the scene's, as raw bits (NaN compared exactly)."""
    with fits.open(path) as hdul:
        out = []
        for hdu in hdul:
            if hdu.name == "SCENE" or hdu.data is None:
                continue
            if isinstance(hdu, fits.BinTableHDU) and not isinstance(hdu, fits.CompImageHDU):
                out += [np.ascontiguousarray(hdu.data[c.name], dtype="<f4").view("<u4") for c in hdu.columns]
            else:
                out.append(np.ascontiguousarray(hdu.data, dtype="<f4").view("<u4"))
        return out


def stored_scene(path):
    """The SCENE HDU's text, after checking every HDU's checksums and fitsverify."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a checksum astropy cannot verify only warns
        with fits.open(path, checksum=True) as hdul:
            check(hdul[-1].name == "SCENE", f"{path}: the last HDU is {hdul[-1].name}, not SCENE")
            for hdu in hdul:
                check(hdu.verify_checksum() == 1 and hdu.verify_datasum() == 1, f"{path}[{hdu.name}]: checksums")
            h = hdul["SCENE"].header
            check(h["BITPIX"] == 8 and h["NAXIS"] == 1 and h["CONTENT"] == "YAML", f"{path}: SCENE header")
    text = fits.getdata(path, "SCENE").tobytes().decode()  # the one-liner docs/output.md gives
    out = subprocess.run(["fitsverify", path], capture_output=True, text=True).stdout
    check("Verification found 0 warning(s) and 0 error(s)" in out, f"{path}: fitsverify:\n{out}")
    return text


def rerender(path, folder, name, *expect):
    """Renders the scene stored in path as NAME.yaml in an empty FOLDER and
    compares the planes; expect: lines the stored scene must hold."""
    text = stored_scene(path)
    tree = yaml.safe_load(text)
    check(isinstance(tree, dict) and "views" not in tree, f"{path}: the stored scene is not one view: {tree}")
    for line in expect:
        check(line in text.splitlines(), f"{path}: the stored scene lacks {line!r}:\n{text}")
    again = f"{work}/{folder}"
    os.makedirs(again, exist_ok=True)
    with open(f"{again}/{name}.yaml", "w") as f:
        f.write(text)
    render(again, f"{name}.yaml")
    new = f"{again}/{tree['output']['dir']}/{os.path.basename(path)}"
    a, b = planes(path), planes(new)
    check(len(a) == len(b) and len(a) > 0 and all(np.array_equal(x, y) for x, y in zip(a, b)),
          f"{new}: the stored scene renders other planes than {path}")
    return tree


with open(f"{work}/s.yaml", "w") as f:
    f.write(SCENE)
render(work, "s.yaml", "views.dome.camera.dome_fov=200", "views.dome.image.height=80")
tree = rerender(f"{work}/out/s-dome.fits", "again", "s-dome", "  projection: dome", "  height: 80",
                '  bunit: "10**10 solMass"', "  raw: true")
check(tree["camera"]["dome_fov"] == 200 and tree["input"]["types"] == [2, 3], f"parsed: {tree}")
rerender(f"{work}/out/s-dome.raw.fits", "again-raw", "s-dome", "  projection: dome")
rerender(f"{work}/out/s-sky.fits", "again", "s-sky", "  projection: healpix", "  healpix_nside: 8")

# Tile-compressed planes: the SCENE HDU stays a plain image after them.
render(work, "s.yaml", "output.fits_compress=gzip", "output.dir=gz")
with fits.open(f"{work}/gz/s-dome.fits") as hdul:
    check([type(h).__name__ for h in hdul] == ["PrimaryHDU", "CompImageHDU", "ImageHDU"],
          f"compressed file's HDUs: {[type(h).__name__ for h in hdul]}")
rerender(f"{work}/gz/s-dome.fits", "again-gz", "s-dome", "  fits_compress: gzip")

# compose reads the raw planes, skipping the SCENE HDU (the dome view as
# stored, rendered again above into again/).
run = subprocess.run([orrery, "compose", "--quiet", "s-dome.yaml", "--set", "output.png=true"], cwd=f"{work}/again",
                     capture_output=True, text=True)
check(run.returncode == 0 and os.path.exists(f"{work}/again/out/s-dome.png"), f"compose: {run.stderr.strip()}")
check.finish("FITS scene checks")
