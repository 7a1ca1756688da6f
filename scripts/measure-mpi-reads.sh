#!/usr/bin/env bash
# How many bytes of a snapshot each rank of orrery-mpi reads (docs/scale.md):
# writes a Gadget snapshot of 4 files and one of a single file (2^21
# particles each, POS VEL ID; written by the small numpy writer below), and
# a single-file HDF5 box (orrery ics, 128^3 = 2^21), renders each with 1, 2 and 4
# ranks under strace, and sums the bytes every rank's read() and pread64()
# calls return for the snapshot's files (the counts of the calls themselves,
# so the page cache and the machine's load do not matter).
#
#   scripts/measure-mpi-reads.sh            # build/ by default; BUILD=dir to change
#   READS_GRID=64 scripts/measure-mpi-reads.sh   # GRID^3 particles in each
#       snapshot instead of 128^3 = 2^21: the test's size (tests/cli/test_mpi_reads.sh)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$root/build}
grid=${READS_GRID:-128}
work=$(mktemp -d /tmp/orrery-reads-XXXXXX)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# A Gadget-2 SnapFormat 1 snapshot of n type-1 particles in nfiles files
# (facts of the format: docs/formats.md).
"$py" - "$work" $((grid * grid * grid)) <<'PY'
import struct, sys
import numpy as np
def write(base, n, nfiles):
    rng = np.random.default_rng(1)
    per = [n // nfiles + (1 if f < n % nfiles else 0) for f in range(nfiles)]
    first = 0
    for f, m in enumerate(per):
        npart = [0, m, 0, 0, 0, 0]
        total = [0, n, 0, 0, 0, 0]
        head = struct.pack("<6i6dddii6Iiiddddii6Ii", *npart, 0, 1.0, 0, 0, 0, 0, 1.0, 0.0, 0, 0, *total,
                           0, nfiles, 100.0, 0.3, 0.7, 0.7, 0, 0, 0, 0, 0, 0, 0, 0, 0)
        head += b"\0" * (256 - len(head))
        pos = rng.uniform(0, 100, (m, 3)).astype("<f4")
        vel = rng.normal(0, 100, (m, 3)).astype("<f4")
        ids = np.arange(first + 1, first + m + 1, dtype="<u4")
        first += m
        name = base if nfiles == 1 else f"{base}.{f}"
        with open(name, "wb") as out:
            for block in (head, pos.tobytes(), vel.tobytes(), ids.tobytes()):
                out.write(struct.pack("<i", len(block)) + block + struct.pack("<i", len(block)))
write(sys.argv[1] + "/multi", int(sys.argv[2]), 4)
write(sys.argv[1] + "/single", int(sys.argv[2]), 1)
PY
"$BUILD/orrery" ics --zeldovich -o "$work/box.hdf5" --grid "$grid" >/dev/null

cat >"$work/scene.yaml" <<'Y'
camera: {projection: orthographic, width: 100, position: [50, 50, 150]}
image: {width: 256, height: 256}
output: {png: false}
Y

# reads SNAPSHOT NP: the snapshot's bytes read by each rank, in MB.
reads() {
  local snap=$1 np=$2 name
  name=$(basename "$snap")
  rm -f "$work"/trace.*
  mpirun -np "$np" sh -c 'exec strace -qq -y -e trace=read,pread64 -o "$0/trace.$OMPI_COMM_WORLD_RANK" "$@"' \
    "$work" "$BUILD/orrery-mpi" render "$work/scene.yaml" --set input.file="$snap" -o "$work/out" -q
  for r in $(seq 0 $((np - 1))); do
    awk -v n="/$name" '$0 ~ n && $NF ~ /^[0-9]+$/ { s += $NF } END { printf " %.1f", s / 1e6 }' "$work/trace.$r"
  done
}

for snap in multi single box.hdf5; do
  files=("$work/$snap")
  [ -f "$work/$snap.0" ] && files=("$work/$snap".*)
  size=$(stat -c %s "${files[@]}" | awk '{ s += $1 } END { printf "%.1f", s / 1e6 }')
  for np in 1 2 4; do
    echo "$snap (${#files[@]} file(s), $size MB), $np rank(s): MB read per rank:$(reads "$work/$snap" "$np")"
  done
done
