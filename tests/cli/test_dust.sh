# Dust (docs/dust.md) through the command line: a star behind one dust
# kernel is dimmed by exactly exp(-kappa m F(0) / h^2) (F(0) = 3 / (2 pi) for
# the cubic spline); a model render with its dusty gas discs is the same bit
# for bit on one thread and on two; bad dust input gives a clear error and
# writes nothing.
source "$(dirname "$0")/lib.sh"
python_with astropy python3-astropy
python_with h5py python3-h5py

# One star (type 1) 5 units behind a dust kernel (type 0) at the origin,
# seen from a perspective camera on the +z axis.
printf 'x y z mass h type\n0 0 -5 1 0.1 1\n0 0 0 1 0.5 0\n' >blob.txt
cat >blob.yaml <<'YAML'
input:
  file: blob.txt
  types: [1]
camera:
  projection: perspective
  position: [0, 0, 10]
  look_at: [0, 0, 0]
  fov: 30
image: {width: 64, height: 64}
output: {dir: out, png: false}
YAML
"$ORRERY" render blob.yaml -q --set output.name=clear || fail "render without dust"
"$ORRERY" render blob.yaml -q --set output.name=dusty --set 'dust.types=[0]' --set dust.kappa_v=1 \
  --set dust.dust_to_gas=0.25 || fail "render with dust"
"$py" - <<'PY' || fail "a star behind one kernel: dimmed by exp(-tau)"
import math
from astropy.io import fits
clear = fits.getdata("out/clear.fits").astype(float).sum()
dusty = fits.getdata("out/dusty.fits").astype(float).sum()
tau = 0.25 * 1.0 * (1.5 / math.pi) / 0.5**2  # kappa dust_to_gas m F(0) / h^2
print("ratio", dusty / clear, "expected", math.exp(-tau))
assert abs(dusty / clear - math.exp(-tau)) < 1e-4 * math.exp(-tau)
PY

# The extinction plane: A_V to infinity per pixel; through the kernel's
# centre 1.0857 tau, from a perspective and an orthographic camera.
for proj in perspective orthographic; do
  "$ORRERY" render blob.yaml -q --set output.name=av-$proj --set 'dust.types=[0]' --set dust.kappa_v=1 \
    --set dust.dust_to_gas=0.25 --set dust.extinction_plane=true --set camera.projection=$proj \
    --set camera.width=4 || fail "extinction plane, $proj"
done
"$py" - <<'PY' || fail "the extinction plane's A_V through the kernel"
import math
import numpy as np
from astropy.io import fits
want = 2.5 / math.log(10) * 0.25 * (1.5 / math.pi) / 0.5**2
for proj in ("perspective", "orthographic"):
    av = fits.getdata(f"out/av-{proj}.extinction.fits")
    print(proj, "A_V peak", np.nanmax(av), "expected", want, "corner", av[0, 0])
    assert abs(np.nanmax(av) - want) < 0.02 * want and av[0, 0] == 0
PY

# With output.exr the same plane is the EXR layer extinction, channel V
# (extinction.V) beside the light (0, not NaN, off the map), float and half;
# Blender's multilayer reader files it as the pass "extinction" (it drops a
# channel named A_V: three letters), as every other channel.
for half in false true; do
  "$ORRERY" render blob.yaml -q --set output.name=avexr-$half --set 'dust.types=[0]' --set dust.kappa_v=1 \
    --set dust.dust_to_gas=0.25 --set dust.extinction_plane=true --set output.exr=true \
    --set output.exr_half=$half || fail "extinction plane in the EXR, exr_half $half"
