#!/bin/bash
# bench_blocksteps.sh, the script behind issue 42's block-step ratios
# (docs/nbody.md), run small: 3000 particles over 0.032 time units, three
# global steps and two block runs. Checked against what the table's own
# figures must give: the /global column is each run's CPU over the first global run's, the /equal
# column is the global runs' CPU interpolated log-log at the block run's
# error (the cheapest of the bracketing pairs; "-" when none bracket it),
# block steps bounded below by 0.002 compute fewer forces than the global
# step of 0.002, and the energy errors are finite and small. Bad settings
# stop it with a message. (The script itself checks that each run reached
# TIME, from its last report.)
#   test_bench_blocksteps.sh BUILD_DIR SOURCE_DIR
set -u
BUILD=$1
SRC=$2
WORK=$(mktemp -d /tmp/orrery-bench-blocksteps-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

N=3000 TIME=0.032 GLOBAL_DTS="0.004 0.002 0.001" BLOCKS="0.008:0.2:0.002 0.008:0.2" \
  bash "$SRC/bench/bench_blocksteps.sh" "$BUILD" >"$WORK/table.txt" 2>"$WORK/err.txt" ||
  fail "bench_blocksteps.sh failed: $(cat "$WORK/err.txt")"
cat "$WORK/table.txt"
python3 - "$WORK/table.txt" <<'PY' || fail "the table: see above"
import math, re, sys
lines = open(sys.argv[1]).read().splitlines()
assert lines[0] == "isolated Milky Way, 3000 particles, eps 0.2, 0.032 time units, one thread", lines[0]
rows = []
for line in lines[2:]:
    m = re.match(r"(global dt = \S+|block .*?eta = \S+)\s+(\S.*)$", line)
    assert m, line
    f = m.group(2).split()
    assert len(f) == 11, (line, f)
    rows.append((m.group(1), float(f[0]), float(f[1]), float(f[2]), f[9], f[10]))
globals_ = [r for r in rows if r[0].startswith("global")]
blocks = [r for r in rows if r[0].startswith("block")]
assert [g[0] for g in globals_] == ["global dt = 0.004", "global dt = 0.002", "global dt = 0.001"], rows
assert len(blocks) == 2, rows
# printed CPU seconds have three decimals: a ratio of them is known to
# within what +-0.0005 on each allows (and the ratio's own two decimals)
def ratio_within(printed, a, b):
    lo, hi = (a - 0.0005) / (b + 0.0005), (a + 0.0005) / max(b - 0.0005, 1e-9)
    return lo - 0.006 <= float(printed) <= hi + 0.006
cpu0 = globals_[0][1]
for name, cpu, forces, err, per_global, equal in globals_:
    assert 0 < err < 0.01 and math.isfinite(err), (name, err)
    assert ratio_within(per_global, cpu, cpu0), (name, per_global, cpu, cpu0)
    assert equal == "-", (name, equal)
def at_error(e):
    best = None
    for ci, ei in ((g[1], g[3]) for g in globals_):
        for cj, ej in ((g[1], g[3]) for g in globals_):
            c = None
            if ei == e:
                c = ci
            elif ei > e > ej:
                f = (math.log(e) - math.log(ej)) / (math.log(ei) - math.log(ej))
                c = math.exp(math.log(cj) + f * (math.log(ci) - math.log(cj)))
            if c is not None and (best is None or c < best):
                best = c
    return best
for name, cpu, forces, err, per_global, equal in blocks:
    assert 0 < err < 0.01, (name, err)
    assert ratio_within(per_global, cpu, cpu0), (name, per_global, cpu, cpu0)
    want = at_error(err)
    if want is None:
        assert equal == "-", (name, equal)
    else:
        assert ratio_within(equal, cpu, want), (name, equal, cpu, want)
# the errors printed with three digits: the first block run lies inside
# the global runs' range, so its /equal is a number
assert blocks[0][5] != "-", blocks[0]
assert blocks[0][2] < globals_[1][2], ("block steps down to 0.002 computed no fewer forces than dt = 0.002", blocks[0])
PY

# bad settings: a message and a failing exit status, no table
if TIME=0.031 GLOBAL_DTS=0.002 BLOCKS= bash "$SRC/bench/bench_blocksteps.sh" "$BUILD" >"$WORK/out" 2>"$WORK/err"; then
  fail "a TIME that is no whole number of steps was accepted"
fi
grep -q "TIME 0.031 is not a whole number of steps of 0.002" "$WORK/err" || fail "TIME's message: $(cat "$WORK/err")"
if bash "$SRC/bench/bench_blocksteps.sh" "$WORK/no-build" >"$WORK/out" 2>"$WORK/err"; then
  fail "a build folder without orrery-nbody was accepted"
fi
grep -q "no $WORK/no-build/examples/orrery-nbody" "$WORK/err" || fail "the build's message: $(cat "$WORK/err")"

[ "$failures" -eq 0 ] || exit 1
echo "bench_blocksteps.sh: table and errors as expected"
