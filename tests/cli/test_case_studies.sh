# Smoke tests of the case studies (docs/gallery.md) at tiny sizes: each
# scene renders, and its output has the structure the paper describes.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
check="$py $SRC/tests/cli/check_case_studies.py"

# Future Sky: the Milky Way band along the panorama's equator.
"$ORRERY" render "$SRC/configs/futuresky.yaml" -o fs --set input.model.particles=30000 \
  --set views.dome.image.width=64 --set views.dome.image.height=64 \
  --set views.panorama.image.width=128 --set views.panorama.image.height=64 >run.out 2>run.err \
  || fail "futuresky: $(cat run.err)"
[ -s fs/futuresky-dome.png ] || fail "futuresky: no dome master: $(ls fs)"
$check band fs/futuresky-panorama.fits || fail "futuresky: no band on the equator"

# Spiral Metamorphosis: both views written; face-on round, edge-on flat and
# horizontal; redder in the centre.
"$ORRERY" render "$SRC/configs/spiral-metamorphosis.yaml" -o sp --set input.model.particles=30000 \
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

# The evolving version: the example N-body code renders the spiral scene
# in-situ, E0 handed over (the populations select by it: without it every
# star would be young and blue, and the centre no redder).
NBODY=$(dirname "$ORRERY")/examples/orrery-nbody
if [ -x "$NBODY" ]; then
  "$NBODY" --particles 6000 --steps 2 --dt 0.01 --scene "$SRC/configs/spiral-metamorphosis.yaml" \
    --set output.dir=ns --set image.width=160 --set image.height=160 >run.out 2>run.err \
    || fail "spiral in-situ: $(cat run.err)"
  [ -s ns/spiral-faceon_0002.png ] && [ -s ns/spiral-edgeon_0002.png ] || fail "spiral in-situ frames: $(ls ns)"
  $check views ns/spiral-faceon_0002.fits ns/spiral-edgeon_0002.fits ns/spiral-faceon_0002.png \
    || fail "spiral in-situ: view shapes or colours"
fi
finish
