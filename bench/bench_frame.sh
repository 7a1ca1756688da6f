#!/bin/bash
# A production frame, stage by stage, for one or more orrery builds side by
# side in the same run (docs/performance.md, "The flagship as it ships"):
#
#   bench/bench_frame.sh build/orrery                       # this build
#   bench/bench_frame.sh OLD/orrery build/orrery            # before and after
#   FRAME=dome8k REPEAT=3 bench/bench_frame.sh OLD/orrery build/orrery
#
# FRAME picks the frame; all but `benchmark` render the shipped scene,
# configs/futuresky.yaml, as it ships (dust, glow, spawned stars, the
# Hubble PSF, FITS + PNG of each view):
#   main      the README's main job: 2e6 particles (or N), the 3600^2 dome
#             master and the 4096x2048 panorama (the default)
#   both3600  the same at N particles (default 10^7)
#   dome8k    the 8192^2 dome master (domes/flat-180-8k) at N particles
#             (default 10^7), the panorama shrunk to 64x32
#   benchmark bench/production-dome.yaml, the lighter scene issue 24
#             measured (no dust, glow or panorama) at N (10^7) and SIZE^2
#             (3600 or 8192): a second line, not the shipped frame
# FRAMES=n renders the scene n times over as a film's frames
# (animation.frames=n, the same particles each frame): the table is then a
# frame's share of the run's stages, and two lines more give the first
# frame's wall seconds and the later frames' mean, a film's steady cost
# (what the first frame sets up, a film pays once).
# DUST=off renders without the dust (dust=null). Each build renders REPEAT
# times (default 1), the builds interleaved; printed: each build's best
# run's wall and CPU seconds per stage (`orrery render --timings`), its
# total and its peak memory (GNU time's maximum resident set size).
# OMP_NUM_THREADS is left to the caller.
set -euo pipefail
[ $# -ge 1 ] || { sed -n '2,/^set /{/^#/p}' "$0"; exit 2; } # the comment above, whole
here=$(cd "$(dirname "$0")/.." && pwd)
FRAME=${FRAME:-main} REPEAT=${REPEAT:-1} DUST=${DUST:-on} FRAMES=${FRAMES:-1}
scene=$here/configs/futuresky.yaml
case $FRAME in
  main)
    if [ -n "${N:-}" ]; then sets=(--set input.model.particles="$N"); else N=2000000 sets=(); fi ;;
  both3600) N=${N:-10000000} sets=(--set input.model.particles="$N") ;;
  dome8k)
    N=${N:-10000000}
    sets=(--set input.model.particles="$N" --set views.dome.camera.dome=flat-180-8k
          --set views.panorama.image.width=64 --set views.panorama.image.height=32) ;;
  benchmark)
    N=${N:-10000000} SIZE=${SIZE:-3600} scene=$here/bench/production-dome.yaml
    case $SIZE in
      3600) dome=flat-180 ;;
      8192) dome=flat-180-8k ;;
      *) echo "bench_frame.sh: SIZE must be 3600 or 8192, not '$SIZE'" >&2; exit 2 ;;
    esac
    sets=(--set input.model.particles="$N" --set views.dome.camera.dome=$dome) ;;
  *) echo "bench_frame.sh: FRAME must be main, both3600, dome8k or benchmark, not '$FRAME'" >&2; exit 2 ;;
esac
case $DUST in
  on) ;;
  off) sets+=(--set dust=null) ;;
  *) echo "bench_frame.sh: DUST must be on or off, not '$DUST'" >&2; exit 2 ;;
esac
case $FRAMES in
  '' | *[!0-9]* | 0) echo "bench_frame.sh: FRAMES must be a whole number of frames, 1 or more, not '$FRAMES'" >&2; exit 2 ;;
esac
[ "$FRAMES" = 1 ] || sets+=(--set animation.frames="$FRAMES")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for bin in "$@"; do
  [ -x "$bin" ] || { echo "bench_frame.sh: '$bin' is not an executable" >&2; exit 2; }
done
for r in $(seq "$REPEAT"); do
  k=0
  for bin in "$@"; do
    k=$((k + 1))
    # a fresh folder, as a user's first run has: a rerun's --force would
    # time unlinking the last run's files (0.2-0.7 s of `commit`)
    rm -rf "$work/out-$k"
    /usr/bin/time -f "peak %M KB" -o "$work/mem-$k-$r" \
      "$bin" render "$scene" -q --timings --force -o "$work/out-$k" "${sets[@]}" >"$work/t-$k-$r" 2>&1 ||
      { echo "bench_frame.sh: $bin failed:" >&2; cat "$work/t-$k-$r" >&2; exit 1; }
  done
done
/usr/bin/python3 - "$work" "$REPEAT" "$N" "$FRAME $(basename "$scene") dust $DUST" "$FRAMES" "$@" <<'PY'
import re, sys
work, repeat, n, frame, frames, bins = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], int(sys.argv[5]), sys.argv[6:]
def read(k, r):
    """A run's stages (wall, CPU: a frame's share), its frames' wall
    seconds (with FRAMES) and its peak memory."""
    stages, walls = {}, []
    for line in open(f"{work}/t-{k}-{r}"):
        m = re.match(r"\s+(\S[\w+/ ]*?)\s+([\d.]+)\s+([\d.]+)\s", line)
        if m:
            stages[m.group(1)] = (float(m.group(2)) / frames, float(m.group(3)) / frames)
        m = re.match(r"timings: frame \d+: ([\d.]+) s wall", line)
        if m:
            walls.append(float(m.group(1)))
    mem = int(open(f"{work}/mem-{k}-{r}").read().split()[1])
    return stages, mem, walls
best = []
for k in range(1, len(bins) + 1):
    runs = [read(k, r) for r in range(1, repeat + 1)]
    best.append(min(runs, key=lambda x: x[0]["total"][0]))
print(f"production frame: {frame}, {float(n):.0e} particles, best of {repeat}"
      + (f", a frame's share of a {frames}-frame film" if frames > 1 else ""))
print("stage".ljust(16) + "".join(f"{'build ' + str(k + 1):>22}" for k in range(len(bins))))
print(" " * 16 + "".join(f"{'wall s':>11}{'CPU s':>11}" for _ in bins))
for name in best[0][0]:
    if name == "stages summed":
        continue
    row = name.ljust(16)
    for stages, _, _ in best:
        w, c = stages.get(name, (float("nan"),) * 2)
        row += f"{w:11.3f}{c:11.3f}"
    print(row)
if frames > 1:
    print("first frame".ljust(16) + "".join(f"{walls[0]:11.3f}{'':11}" for _, _, walls in best))
    print("later, mean".ljust(16) + "".join(f"{sum(walls[1:]) / len(walls[1:]):11.3f}{'':11}" for _, _, walls in best))
print("peak memory".ljust(16) + "".join(f"{mem / 1024:19.0f} MB" for _, mem, _ in best))
for k, b in enumerate(bins):
    print(f"build {k + 1}: {b}")
PY
