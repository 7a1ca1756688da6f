#!/bin/bash
# orrery-nbody's block (hierarchical) time steps against its global step,
# side by side in one run (docs/nbody.md, "Block (individual) time steps").
#
#   bench/bench_blocksteps.sh [BUILD]        # BUILD: the build folder (default build)
#   N=200000 BLOCKS="0.008:0.25 0.016:0.2:0.002" TIME=0.208 bench/bench_blocksteps.sh
#   N=200000 GLOBAL_DTS="0.002 0.0015 0.001" BLOCKS=0.008:0.25:0.002 bench/bench_blocksteps.sh
#
# The isolated Milky Way of N particles (default 20000) at the films'
# settings (softening EPS = 0.2 kpc, the halo's twice it), evolved for TIME
# time units (default 0.2, 196 Myr) once with each global step of
# GLOBAL_DTS (default GLOBAL_DT, 0.002: the films') and once for each
# DT:ETA[:DTMIN] of BLOCKS (block steps of at most DT chosen by
# sqrt(2 ETA eps / |a|), none shorter than DTMIN when given: --dt-min).
# For each run: the CPU seconds (user + system, bash's `time`), the
# particle forces, the largest and the last |dE/E0| of reports every
# REPORT time units (default 0.016), the disc's rms height and the bulge's
# half-mass radius at the end, the model's Sun (a tracer) at the end and
# its largest |z|, and the block run's CPU over the first global run's.
# With two or more global steps, also the block run's CPU over the global
# step's at the same largest |dE/E0| (the issue's measure): the global
# runs' CPU interpolated linearly in log CPU against log error between the
# two that bracket the block run's error ("-" outside their range).
# One thread (OMP_NUM_THREADS=1, per-core figures); the machine may be
# shared, so CPU seconds are the figure to trust.
set -eu
build=${1:-build}
nbody="$build/examples/orrery-nbody"
[ -x "$nbody" ] || { echo "bench_blocksteps: no $nbody (build first: scripts/build.sh $build)" >&2; exit 1; }
N=${N:-20000} TIME=${TIME:-0.2} EPS=${EPS:-0.2} REPORT=${REPORT:-0.016}
GLOBAL_DTS=${GLOBAL_DTS:-${GLOBAL_DT:-0.002}}
BLOCKS=${BLOCKS:-"0.008:0.2 0.008:0.2:0.002 0.008:0.3"}
export OMP_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# steps DT: how many steps of DT make TIME (a whole number, else an error).
steps() {
  awk -v t="$TIME" -v dt="$1" 'BEGIN { n = t / dt; r = int(n + 0.5); if (r < 1 || (n - r) * (n - r) > 1e-12) exit 1; print r }' ||
    { echo "bench_blocksteps: TIME $TIME is not a whole number of steps of $1" >&2; exit 1; }
}

# run NAME DT [--eta ETA ...]: one run, its output in NAME.log and its CPU in NAME.cpu.
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
  # it simulated TIME: orrery-nbody reports every $every steps and at the last
  local ended
  ended=$(awk '/^report t = / { last = $4 } END { print last }' "$work/$name.log")
  awk -v a="$ended" -v t="$TIME" 'BEGIN { exit !(a != "" && (a - t) * (a - t) < 1e-12) }' ||
    { echo "bench_blocksteps: $name ended at t = ${ended:-(no report)}, not TIME = $TIME" >&2; exit 1; }
}

# figures NAME DT: a run's figures, one line in NAME.fig: cpu forces most
# last z_rms r_half sun_R sun_z sun_most_z.
figures() {
  awk -v cpu="$(cat "$work/$1.cpu")" -v n="$N" -v t="$TIME" -v dt="$2" '
    /^report/ {
      for (i = 1; i <= NF; i++) {
        if ($i == "dE/|E0|") { d = $(i + 2) + 0; last = d < 0 ? -d : d; if (last > most) most = last }
        if ($i == "z_rms(3-10") z = $(i + 3)
        if ($i == "r_half" && $(i - 1) == "bulge") r = $(i + 2)
        if ($i == "Sun" && $(i + 1) == "R") { sr = $(i + 3); sz = $(i + 6) + 0; if ((sz < 0 ? -sz : sz) > sm) sm = sz < 0 ? -sz : sz }
      }
    }
    /^block steps:/ { forces = $6 }
    END {
      if (forces == "") forces = sprintf("%.4g", n * t / dt)
      printf "%s %s %.3e %.3e %s %s %s %+.3f %.3f\n", cpu, forces, most, last, z, r, sr, sz, sm
    }' "$work/$1.log" >"$work/$1.fig"
}

# at_error E: the global runs' CPU at largest error E, interpolated
# log-log between two global runs whose errors bracket E; of several such
# pairs the cheapest answer (the least favourable to block steps); "-"
# when none bracket it.
at_error() {
  awk -v e="$1" '{ err[NR] = $2; cpu[NR] = $1 }
    END {
      for (i = 1; i <= NR; i++) for (j = 1; j <= NR; j++) {
        c = ""
        if (err[i] == e) c = cpu[i]
        else if (err[i] > e && err[j] < e) {
          f = (log(e) - log(err[j])) / (log(err[i]) - log(err[j]))
          c = exp(log(cpu[j]) + f * (log(cpu[i]) - log(cpu[j])))
        }
        if (c != "" && (best == "" || c < best)) best = c
      }
      print best == "" ? "-" : best
    }' "$work/globals"
}

# row LABEL FIG [/GLOBAL [/EQUAL]]: one line of the table.
row() {
  local label=$1 fig=$2 base=${3:-} equal=${4:-}
  read -r cpu forces most last z r sr sz sm <"$fig"
  printf "%-34s %7.3f %10s %11.2e %11.2e %6s %6s %7s %7s %6s %7s %7s\n" "$label" "$cpu" "$forces" "$most" "$last" \
    "$z" "$r" "$sr" "$sz" "$sm" "${base:-1}" "${equal:--}"
}

echo "isolated Milky Way, $N particles, eps $EPS, $TIME time units, one thread"
printf "%-34s %7s %10s %11s %11s %6s %6s %7s %7s %6s %7s %7s\n" run "CPU s" forces "max|dE/E0|" "end|dE/E0|" \
  z_rms r_bulge "Sun R" "Sun z" "|z|max" /global "/equal"
: >"$work/globals"
base=
for dt in $GLOBAL_DTS; do
  run "global_$dt" "$dt"
  figures "global_$dt" "$dt"
  read -r cpu _ most _ <"$work/global_$dt.fig"
  echo "$cpu $most" >>"$work/globals"
  ratio=
  [ -n "$base" ] && ratio=$(awk -v a="$cpu" -v b="$base" 'BEGIN { printf "%.2f", a / b }')
  row "global dt = $dt" "$work/global_$dt.fig" "$ratio"
  [ -n "$base" ] || base=$cpu
done
for b in $BLOCKS; do
  IFS=: read -r dt eta dtmin <<<"$b"
  name="block_${dt}_${eta}_${dtmin}" label="block ${dtmin:+$dtmin <= }dt <= $dt eta = $eta"
  run "$name" "$dt" --eta "$eta" ${dtmin:+--dt-min "$dtmin"}
  figures "$name" "$dt"
  read -r cpu _ most _ <"$work/$name.fig"
  equal=$(at_error "$most")
  [ "$equal" = - ] || equal=$(awk -v a="$cpu" -v b="$equal" 'BEGIN { printf "%.2f", a / b }')
  row "$label" "$work/$name.fig" "$(awk -v a="$cpu" -v b="$base" 'BEGIN { printf "%.2f", a / b }')" "$equal"
done
