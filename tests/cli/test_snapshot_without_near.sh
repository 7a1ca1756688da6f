#!/bin/bash
# scripts/snapshot_without_near.py, with which docs/sky.md measures the near
# disc particles' share of a frame's light: on a small synthetic snapshot
# whose answer is counted here independently, the particles of the type
# within the radius of the observer are gone, every other particle and
# dataset kept, the header's counts follow, and orrery reads the result;
# bad arguments leave no file.
. "$(dirname "$0")/lib.sh"
python_with h5py python3-h5py
script="$SRC/scripts/snapshot_without_near.py"

"$py" - <<'PY' || fail "could not write the test snapshot"
import h5py, numpy as np
rng = np.random.default_rng(3)
with h5py.File("snap.hdf5", "w") as f:
    h = f.create_group("Header")
    h.attrs["NumPart_ThisFile"] = np.array([0, 0, 400, 0, 1, 0], dtype=np.uint32)
    h.attrs["NumPart_Total"] = np.array([0, 0, 400, 0, 1, 0], dtype=np.uint32)
    h.attrs["MassTable"] = np.zeros(6)
    h.attrs["Time"] = 0.0
    h.attrs["NumFilesPerSnapshot"] = 1
    disc = f.create_group("PartType2")
    disc.create_dataset("Coordinates", data=rng.uniform(-3, 3, (400, 3)))
    disc.create_dataset("ParticleIDs", data=np.arange(10, 410, dtype=np.uint64))
    disc.create_dataset("Masses", data=rng.uniform(1, 2, 400))
    sun = f.create_group("PartType4")
    sun.create_dataset("Coordinates", data=np.array([[0.5, -0.25, 0.1]]))
    sun.create_dataset("ParticleIDs", data=np.array([3], dtype=np.uint64))
    sun.create_dataset("Masses", data=np.zeros(1))
PY

"$py" "$script" snap.hdf5 near.hdf5 --radius 1.5 >run.log 2>&1 || fail "the script failed: $(cat run.log)"
"$py" - <<'PY' || fail "near.hdf5 is not snap.hdf5 without the disc particles within 1.5 of the Sun"
import sys, h5py, numpy as np
with h5py.File("snap.hdf5", "r") as a, h5py.File("near.hdf5", "r") as b:
    pos = a["PartType2/Coordinates"][:]
    far = np.linalg.norm(pos - a["PartType4/Coordinates"][0], axis=1) >= 1.5
    bad = []
    if not 0 < (~far).sum() < far.size:
        bad.append(f"the test's radius leaves out {(~far).sum()} of {far.size}")
    for name in ("Coordinates", "ParticleIDs", "Masses"):
        if not np.array_equal(b["PartType2/" + name][:], a["PartType2/" + name][:][far]):
            bad.append(f"PartType2/{name} is not the far particles, in order")
    for name in ("Coordinates", "ParticleIDs", "Masses"):
        if not np.array_equal(b["PartType4/" + name][:], a["PartType4/" + name][:]):
            bad.append(f"PartType4/{name} changed")
    for key in ("NumPart_ThisFile", "NumPart_Total"):
        if list(b["Header"].attrs[key]) != [0, 0, far.sum(), 0, 1, 0]:
            bad.append(f"Header {key} is {list(b['Header'].attrs[key])}")
    print(f"{(~far).sum()} of {far.size} left out")
for m in bad:
    print(m, file=sys.stderr)
sys.exit(1 if bad else 0)
PY
grep -q "particles of type 2 within 1.5 of particle 3 left out" run.log || fail "the script's report: $(cat run.log)"
"$ORRERY" info near.hdf5 >info.log 2>&1 || fail "orrery info cannot read the result: $(cat info.log)"

# Bad arguments: a message naming what was wrong, a non-zero exit, no file.
for args in "--radius 0" "--radius 1 --type 5" "--radius 1 --observer-id 7"; do
  rm -f bad.hdf5 bad.hdf5.partial
  if "$py" "$script" snap.hdf5 bad.hdf5 $args >bad.log 2>&1; then
    fail "$args was accepted"
  elif ! grep -q "snapshot_without_near: " bad.log; then
    fail "$args: no message naming the script: $(cat bad.log)"
  fi
  [ -e bad.hdf5 ] || [ -e bad.hdf5.partial ] && fail "$args left a file"
done
finish
