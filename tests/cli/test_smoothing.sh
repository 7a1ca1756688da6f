# SPH deposit and PSFs through the command line: smoothing lengths from the
# neighbours for a table without h, kernels in perspective and on a dome
# master, Gaussian and Hubble PSFs on flat views. Each render must keep the
# mass: what lands in the image plus what falls off it is the whole table
# (1.0: 2000 particles of 0.0005), read back from the FITS header.
source "$(dirname "$0")/lib.sh"
table=$SRC/examples/plummer-sphere.txt

py=/usr/bin/python3
[ -x "$py" ] || py=python3

# header_value FILE KEY: a card of the first HDU, read by astropy.
header_value() {
  "$py" -c "import sys; from astropy.io import fits; print(repr(fits.getheader(sys.argv[1])[sys.argv[2]]))" "$1" "$2"
}

# render NAME EXPECTED_TOTAL SCENE-LINES...: renders, then checks WIMAGE + WOUTSIDE.
render() {
  local name=$1 total=$2
  shift 2
  {
    echo "input:"
    echo "  file: $table"
    for line in "$@"; do echo "$line"; done
    echo "output:"
    echo "  dir: out"
    echo "  name: $name"
    echo "  png: false"
  } >"$name.yaml"
  if ! "$ORRERY" render --quiet "$name.yaml" 2>err.txt; then
    fail "$name: $(cat err.txt)"
    return
  fi
  local in off
  in=$(header_value "out/$name.fits" WIMAGE)
  off=$(header_value "out/$name.fits" WOUTSIDE)
  awk -v a="$in" -v b="$off" -v t="$total" 'BEGIN { d = a + b - t; if (d < 0) d = -d; exit !(d <= 1e-5 * t) }' ||
    fail "$name: image $in + outside $off != $total"
  grep -q "AddressSanitizer\|runtime error" err.txt && fail "$name: sanitizer report: $(cat err.txt)"
}

persp=("camera:" "  position: [0, 0, 30]" "  look_at: [0, 0, 0]" "  projection: perspective" "  fov: 40"
  "image:" "  width: 160" "  height: 120")
render sph-perspective 1.0 "${persp[@]}" "deposit: sph"
render sph-wendland 1.0 "${persp[@]}" "deposit: sph" "smoothing:" "  kernel: wendland-c4" "  neighbours: 8"
grep -q "HSOURCE = 'neighbours'" out/sph-perspective.fits || fail "sph-perspective: lengths not from the neighbours"
# A Gaussian PSF on a flat view moves light, it does not make or lose it: the
# convolved plane's sum equals the deposited weight (astropy sums it).
render psf-gaussian 1.0 "${persp[@]}" "psf:" "  kind: gaussian" "  fwhm: 3"
render psf-hst 1.0 "${persp[@]}" "psf:" "  kind: hst" "  size: 31"
for name in psf-gaussian psf-hst; do
  "$py" -c "
import sys, numpy as np
from astropy.io import fits
h = fits.open(sys.argv[1])[0]
# Pixels hold weight per steradian: times each pixel's solid angle, f / r^3
# at its centre for the 160 x 120 frame of 40 degrees across (f in pixels).
f = 80 / np.tan(np.radians(20))
y, x = np.mgrid[0:120, 0:160] + 0.5
omega = f / ((x - 80) ** 2 + (y - 60) ** 2 + f * f) ** 1.5
s, w = float(np.nansum(h.data.astype(np.float64) * omega)), h.header['WIMAGE']
# light the PSF carries past the image's edges is lost, a little
sys.exit(0 if abs(s - w) <= 2e-2 * w and s <= w * (1 + 1e-5) else 1)" "out/$name.fits" ||
    fail "$name: the convolved image's sum differs from the deposited weight"
done
# On a dome master around the sphere's centre, every particle is on the sky
# (a 360-degree dome): all the mass but the observer's (not drawn) is in
# the image, none off it.
render sph-dome 0.9995 "observer:" "  id: 0" "  reference_id: 1" "  dim: false" \
  "camera:" "  projection: dome" "  dome_fov: 360" "image:" "  width: 201" "  height: 201" "deposit: sph"

