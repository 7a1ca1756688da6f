#!/bin/bash
# orrery-nbody's gravity in wall time on several threads, for one or more
# builds side by side in the same run (docs/nbody.md, "The tree built on
# every thread", "The ring's sums in vector registers"):
#
#   bench/bench_nbody_wall.sh build/examples/orrery-nbody
#   bench/bench_nbody_wall.sh OLD/orrery-nbody build/examples/orrery-nbody
#   N=500000 STEPS=12 REPEAT=3 bench/bench_nbody_wall.sh OLD/orrery-nbody build/examples/orrery-nbody
#
# The short film's N-body run as examples/futuresky-short.sh ships it (the
# Milky Way and Andromeda, N particles, default 5 x 10^5, M31's four times
# heavier; discs of Q = 3, phase-mixed; block steps of 0.008 down to 0.002,
# eta 0.2; softening 0.2 kpc; the tracer ring and mirror) for STEPS steps
# (default 12), without a scene, each build REPEAT times (default 3), the
# builds interleaved, on OMP_NUM_THREADS threads (default 2).
# STEPPING=global runs the film's settings before 7 December 2026 instead
# (the model's defaults, a global step of 0.002), as the measurements of
# "The tree built on every thread" did. Printed for each build: each run's
# gravity wall seconds per step (from orrery-nbody's own summary lines:
# the tree's builds, the walks and the tracers' ring, the start's forces
# included), the best, and the particle forces per second at the best, in
# all and per thread. The bench_nbody program gives the forces' CPU time on
# one thread; this gives what a film waits for.
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,/^set /{/^#/p}' "$0"; exit 2; } # the comment above, whole
N=${N:-500000} STEPS=${STEPS:-12} REPEAT=${REPEAT:-3} STEPPING=${STEPPING:-block}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
for v in N STEPS REPEAT OMP_NUM_THREADS; do
  case ${!v} in
    '' | *[!0-9]* | 0) echo "bench_nbody_wall.sh: $v must be a whole number, 1 or more, not '${!v}'" >&2; exit 2 ;;
  esac
done
case $STEPPING in
  block) stepping=(--m31-weight 4 --disc-q 3 --phase-mix 0.5 --dt 0.008 --eta 0.2 --dt-min 0.002) ;;
  global) stepping=(--dt 0.002) ;;
  *) echo "bench_nbody_wall.sh: STEPPING must be block or global, not '$STEPPING'" >&2; exit 2 ;;
esac
for b in "$@"; do
  [ -x "$b" ] || { echo "bench_nbody_wall.sh: $b: not an orrery-nbody program (build first: scripts/build.sh)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
builds=() # absolute: the runs start in a folder of their own
for b in "$@"; do
  builds+=("$(cd "$(dirname "$b")" && pwd)/$(basename "$b")")
done
runs=() forces_of=()
for _ in $(seq 1 "$REPEAT"); do
  for i in "${!builds[@]}"; do
    (cd "$work" && "${builds[$i]}" --particles "$N" --steps "$STEPS" "${stepping[@]}" --eps 0.2 --tracer-ring 32 \
      --tracer-mirror --progress 0 --report-every "$STEPS" >"$work/out" 2>&1) ||
      { echo "bench_nbody_wall.sh: ${builds[$i]} failed: $(tail -3 "$work/out")" >&2; exit 1; }
    # "gravity 8.19 s over 25 force evaluations; rendering ...", and with block
    # steps "block steps: 48 force computations, 1.284e+07 particle forces = ..."
    # (those after the start's, whose forces are every particle's): the
    # gravity's seconds and the particle forces computed
    read -r grav forces < <(awk -v n="$N" '
      $1 == "gravity" && $3 == "s" && $4 == "over" { g = $2; f = n * $5 }
      $1 == "block" && $2 == "steps:" && $6 == "particle" { f = n + $5 }
      END { if (g == "") exit 1; printf "%s %s\n", g, f }' "$work/out") ||
      { echo "bench_nbody_wall.sh: ${builds[$i]}: no gravity summary in its output" >&2; exit 1; }
    runs[i]="${runs[i]:-}$(awk -v g="$grav" -v s="$STEPS" 'BEGIN { printf "%.4f", g / s }') "
    forces_of[i]=$forces # the same in every run of a build
  done
done
echo "gravity, wall s per step: $N particles (Milky Way and Andromeda), $STEPPING steps, $STEPS of them, $OMP_NUM_THREADS threads, $REPEAT runs a build"
printf '%-8s %-40s %8s %14s %14s\n' build runs best "forces/s" "per thread"
for i in "${!builds[@]}"; do
  read -r -a r <<<"${runs[i]}"
  best=$(printf '%s\n' "${r[@]}" | sort -g | head -1)
  awk -v b="$((i + 1))" -v runs="${runs[i]% }" -v best="$best" -v f="${forces_of[i]}" -v s="$STEPS" \
    -v t="$OMP_NUM_THREADS" \
    'BEGIN { printf "%-8s %-40s %8.4f %14.3g %14.3g\n", b, runs, best, f / (best * s), f / (best * s) / t }'
done
i=0
for b in "$@"; do
  i=$((i + 1))
  echo "build $i: $b"
done