done
SRC="$SRC" "$py" - <<'PY' || fail "the EXR's extinction.V layer is the extinction plane"
import os
import sys
import numpy as np
from astropy.io import fits
sys.path.insert(0, os.path.join(os.environ["SRC"], "tests", "cli"))
from check_lib import blender_pass, read_exr
for half, tol in (("false", 0.0), ("true", 1e-3)):
    # FITS rows run bottom to top, EXR's top to bottom
    want = np.nan_to_num(fits.getdata(f"out/avexr-{half}.extinction.fits").astype(np.float64))[::-1]
    spec, ch = read_exr(f"out/avexr-{half}.exr")
    print(half, spec.channelnames)
    assert spec.channelnames[-1] == "extinction.V", spec.channelnames
    assert blender_pass("extinction.V") == ("", "extinction", "V") and blender_pass("extinction.A_V") is None
    dropped = [name for name in spec.channelnames if blender_pass(name) is None]
    assert not dropped, f"Blender would drop {dropped}"
    err = np.abs(ch["extinction.V"] - want).max()
    print(half, "A_V peak", want.max(), "largest difference", err)
    assert want.max() > 0.4 and err <= tol * want.max()
PY

# The model with its dusty discs, from the Sun, in colour: one thread and two.
cat >sky.yaml <<'YAML'
input:
  model: {name: mw-m31, particles: 10000, dust_particles: 2000}
  types: [2, 3]
observer: {id: 3, reference_id: 1, normal: [0, 0, 1], dim: true, dim_near: 0.1}
dust: {types: [0], kappa_v: 3.7e4}
camera: {projection: hammer-aitoff}
image: {width: 256, height: 128}
colour:
  populations:
    - {name: bulge, select: {types: [3]}, colour: {temperature: 4000}, luminance: {mass: 1}}
    - {name: disc, select: {types: [2]}, colour: {temperature: 12000}, luminance: {mass: 1}}
output: {dir: out, png: false}
YAML
OMP_NUM_THREADS=1 "$ORRERY" render sky.yaml -q --set output.name=one || fail "model with dust, one thread"
OMP_NUM_THREADS=2 "$ORRERY" render sky.yaml -q --set output.name=two || fail "model with dust, two threads"
"$ORRERY" render sky.yaml -q --set output.name=clear --set 'dust.types=[5]' || fail "model, dust of type 5"
"$ORRERY" render sky.yaml -q --set output.name=f99 --set dust.curve=f99 || fail "model with dust, dust.curve: f99"
"$py" - <<'PY' || fail "the same image on one thread and two; dimmer and redder than without dust, with either curve"
import numpy as np
from astropy.io import fits
planes = lambda f: [fits.getdata(f, ext=k).astype(float) for k in range(3)]
one, two, clear = planes("out/one.fits"), planes("out/two.fits"), planes("out/clear.fits")
for k in range(3):
    assert np.array_equal(one[k], two[k], equal_nan=True), "thread count changed the image"
X, Y, Z = (np.nansum(p) for p in one)
Xc, Yc, Zc = (np.nansum(p) for p in clear)
print("Y dusty / clear", Y / Yc, "Z/Y", Z / Y, "clear", Zc / Yc)
assert Y < 0.9 * Yc and Z / Y < Zc / Yc
Xf, Yf, Zf = (np.nansum(p) for p in planes("out/f99.fits"))
print("f99: Y dusty / clear", Yf / Yc, "Z/Y", Zf / Yf)
assert Yf < 0.9 * Yc and Zf / Yf < Zc / Yc and (Xf, Yf, Zf) != (X, Y, Z)
PY

# Real data: the gas of the shared GADGET-4 lcdm_gas snapshot as dust in
# front of its own dark matter (a smoke test): it runs, each pixel is dimmed
# and none brightened, and a vanishing opacity gives the dust-free image.
lcdm="${ORRERY_SHARED_DATA:-$SRC/../shared/data}/hdf5/gadget4_lcdm_gas/snapshot_004.hdf5"
if [ -f "$lcdm" ]; then
  cat >lcdm.yaml <<YAML
input: {file: $lcdm, types: [1]}
camera: {projection: orthographic, position: [25000, 25000, 60000], look_at: [25000, 25000, 0], width: 50000}
image: {width: 128, height: 128}
output: {dir: out, png: false}
YAML
  "$ORRERY" render lcdm.yaml -q --set output.name=lc0 || fail "lcdm_gas without dust"
  "$ORRERY" render lcdm.yaml -q --set output.name=lc1 --set 'dust.types=[0]' --set dust.kappa_v=1e6 ||
    fail "lcdm_gas, its gas as dust"
  "$ORRERY" render lcdm.yaml -q --set output.name=lc2 --set 'dust.types=[0]' --set dust.kappa_v=1e-10 ||
    fail "lcdm_gas, a vanishing opacity"
  "$py" - <<'PY' || fail "lcdm_gas: the gas dims its dark matter, and no opacity is no dust"
