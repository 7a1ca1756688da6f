# orrery-nbody's snapshots and resume (docs/nbody.md): Gadget-layout HDF5
# every K steps, read back by orrery's own reader (`orrery info`, a render);
# a run of 8 steps and a run of 4 resumed to 8 end in the same bytes (a
# control started from the same snapshot with --ic, through orrery's float
# reader, does not, so the comparison can fail); a run killed while it
# writes snapshots leaves only complete ones, and resumes; bad options and a
# folder that cannot be written are errors naming them, before any step.
source "$(dirname "$0")/lib.sh"
[ -x "$NBODY" ] || { fail "no $NBODY"; finish; }
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
run="--galaxies mw --particles 3000 --dt 0.002 --report-every 4"

# Straight: 8 steps, a snapshot at step 0 and every 2 steps, nothing else left.
"$NBODY" $run --steps 8 --snapshot-every 2 --snapshot-dir straight >straight.log 2>&1 ||
  fail "straight run: $(tail -3 straight.log)"
[ "$(ls -A straight | tr '\n' ' ')" = "snapshot_0000.hdf5 snapshot_0001.hdf5 snapshot_0002.hdf5 snapshot_0003.hdf5 snapshot_0004.hdf5 " ] ||
  fail "straight snapshots: $(ls -A straight)"

# 4 steps, then resumed to 8 (its settings are the snapshot's).
"$NBODY" $run --steps 4 --snapshot-every 2 --snapshot-dir half >half1.log 2>&1 || fail "half run: $(tail -3 half1.log)"
[ ! -e half/snapshot_0003.hdf5 ] || fail "the half run went past step 4"
"$NBODY" --resume half --steps 8 --report-every 4 >half2.log 2>&1 || fail "resume: $(tail -3 half2.log)"
grep -q "^resumed at step 4, t = 0.0080" half2.log || fail "resume line: $(head -3 half2.log)"
grep -q "^step 5 " half2.log && ! grep -q "^step 4 " half2.log || fail "resumed steps: $(grep ^step half2.log)"
# Bit for bit: snapshots hold no write times, so the same state is the same bytes.
cmp -s straight/snapshot_0003.hdf5 half/snapshot_0003.hdf5 || fail "snapshot 3 differs after the resume"
cmp -s straight/snapshot_0004.hdf5 half/snapshot_0004.hdf5 || fail "snapshot 4 differs after the resume"
[ "$(grep '^report' straight.log | tail -1)" = "$(grep '^report' half2.log | tail -1)" ] ||
  fail "last reports differ: $(grep '^report' straight.log | tail -1) / $(grep '^report' half2.log | tail -1)"

# Progress lines on stderr (every step with --progress 1e-9), also with
# --quiet: the step of the run's, the time, the energy error the report
# gives at the same step, a rate, the time left; none with --progress 0.
"$NBODY" $run --steps 4 --progress 1e-9 >progress.out 2>progress.err || fail "progress run: $(cat progress.err)"
[ "$(grep -c '^progress: step [1-4] of 4  t = 0.00[2468]0 ([0-9.]* Myr)  dE/|E0| = [-+][0-9.e+-]*  [0-9.e+]* particle-steps/s  0:0[0-9] left$' progress.err)" -eq 4 ] ||
  fail "progress lines: $(cat progress.err)"
[ "$(grep '^progress: step 4 ' progress.err | sed 's/.*dE\/|E0| = \([^ ]*\).*/\1/')" = \
  "$(grep '^report t = 0.0080' progress.out | sed 's/.*dE\/|E0| = \([^ ]*\).*/\1/')" ] ||
  fail "progress and report disagree on the energy: $(grep 'step 4' progress.err) / $(grep '0.0080' progress.out)"
small="--galaxies mw --particles 1000 --steps 1 --quiet"
"$NBODY" $small --progress 1e-9 2>&1 | grep -q "^progress: step 1 of 1" || fail "no progress line with --quiet"
[ -z "$("$NBODY" $small --progress 0 2>&1)" ] || fail "--progress 0 printed"

# The control: the same snapshot as new initial conditions (--ic) goes
# through orrery's reader, which rounds to float: close, not equal.
"$NBODY" --ic half/snapshot_0002.hdf5 --steps 4 --dt 0.002 --snapshot-every 4 --snapshot-dir fromic >ic.log 2>&1 ||
  fail "--ic from a snapshot: $(tail -3 ic.log)"

