# orrery-nbody-mpi --decompose (docs/nbody.md, "Domain decomposition: --decompose"):
# each rank holds only its own particles, a piece of a Peano-Hilbert curve,
# and writes them as its own file of each snapshot.
# - Each rank's file holds a third of the particles on 3 ranks, the files'
#   ids are disjoint and together every particle (h5py).
# - The same snapshots, byte for byte, on 1 and 2 threads; and after a
#   resume (2 ranks, 2 + 2 steps against 4 straight).
# - Across 1, 2 and 3 ranks (the trees differ): energy within 1e-4 of |E|
#   and the Sun within 0.02 kpc of one rank's after 10 steps.
# - A resume on 3 ranks from a set of 2 files, and from a set missing a
#   file (the newest complete set is taken); a rank killed mid-run stops
#   the run, every complete set reads, the run resumes.
source "$(dirname "$0")/lib.sh"
MPI_NBODY=$(dirname "$ORRERY")/examples/orrery-nbody-mpi
need_mpi "$MPI_NBODY"

run="--galaxies mw --particles 3000 --dt 0.002 --eps 0.2 --progress 0 --decompose"
mrun() { # NP LOG -- arguments
  local np=$1 log=$2
  shift 3
  timeout 120 mpirun -np "$np" "$MPI_NBODY" "$@" >"$log" 2>&1 || fail "$np ranks ($log): $(tail -5 "$log")"
}
for np in 1 2 3; do
  OMP_NUM_THREADS=1 mrun $np np$np.log -- $run --steps 10 --report-every 10 --snapshot-every 5 --snapshot-dir s$np
done
OMP_NUM_THREADS=2 mrun 2 threads2.log -- $run --steps 10 --report-every 10 --snapshot-every 5 --snapshot-dir t2
grep -q "^domains: 3 ranks hold 1000-1000 particles each of 3000" np3.log || fail "3 ranks' shares: $(grep domains np3.log)"
for f in s2/*; do
  cmp -s "$f" "t2/${f#s2/}" || fail "$f differs between 1 and 2 threads"
done
[ "$(ls s2 | wc -l)" = 6 ] && [ -e s1/snapshot_0002.hdf5 ] && [ -e s3/snapshot_0002.2.hdf5 ] \
  || fail "snapshot files: $(ls s1 s2 s3)"

# Resumed: 5 steps, then 5 more from the set of step 5, the same bytes.
OMP_NUM_THREADS=1 mrun 2 half.log -- $run --steps 5 --report-every 5 --snapshot-every 5 --snapshot-dir r2
OMP_NUM_THREADS=1 mrun 2 resumed.log -- --resume r2 --steps 10 --decompose --progress 0
for f in s2/snapshot_0002.*; do
  cmp -s "$f" "r2/${f#s2/}" || fail "$f differs after a resume"
done

# On 3 ranks from the 2-file set of step 5; and with a file of the newest
# set missing (as a killed run may leave it), from the set before.
mkdir -p r3 gap
cp s2/snapshot_0001.* r3/
cp s2/snapshot_0000.* s2/snapshot_0001.* gap/
rm gap/snapshot_0001.1.hdf5
OMP_NUM_THREADS=1 mrun 3 r3.log -- --resume r3 --steps 10 --decompose --progress 0
OMP_NUM_THREADS=1 mrun 3 gap.log -- --resume gap --steps 10 --decompose --progress 0
grep -q "^resumed at step 0," gap.log || fail "a set missing a file was not passed over: $(grep resumed gap.log)"
[ -e gap/snapshot_0001.1.hdf5 ] || fail "the incomplete set was not written again: $(ls gap)"

"$py" - <<'PY' || fail "the ranks' files or their results"
import re, h5py, numpy as np
bad = 0
def ids_of(path):
    with h5py.File(path, "r") as f:
        return np.concatenate([f[g]["ParticleIDs"][:] for g in f if g.startswith("PartType")])
def state(files):
    pos = {}
    for path in files:
        with h5py.File(path, "r") as f:
            for g in (g for g in f if g.startswith("PartType")):
                for i, x in zip(f[g]["ParticleIDs"][:], f[g]["Coordinates"][:]):
                    pos[int(i)] = x
    return pos
# Each of 3 ranks holds its own third, and together all.
parts = [ids_of(f"s3/snapshot_0002.{r}.hdf5") for r in range(3)]
every = np.concatenate(parts)
if [len(p) for p in parts] != [1000] * 3 or len(np.unique(every)) != 3000:
    print("3 ranks' files:", [len(p) for p in parts], len(np.unique(every))); bad += 1
# Across rank counts: the energy and the Sun (the report's last line).
def report(log):
    line = [l for l in open(log) if l.startswith("report t = 0.0200")][-1]
    E = float(re.search(r"E = (\S+)", line).group(1))
    sun = np.array([float(v) for v in re.search(r"Sun at \((\S+), (\S+), (\S+)\)", line).groups()])
    return E, sun
E1, sun1 = report("np1.log")
for log in ["np2.log", "np3.log", "r3.log", "gap.log"]:
    E, sun = report(log)
    if abs(E - E1) > 1e-4 * abs(E1) or np.abs(sun - sun1).max() > 0.02:
        print(log, "E", E, "vs", E1, "Sun", sun, "vs", sun1); bad += 1
# The rank counts' trees differ: so do the particles, a little (the test can fail).
a, b = state([f"s2/snapshot_0002.{r}.hdf5" for r in range(2)]), state(["s1/snapshot_0002.hdf5"])
d = max(np.abs(a[i] - b[i]).max() for i in b)
if not 0 < d < 0.5:
    print("2 ranks against 1: largest difference", d); bad += 1
raise SystemExit(bad)
PY

# A rank killed mid-run (SIGKILL to rank 1): the other stops too, every
# complete set reads, and two ranks resume from the newest.
timeout 120 mpirun -np 2 "$MPI_NBODY" --galaxies mw --particles 3000 --dt 0.001 --steps 100000 --snapshot-every 1 \
  --snapshot-dir killed --decompose --quiet >killed.log 2>&1 &
job=$!
for _ in $(seq 600); do [ -e killed/snapshot_0003.1.hdf5 ] && break; sleep 0.1; done
victim=$(rank_pid "orrery-nbody-mpi --galaxies mw --particles 3000 --dt 0.001 --steps 100000" 1)
[ -n "$victim" ] || fail "no rank 1 to kill: $(cat killed.log)"
kill -KILL "$victim"
rc=0
wait $job || rc=$?
[ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "rank 1 killed: mpirun exit $rc (124: the other rank went on)"
for f in killed/snapshot_*.0.hdf5; do
  [ -e "${f%.0.hdf5}.1.hdf5" ] || continue # a set the kill cut short
  "$ORRERY" info "$f" >/dev/null 2>&1 || fail "$f: not a complete set"
done
newest=$(ls killed | sed -n 's/^snapshot_\([0-9]*\)\.1\.hdf5$/\1/p' | sort -n | tail -1)
timeout 120 mpirun -np 2 "$MPI_NBODY" --resume killed --steps $((10#$newest + 1)) --decompose --quiet \
  >kresumed.log 2>&1 || fail "resuming after the kill: $(tail -5 kresumed.log)"
[ -e "killed/snapshot_$(printf %04d $((10#$newest + 1))).1.hdf5" ] || fail "no set after the resume: $(ls killed)"
! ls -A killed | grep -q orrery-tmp || fail "temporary files left: $(ls -A killed)"
finish
