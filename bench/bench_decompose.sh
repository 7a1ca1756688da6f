#!/bin/bash
# orrery-nbody-mpi's memory per rank before and after the domain
# decomposition (--decompose), side by side in one run (docs/nbody.md,
# "Domain decomposition: --decompose").
#
#   bench/bench_decompose.sh [BUILD]          # BUILD: the build folder (default build)
#   N=200000 STEPS=4 RANKS="2 4" bench/bench_decompose.sh
#
# Builds the engine of BASE (default 88f476d, before the decomposition)
# from `git archive` in a temporary folder, then runs the isolated Milky
# Way of N particles (default 10^6) at the films' settings (eps 0.2, dt
# 0.002) for STEPS steps (default 2) on 1 rank and on each count of RANKS
# (default 4; oversubscribed on fewer cores): BASE's program, and this
# build's without and with --decompose. For each run: the largest peak
# resident memory of a rank (/usr/bin/time's maximum RSS, MB), its share
# of BASE's one-rank run, the wall seconds, and the last report's energy
# and the Sun's position (--decompose) to compare rank counts. One thread a
# rank.
set -eu
build=${1:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
after="$build/examples/orrery-nbody-mpi"
[ -x "$after" ] || { echo "bench_decompose: no $after (build first, with MPI: scripts/build.sh $build)" >&2; exit 1; }
N=${N:-1000000} STEPS=${STEPS:-2} RANKS=${RANKS:-4} BASE=${BASE:-88f476d}
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "building $BASE's orrery-nbody-mpi in $work/base ..." >&2
mkdir -p "$work/src"
git -C "$here" archive "$BASE" | tar -x -C "$work/src"
cmake -S "$work/src" -B "$work/base" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$work/base" --target orrery_nbody_mpi -j "$(nproc)" -- --no-print-directory >/dev/null
before="$work/base/examples/orrery-nbody-mpi"

# run NAME NP PROGRAM [OPTIONS]: one run; each rank's peak RSS in NAME.rss.
run() {
  local name=$1 np=$2 prog=$3
  shift 3
  local start=$SECONDS
  mpirun -np "$np" bash -c "/usr/bin/time -f 'rss %M' -a -o '$work/$name.rss' \"\$@\"" _ "$prog" \
    --galaxies mw --particles "$N" --eps 0.2 --dt 0.002 --steps "$STEPS" --report-every "$STEPS" --progress 0 "$@" \
    >"$work/$name.log" 2>&1 || { echo "bench_decompose: $name failed: $(tail -3 "$work/$name.log")" >&2; exit 1; }
  echo $((SECONDS - start)) >"$work/$name.wall"
}

# row NAME LABEL: the figures of one run.
row() {
  local rss wall
  rss=$(awk '/^rss/ { if ($2 > m) m = $2 } END { printf "%.1f", m / 1024 }' "$work/$1.rss")
  wall=$(cat "$work/$1.wall")
  awk -v label="$2" -v rss="$rss" -v base="$base_rss" -v wall="$wall" '
    /^report/ { line = $0 }
    END {
      match(line, /E = [^ ]+/); e = substr(line, RSTART + 4, RLENGTH - 4)
      sun = "-"; if (match(line, /Sun at \([^)]*\)/)) sun = substr(line, RSTART + 7, RLENGTH - 7)
      printf "%-34s %9s %7.3f %6s  %-14s %s\n", label, rss, rss / base, wall, e, sun
    }' "$work/$1.log"
}

run before1 1 "$before"
base_rss=$(awk '/^rss/ { if ($2 > m) m = $2 } END { printf "%.1f", m / 1024 }' "$work/before1.rss")
run after1 1 "$after" --decompose
for np in $RANKS; do
  run "before$np" "$np" "$before"
  run "plain$np" "$np" "$after"
  run "after$np" "$np" "$after" --decompose
done
echo "isolated Milky Way, $N particles, $STEPS steps of 0.002, eps 0.2, 1 thread a rank"
printf "%-34s %9s %7s %6s  %-14s %s\n" "run" "rank MB" "/ base" "wall s" "E (last)" "Sun at (--decompose)"
row before1 "$BASE, 1 rank"
row after1 "--decompose, 1 rank"
for np in $RANKS; do
  row "before$np" "$BASE, $np ranks"
  row "plain$np" "this build, $np ranks"
  row "after$np" "--decompose, $np ranks"
  grep '^domains' "$work/after$np.log" | sed 's/^/    /'
done
