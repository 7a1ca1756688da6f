#!/bin/bash
# The production frame of issue 24, stage by stage, for one or more orrery
# builds side by side in the same run (docs/performance.md, "A production
# frame"):
#
#   bench/bench_frame.sh build/orrery                       # this build
#   bench/bench_frame.sh OLD/orrery build/orrery            # before and after
#   N=2000000 SIZE=8192 REPEAT=3 bench/bench_frame.sh build/orrery
#
# It renders bench/production-dome.yaml (Future Sky's dome master from the
# Sun: colour populations, CIC, the Hubble PSF with 200 spike stars, FITS +
# PNG) with N particles (default 10^7) at SIZE^2 (3600: domes/flat-180;
# 8192: domes/flat-180-8k), REPEAT times per build, the builds interleaved,
# and prints for each build the best run's wall and CPU seconds per stage
# (`orrery render --timings`), its total and its peak memory (GNU time's
# maximum resident set size). OMP_NUM_THREADS is left to the caller.
set -euo pipefail
[ $# -ge 1 ] || { sed -n 2,16p "$0"; exit 2; }
here=$(cd "$(dirname "$0")/.." && pwd)
N=${N:-10000000} SIZE=${SIZE:-3600} REPEAT=${REPEAT:-1}
case $SIZE in
  3600) dome=flat-180 ;;
  8192) dome=flat-180-8k ;;
  *) echo "bench_frame.sh: SIZE must be 3600 or 8192, not '$SIZE'" >&2; exit 2 ;;
esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for bin in "$@"; do
  [ -x "$bin" ] || { echo "bench_frame.sh: '$bin' is not an executable" >&2; exit 2; }
done
for r in $(seq "$REPEAT"); do
  k=0
  for bin in "$@"; do
    k=$((k + 1))
    /usr/bin/time -f "peak %M KB" -o "$work/mem-$k-$r" \
      "$bin" render "$here/bench/production-dome.yaml" -q --timings --force -o "$work/out-$k" \
      --set input.model.particles="$N" --set views.dome.camera.dome=$dome >"$work/t-$k-$r" 2>&1
  done
done
/usr/bin/python3 - "$work" "$REPEAT" "$N" "$SIZE" "$@" <<'PY'
import re, sys
work, repeat, n, size, bins = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5:]
def read(k, r):
    stages = {}
    for line in open(f"{work}/t-{k}-{r}"):
        m = re.match(r"\s+(\S[\w+/ ]*?)\s+([\d.]+)\s+([\d.]+)\s", line)
        if m:
            stages[m.group(1)] = (float(m.group(2)), float(m.group(3)))
    mem = int(open(f"{work}/mem-{k}-{r}").read().split()[1])
    return stages, mem
best = []
for k in range(1, len(bins) + 1):
    runs = [read(k, r) for r in range(1, repeat + 1)]
    best.append(min(runs, key=lambda x: x[0]["total"][0]))
print(f"production frame: {size}^2 dome master, {float(n):.0e} particles, best of {repeat}")
print("stage".ljust(16) + "".join(f"{'build ' + str(k + 1):>22}" for k in range(len(bins))))
print(" " * 16 + "".join(f"{'wall s':>11}{'CPU s':>11}" for _ in bins))
for name in best[0][0]:
    if name == "stages summed":
        continue
    row = name.ljust(16)
    for stages, _ in best:
        w, c = stages.get(name, (float("nan"),) * 2)
        row += f"{w:11.3f}{c:11.3f}"
    print(row)
print("peak memory".ljust(16) + "".join(f"{mem / 1024:19.0f} MB" for _, mem in best))
for k, b in enumerate(bins):
    print(f"build {k + 1}: {b}")
PY
