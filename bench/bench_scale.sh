#!/bin/bash
# orrery against SPLASH at scale: the benchmark of the scale issue
# (docs/performance.md, "Benchmark against SPLASH").
#
#   bench/bench_scale.sh
#   SIZES="1e6 1e7" IMAGES="1024 3600" SKY_IMAGES="1024 2048" REPEAT=3 bench/bench_scale.sh   # the full run
#
# For each model (MW-M31 pair, Plummer sphere) x N it writes one Gadget-1
# snapshot (bench_snapshot: all particles gas, HSML from the 32nd
# neighbour) and times, at each image side (IMAGES; the all-sky runs at
# each width of SKY_IMAGES, 2:1), both programs with OMP_NUM_THREADS=THREADS:
#   ngp           orrery, nearest-pixel binning, orthographic
#   dome          orrery, nearest-pixel binning, dome master (azimuthal
#                 equidistant), camera inside the particles (the pair: at
#                 the Sun; the Plummer sphere: one scale radius from its centre)
#   sph           orrery, exact mass-conserving SPH column density (cubic
#                 kernel, smoothing lengths from the file), orthographic
#   splash        SPLASH's column density, its default rendering (centre samples)
#   splash-exact  SPLASH with EXACT_RENDERING=T (Petkova et al. 2018)
#   sky           orrery, exact SPH column density over the whole sky, an
#                 equirectangular map (W x W/2) from the dome's camera
#                 (the Sun; one scale radius from the Plummer sphere's
#                 centre), camera.dim: mass per area along each ray
#   splash-360    SPLASH -360 from the same point: the same quantity on the
#                 same grid (docs/splash.md, "All-sky maps")
# The orthographic views are the same for all: the pair 1200 kpc across,
# centred between the galaxies (x-y plane); the Plummer sphere 8 across.
#
# Each run is timed twice: the view, and the same scene with the view moved
# off the particles (everything read, projected, culled and written; nothing
# drawn). splat = view - empty: the rendering alone, as the goals are about
# rendering, not reading files (the method of bench/bench_splash.sh). A sky
# map has no "off": its empty view (both programs) is seen from 10^6 units
# away along -x, every particle a sub-pixel kernel at the map's centre, so
# its splat leaves out the cost of drawing N points (0.2 s of CPU for
# SPLASH at 10^6).
# Wall and CPU seconds from bash's `time` (ms resolution); peak resident
# memory from GNU time (%M). The fastest of REPEAT is kept for each figure
# (the largest for memory). Particles/s = N / splat wall seconds.
# orrery's runs are also timed in memory (bench_inmemory: the file read
# once, the scene rendered from the arrays, only the frame's splat timed):
# the "mem splat" column, which the NGP and dome goals are judged on, since
# nearest-pixel binning of 1e7 particles takes tens of milliseconds, less
# than the noise of two whole runs. The SPH-against-SPLASH ratios use the
# subtraction for both programs (SPLASH cannot be timed in memory).
#
# Environment (defaults give a quick run of a few minutes):
#   ORRERY    orrery binary (default: build/orrery of the source tree)
#   SNAPSHOT_TOOL  the generator (default: bench/bench_snapshot next to ORRERY)
#   INMEMORY  the in-memory timer (default: bench/bench_inmemory next to ORRERY)
#   PLAIN     the yardstick for the ngp runs, a plain C binning loop on the
#             same particles and view (default: bench/bench_plain_ngp next to ORRERY)
#   MODELS    "pair plummer"      SIZES   "1e6"      IMAGES  "1024"
#   SKY_IMAGES  "1024": widths of the all-sky maps (height half of it)
#   RUNS      "ngp dome sph splash splash-exact sky splash-360"
#   EXACT_MAX_N, EXACT_MAX_NPIX   SPLASH exact runs only up to these (1e6,
#             1024): it takes 15 s for the 1e6 pair, minutes at 1e7 or 3600^2
#   THREADS   2                   REPEAT  1
#   COMPARE   1: at 1024^2, compare orrery's SPH image with SPLASH exact's in
#             the well-sampled pixels (bench/compare_scale.py; numpy, astropy);
#             and at every sky width, orrery's sky with SPLASH -360's
#             (bench/compare_sky.py)
#   MAPDIR    if set, the sky maps compared are copied here (orrery's FITS,
#             SPLASH's .pix), for a closer look
#   SNAPDIR   keep the snapshots here and reuse them (default: a temporary
#             folder, removed at the end; 440 MB a snapshot at 1e7)
# SPLASH rows are skipped (with a note) where splash is not installed.
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
ORRERY=${ORRERY:-$root/build/orrery}
SNAPSHOT_TOOL=${SNAPSHOT_TOOL:-$(dirname "$ORRERY")/bench/bench_snapshot}
INMEMORY=${INMEMORY:-$(dirname "$ORRERY")/bench/bench_inmemory}
PLAIN=${PLAIN:-$(dirname "$ORRERY")/bench/bench_plain_ngp}
MODELS=${MODELS:-pair plummer}
SIZES=${SIZES:-1e6}
IMAGES=${IMAGES:-1024}
SKY_IMAGES=${SKY_IMAGES:-1024}
RUNS=${RUNS:-ngp dome sph splash splash-exact sky splash-360}
EXACT_MAX_N=${EXACT_MAX_N:-1e6}
EXACT_MAX_NPIX=${EXACT_MAX_NPIX:-1024}
THREADS=${THREADS:-2}
REPEAT=${REPEAT:-1}
COMPARE=${COMPARE:-1}
SNAPDIR=${SNAPDIR:-}
MAPDIR=${MAPDIR:-}

