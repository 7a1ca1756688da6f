# The Dark Universe case study end to end: `orrery ics` writes a tiny
# Zel'dovich box (16³), the scene configs/dark-universe.yaml flies through it
# in 3 tiny frames, and the tint follows the run (colour.tint.t: run): frame 0
# blue, frame 2 red; `orrery ics --evolve` gives the same bytes on 1 and 2
# threads; the short run on an evolved 16³ box has no jump in its light.
# Also the generator's and the key's bad input.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

mkdir -p out
"$ORRERY" ics --zeldovich --grid 16 --box 100 --z 0 --seed 3 -o out/box.hdf5 >ics.txt 2>err.txt ||
  fail "ics: $(cat err.txt)"
grep -q "wrote 4096 particles to out/box.hdf5" ics.txt || fail "ics output: $(cat ics.txt)"
# The box is in its centre-of-mass frame (equal masses: the velocities
# sum to float round-off), as h5py finds and as it says.
net=$(sed -n 's/^centre-of-mass frame: net velocity \([^ ]*\) km\/s.*/\1/p' ics.txt)
"$py" - "$net" <<'PY' || fail "ics centre-of-mass frame: $(grep centre-of-mass ics.txt)"
import sys, h5py, numpy as np
v = h5py.File("out/box.hdf5", "r")["PartType1/Velocities"][:].astype(np.float64)
net, rms = np.linalg.norm(v.mean(0)), np.sqrt((v ** 2).sum(1).mean())
said = float(sys.argv[1])
raise SystemExit(not (net < 1e-6 * rms and abs(said - net) <= 0.05 * net + 1e-12))
PY
"$ORRERY" info out/box.hdf5 >info.txt 2>err.txt || fail "info: $(cat err.txt)"
grep -q "4096" info.txt && grep -q "BoxSize" info.txt || fail "info of the box: $(cat info.txt)"
# The same seed gives the same bytes (the writer records no times); another
# seed another box.
"$ORRERY" ics --zeldovich --grid 16 --box 100 --z 0 --seed 3 -o out/again.hdf5 >/dev/null 2>&1
"$ORRERY" ics --zeldovich --grid 16 --box 100 --z 0 --seed 4 -o out/other.hdf5 >/dev/null 2>&1
cmp -s out/box.hdf5 out/again.hdf5 || fail "the same seed gave different files"
cmp -s out/box.hdf5 out/other.hdf5 && fail "seeds 3 and 4 gave the same file"

# The particle-mesh run: the same file on 1 and on 2 threads.
OMP_NUM_THREADS=1 "$ORRERY" ics --zeldovich --grid 16 --box 100 --evolve --pm-steps 4 -o out/pm1.hdf5 >pm.txt 2>err.txt ||
  fail "ics --evolve: $(cat err.txt)"
grep -q "particle mesh: 4 steps on a 32³ mesh to z = 0" pm.txt || fail "ics --evolve output: $(cat pm.txt)"
# Progress lines on stderr (every step but the last with --progress 1e-9).
OMP_NUM_THREADS=1 "$ORRERY" ics --zeldovich --grid 16 --box 100 --evolve --pm-steps 4 --progress 1e-9 -o out/pmp.hdf5 \
  >/dev/null 2>pmp.err || fail "ics --evolve --progress: $(cat pmp.err)"
[ "$(grep -c '^particle mesh: step [1-3] of 4  z = [0-9.]*  |sum p| / sum |p| = [0-9.e-]*  [0-9.e+]* particle-steps/s  [0-9]*:[0-9][0-9] left$' pmp.err)" -eq 3 ] ||
  fail "ics progress lines: $(cat pmp.err)"
cmp -s out/pm1.hdf5 out/pmp.hdf5 || fail "ics --evolve with progress lines wrote another box"
OMP_NUM_THREADS=2 "$ORRERY" ics --zeldovich --grid 16 --box 100 --evolve --pm-steps 4 -o out/pm2.hdf5 >/dev/null 2>&1
cmp -s out/pm1.hdf5 out/pm2.hdf5 || fail "ics --evolve gave different files on 1 and 2 threads"

frames() {
  "$ORRERY" render --quiet "$SRC/configs/dark-universe.yaml" -o frames --set input.file=out/box.hdf5 \
    --set animation.frames=3 --set image.width=96 --set image.height=51 --set psf.fwhm=1 \
    --set camera.path.from=[5,40,45] --set camera.path.to=[60,50,50] --set colour.synthesis.white=auto \
    "$@" 2>err.txt || fail "render: $(cat err.txt)"
}
frames
for f in 0 1 2; do
  [ -f "frames/dark-universe_000$f.png" ] || fail "frame $f missing: $(ls frames)"
done
"$py" - <<'EOT' || fail "the tint does not run from blue to red"
import sys
import numpy as np
from PIL import Image
def mean_rgb(f):
    a = np.asarray(Image.open(f"frames/dark-universe_000{f}.png")).reshape(-1, 3).astype(float)
    a = a[a.sum(axis=1) > 60]
    return a.mean(axis=0) if len(a) else np.zeros(3)
