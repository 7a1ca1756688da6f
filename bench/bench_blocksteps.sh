#!/bin/bash
# orrery-nbody's block (hierarchical) time steps against its global step,
# side by side in one run (docs/nbody.md, "Block (individual) time steps").
#
#   bench/bench_blocksteps.sh [BUILD]        # BUILD: the build folder (default build)
#   N=200000 BLOCKS="0.008:0.25 0.016:0.2:0.002" TIME=0.208 bench/bench_blocksteps.sh
#
# The isolated Milky Way of N particles (default 20000) at the films'
# settings (softening EPS = 0.2 kpc, the halo's twice it), evolved for TIME
# time units (default 0.2, 196 Myr) once with the global step GLOBAL_DT
# (default 0.002, the films') and once for each DT:ETA[:DTMIN] of BLOCKS
# (block steps of at most DT chosen by sqrt(2 ETA eps / |a|), none shorter
# than DTMIN when given: --dt-min). For each run: the
# CPU seconds (user + system, bash's `time`), the particle forces, the
# largest and the last |dE/E0| of reports every REPORT time units (default
# 0.016), the disc's rms height and the bulge's half-mass radius at the
# end, and the block run's CPU over the global run's. One thread
# (OMP_NUM_THREADS=1, per-core figures); the machine may be shared, so
# CPU seconds are the figure to trust.
set -eu
build=${1:-build}
nbody="$build/examples/orrery-nbody"
[ -x "$nbody" ] || { echo "bench_blocksteps: no $nbody (build first: scripts/build.sh $build)" >&2; exit 1; }
N=${N:-20000} TIME=${TIME:-0.2} EPS=${EPS:-0.2} GLOBAL_DT=${GLOBAL_DT:-0.002} REPORT=${REPORT:-0.016}
BLOCKS=${BLOCKS:-"0.008:0.2 0.008:0.2:0.002 0.008:0.3"}
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# steps DT: how many steps of DT make TIME (a whole number, else an error).
steps() {
  awk -v t="$TIME" -v dt="$1" 'BEGIN { n = t / dt; r = int(n + 0.5); if (r < 1 || (n - r) * (n - r) > 1e-12) exit 1; print r }' ||
    { echo "bench_blocksteps: TIME $TIME is not a whole number of steps of $1" >&2; exit 1; }
}

# run NAME DT [--eta ETA]: one run, its figures in NAME.log and NAME.cpu.
run() {
  local name=$1 dt=$2
  shift 2
  local n every
  n=$(steps "$dt")
  every=$(awk -v r="$REPORT" -v dt="$dt" 'BEGIN { e = int(r / dt + 0.5); print e < 1 ? 1 : e }')
  local TIMEFORMAT='%U %S'
  { time "$nbody" --galaxies mw --particles "$N" --eps "$EPS" --dt "$dt" --steps "$n" --report-every "$every" \
      --progress 0 "$@" >"$work/$name.log" 2>&1; } 2>"$work/$name.time" ||
    { echo "bench_blocksteps: $name failed: $(tail -3 "$work/$name.log")" >&2; exit 1; }
  awk '{ print $1 + $2 }' "$work/$name.time" >"$work/$name.cpu"
}

# row NAME LABEL [GLOBAL_CPU]: the figures of one run.
row() {
  awk -v label="$2" -v cpu="$(cat "$work/$1.cpu")" -v base="${3:-}" -v n="$N" -v t="$TIME" -v dt="$GLOBAL_DT" '
    /^report/ {
      for (i = 1; i <= NF; i++) {
        if ($i == "dE/|E0|") { d = $(i + 2) + 0; last = d < 0 ? -d : d; if (last > most) most = last }
        if ($i == "z_rms(3-10") z = $(i + 3)
        if ($i == "r_half" && $(i - 1) == "bulge") r = $(i + 2)
      }
    }
    /^block steps:/ { forces = $6 }
    END {
      if (forces == "") forces = sprintf("%.4g", n * t / dt)
      printf "%-38s %8.2f %11s %12.2e %12.2e %8s %8s %8s\n", label, cpu, forces, most, last, z, r,
             base == "" ? "1" : sprintf("%.2f", cpu / base)
    }' "$work/$1.log"
}

echo "isolated Milky Way, $N particles, eps $EPS, $TIME time units, one thread"
printf "%-38s %8s %11s %12s %12s %8s %8s %8s\n" run "CPU s" forces "max|dE/E0|" "end|dE/E0|" z_rms r_bulge "/global"
run global "$GLOBAL_DT"
row global "global dt = $GLOBAL_DT"
base=$(cat "$work/global.cpu")
for b in $BLOCKS; do
  IFS=: read -r dt eta dtmin <<<"$b"
  name="block_${dt}_${eta}_${dtmin}" label="block ${dtmin:+$dtmin <= }dt <= $dt eta = $eta"
  run "$name" "$dt" --eta "$eta" ${dtmin:+--dt-min "$dtmin"}
  row "$name" "$label" "$base"
done
