"""A SWIFT snapshot read with h5py, rendered through the orrery package: the
shared Roberts-flow MHD test (32^3 gas particles in a 2 pi box), weighted by
a quantity derived in numpy, the magnetic energy density B^2 / 2 of each
particle (from MagneticFluxDensities, (N, 3)), passed as a named field and
chosen with input.weight.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/swift_h5py.py --out /tmp
"""
import os

import h5py
import numpy as np

import orrery
from common import arguments, save_png

GAMMA_CUBIC = 1.825742  # SWIFT's kernel support over its h (cubic spline, 3-D)

args = arguments(__doc__)
path = os.path.join(args.data, "hdf5", "swift_robertsflow", "g32_randB_withVP.hdf5")
with h5py.File(path, "r") as f:
    gas = f["PartType0"]
    pos = gas["Coordinates"][...]                        # float64: orrery converts a chunk at a time
    mass = gas["Masses"][...]
    h = gas["SmoothingLengths"][...] * (GAMMA_CUBIC / 2)  # support gamma h = orrery's 2h
    b = gas["MagneticFluxDensities"][...]
    box = float(f["Header"].attrs["BoxSize"][0])
    time = float(f["Header"].attrs["Time"][0])

magnetic_energy = 0.5 * np.einsum("ij,ij->i", b, b)  # per unit volume; times volume m / rho would be energy
scene = orrery.Scene({
    "camera": {"projection": "orthographic", "width": box, "position": [box / 2, box / 2, 3 * box],
               "look_at": [box / 2, box / 2, box / 2], "up": [0, 1, 0]},
    "image": {"width": 256, "height": 256},
    "deposit": "sph",
    "input": {"weight": "B2"},
    "output": {"stretch": "linear", "colormap": "inferno", "bunit": "B2"},
})
image = scene.render(pos, mass, h=h, fields={"B2": magnetic_energy}, time=time)[0]
print(f"{len(pos)} gas particles weighted by B^2/2 in {scene.seconds:.2f} s; plane {list(image.planes)}, "
      f"unit {image.units['B2']}")
save_png(image, os.path.join(args.out, "swift_b2.png"))