die() { echo "bench_scale: $*" >&2; exit 2; }
[ -x "$ORRERY" ] || die "orrery binary not found: $ORRERY (set ORRERY)"
[ -x "$SNAPSHOT_TOOL" ] || die "generator not found: $SNAPSHOT_TOOL (build bench_snapshot, or set SNAPSHOT_TOOL)"
[ -x "$INMEMORY" ] || die "in-memory timer not found: $INMEMORY (build bench_inmemory, or set INMEMORY)"
[ -x "$PLAIN" ] || die "plain C yardstick not found: $PLAIN (build bench_plain_ngp, or set PLAIN)"
[ -x /usr/bin/time ] || die "GNU time (/usr/bin/time) is needed for peak memory"
have_splash=0
command -v splash >/dev/null && have_splash=1
py=/usr/bin/python3
[ -x "$py" ] || py=python3
if [ "$COMPARE" = 1 ] && ! "$py" -c "import numpy, astropy" 2>/dev/null; then
  echo "note: numpy and astropy not found, images not compared" >&2
  COMPARE=0
fi
for m in $MODELS; do case $m in pair | plummer) ;; *) die "MODELS: unknown model '$m' (pair, plummer)" ;; esac; done
for r in $RUNS; do case $r in ngp | dome | sph | splash | splash-exact | sky | splash-360) ;; *) die "RUNS: unknown run '$r'" ;; esac; done
for v in $SIZES $IMAGES $SKY_IMAGES $EXACT_MAX_N $EXACT_MAX_NPIX $THREADS $REPEAT; do
  awk -v v="$v" 'BEGIN { exit !(v + 0 >= 1 && v == v + 0) }' || die "'$v' is not a positive number"
done
for v in $SKY_IMAGES; do [ $((v % 2)) = 0 ] || die "SKY_IMAGES: width $v is odd (the map is 2:1)"; done

work=$(mktemp -d /tmp/orrery-bench-scale-XXXXXX)
trap 'rm -rf "$work"' EXIT
[ -n "$SNAPDIR" ] || SNAPDIR=$work
mkdir -p "$SNAPDIR" || die "cannot create $SNAPDIR"
SNAPDIR=$(cd "$SNAPDIR" && pwd)
if [ -n "$MAPDIR" ]; then
  mkdir -p "$MAPDIR" || die "cannot create $MAPDIR"
  MAPDIR=$(cd "$MAPDIR" && pwd)
fi
cd "$work" || exit 1
export OMP_NUM_THREADS=$THREADS

calc() { awk "BEGIN { $1 }" </dev/null; }
le() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 <= b + 0) }'; }

# The view of each model: orthographic width, centre (x y), dome camera (x y z).
view_width() { [ "$1" = pair ] && echo 1200 || echo 8; }
view_centre() { [ "$1" = pair ] && echo "-190.8 308.8" || echo "0 0"; }
observer() { [ "$1" = pair ] && echo "-8 0 0.02" || echo "1 0 0"; } # the dome's and the sky's camera
dome_camera() { observer "$1" | sed 's/ /, /g'; }
OFF=1e6 # the empty views: the orthographic view moved this far in x; the
        # dome camera this far up (+z, its zenith), every particle below its
        # horizon; the sky's camera this far along -x (everything at l = 0)
