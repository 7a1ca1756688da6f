#!/bin/bash
# bench_nbody_wall.sh, the script behind the wall times of "The tree built
# on every thread" and "The ring's sums in vector registers"
# (docs/nbody.md), run small: 3000 particles, four steps, the same build
# twice, two runs each, with the film's block steps and with the global
# step. Checked against what its own figures must give: two runs a build,
# each positive, the best the least of them, the forces per second the
# particle forces over the best's gravity seconds (with the global step
# N (STEPS + 1) of them, known in advance; with block steps at least
# N (STEPS + 1) / 4 and at most N (4 STEPS + 1)), and per thread that over
# the threads; and a bad setting or a missing program stops it with a
# message naming it (exit 2).
#   test_bench_nbody_wall.sh NBODY SOURCE_DIR
set -u
NBODY=$1
SRC=$2
WORK=$(mktemp -d /tmp/orrery-bench-nbody-wall-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

for stepping in block global; do
  N=3000 STEPS=4 REPEAT=2 OMP_NUM_THREADS=2 STEPPING=$stepping bash "$SRC/bench/bench_nbody_wall.sh" "$NBODY" \
    "$NBODY" >"$WORK/table.txt" 2>"$WORK/err.txt" || fail "bench_nbody_wall.sh ($stepping) failed: $(cat "$WORK/err.txt")"
  cat "$WORK/table.txt"
  python3 - "$WORK/table.txt" "$NBODY" "$stepping" <<'PY' || fail "the table ($stepping): see above"
import sys
lines = open(sys.argv[1]).read().splitlines()
stepping = sys.argv[3]
assert lines[0] == (f"gravity, wall s per step: 3000 particles (Milky Way and Andromeda), {stepping} steps, 4 of them, "
                    "2 threads, 2 runs a build"), lines[0]
assert lines[1].split() == ["build", "runs", "best", "forces/s", "per", "thread"], lines[1]
n, steps = 3000, 4
for k, line in enumerate(lines[2:4], 1):
    f = line.split()
    assert f[0] == str(k), line
    runs, best, rate, per = [float(x) for x in f[1:3]], float(f[3]), float(f[4]), float(f[5])
    assert all(r > 0 for r in runs), line
    assert abs(best - min(runs)) < 1e-12, line
    forces = rate * best * steps  # the particle forces over the run
    if stepping == "global":
        assert abs(forces / (n * (steps + 1)) - 1) < 6e-3, line  # three digits printed
    else:
        assert n * (steps + 1) / 4 <= forces * 1.006 and forces <= n * (4 * steps + 1) * 1.006, line
    assert abs(per / (rate / 2) - 1) < 6e-3, line
assert lines[4:] == [f"build 1: {sys.argv[2]}", f"build 2: {sys.argv[2]}"], lines[4:]
PY
done
REPEAT=0 bash "$SRC/bench/bench_nbody_wall.sh" "$NBODY" >/dev/null 2>"$WORK/err.txt"
[ $? -eq 2 ] && grep -q "REPEAT must be a whole number, 1 or more, not '0'" "$WORK/err.txt" ||
  fail "REPEAT=0: $(cat "$WORK/err.txt")"
STEPPING=leapfrog bash "$SRC/bench/bench_nbody_wall.sh" "$NBODY" >/dev/null 2>"$WORK/err.txt"
[ $? -eq 2 ] && grep -q "STEPPING must be block or global, not 'leapfrog'" "$WORK/err.txt" ||
  fail "STEPPING=leapfrog: $(cat "$WORK/err.txt")"
bash "$SRC/bench/bench_nbody_wall.sh" "$WORK/no-such-nbody" >/dev/null 2>"$WORK/err.txt"
[ $? -eq 2 ] && grep -q "no-such-nbody: not an orrery-nbody program" "$WORK/err.txt" ||
  fail "a missing program: $(cat "$WORK/err.txt")"
[ $failures -eq 0 ] && echo "bench_nbody_wall: all checks passed"
exit $((failures != 0))