# The same model as a text table, for the fields fixed at the start.
"$ORRERY" model -o model.txt --galaxies mw --particles 3000 >model.log 2>&1 || fail "orrery model: $(cat model.log)"

PYTHONPATH="$SRC/tests/cli" "$py" - <<'PY' || fail "snapshot contents"
import h5py, numpy as np
from expect import check, done
a = h5py.File("straight/snapshot_0004.hdf5", "r")
b = h5py.File("half/snapshot_0004.hdf5", "r")
c = h5py.File("fromic/snapshot_0001.hdf5", "r")
h = a["Header"].attrs
check(list(h["NumPart_ThisFile"]) == [0, 2026, 810, 162, 1, 1], f"counts {list(h['NumPart_ThisFile'])}")
check(h["Time"] == b["Header"].attrs["Time"] and abs(h["Time"] - 0.016) < 1e-12, f"time {h['Time']}")
check(a["OrreryNbody"].attrs["Step"] == 8, "step")
for t in range(1, 6):
    g, k = a[f"PartType{t}"], b[f"PartType{t}"]
    for name in ("Coordinates", "Velocities", "Masses", "ParticleIDs", "r", "E0", "ez"):
        check(np.array_equal(g[name][:], k[name][:]), f"PartType{t}/{name} differs")
    check(g["Coordinates"].dtype == np.float64, "Coordinates not double")
    check(np.all(np.isfinite(g["Coordinates"][:])), "non-finite coordinates")
# The model's extra fields travel: E0 (the initial potential) is negative;
# ez is the model's own, particle for particle, after 8 steps (0 off the disc).
check(np.all(a["PartType2/E0"][:] < 0), "E0 field")
m = np.loadtxt("model.txt", skiprows=1, dtype=np.float64)  # x y z mass id type vx vy vz r E0 ez
for t in range(1, 6):
    ids, ez = a[f"PartType{t}/ParticleIDs"][:], a[f"PartType{t}/ez"][:]
    want = np.zeros(int(m[:, 4].max()) + 1)
    want[m[:, 4].astype(np.int64)] = m[:, 11]
    check(np.array_equal(ez.astype(np.float64), np.float32(want[ids])), f"PartType{t}/ez is not the model's")
    check(np.any(ez > 0) == (t == 2), f"PartType{t}/ez: {ez.min()} to {ez.max()}")
# The --ic control: same particles, near the same places, not the same bits.
def by_id(f, name):
    rows = [(f[f"PartType{t}/ParticleIDs"][:], f[f"PartType{t}/{name}"][:]) for t in range(1, 6)]
    ids = np.concatenate([r[0] for r in rows]); v = np.concatenate([r[1] for r in rows])
    return v[np.argsort(ids)]
x, y = by_id(a, "Coordinates"), by_id(c, "Coordinates")
d = np.abs(x - y).max()
check(0 < d < 1e-2, f"--ic control: max |dx| = {d}, expected small but not 0")
check(c["Header"].attrs["Time"] == h["Time"] or abs(c["Header"].attrs["Time"] - h["Time"]) < 1e-12, "control time")
# What orrery's reader should report for the straight run's last snapshot.
xs = a["PartType1/Coordinates"][:, 0]
for t in range(2, 6):
    xs = np.concatenate([xs, a[f"PartType{t}/Coordinates"][:, 0]])
open("expect.txt", "w").write(f"{np.float32(xs.min())!r} {np.float32(xs.max())!r}\n")
done()
PY

# orrery's own reader: the count, time, types and x range h5py gives.
"$ORRERY" info straight/snapshot_0004.hdf5 >info.txt 2>&1 || fail "orrery info: $(cat info.txt)"
grep -q "^particles: *3000$" info.txt && grep -q "^time: *0.016$" info.txt && grep -q "type 2: *810 particles" info.txt ||
  fail "orrery info: $(cat info.txt)"
read -r xmin xmax <expect.txt
awk -v lo="$xmin" -v hi="$xmax" '/^x range:/ { gsub(/[\[\],]/, " "); if (($3 - lo)^2 > 1e-8 || ($4 - hi)^2 > 1e-8) exit 1; found = 1 }
  END { exit !found }' info.txt || fail "x range: $(grep 'x range' info.txt), h5py: $xmin $xmax"