is_sky() { case $1 in sky | splash-360) return 0 ;; esac; return 1; }

# measure LOG CMD...: runs CMD (output to LOG); prints "wall cpu peak_kB".
measure() {
  local log=$1 t
  shift
  t=$( { TIMEFORMAT='%3R %3U %3S'; time /usr/bin/time -f '%M' -o rss.txt "$@" >"$log" 2>&1; } 2>&1) ||
    { echo "bench_scale: failed: $* (log: $(tail -3 "$log"))" >&2; exit 1; }
  echo "$t $(tail -1 rss.txt)" | awk '{ printf "%s %.3f %s\n", $1, $2 + $3, $4 }'
}

# orrery_scene FILE SNAP KIND NPIX EMPTY(0|1) MODEL: SNAP "insitu"
# makes the scene of bench_inmemory (particles from memory, nothing written).
orrery_scene() {
  local file=$1 snap=$2 kind=$3 npix=$4 empty=$5 model=$6 camera deposit input="{file: $2}"
  local output="{dir: out, name: $kind$empty, png: false}"
  [ "$snap" = insitu ] && input="{insitu: true}" output="{name: $kind, fits: false, png: false}"
  read -r cx cy <<<"$(view_centre "$model")"
  [ "$empty" = 1 ] && cx=$(calc "print $cx + $OFF")
  camera="{projection: orthographic, width: $(view_width "$model"), position: [$cx, $cy, 0]}"
  deposit=ngp height=$npix
  if [ "$kind" = dome ]; then
    camera="{projection: dome, position: [$(dome_camera "$model")]}"
    [ "$empty" = 1 ] && camera="{projection: dome, position: [0, 0, $OFF]}"
  fi
  if [ "$kind" = sky ]; then # mass per area along each ray: SPLASH -360's quantity
    local pos
    pos=$(dome_camera "$model")
    [ "$empty" = 1 ] && pos="-$OFF, 0, 0"
    camera="{projection: equirectangular, position: [$pos], dim: true}"
    height=$((npix / 2))
  fi
  case $kind in sph | sky) deposit="sph
smoothing: {kernel: cubic, lengths: file}" ;;
  esac
  cat >"$file" <<EOF
input: $input
deposit: $deposit
camera: $camera
image: {width: $npix, height: $height}
output: $output
EOF
}

# SPLASH reads splash.defaults and splash.limits from the current folder:
# its defaults saved from the menu, then the cubic kernel, no normalisation,
# no accelerated rendering (docs/splash.md).
splash_setup() {
  rm -f splash.defaults
  printf 's\nq\n' | splash -f gadget "$1" >/dev/null 2>&1
  [ -f splash.defaults ] || die "splash did not write splash.defaults"
  splash_set IKERNEL 1
  splash_set INORMALISE_INTERPOLATIONS F
  splash_set IFASTRENDER F
  splash_set IDENSITYWEIGHTEDINTERPOLATION F
  sky360_setup
}
splash_set() {
  grep -q "^ $1=" splash.defaults || die "splash.defaults has no $1"
  sed -i "s/^ $1=.*/ $1=$2,/" splash.defaults
}
# SPLASH -360 runs in its own folder (sky360/), with the same settings
# plus: spherical coordinates (r, phi, theta; -360 does not set them when a
# splash.defaults exists), no exact rendering, and the image's size from a
# device of W x W/2 pixels with no axes and no colour bar (with NPIX its rows
# would be as many as its columns; with -dev /null it is 1 x 1); the limits
# phi -pi..pi, theta 0..pi (docs/splash.md, "All-sky maps").
sky360_setup() {
  rm -rf sky360
  { mkdir sky360 && cp splash.defaults sky360/; } || die "cannot set up sky360/"
  (
    cd sky360 || exit 1
    splash_set ICOORDSNEW 3
    splash_set EXACT_RENDERING F
    splash_set NPIX 0
    splash_set IPAPERSIZE 24
    splash_set IPAPERSIZEUNITS 0
    splash_set ASPECTRATIO 0.5
    splash_set IAXIS -2
    splash_set ICOLOURBARSTYLE 0
    awk 'BEGIN { pi = atan2(0, -1); printf "0 1e30\n%.15g %.15g\n0 %.15g\n", -pi, pi, pi
      for (i = 0; i < 7; i++) print "0 1" }' >splash.limits
  ) || exit 1
}
# sky360_origin MODEL EMPTY: SPLASH's -360 projection adds XORIGIN to the
# positions (interpolate3D_proj_geom), so it looks from -XORIGIN.
sky360_origin() {
  local x y z
  read -r x y z <<<"$(observer "$1")"
  [ "$2" = 1 ] && x=-$OFF y=0 z=0
  (cd sky360 && splash_set XORIGIN "$(awk -v x="$x" -v y="$y" -v z="$z" 'BEGIN { printf "%.9g, %.9g, %.9g", -x, -y, -z }')") || exit 1
}
# splash_limits MODEL EMPTY: x and y of the view (10 columns: x y z vx vy vz m u rho h).
splash_limits() {
  read -r cx cy <<<"$(view_centre "$1")"
  awk -v cx="$cx" -v cy="$cy" -v w="$(view_width "$1")" -v off="$([ "$2" = 1 ] && echo $OFF || echo 0)" 'BEGIN {
    printf "%.9g %.9g\n%.9g %.9g\n-1e30 1e30\n", cx + off - w / 2, cx + off + w / 2, cy - w / 2, cy + w / 2
    for (i = 0; i < 7; i++) print "0 1" }' >splash.limits
}

