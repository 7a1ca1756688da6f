#!/bin/bash
# The cost of motion blur (animation.shutter, docs/animation.md#motion-blur):
# the same frame with and without it, in the same run.
#
#   bench/bench_blur.sh [PIXELS_PER_FRAME ...]
#
# The frame is configs/first-light.yaml (the Milky Way-Andromeda model,
# 10^6 particles, 1024^2, CIC, orthographic 200 kpc across: 5.12 px a
# kpc). With a shutter of 0.5 each disc star, at about 220 km/s, streaks
# PIXELS_PER_FRAME pixels when the frame interval is PIXELS_PER_FRAME /
# (0.5 * 220 * 5.12) time units (kpc / (km/s)); the two galaxies' bulk
# motions (about 100 km/s each) come on top. Default: 1 4 16 64.
# Environment: ORRERY (default build/orrery), REPEAT (runs of each, the
# fastest kept; default 3), N (particles, default 1e6).
# Prints wall and CPU seconds per frame, blurred and not, and their ratio.
set -u
here=$(cd "$(dirname "$0")" && pwd)
ORRERY=${ORRERY:-$here/../build/orrery}
REPEAT=${REPEAT:-3}
N=${N:-1000000}
work=$(mktemp -d /tmp/orrery-bench-blur-XXXXXX)
trap 'rm -rf "$work"' EXIT
steps=("$@")
[ ${#steps[@]} -eq 0 ] && steps=(1 4 16 64)

# Fastest of REPEAT runs: "wall cpu" seconds.
timed() {
  local best_w="" best_c=""
  for _ in $(seq "$REPEAT"); do
    /usr/bin/time -f "%e %U %S" -o "$work/t" "$ORRERY" render "$here/../configs/first-light.yaml" -q \
      -o "$work/out" --set input.model.particles="$N" "$@" >/dev/null || exit 1
    read -r w u s <"$work/t"
    c=$(echo "$u + $s" | bc)
    if [ -z "$best_w" ] || [ "$(echo "$w < $best_w" | bc)" = 1 ]; then best_w=$w; best_c=$c; fi
  done
  echo "$best_w $best_c"
}

printf "%-18s %10s %10s %10s %10s %8s\n" "streak (px/frame)" "wall" "cpu" "wall blur" "cpu blur" "ratio"
for px in "${steps[@]}"; do
  interval=$(echo "scale=8; $px / (0.5 * 220 * 5.12)" | bc)
  read -r w0 c0 < <(timed)
  read -r w1 c1 < <(timed --set animation.shutter=0.5 --set animation.frame_interval="$interval")
  printf "%-18s %10s %10s %10s %10s %8.2f\n" "$px" "$w0" "$c0" "$w1" "$c1" "$(echo "$c1 / $c0" | bc -l)"
done