import numpy as np
from astropy.io import fits
a, b, c = (fits.getdata(f"out/lc{k}.fits").astype(float) for k in range(3))
print("lcdm_gas: kept", b.sum() / a.sum(), "with kappa 1e-10:", c.sum() / a.sum())
assert 0.05 < b.sum() / a.sum() < 0.95 and (b <= a * (1 + 1e-6)).all()
assert np.abs(c - a).max() <= 1e-6 * a.max()
PY
fi

# Bad input: nothing written.
mkdir -p bad
printf 'x y z mass h type\n0 0 -5 1 0.1 1\n0 0 0 -1 0.5 0\n' >negmass.txt
printf 'x y z mass h type\n0 0 -5 1 0.1 1\n0 0 0 1 0 0\n' >zeroh.txt
printf 'x y z mass type\n0 0 -5 1 1\n0 0 0 1 0\n' >oneh.txt
printf 'x y z mass Z type\n0 0 -5 1 0.02 1\n0 0 0 1 nan 0\n0.1 0 0 1 0.01 0\n' >nanz.txt
printf '360 1.5\n400 1.3\n380 1.4\n420 1.2\n' >unsorted.txt
dust=(--set output.dir=bad --set 'dust.types=[0]' --set dust.kappa_v=1)
expect_fail 2 "dust.types: type\(s\) \[0\] are also drawn as light" bad -- render blob.yaml "${dust[@]}" \
  --set 'input.types=[0,1]'
expect_fail 2 "dust.kappa_v is required" bad -- render blob.yaml --set output.dir=bad --set 'dust.types=[0]'
expect_fail 2 "dust.kappa_v" bad -- render blob.yaml "${dust[@]}" --set dust.kappa_v=-2
expect_fail 2 "dust.kappa_v" bad -- render blob.yaml "${dust[@]}" --set dust.kappa_v=nan
expect_fail 2 "dust.curve: file needs dust.curve_file" bad -- render sky.yaml "${dust[@]}" --set dust.curve=file
expect_fail 1 "unsorted.txt:3: dust.curve: wavelength 380 nm after 400 nm" bad -- render sky.yaml "${dust[@]}" \
  --set dust.curve=file --set dust.curve_file=unsorted.txt
# A curve file is read in single-band renders too, though only colour uses it.
expect_fail 1 "blob.yaml: unsorted.txt:3: dust.curve: wavelength 380 nm after 400 nm" bad -- render blob.yaml \
  "${dust[@]}" --set dust.curve=file --set dust.curve_file=unsorted.txt
expect_fail 1 "blob.yaml: no-such-curve.txt: dust.curve: cannot open" bad -- render blob.yaml "${dust[@]}" \
  --set dust.curve=file --set dust.curve_file=no-such-curve.txt
# Opacities beyond single precision: refused by name, not found later as a
# star's "non-finite weight".
expect_fail 2 "dust.kappa_v \* dust.dust_to_gas = 1e\+300 \* 0.01 is beyond single precision" bad -- \
  render blob.yaml "${dust[@]}" --set dust.kappa_v=1e300
printf 'x y z mass h type\n0 0 -5 1 0.1 1\n0 0 0 1e10 0.5 0\n' >heavy.txt
expect_fail 1 "heavy.txt: dust particle 1 \(id 1, type 0\): its opacity dust.kappa_v \* dust.dust_to_gas \* mass = 1e\+39 is beyond single precision" \
  bad -- render blob.yaml "${dust[@]}" --set dust.kappa_v=1e31 --set input.file=heavy.txt
expect_fail 1 "negmass.txt:3: column 'mass': particle 1: mass -1 is negative" bad -- render blob.yaml "${dust[@]}" \
  --set input.file=negmass.txt
