#!/bin/bash
# bench_frame.sh, the script that prints issue 41's goals (docs/performance.md),
# run as the docs run it but small: the README's main job at 2 x 10^4
# particles as a two-frame film (FRAMES=2), one build given twice. Its table
# must name every stage with a wall and CPU figure per build, the film's
# first frame and later frames' mean must agree with the table's total (a
# frame's share of the run), and bad settings must stop it with a message
# and exit status 2. The sanitizer build skips it (77): the full-size views
# take minutes there.
#   test_bench_frame.sh ORRERY SOURCE_DIR SANITIZE
set -u
ORRERY=$1
SRC=$2
if [ "${3:-OFF}" = ON ]; then
  echo "bench_frame.sh renders full-size views: skipped in the sanitizer build"
  exit 77
fi
WORK=$(mktemp -d /tmp/orrery-bench-frame-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

N=20000 FRAMES=2 bash "$SRC/bench/bench_frame.sh" "$ORRERY" "$ORRERY" >table.txt 2>err.txt ||
  fail "bench_frame.sh failed: $(cat err.txt)"
cat table.txt
python3 - table.txt <<'PY' || fail "the table: see above"
import math, re, sys
lines = open(sys.argv[1]).read().splitlines()
assert lines[0] == ("production frame: main futuresky.yaml dust on, 2e+04 particles, best of 1, "
                    "a frame's share of a 2-frame film"), lines[0]
rows = {}
for line in lines[3:]:
    m = re.match(r"(\S[\w+/ ,]*?)\s{2,}(\S.*)$", line)
    if m:
        rows[m.group(1)] = m.group(2).split()
for stage in ("setup", "source", "lengths", "gather+project", "deposit", "reduce", "colour/post", "fits", "png", "total"):
    figures = [float(x) for x in rows[stage]]
    assert len(figures) == 4 and all(math.isfinite(x) and x >= 0 for x in figures), (stage, figures)
total = [float(x) for x in rows["total"]]
assert total[0] > 0 and total[1] >= total[0] * 0.5, total  # CPU at least half the wall on any machine
first = [float(x) for x in rows["first frame"]]
later = [float(x) for x in rows["later, mean"]]
for k in range(2):
    frames_mean = (first[k] + later[k]) / 2
    assert abs(frames_mean - total[2 * k]) <= 0.1 * total[2 * k] + 0.05, (k, frames_mean, total)
mem = rows["peak memory"]
assert mem[1] == "MB" and mem[3] == "MB" and float(mem[0]) > 0, mem
print("bench_frame.sh: every stage, both builds; frames' mean matches the total")
PY

# Bad settings: exit 2, a message naming the setting, no table.
bad() { # WANT-MESSAGE ENV... -- ARGS...
  local want=$1; shift
  local envs=()
  while [ "$1" != -- ]; do envs+=("$1"); shift; done; shift
  env "${envs[@]}" bash "$SRC/bench/bench_frame.sh" "$@" >out.txt 2>err.txt
  local rc=$?
  [ $rc -eq 2 ] || fail "${envs[*]} $*: exit $rc, not 2"
  grep -q -- "$want" err.txt || fail "${envs[*]} $*: no '$want' in: $(cat err.txt)"
  [ -s out.txt ] && fail "${envs[*]} $*: printed a table"
}
# No build: the usage, the script's whole comment, and exit 2.
bash "$SRC/bench/bench_frame.sh" >usage.txt 2>&1
rc=$?
[ $rc -eq 2 ] || fail "no arguments: exit $rc, not 2"
grep -q "^#   bench/bench_frame.sh build/orrery" usage.txt && grep -q "^# OMP_NUM_THREADS is left to the caller" usage.txt ||
  fail "no arguments: not the whole usage: $(cat usage.txt)"
bad "FRAMES must be a whole number" FRAMES=0 -- "$ORRERY"
bad "FRAMES must be a whole number" FRAMES=two -- "$ORRERY"
bad "FRAME must be main" FRAME=dome -- "$ORRERY"
bad "DUST must be on or off" DUST=maybe -- "$ORRERY"
bad "is not an executable" FRAME=main -- "$WORK/no-such-orrery"
[ $failures -eq 0 ] && echo "bench_frame.sh: all checks passed"
[ $failures -eq 0 ]