# run_one MODEL N NPIX KIND SNAP EMPTY LOG: one timing; prints "wall cpu kB".
run_one() {
  local model=$1 n=$2 npix=$3 kind=$4 snap=$5 empty=$6 log=$7 out=""
  case $kind in
  ngp | dome | sph | sky)
    orrery_scene scene.yaml "$snap" "$kind" "$npix" "$empty" "$model"
    measure "$log" "$ORRERY" render scene.yaml
    ;;
  splash-360)
    (cd sky360 && splash_set PAPERSIZEX "$npix.") || exit 1
    sky360_origin "$model" "$empty"
    # The map is written at every width compared (view and empty alike).
    [ "$COMPARE" = 1 ] && out="-o ascii"
    cd sky360 || exit 1
    rm -f ./*_columndensity_proj.pix ./*.png
    # shellcheck disable=SC2086
    measure "../$log" splash -360 -f gadget -x 2 -y 3 -r 9 -dev sky.png $out "$snap"
    grep -q "projecting (non-cartesian): *$npix x *$((npix / 2)) on *$THREADS cpus" "../$log" ||
      die "splash -360 did not render $npix x $((npix / 2)) on $THREADS cpus: $(grep -i projecting "../$log")"
    if [ -n "$out" ] && [ "$empty" = 0 ]; then
      mv "$(basename "$snap")"_columndensity_proj.pix "../splash-360-$model-$n-$npix.pix" || die "SPLASH -360 wrote no map"
    fi
    ;;
  splash | splash-exact)
    splash_set NPIX "$npix"
    splash_set EXACT_RENDERING "$([ "$kind" = splash-exact ] && echo T || echo F)"
    splash_limits "$model" "$empty"
    # The exact map at 1024^2 is written (view and empty alike, so the
    # splatting time is unchanged) for the comparison with orrery's.
    [ "$kind" = splash-exact ] && [ "$npix" = 1024 ] && [ "$COMPARE" = 1 ] && out="-o ascii"
    rm -f ./*_columndensity_proj.pix
    # shellcheck disable=SC2086
    measure "$log" splash -f gadget -x 1 -y 2 -r 9 -dev /null $out "$snap"
    grep -q "projecting.*: *$npix x *$npix on *$THREADS cpus" "$log" ||
      die "splash did not render $npix x $npix on $THREADS cpus: $(grep -i projecting "$log")"
    if [ -n "$out" ] && [ "$empty" = 0 ]; then
      mv "$(basename "$snap")"_columndensity_proj.pix "splash-exact-$model-$n.pix" || die "SPLASH wrote no map"
    fi
    ;;
  esac
}

declare -A WALL CPU SWALL SCPU RSS MWALL MCPU
key_list=()
# bench MODEL N NPIX KIND SNAP: REPEAT timings of the view and the empty
# view; keeps the fastest of each and the largest peak memory.
bench() {
  local key="$1 $2 $3 $4" r v e
  local bw="" bc="" ew="" ec="" rss=0
  for r in $(seq "$REPEAT"); do
    v=$(run_one "$@" 0 "$4-view.log") || exit 1
    e=$(run_one "$@" 1 "$4-empty.log") || exit 1
    read -r vw vc vr <<<"$v"
    read -r eww ecc _ <<<"$e"
    echo "    $4 run $r: view $vw s wall, $vc s CPU, $((vr / 1024)) MB; empty view $eww s wall, $ecc s CPU"
    bw=$(calc "print ($bw+0 == 0 || $vw < $bw+0) ? $vw : $bw+0")
    bc=$(calc "print ($bc+0 == 0 || $vc < $bc+0) ? $vc : $bc+0")
    ew=$(calc "print ($ew+0 == 0 || $eww < $ew+0) ? $eww : $ew+0")
    ec=$(calc "print ($ec+0 == 0 || $ecc < $ec+0) ? $ecc : $ec+0")
    [ "$vr" -gt "$rss" ] && rss=$vr
  done
  case $4 in
  ngp | dome | sph | sky)
    grep -h "weight in the image" "$4-view.log" | sed 's/^ */    orrery: /'
    orrery_scene mem.yaml insitu "$4" "$3" 0 "$1"
    "$INMEMORY" "$5" mem.yaml "$REPEAT" >mem.log 2>&1 || die "bench_inmemory failed: $(cat mem.log)"
    sed 's/^/    in memory: /' mem.log
    read -r mw mc <<<"$(awk '{ print $5, $8 }' mem.log)"
    MWALL[$key]=$mw MCPU[$key]=$mc
    ;;
  esac
  if [ "$4" = ngp ]; then # the yardstick: a plain C loop on the same particles and view
    read -r cx cy <<<"$(view_centre "$1")"
    "$PLAIN" "$5" "$cx" "$cy" "$(view_width "$1")" "$3" "$REPEAT" >plain.log 2>&1 ||
      die "bench_plain_ngp failed: $(cat plain.log)"
    sed 's/^/    /' plain.log
    plain+=("$1 N=$2 $3^2: $(awk '{ print $10 }' plain.log) particles/s (orrery in memory: $(calc "printf \"%.3g\", $2 / ${MWALL[$key]}"))")
  fi
  # SPLASH's own timer of its interpolation (printed from 5 s on), view's last run.
  case $4 in splash*) grep -h "pixel size > 2h\|completed in" "$4-view.log" | sed 's/^ */    SPLASH: /' ;; esac
  WALL[$key]=$bw CPU[$key]=$bc SWALL[$key]=$(calc "printf \"%.3f\", $bw - $ew") SCPU[$key]=$(calc "printf \"%.3f\", $bc - $ec")
  RSS[$key]=$((rss / 1024))
  key_list+=("$key")
}