expect_fail 1 "zeroh.txt: dust particle 1 \(id 1, type 0\): smoothing length h = 0" bad -- render blob.yaml \
  "${dust[@]}" --set input.file=zeroh.txt
expect_fail 1 "1 dust particle\(s\) without smoothing lengths" bad -- render blob.yaml "${dust[@]}" \
  --set input.file=oneh.txt
expect_fail 1 "nanz.txt: dust particle 1 \(id 1, type 0\): Z = nan" bad -- render blob.yaml "${dust[@]}" \
  --set input.file=nanz.txt --set dust.metallicity=Z
expect_fail 2 "dust.types with input.periodic.replicas" bad -- render blob.yaml "${dust[@]}" \
  --set input.periodic.replicas=3 --set input.periodic.box=20
# A snapshot sequence keeps the dust's types as a single file does: the
# star behind the kernel, in two identical Gadget HDF5 snapshots (whose
# units make tau another number than the text table's), is dimmed in every
# frame as in the single-file render of the first (before, a sequence read
# only input.types and drew no dust).
"$py" - <<'PY' || fail "writing the blob as Gadget HDF5 snapshots"
import h5py, numpy as np
for i, t in enumerate([0.0, 1.0]):
    with h5py.File(f"blob_{i}.hdf5", "w") as f:
        h = f.create_group("Header")
        h.attrs["NumPart_ThisFile"] = h.attrs["NumPart_Total"] = np.array([1, 1, 0, 0, 0, 0], dtype=np.uint32)
        h.attrs["MassTable"] = np.zeros(6)
        h.attrs["Time"], h.attrs["NumFilesPerSnapshot"] = t, 1
        for part, z, pid in (("PartType0", 0.0, 2), ("PartType1", -5.0, 1)):
            g = f.create_group(part)
            g["Coordinates"] = np.array([[0, 0, z]], dtype=np.float32)
            g["Velocities"] = np.zeros((1, 3), dtype=np.float32)
            g["Masses"] = np.ones(1, dtype=np.float32)
            g["ParticleIDs"] = np.array([pid], dtype=np.uint32)
            g["SmoothingLength"] = np.array([0.5 if pid == 2 else 0.1], dtype=np.float32)
PY
sed 's/^  file: blob.txt/  sequence: {files: [blob_0.hdf5, blob_1.hdf5]}/' blob.yaml >blobseq.yaml
echo "animation: {frames: 2}" >>blobseq.yaml
sed 's/^  file: blob.txt/  file: blob_0.hdf5/' blob.yaml >blobh5.yaml
for w in clear dusty; do
  dust=()
  [ $w = dusty ] && dust=(--set 'dust.types=[0]' --set dust.kappa_v=1 --set dust.dust_to_gas=0.25)
  "$ORRERY" render blobh5.yaml -q --set output.name=h5$w "${dust[@]}" || fail "the first snapshot alone, $w"
done
"$ORRERY" render blobseq.yaml -q --set output.name=seqclear || fail "a sequence without dust"
"$ORRERY" render blobseq.yaml -q --set output.name=seqdusty --set 'dust.types=[0]' --set dust.kappa_v=1 \
  --set dust.dust_to_gas=0.25 || fail "a sequence with dust"
"$py" - <<'PY' || fail "a sequence's frames dimmed as the single snapshot"
from astropy.io import fits
want = fits.getdata("out/h5dusty.fits").astype(float).sum() / fits.getdata("out/h5clear.fits").astype(float).sum()
assert want < 0.99, f"the single snapshot's dust dims by {want}"
for k in (0, 1):
    clear, dusty = (fits.getdata(f"out/seq{w}_{k:04d}.fits").astype(float).sum() for w in ("clear", "dusty"))
    print("frame", k, "ratio", dusty / clear, "expected", want)
    assert abs(dusty / clear - want) < 1e-4 * want
PY

grep -v '^image:' sky.yaml >skyhp.yaml
expect_fail 2 "dust.extinction_plane is not written for camera.projection: healpix" bad -- render skyhp.yaml \
  --set output.dir=bad --set dust.extinction_plane=true --set camera.projection=healpix --set deposit=ngp
finish