# ... and a render of it: every particle read, the galaxy in the middle.
printf 'input: {file: straight/snapshot_0004.hdf5}\ncamera: {projection: orthographic, width: 600, position: [0, 0, 1000]}\nimage: {width: 64, height: 64}\noutput: {png: false, name: snap, dir: rendered}\n' >snap.yaml
"$ORRERY" render snap.yaml -q 2>render.err || fail "render: $(cat render.err)"
"$py" - <<'PY' || fail "rendered snapshot"
import numpy as np
from astropy.io import fits
h = fits.open("rendered/snap.fits")[0]
y, x = np.unravel_index(np.argmax(h.data), h.data.shape)
ok = h.header["NPART"] == 3000 and h.data.max() > 0 and abs(x - 31.5) < 3 and abs(y - 31.5) < 3
print("" if ok else f"NPART {h.header['NPART']}, peak at {x}, {y}")
raise SystemExit(not ok)
PY

# Rendering in-situ, a resumed run goes on with the next frame's number.
printf 'camera: {projection: orthographic, width: 60, position: [0, 0, 100]}\nimage: {width: 32, height: 32}\noutput: {png: false, name: f}\n' >insitu.yaml
"$NBODY" --galaxies mw --particles 2000 --steps 2 --dt 0.002 --snapshot-every 2 --snapshot-dir framed \
  --scene insitu.yaml --set output.dir=frames >framed1.log 2>&1 || fail "framed run: $(tail -3 framed1.log)"
"$NBODY" --resume framed --steps 4 --scene insitu.yaml --set output.dir=frames >framed2.log 2>&1 ||
  fail "framed resume: $(tail -3 framed2.log)"
[ "$(ls frames | tr '\n' ' ')" = "f_0000.fits f_0001.fits f_0002.fits f_0003.fits f_0004.fits " ] || fail "frames: $(ls frames)"
grep -q "rendering 0.* over 2 frames" framed2.log || fail "frames rendered by the resume: $(grep rendering framed2.log)"
# In situ, colour populations find the model's field ez (a thin disc drawn
# by it); a field the particles lack is an error naming it.
thin="colour: {populations: [{name: thin, select: {types: [2], random: {field: FIELD, law: logistic, v0: 0.7, dv: 0.25}}, colour: {bv: 0}}, {name: rest, select: {}, colour: {bv: 1}}]}"
echo "${thin/FIELD/ez}" | cat insitu.yaml - >thin.yaml
echo "${thin/FIELD/ezz}" | cat insitu.yaml - >nothin.yaml
"$NBODY" --galaxies mw --particles 2000 --steps 1 --scene thin.yaml --set output.dir=thin >thin.log 2>&1 ||
  fail "in-situ populations by ez: $(tail -3 thin.log)"
[ -s thin/f_0001.fits ] || fail "in-situ populations by ez: $(ls thin)"
! "$NBODY" --galaxies mw --particles 2000 --steps 1 --scene nothin.yaml --set output.dir=nothin >nothin.log 2>&1 &&
  grep -q "no field 'ezz'" nothin.log || fail "a population's missing field: $(tail -3 nothin.log)"
# ... and so do they from a snapshot file (orrery's reader reads ez by name).
{ echo "input: {file: straight/snapshot_0004.hdf5}"; cat thin.yaml; } >thin-file.yaml
"$ORRERY" render thin-file.yaml -o thin-file -q 2>thin-file.err && [ -s thin-file/f.fits ] ||
  fail "populations by ez from a snapshot: $(cat thin-file.err)"

# scripts/model_ez.py on the run (docs/model.md, "Vertical energy ez"): a
# snapshot against itself gives the start's thickness of the selected stars;
# over 16 Myr the carried ez still sorts the stars (its correlation with ez
# recomputed from v_z and z is 0.65 with these 810 disc stars; 0.80 at the
# start, the bins' sigma_z being noisy); snapshots of other stars are refused.
ez=$("$py" "$SRC/scripts/model_ez.py" straight/snapshot_0000.hdf5 straight/snapshot_0000.hdf5 straight/snapshot_0004.hdf5) ||
  fail "model_ez.py on snapshots: $ez"
thin0=$(echo "$ez" | sed -n 's/^logistic v0 0.7 dv 0.25: keeps [0-9.]*, mean |z| \([0-9.]*\) kpc.*/\1/p')
thin_same=$(echo "$ez" | sed -n 's/^straight\/snapshot_0000.hdf5: mean |z| .*v0 0.7 dv 0.25: \([0-9.]*\) .*/\1/p')
corr=$(echo "$ez" | sed -n 's/^straight\/snapshot_0004.hdf5: .*carried ez against recomputed: correlation \([0-9.]*\).*/\1/p')
[ -n "$thin0" ] && [ "$thin0" = "$thin_same" ] && awk -v c="$corr" 'BEGIN { exit !(c > 0.5 && c < 1) }' ||
  fail "model_ez.py on snapshots ($thin0, $thin_same, $corr): $ez"