# verdict VALUE GOAL: "met" when VALUE >= GOAL; "unresolved" (a splatting
# time of zero or less: the view and the empty view differ by less than
# their noise) gives no verdict.
verdict() {
  if [ "$1" = unresolved ]; then echo "unresolved (splat time <= 0)"; elif le "$2" "$1"; then echo met; else echo "NOT met"; fi
}

# The goal column of a row, from the figures of its case.
goal() {
  local model=$1 n=$2 npix=$3 kind=$4 key="$1 $2 $3 $4" s rate words=""
  # (not "print a > 0 ? ...": awk reads that as printing to a file named 0)
  rate=$(calc "if (${MWALL[$key]:-0} > 0) print $n / ${MWALL[$key]:-0}; else print 0")
  [ "$kind" = ngp ] && [ "$npix" = 1024 ] && words=">= 4e8/s: $(verdict "$rate" 4e8)"
  [ "$kind" = dome ] && [ "$npix" = 3600 ] && words=">= 2e8/s: $(verdict "$rate" 2e8)"
  if [ "$kind" = sph ] && [ "$npix" = 1024 ]; then
    # Issue 24's goal: 3x SPLASH's default mode, staying exact (the former
    # 10x and 50x, against its exact mode, were withdrawn: docs/performance.md).
    for s in splash:3; do
      local sk="$model $n $npix ${s%:*}"
      [ -n "${SWALL[$sk]:-}" ] || continue
      local times=unresolved
      le "${SWALL[$key]}" 0 || times=$(calc "print ${SWALL[$sk]} / ${SWALL[$key]}")
      words="$words${words:+; }${s#*:}x ${s%:*}: $(verdict "$times" "${s#*:}")"
    done
  fi
  if [ "$kind" = sky ] && [ -n "${SWALL[$model $n $npix splash-360]:-}" ]; then
    local times=unresolved
    le "${SWALL[$key]}" 0 || times=$(calc "print ${SWALL[$model $n $npix splash-360]} / ${SWALL[$key]}")
    words="3x splash-360: $(verdict "$times" 3)"
  fi
  if [ "$kind" = sph ] && le 1e7 "$n" && [ -n "${RSS[$model $n $npix splash]:-}" ]; then
    words="$words${words:+; }memory <= splash: $(verdict "${RSS[$model $n $npix splash]}" "${RSS[$key]}")"
  fi
  echo "${words:--}"
}

# The orrery/SPLASH column of a row: SPLASH's splat seconds over orrery's
# (how many times faster orrery renders), for each SPLASH mode measured.
versus() {
  local key="$1 $2 $3 $4" out="" s sk rivals="splash splash-exact"
  case $4 in sph) ;; sky) rivals=splash-360 ;; *) echo "-"; return ;; esac
  for s in $rivals; do
    sk="$1 $2 $3 $s"
    [ -n "${SWALL[$sk]:-}" ] || continue
    out="$out${out:+, }$s $(calc "if (${SWALL[$key]} > 0) printf \"%.1fx\", ${SWALL[$sk]} / ${SWALL[$key]}; else print \"-\"")"
  done
  echo "${out:--}"
}

