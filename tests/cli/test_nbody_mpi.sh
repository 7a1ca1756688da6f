# The example N-body code on MPI ranks (orrery-nbody-mpi, docs/insitu.md):
# each rank owns a slice of the particles, gathers every position for the
# tree each step and renders in-situ with only its own particles. One rank
# gives the serial program's frames bit for bit; two ranks evolve the same
# particles (the forces on each are computed from the same tree) and their
# frames differ from one rank's only by the order the ranks' planes are
# summed: within 10^-5 of the image maximum per pixel over 8 steps. The
# GADGET-2 merger ICs are read as each rank's share of the file.
source "$(dirname "$0")/lib.sh"
MPI_NBODY=$(dirname "$ORRERY")/examples/orrery-nbody-mpi
need_mpi "$MPI_NBODY"

printf 'camera: {projection: orthographic, width: 1200, position: [0, 0, 3000]}\nimage: {width: 96, height: 96}\noutput: {png: false, name: nb}\n' >model.yaml
run="--particles 4000 --steps 8 --dt 0.01 --scene model.yaml"
"$NBODY" $run --set output.dir=serial >serial.log 2>&1 || fail "serial: $(tail -3 serial.log)"
for np in 1 2; do
  mpirun -np $np "$MPI_NBODY" $run --set output.dir=np$np >np$np.log 2>&1 || fail "-np $np: $(tail -5 np$np.log)"
done
grep -q "^4000 bodies from model on 2 processes" np2.log || fail "np 2 report: $(head -3 np2.log)"

ic="${ORRERY_SHARED_DATA:-}/gadget2/gadget2_examples/galaxy_littleendian.dat"
merger=0
if [ -f "$ic" ]; then
  merger=1
  printf 'camera: {projection: orthographic, width: 400, position: [0, 0, 1000]}\nimage: {width: 64, height: 64}\noutput: {png: false, name: nb}\n' >merger.yaml
  for np in 1 2; do
    mpirun -np $np "$MPI_NBODY" --ic "$ic" --steps 2 --dt 0.01 --eps 1 --theta 1.0 --scene merger.yaml \
      --set output.dir=merger$np >merger$np.log 2>&1 || fail "merger -np $np: $(tail -5 merger$np.log)"
  done
fi

"$py" - "$merger" <<'PY' || fail "frames differ between rank counts"
import sys
import numpy as np
from astropy.io import fits
bad = 0
def load(path):
    h = fits.open(path)[0]
    return h.data.astype(float), h.header["NPART"]
def compare(ref_dir, dir_, frames, exact):
    global bad
    for f in range(frames):
        x, nx = load(f"{ref_dir}/nb_{f:04d}.fits")
        y, ny = load(f"{dir_}/nb_{f:04d}.fits")
        diff = np.abs(x - y).max()
        if (exact and diff != 0) or diff > 1e-5 * x.max() or nx != ny or x.max() <= 0:
            print(f"{dir_} frame {f}: max diff {diff} of {x.max()}, NPART {ny} vs {nx}"); bad += 1
compare("serial", "np1", 9, True)
compare("np1", "np2", 9, False)
# The particles moved: the last frame is not the first.
if np.array_equal(load("np2/nb_0000.fits")[0], load("np2/nb_0008.fits")[0]):
    print("the particles did not move"); bad += 1
if sys.argv[1] == "1":
    compare("merger1", "merger2", 3, False)
raise SystemExit(bad)
PY

# Ranks that disagree on the run stop, every one, with one message from
# rank 0 (exit 2): a different command line (checked before it is parsed:
# a rank whose options are refused does not leave the others waiting), and
# the same command reading a different scene or initial-conditions file
# (each rank in its own folder, as on nodes with their own copies).
disagree() { # EXPECTED_MESSAGE -- mpirun's arguments
  local want=$1 n
  shift 2
  timeout 120 mpirun "$@" >dis.log 2>&1
  local rc=$?
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "ranks disagreeing on $want: exit $rc: $(tail -5 dis.log)"
  n=$(grep -c "orrery-nbody: rank 1's $want differs from rank 0's: every rank must run the same command" dis.log)
  [ "$n" = 1 ] || fail "ranks disagreeing on $want: $n messages: $(grep orrery-nbody dis.log)"
}
small="--particles 2000 --steps 2 --dt 0.01 --quiet"
disagree "command line" -- -np 1 "$MPI_NBODY" $small : -np 1 "$MPI_NBODY" $small --eps 0.1
disagree "command line" -- -np 1 "$MPI_NBODY" $small : -np 1 "$MPI_NBODY" $small --no-such-option 1
mkdir -p rank0 rank1
sed 's/width: 1200/width: 1100/' model.yaml >rank1/s.yaml
cp model.yaml rank0/s.yaml
disagree "scene file s.yaml" -- -np 1 -wdir rank0 "$MPI_NBODY" $small --scene s.yaml : \
  -np 1 -wdir rank1 "$MPI_NBODY" $small --scene s.yaml
