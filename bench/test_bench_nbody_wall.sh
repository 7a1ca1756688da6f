#!/bin/bash
# bench_nbody_wall.sh, the script behind the wall times of "The tree built
# on every thread" (docs/nbody.md), run small: 3000 particles, two steps,
# the same build twice, two runs each. Checked against what its own figures
# must give: two runs a build, each positive, the best the least of them,
# the forces per second N over the best, and per thread that over the
# threads; and a bad setting or a missing program stops it with a message
# naming it (exit 2).
#   test_bench_nbody_wall.sh NBODY SOURCE_DIR
set -u
NBODY=$1
SRC=$2
WORK=$(mktemp -d /tmp/orrery-bench-nbody-wall-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

N=3000 STEPS=2 REPEAT=2 OMP_NUM_THREADS=2 bash "$SRC/bench/bench_nbody_wall.sh" "$NBODY" "$NBODY" \
  >"$WORK/table.txt" 2>"$WORK/err.txt" || fail "bench_nbody_wall.sh failed: $(cat "$WORK/err.txt")"
cat "$WORK/table.txt"
python3 - "$WORK/table.txt" "$NBODY" <<'PY' || fail "the table: see above"
import sys
lines = open(sys.argv[1]).read().splitlines()
assert lines[0] == ("gravity, wall s per force computation: 3000 particles (Milky Way and Andromeda), 2 steps, "
                    "2 threads, 2 runs a build"), lines[0]
assert lines[1].split() == ["build", "runs", "best", "forces/s", "per", "thread"], lines[1]
for k, line in enumerate(lines[2:4], 1):
    f = line.split()
    assert f[0] == str(k), line
    runs, best, rate, per = [float(x) for x in f[1:3]], float(f[3]), float(f[4]), float(f[5])
    assert all(r > 0 for r in runs), line
    assert abs(best - min(runs)) < 1e-12, line
    assert abs(rate / (3000 / best) - 1) < 6e-3, line  # three digits printed
    assert abs(per / (3000 / best / 2) - 1) < 6e-3, line
assert lines[4:] == [f"build 1: {sys.argv[2]}", f"build 2: {sys.argv[2]}"], lines[4:]
PY
REPEAT=0 bash "$SRC/bench/bench_nbody_wall.sh" "$NBODY" >/dev/null 2>"$WORK/err.txt"
[ $? -eq 2 ] && grep -q "REPEAT must be a whole number, 1 or more, not '0'" "$WORK/err.txt" ||
  fail "REPEAT=0: $(cat "$WORK/err.txt")"
bash "$SRC/bench/bench_nbody_wall.sh" "$WORK/no-such-nbody" >/dev/null 2>"$WORK/err.txt"
[ $? -eq 2 ] && grep -q "no-such-nbody: not an orrery-nbody program" "$WORK/err.txt" ||
  fail "a missing program: $(cat "$WORK/err.txt")"
[ $failures -eq 0 ] && echo "bench_nbody_wall: all checks passed"
exit $((failures != 0))