# bench_runs MODEL N NN SIDE SNAP SKY(0|1): the runs of RUNS that draw
# flat images (SKY 0) or the whole sky (SKY 1) at this side (width).
bench_runs() {
  local model=$1 n=$2 nn=$3 npix=$4 snap=$5 sky=$6 kind
  for kind in $RUNS; do
    if is_sky "$kind"; then [ "$sky" = 1 ] || continue; else [ "$sky" = 0 ] || continue; fi
    case $kind in
    splash*) [ "$have_splash" = 1 ] || continue ;;
    esac
    if [ "$kind" = splash-exact ] && ! { le "$n" "$EXACT_MAX_N" && le "$npix" "$EXACT_MAX_NPIX"; }; then
      echo "    splash-exact: not run (N > EXACT_MAX_N=$EXACT_MAX_N or side > EXACT_MAX_NPIX=$EXACT_MAX_NPIX)"
      continue
    fi
    bench "$model" "$nn" "$npix" "$kind" "$snap"
  done
}

# compare_sky MODEL N NN WIDTH SNAP: orrery's sky against SPLASH -360's.
compare_sky() {
  local model=$1 n=$2 nn=$3 npix=$4 snap=$5 map="splash-360-$1-$3-$4.pix"
  [ "$COMPARE" = 1 ] && [ -f "$map" ] && [ -f out/sky0.fits ] || return 0
  echo "    orrery sky against SPLASH -360 (bench/compare_sky.py):"
  if [ -n "$MAPDIR" ]; then
    cp out/sky0.fits "$MAPDIR/sky-$model-$nn-$npix.fits" && cp "$map" "$MAPDIR/" || die "cannot copy the maps to $MAPDIR"
  fi
  # shellcheck disable=SC2046
  "$py" "$here/compare_sky.py" out/sky0.fits "$map" "$snap" $(observer "$model") >compare.log 2>&1 ||
    { cat compare.log; die "the sky comparison failed"; }
  sed 's/^/      /' compare.log
  sky_agreement+=("$model N=$n ${npix}x$((npix / 2)): $(grep -o 'well sampled: [0-9.]* %' compare.log | head -1) of the pixels,\
 $(grep -o 'within 1 %: [0-9.]* % of those' compare.log | head -1), median ratio\
 $(grep -o 'SPLASH median [0-9.]*' compare.log | head -1 | cut -d' ' -f3) ($(grep -o 'agreement.*' compare.log | cut -d' ' -f2))")
  rm -f "$map"
}