for k in 1 2; do # two snapshots of 300 particles, one step of different lengths apart
  "$NBODY" --particles 300 --steps 1 --dt 0.0$k --snapshot-every 1 --snapshot-dir snap$k --quiet >/dev/null \
    || fail "snapshots for the initial conditions"
done
cp snap1/snapshot_0001.hdf5 rank0/ic.hdf5
cp snap2/snapshot_0001.hdf5 rank1/ic.hdf5
disagree "initial conditions ic.hdf5" -- -np 1 -wdir rank0 "$MPI_NBODY" --ic ic.hdf5 --steps 1 --dt 0.01 --quiet : \
  -np 1 -wdir rank1 "$MPI_NBODY" --ic ic.hdf5 --steps 1 --dt 0.01 --quiet
# ... and the same files on both: the run goes on.
cp rank0/ic.hdf5 rank1/ic.hdf5
timeout 120 mpirun -np 1 -wdir rank0 "$MPI_NBODY" --ic ic.hdf5 --steps 1 --dt 0.01 --quiet : \
  -np 1 -wdir rank1 "$MPI_NBODY" --ic ic.hdf5 --steps 1 --dt 0.01 --quiet >agree.log 2>&1 \
  || fail "ranks agreeing, each in its own folder: $(tail -5 agree.log)"

# --tracer-start circular (the default with --tracer-ring) on two ranks, the
# Sun owned by one and the sums over both, and with --decompose: the Sun
# starts at the circular speed of a direct sum over snapshot 0
# (tests/cli/ring_start.py, h5py), all of it along the circle; decomposed,
# with the ring mirrored (--tracer-mirror, ring_start.py --mirror).
for mode in gathered decompose; do
  flag=$([ $mode = decompose ] && echo --decompose --tracer-mirror || true)
  mirror=$([ $mode = decompose ] && echo --mirror || true)
  mpirun -np 2 "$MPI_NBODY" --galaxies mw --particles 4000 --steps 0 --tracer-ring 16 $flag --snapshot-every 1 \
    --snapshot-dir start-$mode >start-$mode.log 2>&1 || fail "--tracer-start on 2 ranks, $mode: $(tail -5 start-$mode.log)"
  grep -q "^tracer 0 started on its ring's circular orbit" start-$mode.log || fail "$mode: $(cat start-$mode.log)"
  read -r R _ vc vphi vR vz <<<"$("$py" "$SRC/tests/cli/ring_start.py" --points 16 $mirror start-$mode/snapshot_0000*.hdf5)" ||
    fail "ring_start.py on start-$mode"
  awk -v vc="$vc" -v vphi="$vphi" -v vR="$vR" -v vz="$vz" 'function abs(x) { return x < 0 ? -x : x }
    BEGIN { exit !(vc > 150 && abs(abs(vphi) - vc) < 1e-6 * vc && abs(vR) < 1e-6 && abs(vz) < 1e-6) }' ||
    fail "2 ranks, $mode: the Sun started at v_phi $vphi (v_R $vR, v_z $vz), the direct sum's v_c $vc"
done

# A rank killed mid-run (SIGKILL to rank 1, not the one that writes): the
# other stops too (mpirun ends the job, non-zero, well within the timeout),
# every snapshot under its final name is complete, and two ranks resume
# from the newest and go on.
timeout 120 mpirun -np 2 "$MPI_NBODY" --galaxies mw --particles 3000 --dt 0.001 --steps 100000 --snapshot-every 1 \
  --snapshot-dir mkilled --quiet >mkilled.log 2>&1 &
job=$!
for _ in $(seq 600); do [ -e mkilled/snapshot_0003.hdf5 ] && break; sleep 0.1; done
victim=$(rank_pid "orrery-nbody-mpi --galaxies mw --particles 3000" 1)
[ -n "$victim" ] || fail "no rank 1 to kill: $(cat mkilled.log)"
kill -KILL "$victim"
rc=0
wait $job || rc=$?
[ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "rank 1 killed: mpirun exit $rc (124: the other rank went on)"
[ -e mkilled/snapshot_0003.hdf5 ] || fail "the run to kill wrote no snapshots: $(cat mkilled.log)"
for f in mkilled/snapshot_*.hdf5; do
  "$ORRERY" info "$f" >/dev/null 2>&1 || fail "$f is not a complete snapshot"
done
last=$(ls mkilled | grep -c '^snapshot_')
timeout 120 mpirun -np 2 "$MPI_NBODY" --resume mkilled --steps $((last + 1)) --quiet >mresumed.log 2>&1 \
  || fail "two ranks resuming after the kill: $(tail -5 mresumed.log)"
[ -e "mkilled/snapshot_$(printf %04d $((last + 1))).hdf5" ] || fail "no snapshot after the resume: $(ls mkilled)"
! ls -A mkilled | grep -q orrery-tmp || fail "temporary files left: $(ls -A mkilled)"
finish
