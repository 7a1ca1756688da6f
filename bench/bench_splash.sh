#!/bin/bash
# SPH splatting throughput of orrery against SPLASH (D. Price's SPH
# renderer, Debian package `splash`), same particles, same image, same run,
# both on one core (OMP_NUM_THREADS=1; SPLASH is OpenMP-parallel).
#
#   bench/bench_splash.sh [CASE ...]
#
# CASE is uniform:H (particles uniform over the view, h = H pixels for all)
# or plummer (a Plummer sphere, h = 1.2 (m / rho)^(1/3) from its density:
# 2.5 pixels at the centre, 5.6 at the median, 21 at the 90th percentile).
# Default: uniform:1 uniform:3 uniform:10 plummer. Environment:
#   ORRERY   orrery binary (default: build/orrery of the source tree)
#   N        particles (default 1e6)    NPIX   image side (default 1024)
#   REPEAT   runs of each timing, alternating between the programs, the
#            fastest kept (default 3)
#   FAST=1   also time SPLASH's "accelerated rendering" (kernels of more than
#            5 pixels drawn by quadrants around the pixel centre nearest the
#            particle: not the same image, up to half a pixel off)
#
# Input: one Gadget-1 snapshot (gas; HSML = 2h, which both programs halve)
# that both read in well under a second. Each program renders the view
# (8 x 8 length units, orthographic, cubic kernel) and, to take reading,
# set-up and output out of the figure, the same scene with the view moved
# off the particles (every particle is read, projected and culled, nothing
# drawn): splatting time = CPU time of the view - CPU time of the empty view.
# CPU time (user + system), not wall time: the machine may be shared.
# Prints per case: CPU seconds (total and splatting), particles per CPU
# second of splatting, and SPLASH / orrery.
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
N=${N:-1e6}
NPIX=${NPIX:-1024}
REPEAT=${REPEAT:-3}
FAST=${FAST:-0}
WIDTH=8
ORRERY=${ORRERY:-$root/build/orrery}
[ -x "${ORRERY:-}" ] || { echo "orrery binary not found: set ORRERY" >&2; exit 2; }
command -v splash >/dev/null || { echo "splash is not installed (Debian package splash)" >&2; exit 2; }
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" -c "import numpy" 2>/dev/null || { echo "numpy is needed to write the particles" >&2; exit 2; }
[ $# -gt 0 ] && cases=("$@") || cases=(uniform:1 uniform:3 uniform:10 plummer)

work=$(mktemp -d /tmp/orrery-bench-splash-XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
export OMP_NUM_THREADS=1

# write_snapshot CASE FILE: a Gadget-1 snapshot of N gas particles.
write_snapshot() {
  "$py" - "$1" "$2" "$N" "$NPIX" "$WIDTH" <<'EOF'
import struct, sys
import numpy as np
case, out, n, npix, width = sys.argv[1], sys.argv[2], int(float(sys.argv[3])), int(sys.argv[4]), float(sys.argv[5])
rng = np.random.default_rng(1)
m = 1.0 / n
dx = width / npix
if case == "plummer":
    rmax = 10.0
    u = rng.uniform(0.0, rmax**3 / (rmax**2 + 1.0) ** 1.5, n)
    r = 1.0 / np.sqrt(u ** (-2.0 / 3.0) - 1.0)
    v = rng.normal(size=(n, 3))
    p = r[:, None] * v / np.linalg.norm(v, axis=1)[:, None]
    rho = 3.0 / (4.0 * np.pi) * (1.0 + r * r) ** -2.5
    h = 1.2 * (m / rho) ** (1.0 / 3.0)
elif case.startswith("uniform:"):
    p = rng.uniform(-0.5 * width, 0.5 * width, (n, 3))
    h = np.full(n, float(case.split(":")[1]) * dx)
    rho = m / (h / 1.2) ** 3
else:
    sys.exit("unknown case %s (uniform:H or plummer)" % case)
def record(f, b):
    f.write(struct.pack("<i", len(b))); f.write(b); f.write(struct.pack("<i", len(b)))
head = bytearray(256)
struct.pack_into("<6i", head, 0, n, 0, 0, 0, 0, 0)
struct.pack_into("<6d", head, 24, m, 0, 0, 0, 0, 0)  # one mass for all gas: no MASS block
struct.pack_into("<6I", head, 96, n, 0, 0, 0, 0, 0)
struct.pack_into("<i", head, 124, 1)
with open(out, "wb") as f:
    record(f, bytes(head))
    record(f, p.astype("<f4").tobytes())
    record(f, np.zeros((n, 3), "<f4").tobytes())
    record(f, np.arange(n, dtype="<u4").tobytes())
    record(f, np.ones(n, "<f4").tobytes())                 # U
    record(f, rho.astype("<f4").tobytes())                # RHO (SPLASH's weights m / (rho h^3))
    record(f, (2.0 * h).astype("<f4").tobytes())          # HSML: Gadget's support radius
hp = h / dx
print("h in pixels: min %.3g, median %.3g, 90th percentile %.3g, max %.3g" % (hp.min(), np.median(hp), np.percentile(hp, 90), hp.max()))
EOF
}

# cpu_time OUTFILE CMD...: runs CMD once (output to OUTFILE), prints its CPU
# time (user + system) in seconds.
cpu_time() {
  local out=$1
  shift
  { TIMEFORMAT='%U %S'; time "$@" >"$out" 2>&1; } 2>&1 | awk '{ print $1 + $2 }'
}
least() { awk -v a="$1" -v b="$2" 'BEGIN { print (b == "" || a < b) ? a : b }'; }

# SPLASH's settings: its defaults saved from the menu, then plain rendering
# (cubic kernel, not normalised, not exact, not accelerated) at NPIX.
splash_setup() {
  rm -f splash.defaults
  printf 's\nq\n' | splash -f gadget "$1" >/dev/null 2>&1
  [ -f splash.defaults ] || { echo "splash did not write splash.defaults" >&2; exit 1; }
  sed -i "s/^ NPIX=.*/ NPIX=$NPIX,/; s/^ IKERNEL=.*/ IKERNEL=1,/; s/^ INORMALISE_INTERPOLATIONS=.*/ INORMALISE_INTERPOLATIONS=F,/; s/^ EXACT_RENDERING=.*/ EXACT_RENDERING=F,/; s/^ IFASTRENDER=.*/ IFASTRENDER=F,/" splash.defaults
}
# splash_limits X0: x from X0 to X0 + WIDTH, y centred (10 columns: x y z vx vy vz m u rho h).
splash_limits() {
  awk -v x0="$1" -v w=$WIDTH 'BEGIN { printf "%g %g\n%g %g\n-1e3 1e3\n", x0, x0 + w, -w / 2, w / 2; for (i = 0; i < 7; i++) print "0 1" }' >splash.limits
}
# orrery_scene NAME X-CENTRE
orrery_scene() {
  cat >"$1.yaml" <<EOF
input: {file: snap}
deposit: sph
smoothing: {kernel: cubic, lengths: file}
camera: {projection: orthographic, width: $WIDTH, position: [$2, 0, 0]}
image: {width: $NPIX, height: $NPIX}
output: {dir: out, name: $1, png: false}
EOF
}

rate() { awk -v n="$N" -v t="$1" 'BEGIN { if (t > 0) printf "%.3g", n / t; else printf "-" }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a > 0 && b > 0) printf "%.2f", a / b; else printf "-" }'; }
minus() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a - b }'; }

echo "orrery: $ORRERY"
echo "splash: $(splash --version 2>&1 | grep -m1 -o 'v[0-9][0-9.]*') ($(command -v splash))"
echo "N = $N particles, $NPIX x $NPIX pixels, one core each, CPU seconds (fastest of $REPEAT)"
uptime
summary=()
for c in "${cases[@]}"; do
  echo
  echo "== $c"
  write_snapshot "$c" snap || exit 1
  splash_setup snap
  orrery_scene view 0
  orrery_scene empty 1000
  # The runs of the two programs alternate, so that both see the same
  # load on a shared machine; the fastest of REPEAT is kept for each.
  o_view="" o_empty="" s_view="" s_empty="" s_fast=""
  for r in $(seq "$REPEAT"); do
    t_ov=$(cpu_time orrery-view.log "$ORRERY" render view.yaml)
    splash_limits $((-WIDTH / 2))
    t_sv=$(cpu_time splash-view.log splash -f gadget -x 1 -y 2 -r 9 -dev /null snap)
    grep -q "projecting: *$NPIX x *$NPIX on *1 cpus" splash-view.log ||
      { echo "splash did not render $NPIX x $NPIX on 1 cpu:" >&2; grep -i project splash-view.log >&2; exit 1; }
    t_sf=""
    if [ "$FAST" = 1 ]; then
      sed -i "s/^ IFASTRENDER=.*/ IFASTRENDER=T,/" splash.defaults
      t_sf=$(cpu_time splash-fast.log splash -f gadget -x 1 -y 2 -r 9 -dev /null snap)
      sed -i "s/^ IFASTRENDER=.*/ IFASTRENDER=F,/" splash.defaults
      s_fast=$(least "$t_sf" "$s_fast")
    fi
    t_oe=$(cpu_time orrery-empty.log "$ORRERY" render empty.yaml)
    splash_limits 1000
    t_se=$(cpu_time splash-empty.log splash -f gadget -x 1 -y 2 -r 9 -dev /null snap)
    echo "  run $r: orrery $t_ov s (empty view $t_oe s), SPLASH $t_sv s (empty view $t_se s${t_sf:+, accelerated $t_sf s})"
    o_view=$(least "$t_ov" "$o_view") o_empty=$(least "$t_oe" "$o_empty")
    s_view=$(least "$t_sv" "$s_view") s_empty=$(least "$t_se" "$s_empty")
  done
  grep -h "^read" orrery-view.log | sed 's/^/  orrery view:  /'
  grep -h "^read" orrery-empty.log | sed 's/^/  orrery empty: /'
  grep -h "completed in" splash-view.log | sed 's/^ */  splash view (wall clock of its projection): /'
  o_splat=$(minus "$o_view" "$o_empty")
  s_splat=$(minus "$s_view" "$s_empty")
  printf '  %-8s total %7.2f s, empty view %5.2f s, splatting %7.2f s: %9s particles/s\n' \
    orrery "$o_view" "$o_empty" "$o_splat" "$(rate "$o_splat")" \
    SPLASH "$s_view" "$s_empty" "$s_splat" "$(rate "$s_splat")"
  line="$(printf '%-11s SPLASH / orrery: splatting %6s x, total %6s x' "$c" "$(ratio "$s_splat" "$o_splat")" "$(ratio "$s_view" "$o_view")")"
  if [ "$FAST" = 1 ]; then
    s_fsplat=$(minus "$s_fast" "$s_empty")
    printf '  %-8s total %7.2f s, splatting %7.2f s: %9s particles/s (accelerated, not the same image)\n' \
      SPLASH "$s_fast" "$s_fsplat" "$(rate "$s_fsplat")"
    line="$line$(printf ', accelerated SPLASH / orrery: splatting %6s x' "$(ratio "$s_fsplat" "$o_splat")")"
  fi
  echo "  $line"
  summary+=("$line")
done
echo
echo "== summary (goal: SPLASH / orrery >= 10 per core)"
printf '%s\n' "${summary[@]}"
