#!/bin/bash
# A billion particles on one machine: streams a generated 10^9-particle
# Gadget snapshot from disk through `orrery render` in bounded memory, and
# sets its time beside the disk's own read rate (`cat FILE > /dev/null`).
#
#   bench/bench_billion.sh [N]          N particles (default 1e9)
#
# Environment: ORRERY (default build/orrery), BENCH (default
# build/bench/bench_gadget_stream), DIR (where the snapshot goes, default
# /tmp; it needs 28 bytes per particle: 28 GB for 10^9, in parts of 1.5e8
# particles), KEEP=1 keeps the
# snapshot (otherwise removed at the end), NPIX (image side, default 2048).
# Prints: file size, cat's time and rate, the render's time, particles/s,
# MB/s and peak RSS (from getrusage of the child).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
N=${1:-1e9}
ORRERY=${ORRERY:-$root/build/orrery}
BENCH=${BENCH:-$root/build/bench/bench_gadget_stream}
DIR=${DIR:-/tmp}
NPIX=${NPIX:-2048}
py=/usr/bin/python3
[ -x "$py" ] || py=python3
snap="$DIR/orrery-billion.snap"
scene="$DIR/orrery-billion.yaml"
[ "${KEEP:-0}" = 1 ] || trap 'rm -f "$snap" "$snap".* "$scene" "$DIR/orrery-billion.fits" "$DIR/orrery-billion.png"' EXIT

# Parts of 1.5e8 particles (a Gadget block must fit a 32-bit record marker).
if [ ! -f "$snap" ] && [ ! -f "$snap.0" ]; then
  echo "generating $N particles in $snap(.0, .1, ...) ..."
  "$BENCH" --generate "$snap" --particles "$N" >/dev/null
fi
parts=("$snap")
[ -f "$snap.0" ] && parts=("$snap".*)
size=$(stat -c %s "${parts[@]}" | awk '{ s += $1 } END { printf "%.0f\n", s }')
cat >"$scene" <<Y
input: {file: $snap, chunk: 4194304}
camera: {projection: orthographic, width: 100, position: [50, 50, 50]}
image: {width: $NPIX, height: $NPIX}
deposit: ngp
output: {dir: $DIR, name: orrery-billion}
Y
# Drop the file from the page cache where allowed, so both read the disk.
sync; (echo 1 > /proc/sys/vm/drop_caches) 2>/dev/null || true
"$py" - "$size" "$N" "$ORRERY" "$scene" "${parts[@]}" <<'PY'
import resource, subprocess, sys, time
size, n, orrery, scene, parts = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5:]
def run(cmd):
    t = time.monotonic(); subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL); return time.monotonic() - t
t_cat = run(["cat"] + parts)
try:
    open("/proc/sys/vm/drop_caches", "w").write("1\n")
except OSError:
    pass
t_render = run([orrery, "render", scene, "--quiet"])
rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
print(f"snapshot: {n:.3g} particles, {size / 1e9:.2f} GB")
print(f"cat > /dev/null: {t_cat:.1f} s, {size / t_cat / 1e6:.0f} MB/s")
print(f"orrery render (NGP, {scene}): {t_render:.1f} s, {n / t_render:.3g} particles/s, "
      f"{size / t_render / 1e6:.0f} MB/s, peak RSS {rss:.0f} MiB")
PY
