#!/usr/bin/env python3
"""The camera in orrery's linear OpenEXR, read back with OpenImageIO: a
perspective view's worldToCamera and screen window (OpenEXR's standard
attributes) put every star of a known table on the pixel where the image
has it; output.exr_half stores half samples equal to the float file's
values rounded to half; sky maps carry orrery's own projection attributes.
usage: check_exr_camera.py ORRERY WORKDIR"""
import subprocess

import numpy as np
import OpenImageIO as oiio

from check_lib import Checks, read_exr

check = Checks()
orrery, work = check.orrery, check.work


def render(name, scene, *sets):
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(scene)
    args = [orrery, "render", "--quiet", f"{name}.yaml"]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, cwd=work, check=True)


# Stars far apart, one bright pixel each (NGP, no PSF), seen by a camera
# that is neither at the origin nor looking along an axis.
stars = np.array([[0.0, 0.0, 0.0], [3.0, 1.0, -2.0], [-2.5, 2.0, 1.0], [1.0, -3.0, 2.5], [-1.0, -1.5, -3.0]])
with open(f"{work}/stars.txt", "w") as f:
    f.write("x y z mass\n")
    for s in stars:
        f.write(f"{s[0]} {s[1]} {s[2]} 1\n")
W, H = 160, 100
PERSPECTIVE = (f"input:\n  file: stars.txt\ncamera:\n  projection: perspective\n  fov: 70\n"
               f"  position: [9, 4, 12]\n  look_at: [0.5, 0, 0]\n  up: [0, 1, 0.2]\n"
               f"image:\n  width: {W}\n  height: {H}\ndeposit: ngp\n"
               f"output:\n  dir: out\n  name: persp\n  exr: true\n  png: false\n")
render("persp", PERSPECTIVE)
spec, ch = read_exr(f"{work}/out/persp.exr")
m = spec.getattribute("worldToCamera")
sww = spec.getattribute("screenWindowWidth")
swc = spec.getattribute("screenWindowCenter")
check(m is not None and sww is not None and swc is not None, "worldToCamera and the screen window are there")
fov = spec.getattribute("orrery:fieldOfViewDeg")
check(fov is not None and float(fov) == 70, f"orrery:fieldOfViewDeg {fov}")
M = np.array(m, dtype=np.float64).reshape(4, 4)
# OpenEXR: row vectors, p_camera = p_world * M; camera x right, y up, z
# along the view. The screen window is the image on the plane z = 1, its
# height the width over the image's aspect.
check(abs(np.linalg.det(M[:3, :3]) - 1) < 1e-5 or abs(np.linalg.det(M[:3, :3]) + 1) < 1e-5, "a rotation")
width = float(sww)
height = width * H / W
cx, cy = float(swc[0]), float(swc[1])
check(abs(width - 2 * np.tan(np.radians(35))) < 1e-6, f"screen window width {width} is 2 tan(fov/2)")
y = ch["Y"]
for s in stars:
    p = np.append(s, 1.0) @ M
    check(p[2] > 0, f"star {s} in front of the camera")
    u, v = p[0] / p[2], p[1] / p[2]
    px = (u - (cx - width / 2)) / width * W
    py = ((cy + height / 2) - v) / height * H
    i, j = int(np.floor(px)), int(np.floor(py))
    inside = 0 <= i < W and 0 <= j < H
    check(inside and y[j, i] > 0, f"star {s}: predicted pixel ({px:.2f}, {py:.2f}) is dark")
check(np.count_nonzero(y) == len(stars), f"{np.count_nonzero(y)} lit pixels for {len(stars)} stars")

# Half samples: the same values rounded to half.
render("half", PERSPECTIVE, "output.name=half", "output.exr_half=true", "deposit=cic")
render("float", PERSPECTIVE, "output.name=float", "deposit=cic")
hspec, half = read_exr(f"{work}/out/half.exr")
_, full = read_exr(f"{work}/out/float.exr")
check(hspec.format == oiio.HALF, f"exr_half: pixel type {hspec.format}")
for name in ("Y", "A"):
    check(np.array_equal(half[name], full[name].astype(np.float16).astype(np.float32)),
          f"half {name} is not the float file's {name} rounded to half")
check(full["Y"].max() > 0, "the cic render has light")

# A dome master: no standard lens in OpenEXR, orrery's own attributes.
render("dome", PERSPECTIVE.replace("projection: perspective\n  fov: 70", "projection: dome"), "output.name=dome")
dspec, _ = read_exr(f"{work}/out/dome.exr")
check(dspec.getattribute("orrery:domeFieldOfViewDeg") == "180", "orrery:domeFieldOfViewDeg")
check(dspec.getattribute("orrery:longitudeGrows") == "left", "orrery:longitudeGrows")
check(dspec.getattribute("orrery:projection") == "dome", "orrery:projection")
check.finish("EXR camera checks")