# A run of frames over one file finds the smoothing lengths once and keeps
# them (render/plan.c, lengths_key): the frames are those rendered one by
# one (pixels identical), and the run's lengths stage costs about one
# frame's, not three (CPU seconds of --timings: at most 2 times one frame's).
"$ORRERY" ics --zeldovich --grid 32 --box 100 --evolve -o box.hdf5 >/dev/null 2>err.txt || fail "ics: $(cat err.txt)"
du=(--set input.file="$PWD/box.hdf5" --set animation.frames=3 --set image.width=96 --set image.height=50
  --set psf.fwhm=1)
"$ORRERY" render "$SRC/configs/dark-universe.yaml" -o run "${du[@]}" --timings >run.txt 2>&1 ||
  fail "a run of 3 frames: $(cat run.txt)"
"$ORRERY" render "$SRC/configs/dark-universe.yaml" -o alone "${du[@]}" --frames 0 --timings >alone.txt 2>&1 ||
  fail "frame 0 alone: $(cat alone.txt)"
for f in 1 2; do
  "$ORRERY" render "$SRC/configs/dark-universe.yaml" -o alone "${du[@]}" --frames $f --quiet 2>err.txt ||
    fail "frame $f alone: $(cat err.txt)"
done
"$py" - <<'PY' || fail "frames of a run differ from frames rendered alone"
import numpy as np
from astropy.io import fits
for f in range(3):
    a, b = (fits.getdata(f"{d}/dark-universe_{f:04d}.fits") for d in ("run", "alone"))
    assert np.array_equal(a, b), f"frame {f}"
PY
cpu_of_lengths() { awk '$1 == "lengths" && NF == 4 { print $3 }' "$1" | tail -1; }
run_cpu=$(cpu_of_lengths run.txt)
one_cpu=$(cpu_of_lengths alone.txt)
awk -v r="$run_cpu" -v o="$one_cpu" 'BEGIN { exit !(o > 0 && r < 2 * o) }' ||
  fail "the run's lengths took $run_cpu s of CPU for 3 frames, one frame's $one_cpu s: found again every frame?"

# The glow's lengths left at a bound where a particle's own kernel is the
# wider (pass/lengths.h) change no bit: Future Sky small, with the bound and
# with every length searched (ORRERY_EXACT_LENGTHS=1).
sky=(--set input.model.particles=20000 --set views.dome.image.width=128 --set views.dome.image.height=128
     --set views.panorama.image.width=128 --set views.panorama.image.height=64 --set output.png=false)
"$ORRERY" render "$SRC/configs/futuresky.yaml" "${sky[@]}" -o bounded >bounded.txt 2>&1 || fail "futuresky, bounded: $(cat bounded.txt)"
ORRERY_EXACT_LENGTHS=1 "$ORRERY" render "$SRC/configs/futuresky.yaml" "${sky[@]}" -o exact >exact.txt 2>&1 ||
  fail "futuresky, exact: $(cat exact.txt)"
grep -q "the glow's lengths: [1-9][0-9]* of [0-9]* left at a bound" bounded.txt || fail "no lengths bounded: $(cat bounded.txt)"
grep -q "left at a bound" exact.txt && fail "ORRERY_EXACT_LENGTHS=1 still bounded lengths"
"$py" - <<'PY' || fail "the bounded lengths changed the images"
import numpy as np
from astropy.io import fits
for view in ("dome", "panorama"):
    with fits.open(f"bounded/futuresky-{view}.fits") as a, fits.open(f"exact/futuresky-{view}.fits") as b:
        planes = [(x.data, y.data) for x, y in zip(a, b) if x.data is not None and x.data.ndim == 2]
        assert len(planes) == 3 and len(a) == len(b), view
        for x, y in planes: # (bit for bit; NaN off the map)
            assert x.tobytes() == y.tobytes() and np.nansum(x) > 0, view
PY

# Errors: spike stars on a flat view without psf.fwhm (which convolves every star with the
# whole PSF); lengths from a file without them.
mkdir -p empty
write_scene bad1.yaml "$table" "psf:" "  kind: hst" "  spike_stars: 10"
expect_fail 2 "psf.spike_stars is for psf.kind: hst or file on sky maps, or on flat views with psf.fwhm" empty -- render bad1.yaml -o empty
write_scene bad2.yaml "$table" "deposit: sph" "smoothing:" "  lengths: file"
expect_fail 1 "smoothing.lengths is file, but .*plummer-sphere.txt has no smoothing lengths" empty -- render bad2.yaml -o empty
finish