"$py" "$SRC/scripts/model_ez.py" straight/snapshot_0000.hdf5 framed/snapshot_0001.hdf5 >/dev/null 2>err.txt &&
  fail "model_ez.py compared other stars"
grep -q "hold other disc stars or other ez" err.txt || fail "model_ez.py, other stars: $(cat err.txt)"

# Killed (SIGKILL) while writing a snapshot every step: every snapshot under
# its final name is complete, the run resumes from the newest, and the
# resumed run's snapshots are the bytes of an uninterrupted run's.
"$NBODY" --galaxies mw --particles 3000 --dt 0.001 --steps 100000 --snapshot-every 1 --snapshot-dir killed \
  --quiet >killed.log 2>&1 &
pid=$!
for _ in $(seq 300); do [ -e killed/snapshot_0003.hdf5 ] && break; sleep 0.1; done
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
[ -e killed/snapshot_0003.hdf5 ] || fail "the run to kill wrote no snapshots: $(cat killed.log)"
for f in killed/snapshot_*.hdf5; do
  "$ORRERY" info "$f" >/dev/null 2>&1 || fail "$f is not a complete snapshot"
done
last=$(ls killed | grep -c '^snapshot_')
"$NBODY" --resume killed --steps $((last + 1)) >resumed.log 2>&1 || fail "resume after kill: $(tail -3 resumed.log)"
grep -q "^resumed at step $((last - 1))," resumed.log || fail "resumed where: $(head -3 resumed.log)"
[ -e "killed/snapshot_$(printf %04d $((last + 1))).hdf5" ] || fail "no snapshot after the resume: $(ls killed)"
! ls -A killed | grep -q orrery-tmp || fail "temporary files left: $(ls -A killed)"
"$NBODY" --galaxies mw --particles 3000 --dt 0.001 --steps $((last + 1)) --snapshot-every 1 --snapshot-dir whole \
  --quiet >whole.log 2>&1 || fail "uninterrupted run: $(tail -3 whole.log)"
[ "$(ls killed)" = "$(ls whole)" ] || fail "snapshots of the killed and resumed run: $(ls killed) / $(ls whole)"
for f in whole/snapshot_*.hdf5; do
  cmp -s "$f" "killed/${f#whole/}" || fail "killed and resumed: ${f#whole/} differs from the uninterrupted run's"
done

# Initial conditions that cannot be evolved: an error naming the file, the
# particle and its field, exit 1, before any step.
for bad in "Velocities 5 1 nan" "Coordinates 7 2 inf"; do
  set -- $bad
  rm -rf badic && mkdir badic && cp straight/snapshot_0000.hdf5 badic/ic.hdf5
  "$py" - "$@" <<'PY'
import sys, h5py, numpy as np
name, row, col, value = sys.argv[1], int(sys.argv[2]), sys.argv[3], float(sys.argv[4])
with h5py.File("badic/ic.hdf5", "r+") as f:
    d = f[f"PartType2/{name}"]
    a = d[:]
    if col == "-": a[row] = value
    else: a[row, int(col)] = value
    d[...] = a
    print(f["PartType2/ParticleIDs"][row], file=open("badic/id", "w"))
PY
  id=$(cat badic/id)
  field=$([ $1 = Velocities ] && echo "velocity y = nan" || echo "position z = inf")
  got=0
  "$NBODY" --ic badic/ic.hdf5 --steps 1 --snapshot-every 1 --snapshot-dir badic/out >out.txt 2>err.txt || got=$?
  [ $got -eq 1 ] || fail "initial conditions with $bad: exit $got"
  grep -q "^orrery-nbody: badic/ic.hdf5: particle id $id (type 2): $field: cannot evolve it" err.txt ||
    fail "initial conditions with $bad: $(cat err.txt)"
  [ ! -e badic/out/snapshot_0000.hdf5 ] || fail "initial conditions with $bad: a snapshot was written"
done

