# orrery-nbody's block time steps (--eta, docs/nbody.md). With every
# particle on the longest step they are the global leapfrog bit for bit; on
# a 5000-particle Milky Way over 0.1 time units, steps of up to 0.004 chosen
# by sqrt(2 eta eps / |a|) (eta = 0.2) conserve energy better than one
# global step of 0.001 while computing fewer particle forces (measured:
# largest |dE/E0| 9.9e-4 against 5.1e-3, 3.9e5 forces against 5.0e5); a run
# in block steps resumes bit for bit, owing it to each particle's step kept
# in the snapshot, also on two MPI ranks; --dt-min bounds the steps from
# below and is kept too, and tracers take it; bad --eta and --dt-min
# values are errors naming them.
source "$(dirname "$0")/lib.sh"
[ -x "$NBODY" ] || { fail "no $NBODY"; finish; }
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
mw="--galaxies mw --particles 5000"

# A huge eta puts every particle on --dt: the global step exactly.
"$NBODY" $mw --steps 3 --dt 0.002 --snapshot-every 3 --snapshot-dir global >global.log 2>&1 || fail "global: $(tail -3 global.log)"
"$NBODY" $mw --steps 3 --dt 0.002 --eta 1e9 --snapshot-every 3 --snapshot-dir one >one.log 2>&1 || fail "eta 1e9: $(tail -3 one.log)"
grep -q "^block steps: 3 force computations, 1.5e+04 particle forces" one.log || fail "eta 1e9 steps: $(grep ^block one.log)"

# Energy at less cost: the largest |dE/E0| of the reports, and the forces.
"$NBODY" $mw --steps 100 --dt 0.001 --report-every 2 >fixed.log 2>&1 || fail "fixed: $(tail -3 fixed.log)"
"$NBODY" $mw --steps 25 --dt 0.004 --eta 0.2 --report-every 1 --snapshot-every 5 --snapshot-dir block >block.log 2>&1 ||
  fail "block: $(tail -3 block.log)"
max_de() {
  awk '/^report/ { for (i = 1; i <= NF; i++) if ($i == "dE/|E0|") { d = $(i + 2) + 0; if (d < 0) d = -d; if (d > m) m = d } }
    END { print m }' "$1"
}
fixed_de=$(max_de fixed.log) block_de=$(max_de block.log)
forces=$(awk '/^block steps:/ { print $6 }' block.log)
echo "largest |dE/E0|: fixed step 0.001 $fixed_de, block steps $block_de ($forces particle forces against 500000)"
awk -v f="$fixed_de" -v b="$block_de" -v n="$forces" 'BEGIN { exit !(b > 0 && b < 0.75 * f && n > 0 && n < 500000) }' ||
  fail "block steps: |dE/E0| $block_de vs $fixed_de, forces $forces vs 500000"
grep -q "^report t = 0.1000" block.log || fail "block run did not reach t = 0.1: $(grep ^report block.log | tail -1)"

# Resumed in block steps: the same bytes (eta and dt from the snapshot).
mkdir half
cp block/snapshot_0000.hdf5 block/snapshot_0001.hdf5 block/snapshot_0002.hdf5 half/
"$NBODY" --resume half --steps 25 >resume.log 2>&1 || fail "resume: $(tail -3 resume.log)"
grep -q "^resumed at step 10," resume.log || fail "resume: $(head -3 resume.log)"
cmp -s block/snapshot_0005.hdf5 half/snapshot_0005.hdf5 || fail "a resumed block-step run differs"

# The resume owes that to each particle's step, kept in the snapshot (a
# step lengthens only with room to spare, so it depends on the last one):
# the levels span a range, and without them the resume differs.
mkdir nolevels
cp block/snapshot_0000.hdf5 block/snapshot_0001.hdf5 block/snapshot_0002.hdf5 nolevels/
"$py" - <<'PY' || fail "step levels in the snapshot"
import h5py, numpy as np
with h5py.File("nolevels/snapshot_0002.hdf5", "r+") as f:
    groups = [g for g in f if g.startswith("PartType") and len(f[g]["ParticleIDs"])]
    levels = np.concatenate([f[g]["OrreryNbodyStepLevel"][:] for g in groups])
    for g in groups:
        del f[g]["OrreryNbodyStepLevel"]
