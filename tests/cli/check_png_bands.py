#!/usr/bin/env python3
"""A colour dome master (8 and 16 bits, RGB and RGBA) written with one
thread and with two: the PNG files are the same bytes; PIL and OpenImageIO
decode the same values from them, with the tEXt chunks and the sRGB chunk
kept; the picture is dark off the dome and lit on it.
usage: check_png_bands.py ORRERY WORKDIR"""
import os
import subprocess

import numpy as np
import OpenImageIO as oiio
from PIL import Image

from check_lib import Checks, colour_dome_scene

check = Checks()
orrery, work = check.orrery, check.work

# 1100 x 1100: 3301 filtered bytes a row at 8 bits, so four bands at
# 8 bits RGB and more at 16 bits RGBA: the bands' seams are exercised.
SCENE = colour_dome_scene(1100, "  dir: out\n  name: dome\n  fits: false\n")
with open(f"{work}/c.yaml", "w") as f:
    f.write(SCENE)


def render(threads, *sets):
    out = f"t{threads}-" + "-".join(s.split("=")[1] for s in sets)
    args = [orrery, "render", "--quiet", "c.yaml", "--set", f"output.dir={out}"]
    for s in sets:
        args += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    run = subprocess.run(args, cwd=work, capture_output=True, text=True, env=env)
    check(run.returncode == 0, f"render {threads} threads {sets}: {run.stderr.strip()}")
    return f"{work}/{out}/dome.png"


def oiio_pixels(path):
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)  # the values as stored, not premultiplied
    inp = oiio.ImageInput.open(path, config)
    spec = inp.spec()
    fmt = oiio.UINT16 if spec.format == oiio.TypeDesc("uint16") else oiio.UINT8
    pixels = inp.read_image(fmt)
    inp.close()
    return pixels, spec


for sets in [("output.png_bits=8", "output.alpha_mask=false"), ("output.png_bits=16", "output.alpha_mask=true")]:
    one, two = render(1, *sets), render(2, *sets)
    with open(one, "rb") as a, open(two, "rb") as b:
        check(a.read() == b.read(), f"{sets}: the PNG differs between one thread and two")
    im = Image.open(two)
    pil = np.asarray(im)
    check("Software" in im.info and "Description" in im.info, f"{sets}: tEXt chunks lost: {list(im.info)}")
    check("srgb" in im.info, f"{sets}: no sRGB chunk")
    ours, spec = oiio_pixels(two)
    channels = 4 if sets[1].endswith("true") else 3
    check(spec.nchannels == channels and ours.shape == (1100, 1100, channels), f"{sets}: {ours.shape}")
    # PIL keeps 8 bits of a 16-bit colour PNG: the high byte of each sample.
    high = ours >> 8 if ours.dtype == np.uint16 else ours
    check(pil.shape == ours.shape and np.array_equal(pil.astype(np.uint32), high.astype(np.uint32)),
          f"{sets}: PIL and OpenImageIO decode different pixels")
    check(ours[0, 0, :3].max() == 0 and ours[550, 550, :3].max() > 0, f"{sets}: the dome is not drawn")

check.finish("PNG bands")
