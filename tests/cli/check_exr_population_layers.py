#!/usr/bin/env python3
"""output.exr_population_layers, read with OpenImageIO as a compositor would:
each colour population's light is the layer NAME.R, NAME.G, NAME.B, NAME.A
beside R, G, B, A and xyz; the layers' R, G, B sum to the beauty's R, G, B
pixel by pixel (through the deposit, the dust, the PSF and its bright stars,
a sky map's rim), their A is the beauty's; a population's layer is the
R, G, B the same scene draws with colour.only that population (so 0 where
only the others' stars land); 1 and 2 threads write the same pixels;
output.exr_half makes the layers half too; the FITS file keeps X, Y, Z
alone; Blender's multilayer reader would drop no channel.
usage: check_exr_population_layers.py ORRERY WORKDIR"""
import os
import shutil
import subprocess

import numpy as np
from astropy.io import fits

from check_lib import Checks, blender_pass, read_exr

check = Checks()
orrery, work = check.orrery, check.work
MPI = os.path.join(os.path.dirname(os.path.abspath(orrery)), "orrery-mpi")
POPS = ("bulge", "old_disc", "young-disc")
RGB = ("R", "G", "B")
LAYERS = [f"{p}.{c}" for p in POPS for c in RGB + ("A",)]
BASE_CHANNELS = {"R", "G", "B", "A", "xyz.X", "xyz.Y", "xyz.Z"}

# Bulge stars (type 3), and the disc stars (type 2) split at random in two:
# three populations, two of them mixed across the same disc.
MODEL = "input:\n  model:\n    name: mw-m31\n    particles: 30000\n    dust_particles: 3000\n  types: [2, 3]\n"
IMAGE = "image:\n  width: 96\n  height: 96\n"
EDGE_ON = "camera:\n  projection: perspective\n  position: [0, -320, 0]\n  look_at: [0, 0, 0]\n  up: [0, 0, 1]\n  fov: 20\n"
DOME = "camera:\n  projection: dome\n  position: [-30, 0, 10]\n  look_at: [0, 0, 0]\n"
DUST = "dust:\n  types: [0]\n  kappa_v: 3.7e4\n"
POPULATIONS = ("colour:\n  populations:\n"
               "    - name: bulge\n      select: {types: [3]}\n"
               "      colour: {temperature: 4000}\n      luminance: {mass: 1}\n"
               "    - name: old_disc\n      select: {types: [2], random: {p: 0.5}}\n"
               "      colour: {temperature: 6000}\n      luminance: {mass: 1}\n"
               "    - name: young-disc\n      select: {types: [2]}\n"
               "      colour: {temperature: 12000}\n      luminance: {mass: 1}\n")


def render(name, scene, output="  exr_population_layers: true\n", threads=None, colour="", image=IMAGE,
           model=MODEL, ranks=None):
    with open(f"{work}/{name}.yaml", "w") as f:
        f.write(model + image + scene + POPULATIONS + colour +
                f"output:\n  dir: out\n  name: {name}\n  exr: true\n  png: false\n" + output)
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    command = [orrery, "render", "--quiet", f"{name}.yaml"]
    if ranks:  # orrery-mpi beside orrery, as tests/cli/test_mpi.sh runs it
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
        env["ASAN_OPTIONS"] = env.get("ASAN_OPTIONS", "") + ":detect_leaks=0"
        command = ["mpirun", "-np", str(ranks), MPI] + command[1:]
    subprocess.run(command, cwd=work, check=True, env=env)
    return read_exr(f"{work}/out/{name}.exr")


def check_sum(name, ch, fft_psf=False):
    """The populations' R, G, B add up to the beauty's R, G, B. Each is a
    sum of floats in another order, then the sRGB matrix, whose rows' sizes
    add to at most 5.3 (R: 3.24 + 1.54 + 0.50): so the difference is
    measured against the pixel's X + Y + Z, relative 1e-5 where Y is above
    1e-6 of the peak. A PSF convolved by FFT (in float) leaves rounding of
    about 1e-6 of the peak in every pixel, lit or not: then only where Y is
    above 1 % of the peak. Everywhere within 1e-5 of the peak. Each layer's
    A is the beauty's A."""
    y = ch["xyz.Y"].astype(np.float64)
    scale = sum(ch[f"xyz.{c}"].astype(np.float64) for c in "XYZ") * ch["A"]
    peak = scale.max()
    lit = y > (1e-2 if fft_psf else 1e-6) * y.max()
    check(lit.sum() > 100, f"{name}: only {lit.sum()} lit pixels")
    worst_rel = worst_off = 0.0
    for c in RGB:
        beauty = ch[c].astype(np.float64)
        total = sum(ch[f"{p}.{c}"].astype(np.float64) for p in POPS)
        worst_rel = max(worst_rel, (np.abs(total - beauty)[lit] / scale[lit]).max())
        worst_off = max(worst_off, np.abs(total - beauty).max() / peak)
    check(worst_rel < 1e-5, f"{name}: the populations' R, G, B differ from R, G, B by {worst_rel:g} of X + Y + Z")
    check(worst_off <= 1e-5, f"{name}: the populations' R, G, B differ from R, G, B by {worst_off:g} of the peak")
    for layer in LAYERS:
        check(np.abs(ch[layer]).max() > 0, f"{name}: {layer} is empty")
        check(np.isfinite(ch[layer]).all(), f"{name}: {layer} has NaN or infinity")
    for p in POPS:
        check(np.array_equal(ch[f"{p}.A"], ch["A"]), f"{name}: {p}.A is not the beauty's A")
    print(f"{name}: the populations' R, G, B sum to R, G, B within {worst_rel:.3g} of X + Y + Z "
          f"({lit.sum()} pixels), {worst_off:.3g} of the peak")