print("levels", np.bincount(levels))
raise SystemExit(not (levels.min() >= 0 and levels.max() <= 10 and levels.max() - levels.min() >= 2))
PY
"$NBODY" --resume nolevels --steps 15 >nolevels.log 2>&1 || fail "resume without levels: $(tail -3 nolevels.log)"
! cmp -s block/snapshot_0003.hdf5 nolevels/snapshot_0003.hdf5 || fail "the step levels made no difference"

# --dt-min: no step shorter (here 0.002 of dt 0.004: levels 0 and 1 only,
# where the run above went down to level 4); kept in the snapshot, so a
# resume takes it and gives the same bytes.
"$NBODY" $mw --steps 4 --dt 0.004 --eta 0.2 --dt-min 0.002 --snapshot-every 2 --snapshot-dir dtmin >dtmin.log 2>&1 ||
  fail "--dt-min: $(tail -3 dtmin.log)"
mkdir dtminhalf
cp dtmin/snapshot_0000.hdf5 dtmin/snapshot_0001.hdf5 dtminhalf/
"$NBODY" --resume dtminhalf --steps 4 >dtminhalf.log 2>&1 || fail "--dt-min resume: $(tail -3 dtminhalf.log)"
cmp -s dtmin/snapshot_0002.hdf5 dtminhalf/snapshot_0002.hdf5 || fail "a resumed --dt-min run differs"
"$py" - <<'PY' || fail "--dt-min levels"
import h5py, numpy as np
f = h5py.File("dtmin/snapshot_0002.hdf5", "r")
levels = np.concatenate([f[g]["OrreryNbodyStepLevel"][:] for g in f if g.startswith("PartType") and len(f[g]["ParticleIDs"])])
print("levels with --dt-min", np.bincount(levels), "DtMin", f["OrreryNbody"].attrs["DtMin"])
raise SystemExit(not (levels.max() == 1 and f["OrreryNbody"].attrs["DtMin"] == 0.002))
PY

# A tracer (the model's Sun, id 3) takes the shortest step --dt-min allows,
# whatever the criterion wants of it: with steps of up to 0.008 and at
# least 0.002, level 2, where its own softening, the local spacing, would
# give it a longer one (docs/nbody.md, "Tracers on the shortest step").
# Without --dt-min it follows the criterion as any particle.
for run in "tracer --dt-min 0.002" "tracerfree"; do
  set -- $run
  "$NBODY" $mw --steps 2 --dt 0.008 --eta 0.2 --tracer-ring 8 "${@:2}" --snapshot-every 1 --snapshot-dir "$1" >"$1.log" 2>&1 ||
    fail "$1: $(tail -3 "$1.log")"
done
"$py" - <<'PY' || fail "the tracer's step"
import h5py, numpy as np
def sun_level(path):
    f = h5py.File(path, "r")
    ids, levels = f["PartType4/ParticleIDs"][:], f["PartType4/OrreryNbodyStepLevel"][:]
    others = np.concatenate([f[g]["OrreryNbodyStepLevel"][:] for g in f if g.startswith("PartType") and g != "PartType4" and len(f[g]["ParticleIDs"])])
    return int(levels[ids == 3][0]), np.bincount(others, minlength=3)
pinned, others = sun_level("tracer/snapshot_0001.hdf5")
free, _ = sun_level("tracerfree/snapshot_0001.hdf5")
print("the Sun's level with --dt-min", pinned, "without", free, "the others'", others)
raise SystemExit(not (pinned == 2 and free < 2 and others[:2].sum() > 0))
PY