echo "orrery: $ORRERY"
[ "$have_splash" = 1 ] && echo "splash: $(command -v splash)" || echo "splash: not installed, SPLASH rows skipped"
echo "threads: $THREADS, repeats: $REPEAT; $(date -u '+%Y-%m-%d %H:%M UTC'); load average at start:$(cut -d' ' -f1-3 /proc/loadavg | sed 's/^/ /')"
flat_runs="" sky_runs=""
for r in $RUNS; do if is_sky "$r"; then sky_runs+=" $r"; else flat_runs+=" $r"; fi; done
agreement=()
sky_agreement=()
plain=()
for model in $MODELS; do
  for n in $SIZES; do
    nn=$(calc "printf \"%d\", $n")
    snap=$SNAPDIR/$model-$n.gadget
    if [ ! -f "$snap" ]; then
      echo "== writing $snap"
      "$SNAPSHOT_TOOL" "$model" "$nn" "$snap" | sed 's/^/    /' || die "bench_snapshot failed"
    fi
    [ "$have_splash" = 1 ] && splash_setup "$snap"
    for npix in $IMAGES; do
      [ -n "$flat_runs" ] || break
      echo "== $model, N = $n, $npix x $npix"
      bench_runs "$model" "$n" "$nn" "$npix" "$snap" 0
      if [ "$COMPARE" = 1 ] && [ -f "splash-exact-$model-$nn.pix" ] && [ -f out/sph0.fits ] && [ "$npix" = 1024 ]; then
        echo "    orrery sph against SPLASH exact (bench/compare_scale.py):"
        read -r cx cy <<<"$(view_centre "$model")"
        "$py" "$here/compare_scale.py" out/sph0.fits "splash-exact-$model-$nn.pix" "$snap" "$(view_width "$model")" "$cx" "$cy" >compare.log 2>&1 ||
          { cat compare.log; die "the comparison failed"; }
        sed 's/^/      /' compare.log
        agreement+=("$model N=$n $npix^2: $(grep -v '^agreement' compare.log | grep -o 'well sampled.*of those' | head -1) ($(grep -o 'agreement.*' compare.log | cut -d' ' -f2))")
        rm -f "splash-exact-$model-$nn.pix"
      fi
      rm -rf out
    done
    for npix in $SKY_IMAGES; do
      [ -n "$sky_runs" ] || break
      echo "== $model, N = $n, the whole sky from ($(observer "$model")), $npix x $((npix / 2))"
      bench_runs "$model" "$n" "$nn" "$npix" "$snap" 1
      compare_sky "$model" "$n" "$nn" "$npix" "$snap"
      rm -rf out
    done
  done
done

echo
echo "load average at the end:$(cut -d' ' -f1-3 /proc/loadavg | sed 's/^/ /')"
row='%-8s %4s %9s %-13s %8s %8s %10s %9s %11s %8s %10s %8s %11s  %-31s %s\n'
# shellcheck disable=SC2059
printf "$row" model N image run "wall s" "CPU s" "splat wall" "splat CPU" "particles/s" "peak MB" \
  "mem splat" "mem CPU" "mem part/s" "SPLASH splat / orrery's" goal
for key in "${key_list[@]}"; do
  read -r model n npix kind <<<"$key"
  rate=$(calc "if (${SWALL[$key]} > 0) printf \"%.3g\", $n / ${SWALL[$key]}; else print \"-\"")
  mrate=$(calc "if (${MWALL[$key]:-0} > 0) printf \"%.3g\", $n / ${MWALL[$key]:-0}; else print \"-\"")
  image=$npix
  is_sky "$kind" && image=${npix}x$((npix / 2))
  # shellcheck disable=SC2059
  printf "$row" "$model" "$(calc "printf \"%.0e\", $n" | sed 's/e+0*/e/')" \
    "$image" "$kind" "${WALL[$key]}" "${CPU[$key]}" "${SWALL[$key]}" "${SCPU[$key]}" "$rate" "${RSS[$key]}" \
    "${MWALL[$key]:--}" "${MCPU[$key]:--}" "$mrate" "$(versus $key)" "$(goal $key)"
done
if [ ${#plain[@]} -gt 0 ]; then
  echo
  echo "yardstick: a plain C loop binning the same particles into the orthographic view (bench_plain_ngp):"
  printf '  %s\n' "${plain[@]}"
fi
if [ ${#agreement[@]} -gt 0 ]; then
  echo
  echo "agreement with SPLASH exact (goal: within 1 % in every well-sampled pixel):"
  printf '  %s\n' "${agreement[@]}"
fi
if [ ${#sky_agreement[@]} -gt 0 ]; then
  echo
  echo "agreement of the sky with SPLASH -360 (goal: within 1 % where well sampled):"
  printf '  %s\n' "${sky_agreement[@]}"
fi
