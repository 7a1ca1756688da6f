# --phase-mix T (docs/nbody.md, "Discs phase-mixed before the run"): before
# a new run every disc star follows its own orbit in its galaxy's
# axisymmetric pull for a time from 0 to T drawn from its id.
# - Only the discs move: every other particle keeps its place relative to
#   the Milky Way's black hole (h5py, snapshot 0 against the same run
#   without mixing); the disc keeps its half-mass radius (within 3 %) and
#   its mean height (within 30 %: the hot disc puffs a little, 18 %).
# - What it is for: the model's hot disc (Q = 3) breathes at first, its
#   rings moving out and in together; 20 Myr in, the rms over the rings
#   2-4, 4-6 and 6-10 kpc of their mean radial speed is 6.1 km/s unmixed
#   and 2.4 mixed at these 50 000 particles. The check: mixed below half
#   of unmixed, unmixed above 4.
# - The same snapshots on one thread and two, and the count said is the
#   file's disc stars.
# Then bad values: errors naming --phase-mix, and initial conditions with no
# black hole to centre a galaxy on.
source "$(dirname "$0")/lib.sh"
NBODY=$(dirname "$ORRERY")/examples/orrery-nbody
[ -x "$NBODY" ] || { fail "no $NBODY"; finish; }

run() { # THREADS DIR [options]
  OMP_NUM_THREADS=$1 "$NBODY" --galaxies mw --particles 50000 --disc-q 3 --steps 10 --dt 0.002 --eps 0.2 \
    --report-every 10 --progress 0 --snapshot-every 10 --snapshot-dir "$2" "${@:3}" >"$2.out" 2>&1 ||
    fail "$2: $(cat "$2.out")"
}
run 2 plain
run 2 mixed --phase-mix 0.5
run 1 mixed1 --phase-mix 0.5
said=$(sed -n 's/^phase mixing: \([0-9]*\) disc stars moved .*/\1/p' mixed.out)
[ -n "$said" ] || fail "no 'phase mixing' line: $(head -3 mixed.out)"
grep -q '^phase mixing' plain.out && fail "a run without --phase-mix said it mixed"

PYTHONPATH="$SRC/tests/cli" "$py" - "$said" <<'PY' || fail "--phase-mix: the discs"
import sys, h5py, numpy as np
from expect import check, done
def load(path):
    f = h5py.File(path, "r")
    return {int(k[-1]): {n: f[k][n][:] for n in ("Coordinates", "Velocities", "Masses", "ParticleIDs")}
            for k in f if k.startswith("PartType")}
def disc_frame(d):
    x = np.concatenate([d[t]["Coordinates"] for t in (2, 3)])
    v = np.concatenate([d[t]["Velocities"] for t in (2, 3)])
    m = np.concatenate([d[t]["Masses"] for t in (2, 3)])
    c, cv = (m[:, None] * x).sum(0) / m.sum(), (m[:, None] * v).sum(0) / m.sum()
    y, w = d[2]["Coordinates"] - c, d[2]["Velocities"] - cv
    R = np.hypot(y[:, 0], y[:, 1])
    return R, y[:, 2], (y[:, 0] * w[:, 0] + y[:, 1] * w[:, 1]) / R
plain, mixed = load("plain/snapshot_0000.hdf5"), load("mixed/snapshot_0000.hdf5")
check(int(sys.argv[1]) == len(mixed[2]["Masses"]), f"said {sys.argv[1]} disc stars, the file has {len(mixed[2]['Masses'])}")
bh = lambda d: d[5]["Coordinates"][0]
for t in (1, 3, 4):
    moved = np.abs((mixed[t]["Coordinates"] - bh(mixed)) - (plain[t]["Coordinates"] - bh(plain))).max()
    check(moved < 1e-9, f"type {t} moved by {moved} kpc relative to the black hole")
disc_moved = np.abs(mixed[2]["Coordinates"] - plain[2]["Coordinates"]).max()
check(disc_moved > 1.0, f"the disc moved by at most {disc_moved} kpc")
(Rp, zp, _), (Rm, zm, _) = disc_frame(plain), disc_frame(mixed)
check(abs(np.median(Rm) / np.median(Rp) - 1) < 0.03, f"half-mass radius {np.median(Rp):.3f} -> {np.median(Rm):.3f}")
height = np.abs(zm).mean() / np.abs(zp).mean()
check(0.9 < height < 1.3, f"mean height {np.abs(zp).mean():.3f} -> {np.abs(zm).mean():.3f}")
def breathing(run):
    R, _, vR = disc_frame(load(run + "/snapshot_0001.hdf5"))
    rings = [vR[(R > lo) & (R < hi)].mean() for lo, hi in ((2, 4), (4, 6), (6, 10))]
    return np.sqrt(np.mean(np.square(rings)))
b_plain, b_mixed = breathing("plain"), breathing("mixed")
print(f"rings' mean radial speed after 20 Myr, rms: {b_plain:.2f} km/s unmixed, {b_mixed:.2f} mixed")
check(b_plain > 4 and b_mixed < 0.5 * b_plain, f"breathing: {b_plain:.2f} unmixed, {b_mixed:.2f} mixed")
one, two = load("mixed1/snapshot_0001.hdf5"), load("mixed/snapshot_0001.hdf5")
for t in one:
    for n in ("Coordinates", "Velocities"):
        check(np.array_equal(one[t][n], two[t][n]), f"type {t} {n}: one thread and two differ")
done()
PY

bad() { # VALUE WORDS [more options]
  "$NBODY" --galaxies mw --particles 2000 --steps 0 --phase-mix "$1" "${@:3}" >bad.out 2>&1
  [ $? -eq 2 ] || fail "--phase-mix $1: expected exit 2: $(cat bad.out)"
  grep -q -- "--phase-mix.*$2" bad.out || fail "--phase-mix $1: $(cat bad.out)"
}
bad -1 "from 0 (off) to 2"
bad nan "from 0 (off) to 2"
bad 3 "from 0 (off) to 2"
bad 0.5 "not with --resume" --resume plain
# Initial conditions without a black hole: no galaxy to centre on.
"$py" - <<'PY' || fail "could not write a snapshot without its black hole"
import h5py, shutil
shutil.copy("plain/snapshot_0000.hdf5", "nohole.hdf5")
with h5py.File("nohole.hdf5", "r+") as f:
    del f["PartType5"]
    for key in ("NumPart_ThisFile", "NumPart_Total"):
        n = f["Header"].attrs[key]
        n[5] = 0
        f["Header"].attrs[key] = n
PY
"$NBODY" --ic nohole.hdf5 --steps 0 --phase-mix 0.5 >nohole.out 2>&1
[ $? -eq 1 ] || fail "no black hole: expected exit 1: $(cat nohole.out)"
grep -q -- "--phase-mix 0.5: nohole.hdf5 has no black hole (type 5 particle)" nohole.out ||
  fail "no black hole: $(cat nohole.out)"
finish