first, middle, last = mean_rgb(0), mean_rgb(1), mean_rgb(2)
print("mean RGB of lit pixels: frame 0", first.round(1), "frame 1", middle.round(1), "frame 2", last.round(1))
ok = first[2] > 1.1 * first[0] and last[0] > 1.5 * last[2]
ok &= first[2] / first[0] > middle[2] / middle[0] > last[2] / last[0]
sys.exit(0 if ok else 1)
EOT
# A number still fixes the tint: every frame as frame 0 of the run.
rm -rf frames
frames --set colour.tint.t=0
"$py" - <<'EOT' || fail "colour.tint.t=0 does not hold the tint"
import sys
import numpy as np
from PIL import Image
ratios = []
for f in range(3):
    a = np.asarray(Image.open(f"frames/dark-universe_000{f}.png")).reshape(-1, 3).astype(float)
    a = a[a.sum(axis=1) > 60].mean(axis=0)
    ratios.append(a[2] / a[0])
print("blue/red by frame:", np.round(ratios, 3))
sys.exit(0 if min(ratios) > 1.1 else 1)
EOT

# The short run's fly-through (48 frames, an evolved 16³ box, small frames)
# crosses faces of the box twice: the light of consecutive frames (scripts/
# frame_light.py: each pixel's value, per steradian, times its exact solid
# angle as a flat pinhole camera's pixel) changes by 5 % at most (with
# copies around the camera's cell it jumped +654 % at the first face).
# (16³ rather than 32³: each particle is an SPH kernel at its images within
# 200 Mpc/h, which took the sanitizer build 4 min for 32³; measured 1.70 %.)
"$ORRERY" ics --zeldovich --grid 16 --box 100 --evolve --pm-steps 10 -o out/box16e.hdf5 >/dev/null 2>err.txt ||
  fail "ics 16 --evolve: $(cat err.txt)"
"$ORRERY" render --quiet "$SRC/configs/dark-universe.yaml" -o short --jobs 2 --set input.file=out/box16e.hdf5 \
  --set animation.frames=48 --set image.width=256 --set image.height=135 --set psf.fwhm=1 2>err.txt ||
  fail "short run: $(cat err.txt)"
"$py" "$SRC/scripts/frame_light.py" --max-change 0.05 short/dark-universe_00*.fits >light.txt ||
  fail "the light jumps between frames of the short run: $(tail -1 light.txt)"
tail -1 light.txt
grep -q "^48 frames" light.txt || fail "not 48 frames: $(tail -1 light.txt)"

expect_fail 2 "colour.tint.t: expected a number or run, got .*walk" none -- render "$SRC/configs/dark-universe.yaml" \
  --set input.file=out/box.hdf5 --set colour.tint.t=walk
expect_fail 2 "colour.tint.t.*1.5" none -- render "$SRC/configs/dark-universe.yaml" \
  --set input.file=out/box.hdf5 --set colour.tint.t=1.5
expect_fail 2 "orrery: error: --grid 15: expected an even whole number" none -- ics --zeldovich --grid 15 -o none/x.hdf5
expect_fail 2 "orrery: error: give the method: --zeldovich" none -- ics --grid 16 -o none/x.hdf5
expect_fail 2 "omega_m 0: expected a value in \(0, 2\]" none -- ics --zeldovich --grid 4 --omega-m 0 -o none/x.hdf5
expect_fail 2 "box -5: expected a side in Mpc/h" none -- ics --zeldovich --grid 4 --box -5 -o none/x.hdf5
expect_fail 2 "unknown option '--frobnicate'" none -- ics --zeldovich --frobnicate -o none/x.hdf5
expect_fail 2 "orrery: error: --pm-steps: only with --evolve" none -- ics --zeldovich --grid 4 --pm-steps 5 -o none/x.hdf5
expect_fail 2 "orrery: error: --progress: only with --evolve" none -- ics --zeldovich --grid 4 --progress 5 -o none/x.hdf5
expect_fail 2 "orrery: error: --progress x: expected seconds" none -- ics --zeldovich --grid 4 --evolve --progress x -o none/x.hdf5
expect_fail 2 "orrery: error: --pm-grid 7: expected an even whole number" none -- ics --zeldovich --evolve --pm-grid 7 -o none/x.hdf5
expect_fail 2 "orrery: error: --z-start 0: expected a redshift above 0" none -- ics --zeldovich --evolve --z-start 0 -o none/x.hdf5
expect_fail 2 "orrery: error: --z-start 24: expected a redshift above --z 30" none -- ics --zeldovich --evolve --z 30 -o none/x.hdf5
expect_fail 2 "pm-steps 0" none -- ics --zeldovich --evolve --pm-steps 0 -o none/x.hdf5
expect_fail 1 "/nonexistent-orrery-dir" none -- ics --zeldovich --grid 4 -o /nonexistent-orrery-dir/x.hdf5
finish
