# Smoke tests of the case studies (docs/gallery.md) at tiny sizes: each
# scene renders, and its output has the structure the paper describes.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
check="$py $SRC/tests/cli/check_case_studies.py"

# Future Sky: the Milky Way band along the panorama's equator (without its
# dust), and with it a dark lane along the band.
small="--set input.model.particles=30000 --set views.dome.image.width=64 --set views.dome.image.height=64
  --set views.panorama.image.width=128 --set views.panorama.image.height=64"
"$ORRERY" render "$SRC/configs/futuresky.yaml" -o fs $small --set input.model.dust_particles=0 >run.out 2>run.err \
  || fail "futuresky: $(cat run.err)"
[ -s fs/futuresky-dome.png ] || fail "futuresky: no dome master: $(ls fs)"
$check band fs/futuresky-panorama.fits || fail "futuresky: no band on the equator"
"$ORRERY" render "$SRC/configs/futuresky.yaml" -o fsd $small --set input.model.dust_particles=5000 >run.out 2>run.err \
  || fail "futuresky with dust: $(cat run.err)"
$check lane fsd/futuresky-panorama.fits fs/futuresky-panorama.fits || fail "futuresky: no dark dust lane"

# Spiral Metamorphosis: both views written; face-on round, edge-on flat and
# horizontal; redder in the centre.
"$ORRERY" render "$SRC/configs/spiral-metamorphosis.yaml" -o sp --set input.model.particles=30000 --set input.model.dust_particles=3000 \
  --set image.width=160 --set image.height=160 >run.out 2>run.err || fail "spiral: $(cat run.err)"
for v in faceon edgeon; do
  [ -s sp/spiral-$v.png ] && [ -s sp/spiral-$v.fits ] || fail "spiral: view $v missing: $(ls sp)"
done
$check views sp/spiral-faceon.fits sp/spiral-edgeon.fits sp/spiral-faceon.png || fail "spiral: view shapes or colours"

# The anaglyph: the near side's red image right of its cyan one (crossed
# parallax), the far side's left of it. A wide eye separation makes the
# parallax several pixels even at this size.
"$ORRERY" render "$SRC/configs/spiral-metamorphosis-anaglyph.yaml" -o an --set input.model.particles=30000 \
  --set image.width=192 --set image.height=108 --set stereo.eye_separation=40 >run.out 2>run.err \
  || fail "anaglyph: $(cat run.err)"
$check parallax an/spiral-anaglyph.png an/spiral-anaglyph.fits || fail "anaglyph: parallax sign"

# The evolving version (configs/spiral-metamorphosis-insitu.yaml and its
# anaglyph): the cameras look at the pair's centre of mass, where the
# galaxies meet, from the offsets the paper's views need...
"$ORRERY" model -o model.txt --particles 20000 >run.out 2>run.err || fail "model: $(cat run.err)"
$check cameras model.txt "$SRC/configs/spiral-metamorphosis-insitu.yaml" faceon:0,0,320 edgeon:0,-320,0 ||
  fail "spiral in-situ: cameras not on the centre of mass"
$check cameras model.txt "$SRC/configs/spiral-metamorphosis-anaglyph-insitu.yaml" -:0,-277.1,160 ||
  fail "spiral anaglyph in-situ: camera not on the centre of mass"
# ...which the galaxies reach only after 4 Gyr: for two steps the cameras
# are moved by the centre of mass back onto the Milky Way, and the example
# N-body code renders both views with E0 handed over (the populations select
# by it: without it every star would be young and blue, the centre no
# redder), with the scene's fixed white level.
NBODY=$(dirname "$ORRERY")/examples/orrery-nbody
if [ -x "$NBODY" ]; then
  "$NBODY" --particles 6000 --steps 2 --dt 0.01 --scene "$SRC/configs/spiral-metamorphosis-insitu.yaml" \
    --set output.dir=ns --set image.width=160 --set image.height=160 \
    --set "views.faceon.camera.position=[0, 0, 320]" --set "views.faceon.camera.look_at=[0, 0, 0]" \
    --set "views.edgeon.camera.position=[0, -320, 0]" --set "views.edgeon.camera.look_at=[0, 0, 0]" \
    --set views.faceon.camera.fov=20 --set views.edgeon.camera.fov=20 >run.out 2>run.err \
    || fail "spiral in-situ: $(cat run.err)"
  [ -s ns/spiral-faceon_0002.png ] && [ -s ns/spiral-edgeon_0002.png ] || fail "spiral in-situ frames: $(ls ns)"
  $check views ns/spiral-faceon_0002.fits ns/spiral-edgeon_0002.fits ns/spiral-faceon_0002.png \
    || fail "spiral in-situ: view shapes or colours"
  white=$(sed -n 's/^ *white: \([0-9.e+-]*\).*/\1/p' "$SRC/configs/spiral-metamorphosis-insitu.yaml")
  "$py" -c "import sys; from PIL import Image; d = Image.open(sys.argv[1]).info['Description']; \
sys.exit(0 if abs(float(d.rsplit(' ', 1)[1]) / float(sys.argv[2]) - 1) < 1e-5 else 'white: ' + d)" \
    ns/spiral-faceon_0002.png "$white" \
    || fail "spiral in-situ: not graded with the fixed white level $white"
  "$NBODY" --particles 6000 --steps 2 --dt 0.01 --scene "$SRC/configs/spiral-metamorphosis-anaglyph-insitu.yaml" \
    --set output.dir=na --set image.width=192 --set image.height=108 --set stereo.eye_separation=40 \
    --set "camera.position=[0, -277.1, 160]" --set "camera.look_at=[0, 0, 0]" --set camera.fov=24 \
    >run.out 2>run.err || fail "spiral anaglyph in-situ: $(cat run.err)"
  $check parallax na/spiral-anaglyph_0002.png na/spiral-anaglyph_0002.fits || fail "anaglyph in-situ: parallax sign"
fi
# scripts/band_share.py (docs/gallery.md, Future Sky) on a uniform sky, a
# plate carree map whose every pixel holds 1 per steradian: the share of
# the light within |b| < 15 deg is sin 15 deg = 0.259, and half the light
# lies within |b| < 30 deg (sin b = 1/2; to a pixel of 1 deg).
"$py" - <<'PY' || fail "a uniform sky for band_share.py"
import numpy as np
from astropy.io import fits
h = fits.Header({"CTYPE1": "GLON-CAR", "CTYPE2": "GLAT-CAR", "CRPIX1": 180.5, "CRPIX2": 90.5,
                 "CRVAL1": 0.0, "CRVAL2": 0.0, "CDELT1": -1.0, "CDELT2": 1.0})
fits.HDUList([fits.PrimaryHDU(), fits.ImageHDU(np.ones((180, 360), np.float32), h, name="Y")]).writeto("uniform.fits")
PY
band=$("$py" "$SRC/scripts/band_share.py" uniform.fits) || fail "band_share.py on a uniform sky"
echo "$band" | awk '{ for (i = 1; i <= NF; i++) { if ($i == "=" && $(i - 1) == "15)") s = $(i + 1); if ($i == "|b|" && $(i + 1) == "=") h = $(i + 2) } }
  END { exit !(s > 0.254 && s < 0.264 && h >= 29 && h <= 31) }' || fail "band_share.py on a uniform sky: $band"
finish