# A level no run writes (steps are dt / 2^k, k <= 10): an error naming it.
mkdir badlevel
cp block/snapshot_0002.hdf5 badlevel/
"$py" -c "
import h5py
with h5py.File('badlevel/snapshot_0002.hdf5', 'r+') as f:
    f['PartType2/OrreryNbodyStepLevel'][3] = 11
    print(f['PartType2/ParticleIDs'][3])" >badid.txt || fail "h5py could not edit the level"
got=0
"$NBODY" --resume badlevel --steps 15 >badlevel.log 2>&1 || got=$?
[ $got -eq 1 ] && grep -q "badlevel/snapshot_0002.hdf5: particle id $(cat badid.txt): OrreryNbodyStepLevel = 11: a block step's level is at most 10" badlevel.log &&
  [ ! -e badlevel/snapshot_0003.hdf5 ] || fail "level 11: exit $got: $(cat badlevel.log)"

"$py" - <<'PY' || fail "eta 1e9 against the global step"
import h5py, numpy as np
a, b = h5py.File("global/snapshot_0001.hdf5", "r"), h5py.File("one/snapshot_0001.hdf5", "r")
same = all(np.array_equal(a[f"PartType{t}/{n}"][:], b[f"PartType{t}/{n}"][:])
           for t in range(1, 6) for n in ("Coordinates", "Velocities"))
moved = not np.array_equal(a["PartType2/Coordinates"][:], h5py.File("global/snapshot_0000.hdf5", "r")["PartType2/Coordinates"][:])
print("" if same and moved else f"same {same}, moved {moved}")
raise SystemExit(not (same and moved))
PY

# On two MPI ranks (each resumes its share of the levels, rank 0 writes
# them gathered from both): the serial run's datasets, levels among them.
MPI_NBODY=$(dirname "$NBODY")/orrery-nbody-mpi
if [ -x "$MPI_NBODY" ] && command -v mpirun >/dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0" # OpenMPI's own start-up allocations
  mkdir mpi
  cp block/snapshot_0000.hdf5 block/snapshot_0001.hdf5 block/snapshot_0002.hdf5 mpi/
  OMP_NUM_THREADS=1 mpirun -np 2 "$MPI_NBODY" --resume mpi --steps 15 >mpi.log 2>&1 || fail "MPI resume: $(tail -5 mpi.log)"
  "$py" - <<'PY' || fail "MPI block steps against the serial run's"
import h5py, numpy as np
a, b = h5py.File("block/snapshot_0003.hdf5", "r"), h5py.File("mpi/snapshot_0003.hdf5", "r")
bad = [f"{g}/{n}" for g in a if g.startswith("PartType") for n in a[g] if not np.array_equal(a[g][n][:], b[g][n][:])]
levels = sum("OrreryNbodyStepLevel" in b[g] for g in b if g.startswith("PartType") and len(b[g]["ParticleIDs"]))
print(f"differ: {bad}" if bad else "", f"levels in {levels} groups")
raise SystemExit(bool(bad) or levels < 3)
PY
fi

for bad in 0 -1 nan 0.005; do
  got=0
  "$NBODY" $mw --steps 1 --dt 0.004 --eta 0.2 --dt-min $bad >out.txt 2>err.txt || got=$?
  [ $got -eq 2 ] && grep -q -- "--dt-min $bad: the shortest block step must be above 0 and at most --dt 0.004" err.txt &&
    ! grep -q "^step" out.txt || fail "--dt-min $bad: exit $got: $(cat err.txt)"
done
for bad in 0 -1 nan; do
  got=0
  "$NBODY" $mw --steps 1 --eta $bad >out.txt 2>err.txt || got=$?
  [ $got -eq 2 ] && grep -q -- "--eta $bad: the time-step accuracy must be a number above 0" err.txt &&
    ! grep -q "^step" out.txt || fail "--eta $bad: exit $got: $(cat err.txt)"
done
finish
