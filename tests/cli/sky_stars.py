"""Stars around an observer, rendered onto a sky map, for the sky-map PSF
checks (check_sky_psf.py, check_sky_spikes.py).

The star table puts the observer (id 1) at the origin, the reference
particle (id 2, which sets l = 0) 1000 units along +x, and each star 10
units out in its direction; the scene looks from the observer with
observer.normal +z, draws by nearest pixel and writes one FITS image."""
import math
import subprocess

import numpy as np
from astropy.io import fits

from solid_angle import solid_angles


def unit(t_deg, a_deg):
    """The direction t_deg from +z (the dome's zenith) at azimuth a_deg from +x."""
    t, a = math.radians(t_deg), math.radians(a_deg)
    return (math.sin(t) * math.cos(a), math.sin(t) * math.sin(a), math.cos(t))


_solid_angles = {}


def pixel_solid_angles(head):
    """solid_angles(head), computed once for each map (the costly part of
    a check that renders many frames of one map)."""
    key = tuple((k, head.get(k)) for k in ("NAXIS1", "NAXIS2", "CTYPE1", "CTYPE2", "CRPIX1", "CRPIX2",
                                           "CDELT1", "CDELT2", "CRVAL1", "CRVAL2", "LONPOLE", "LATPOLE",
                                           "PV2_1", "PV2_2"))
    if key not in _solid_angles:
        _solid_angles[key] = solid_angles(head)
    return _solid_angles[key]


def render(orrery, work, name, stars, camera, size, psf):
    """Renders stars [(direction, mass)] in WORK as NAME: camera and psf are
    the scene's indented lines under camera: and psf:, size (width, height).
    Returns the image as flux per pixel (its values times each pixel's
    solid angle from the WCS; row 0 at the top, NaN off the map) and its
    header."""
    rows = ["x y z mass id", "0 0 0 1 1", "1000 0 0 1e-9 2"]
    for k, (d, m) in enumerate(stars):
        rows.append("%r %r %r %r %d" % (10 * d[0], 10 * d[1], 10 * d[2], m, k + 3))
    with open(f"{work}/{name}.txt", "w") as f:
        f.write("\n".join(rows) + "\n")
    scene = f"""input:
  file: {name}.txt
observer:
  id: 1
  reference_id: 2
  normal: [0, 0, 1]
  dim: false
camera:
{camera}
image:
  width: {size[0]}
  height: {size[1]}
deposit: ngp
psf:
{psf}
output:
  dir: out
  name: {name}
  png: false
"""
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(scene)
    subprocess.run([orrery, "render", "--quiet", f"{name}.yaml"], cwd=work, check=True)
    data = fits.getdata(f"{work}/out/{name}.fits").astype(np.float64)
    head = fits.getheader(f"{work}/out/{name}.fits")
    flux = data * pixel_solid_angles(head)  # the map holds flux per steradian
    return flux[::-1], head  # FITS rows bottom-up
