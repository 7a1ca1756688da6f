#!/usr/bin/env bash
# scripts/measure-mpi-reads.sh, the bytes of a snapshot each rank of
# orrery-mpi reads (docs/scale.md), at 64^3 = 2^18 particles per snapshot
# (READS_GRID; the docs' table is 2^21, 8 times as many): checks what the
# docs claim of it: one rank reads the positions and ids (16 bytes a
# particle), and with N ranks each reads about 1/N of that (within
# 0.1 MB, the script's rounding, and the headers' few kB).
source "$(dirname "$0")/lib.sh"
need_mpi "$(dirname "$ORRERY")/orrery-mpi"
# strace is a dependency (scripts/install-deps.sh installs it): fail, not
# skip, when it is missing; skip only where the container forbids ptrace.
command -v strace >/dev/null || { echo "FAIL: strace not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
strace -qq -o /dev/null true 2>/dev/null || { echo "strace cannot trace here (ptrace not allowed): skipped"; exit 77; }

READS_GRID=64 BUILD=$(dirname "$ORRERY") bash "$SRC/scripts/measure-mpi-reads.sh" >reads.txt 2>reads.err ||
  { fail "measure-mpi-reads.sh failed: $(cat reads.err)"; finish; }
"$py" - reads.txt <<'PY' || fail "measure-mpi-reads.sh's counts: $(cat reads.txt)"
import re, sys
want = 16 * 64**3 / 1e6  # MB: POS (3 floats) and ID (4 bytes) of every particle
seen, bad = set(), []
for line in open(sys.argv[1]):
    m = re.match(r"(\S+) \(.*\), (\d) rank\(s\): MB read per rank:((?: [\d.]+)+)$", line.strip())
    if not m:
        bad.append(f"unexpected line: {line.strip()}")
        continue
    snap, n, mb = m.group(1), int(m.group(2)), [float(x) for x in m.group(3).split()]
    seen.add((snap, n))
    if len(mb) != n or any(abs(x - want / n) > 0.15 for x in mb):
        bad.append(f"{snap} on {n} rank(s): {mb} MB, expected {n} x {want / n:.2f}")
missing = {(s, n) for s in ("multi", "single", "box.hdf5") for n in (1, 2, 4)} - seen
bad += [f"no line for {s} on {n} rank(s)" for s, n in sorted(missing)]
for b in bad:
    print(b, file=sys.stderr)
sys.exit(1 if bad else 0)
PY
finish