# Bad options and folders: an error naming them, before any step.
expect_nbody_error() { # CODE PATTERN ARGS... (a small model unless resumed)
  local code=$1 pattern=$2 got=0 model=(--galaxies mw --particles 1000)
  shift 2
  case " $* " in *" --resume "*) model=() ;; esac
  "$NBODY" "${model[@]}" --steps 1 "$@" >out.txt 2>err.txt || got=$?
  [ "$got" -eq "$code" ] || fail "orrery-nbody $* exited $got, expected $code"
  grep -q -- "$pattern" err.txt || fail "orrery-nbody $*: stderr does not say '$pattern': $(cat err.txt)"
  ! grep -q "^report\|^step" out.txt || fail "orrery-nbody $* ran anyway"
}
touch a-file
expect_nbody_error 1 "--snapshot-dir a-file/snaps: .*a-file/snaps: cannot access it: Not a directory" --snapshot-every 1 --snapshot-dir a-file/snaps
expect_nbody_error 1 "--snapshot-dir a-file: .*not a directory" --snapshot-every 1 --snapshot-dir a-file
expect_nbody_error 2 "--snapshot-every 0: expected a whole number of steps" --snapshot-every 0 --snapshot-dir s
expect_nbody_error 2 "--snapshot-every often: expected a whole number of steps" --snapshot-every often --snapshot-dir s
expect_nbody_error 2 "--snapshot-every needs --snapshot-dir" --snapshot-every 2
expect_nbody_error 2 "--resume half: .*not with --ic" --resume half --ic model
# The model's options change nothing of a file's or a resumed run's particles.
expect_nbody_error 2 "--galaxies shapes the built-in model: not with --ic half/snapshot_0002.hdf5" \
  --ic half/snapshot_0002.hdf5
expect_nbody_error 2 "--m31-weight shapes the built-in model: not with --resume half" --resume half --m31-weight 4
mkdir empty
expect_nbody_error 1 "--resume empty: empty: holds no snapshot_NNNN.hdf5" --resume empty
expect_nbody_error 1 "--resume missing: missing: cannot read the folder" --resume missing
mkdir foreign
"$py" -c "
import h5py
f = h5py.File('foreign/snapshot_0000.hdf5', 'w')
f.create_group('Header').attrs['NumPart_ThisFile'] = [0, 1, 0, 0, 0, 0]
f['Header'].attrs['Time'] = 0.0"
expect_nbody_error 1 "not a snapshot orrery-nbody wrote" --resume foreign

# On MPI ranks (orrery-nbody-mpi): rank 0 writes the snapshots gathered
# from both, equal dataset for dataset to the serial run's (the forces do
# not depend on the number of ranks); two ranks resume the serial run's
# snapshot 2 to the same datasets, and their own run to the same bytes.
MPI_NBODY=$(dirname "$ORRERY")/examples/orrery-nbody-mpi
if [ -x "$MPI_NBODY" ] && command -v mpirun >/dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0" # OpenMPI's own start-up allocations
  mpi() { OMP_NUM_THREADS=1 mpirun -np 2 "$MPI_NBODY" "$@"; }
  mpi $run --steps 8 --snapshot-every 2 --snapshot-dir mpi >mpi.log 2>&1 || fail "MPI run: $(tail -5 mpi.log)"
  mpi $run --steps 4 --snapshot-every 2 --snapshot-dir mpihalf >mpihalf.log 2>&1 || fail "MPI half: $(tail -5 mpihalf.log)"
  mpi --resume mpihalf --steps 8 >mpiresume.log 2>&1 || fail "MPI resume: $(tail -5 mpiresume.log)"
  cmp -s mpi/snapshot_0004.hdf5 mpihalf/snapshot_0004.hdf5 || fail "MPI resumed run differs"
  mkdir fromserial
  cp half/snapshot_0000.hdf5 half/snapshot_0001.hdf5 half/snapshot_0002.hdf5 fromserial/
  mpi --resume fromserial --steps 8 >fromserial.log 2>&1 || fail "MPI resume of a serial run: $(tail -5 fromserial.log)"
  PYTHONPATH="$SRC/tests/cli" "$py" - <<'PY' || fail "MPI snapshots against the serial run's"
import h5py, numpy as np
from expect import check, done
ref = h5py.File("straight/snapshot_0004.hdf5", "r")
for path in ("mpi/snapshot_0004.hdf5", "fromserial/snapshot_0004.hdf5"):
    f = h5py.File(path, "r")
    check(f["Header"].attrs["Time"] == ref["Header"].attrs["Time"], f"{path}: time")
    for t in range(1, 6):
        for name in ref[f"PartType{t}"]:
            check(np.array_equal(f[f"PartType{t}/{name}"][:], ref[f"PartType{t}/{name}"][:]),
                  f"{path}: PartType{t}/{name} differs from the serial run's")
done()
PY
fi
finish
