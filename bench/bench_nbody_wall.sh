#!/bin/bash
# orrery-nbody's gravity in wall time on several threads, for one or more
# builds side by side in the same run (docs/nbody.md, "The tree built on
# every thread"):
#
#   bench/bench_nbody_wall.sh build/examples/orrery-nbody
#   bench/bench_nbody_wall.sh OLD/orrery-nbody build/examples/orrery-nbody
#   N=500000 STEPS=24 REPEAT=5 bench/bench_nbody_wall.sh OLD/orrery-nbody build/examples/orrery-nbody
#
# The short film's run (examples/futuresky-short.sh: the Milky Way and
# Andromeda, N particles, default 5 x 10^5; steps of 0.002, softening 0.2
# kpc, the tracer ring and mirror) for STEPS steps (default 24), without a
# scene, each build REPEAT times (default 3), the builds interleaved, on
# OMP_NUM_THREADS threads (default 2). Printed for each build: each run's
# gravity wall seconds per force computation (from orrery-nbody's own
# summary line: the tree's build, the walk and the tracers' ring), the
# best, and the particles' forces per second at the best, in all and per
# thread. The bench_nbody program gives the forces' CPU time on one thread;
# this gives what a film waits for.
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,/^set /{/^#/p}' "$0"; exit 2; } # the comment above, whole
N=${N:-500000} STEPS=${STEPS:-24} REPEAT=${REPEAT:-3}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
for v in N STEPS REPEAT OMP_NUM_THREADS; do
  case ${!v} in
    '' | *[!0-9]* | 0) echo "bench_nbody_wall.sh: $v must be a whole number, 1 or more, not '${!v}'" >&2; exit 2 ;;
  esac
done
for b in "$@"; do
  [ -x "$b" ] || { echo "bench_nbody_wall.sh: $b: not an orrery-nbody program (build first: scripts/build.sh)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
builds=() # absolute: the runs start in a folder of their own
for b in "$@"; do
  builds+=("$(cd "$(dirname "$b")" && pwd)/$(basename "$b")")
done
runs=()
for _ in $(seq 1 "$REPEAT"); do
  for i in "${!builds[@]}"; do
    (cd "$work" && "${builds[$i]}" --particles "$N" --steps "$STEPS" --dt 0.002 --eps 0.2 --tracer-ring 32 \
      --tracer-mirror --progress 0 --report-every "$STEPS" >"$work/out" 2>&1) ||
      { echo "bench_nbody_wall.sh: ${builds[$i]} failed: $(tail -3 "$work/out")" >&2; exit 1; }
    # "gravity 8.19 s over 25 force evaluations; rendering ...": seconds a force computation
    per=$(awk '$1 == "gravity" && $3 == "s" && $4 == "over" { printf "%.4f", $2 / $5; found = 1 } END { exit !found }' "$work/out") ||
      { echo "bench_nbody_wall.sh: ${builds[$i]}: no gravity summary in its output" >&2; exit 1; }
    runs[i]="${runs[i]:-}$per "
  done
done
echo "gravity, wall s per force computation: $N particles (Milky Way and Andromeda), $STEPS steps, $OMP_NUM_THREADS threads, $REPEAT runs a build"
printf '%-8s %-40s %8s %14s %14s\n' build runs best "forces/s" "per thread"
for i in "${!builds[@]}"; do
  read -r -a r <<<"${runs[i]}"
  best=$(printf '%s\n' "${r[@]}" | sort -g | head -1)
  awk -v b="$((i + 1))" -v runs="${runs[i]% }" -v best="$best" -v n="$N" -v t="$OMP_NUM_THREADS" \
    'BEGIN { printf "%-8s %-40s %8.4f %14.3g %14.3g\n", b, runs, best, n / best, n / best / t }'
done
i=0
for b in "$@"; do
  i=$((i + 1))
  echo "build $i: $b"
done
