"""Particles loaded with yt (Debian's python3-yt), passed to the orrery
package: the dark matter of the shared GADGET-4 box. yt hands out unyt
arrays, numbers with units; orrery takes plain numbers, so the units are
stripped in one documented step: convert to the unit the scene is written
in, then take the values (.to(unit).d, a numpy view, no copy).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/yt_particles.py --out /tmp
"""
import os

import orrery
from common import arguments, save_png

import yt  # noqa: E402  (after the package, so a missing yt is the only error)

yt.set_log_level("error")
args = arguments(__doc__)
ds = yt.load(os.path.join(args.data, "hdf5", "gadget4_lcdm_gas", "snapshot_004.hdf5"))
ad = ds.all_data()
pos = ad["PartType1", "Coordinates"].to("Mpccm/h").d  # comoving Mpc/h, as numbers
mass = ad["PartType1", "Masses"].to("1e10*Msun/h").d
box = float(ds.domain_width[0].to("Mpccm/h"))

image = orrery.Scene({
    "camera": {"projection": "orthographic", "width": box, "position": [box / 2, box / 2, 2 * box],
               "look_at": [box / 2, box / 2, box / 2], "up": [0, 1, 0]},
    "image": {"width": 512, "height": 512},
    "output": {"bunit": "1e10 solMass h-1"},  # a FITS unit: negative powers, no "/"
}).render(pos, mass, time=float(ds.current_time.d))[0]
print(f"{len(pos)} dark-matter particles from yt {yt.__version__}; plane unit {image.units['mass']}")
save_png(image, os.path.join(args.out, "yt_dm.png"))