# Cloud-in-cell and dust on a perspective view.
CIC = EDGE_ON + DUST + "deposit: cic\n"
spec, ch = render("cic", CIC)
check(set(spec.channelnames) == BASE_CHANNELS | set(LAYERS), f"channels {sorted(spec.channelnames)}")
dropped = [name for name in spec.channelnames if blender_pass(name) is None]
check(not dropped, f"Blender's multilayer reader would drop {dropped}")
check(blender_pass("young-disc.R") == ("", "young-disc", "R"), "young-disc.R: not Blender's pass young-disc")
check_sum("cic", ch)
with fits.open(f"{work}/out/cic.fits") as hdul:
    names = [h.name for h in hdul if h.name in ("X", "Y", "Z") or h.name.startswith("POP")]
check(names == ["X", "Y", "Z"], f"the FITS file holds {names}, not X, Y, Z alone")

# Each layer is the R, G, B the scene draws of that population alone.
only_bulge = None
for pop in POPS:
    _, alone = render(f"only-{pop}", CIC, output="", colour=f"  only: {pop}\n")
    if pop == "bulge":
        only_bulge = alone
    for c in RGB:
        diff = np.abs(ch[f"{pop}.{c}"] - alone[c]).max()
        check(diff <= 1e-6 * np.abs(alone[c]).max(), f"{pop}.{c} differs from colour.only: {pop}'s {c} by {diff:g}")
# Where the disc's stars land and no bulge star does, the bulge's layer is 0.
disc_only = (only_bulge["xyz.Y"] == 0) & (ch["young-disc.G"] > 0)
check(disc_only.sum() > 40, f"only {disc_only.sum()} pixels of disc stars without bulge stars")
check(all((ch[f"bulge.{c}"][disc_only] == 0).all() for c in RGB),
      "the bulge's layer has light where only disc stars land")

# A Gaussian PSF; 1 and 2 threads: the same pixels in every channel.
GAUSS = CIC + "psf:\n  kind: gaussian\n  fwhm: 2\n"
_, one = render("t1", GAUSS, threads=1)
_, two = render("t2", GAUSS, threads=2)
check_sum("gaussian", one, fft_psf=True)
for name in one:
    check(np.array_equal(one[name], two[name]), f"{name}: 1 and 2 threads differ")

# Bright stars drawn one by one with the whole PSF (hst, a flat view): each
# star's population gets its light.
spec, ch = render("hst", EDGE_ON + "deposit: ngp\npsf:\n  kind: hst\n  fwhm: 2\n  spike_stars: 50\n")
check_sum("hst", ch, fft_psf=True)

# A dome master: the fused NGP gather, the rim folded; then SPH kernels.
spec, ch = render("dome-ngp", DOME + "deposit: ngp\n")
check_sum("dome-ngp", ch)
check(all((ch[f"bulge.{c}"][ch["A"] == 0] == 0).all() for c in RGB), "dome-ngp: light outside the circle")
spec, ch = render("dome-sph", DOME + DUST + "deposit: sph\n")
check_sum("dome-sph", ch)

# An image above 2^22 pixels: point deposits sorted into bands
# (pass/splat_pass.c, reduce/lanes.h), the populations' weights with them.
spec, ch = render("bands", EDGE_ON + "deposit: ngp\n", output="  exr_population_layers: true\n  fits: false\n",
                  image="image:\n  width: 2049\n  height: 2048\n")
check_sum("bands", ch)
del ch

# Streaks (animation.shutter: each star drawn as samples along its path),
# and a periodic box's copies.
spec, ch = render("blur", EDGE_ON + "deposit: cic\nanimation:\n  shutter: 0.5\n  frame_interval: 0.1\n")
check_sum("blur", ch)
spec, ch = render("periodic", EDGE_ON + "deposit: cic\n",
                  model=MODEL + "  periodic: {box: 400, replicas: 3, centre: origin}\n")
check_sum("periodic", ch)

# A dome master's hst PSF: its brightest stars, with their populations' Y,
# are shared between MPI ranks; 1 and 2 ranks write the same pixels.
if os.access(MPI, os.X_OK) and shutil.which("mpirun"):
    HST_DOME = DOME + "deposit: ngp\npsf:\n  kind: hst\n  spike_stars: 50\n"
    _, one = render("rank1", HST_DOME, ranks=1)
    _, two = render("rank2", HST_DOME, ranks=2)
    check_sum("dome-hst, 1 rank", one, fft_psf=True)
    check_sum("dome-hst, 2 ranks", two, fft_psf=True)
    for name in one:
        check(np.array_equal(one[name], two[name]), f"{name}: 1 and 2 MPI ranks differ")
else:
    print("no orrery-mpi or mpirun: the MPI ranks are not checked")

# Half floats: the layers too.
spec, ch = render("half", EDGE_ON, output="  exr_population_layers: true\n  exr_half: true\n")
formats = {n: str(f) for n, f in zip(spec.channelnames, spec.channelformats)} if spec.channelformats else {}
check(all(formats.get(layer, str(spec.format)) == "half" for layer in LAYERS), f"half: formats {formats or spec.format}")
check(set(spec.channelnames) == BASE_CHANNELS | set(LAYERS), f"half: channels {sorted(spec.channelnames)}")
check.finish("EXR population layer checks")
