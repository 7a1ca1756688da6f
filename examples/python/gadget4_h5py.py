"""A GADGET-4 snapshot read with h5py, rendered through the orrery package:
the gas of the shared lcdm_gas box at z = 0 (32^3 gas particles, 50 Mpc/h)
seen face-on, SPH kernels from the file's smoothing lengths.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/gadget4_h5py.py --out /tmp
"""
import os

import h5py
import numpy as np

import orrery
from common import arguments, save_png

args = arguments(__doc__)
path = os.path.join(args.data, "hdf5", "gadget4_lcdm_gas", "snapshot_004.hdf5")
with h5py.File(path, "r") as f:
    gas = f["PartType0"]
    pos = gas["Coordinates"][...]              # (N, 3) float32, kpc/h, read as stored: no copy by orrery
    h = gas["SmoothingLength"][...] / 2        # GADGET's is the kernel's support radius; orrery's support is 2h
    mass = f["Header"].attrs["MassTable"][0]   # no Masses dataset: one mass for every gas particle
    box = float(f["Header"].attrs["BoxSize"])
    time = float(f["Header"].attrs["Time"])

scene = orrery.Scene({
    "camera": {"projection": "orthographic", "width": box, "position": [box / 2, box / 2, 2 * box],
               "look_at": [box / 2, box / 2, box / 2], "up": [0, 1, 0]},
    "image": {"width": 512, "height": 512},
    "deposit": "sph",
    "output": {"stretch": "log", "colormap": "magma"},
})
image = scene.render(pos, mass, h=h, time=time)[0]
# WIMAGE and WOUTSIDE: the mass drawn, and the mass of kernels reaching past the box's edges.
print(f"{len(pos)} gas particles, {scene.seconds:.2f} s; mass in the image {image.header['WIMAGE']:.6g}, "
      f"off it {image.header['WOUTSIDE']:.6g}, of {mass * len(pos):.6g}")
save_png(image, os.path.join(args.out, "gadget4_gas.png"))
