# The example N-body code renders Future Sky in-situ every step through
# orrery.h (no snapshot written), and evolves GADGET-2's merger ICs.
source "$(dirname "$0")/lib.sh"
NBODY=$(dirname "$ORRERY")/examples/orrery-nbody
[ -x "$NBODY" ] || { fail "no $NBODY"; finish; }

small="--set views.dome.image.width=96 --set views.dome.image.height=96"
small="$small --set views.panorama.image.width=128 --set views.panorama.image.height=64"
"$NBODY" --particles 3000 --steps 3 --dt 0.002 --scene "$SRC/configs/futuresky.yaml" \
  --set output.dir=out $small >run.out 2>run.err || fail "nbody in-situ: $(cat run.err)"
for f in 0 1 2 3; do
  for v in dome panorama; do
    [ -s out/futuresky-${v}_000$f.png ] && [ -s out/futuresky-${v}_000$f.fits ] || fail "frame $f of $v missing: $(ls out)"
  done
done
grep -q "rendering per frame = " run.out || fail "no cost report: $(cat run.out)"
# The Sun moved between frames, so the observer frame was rebuilt: the
# camera positions in the FITS headers differ.
p0=$(grep -ao "CAMPOSX = *[-0-9.E+]*" out/futuresky-dome_0000.fits)
p3=$(grep -ao "CAMPOSX = *[-0-9.E+]*" out/futuresky-dome_0003.fits)
[ -n "$p0" ] && [ "$p0" != "$p3" ] || fail "observer did not move: '$p0' '$p3'"

# A bad scene key is an error naming it, exit 2.
"$NBODY" --particles 3000 --steps 1 --scene "$SRC/configs/futuresky.yaml" --set camera.fov=500 >/dev/null 2>err.txt
[ $? -eq 2 ] && grep -q "camera.fov" err.txt || fail "bad key: $(cat err.txt)"

# A text table's count is known only once read: refused, not truncated.
"$NBODY" --ic "$SRC/examples/plummer-sphere.txt" --steps 1 >/dev/null 2>err.txt
[ $? -eq 1 ] && grep -q "plummer-sphere.txt: its particle count is not known" err.txt || fail "text ICs: $(cat err.txt)"

# GADGET-2's galaxy-merger initial conditions, when the shared data is there.
ic="${ORRERY_SHARED_DATA:-}/gadget2/gadget2_examples/galaxy_littleendian.dat"
if [ -f "$ic" ]; then
  printf 'camera: {projection: orthographic, width: 400}\nimage: {width: 64, height: 64}\noutput: {dir: merger}\n' >merger.yaml
  "$NBODY" --ic "$ic" --steps 1 --dt 0.01 --eps 1 --theta 1.0 --scene merger.yaml >run.out 2>run.err || fail "merger: $(cat run.err)"
  grep -q "^60000 bodies" run.out || fail "merger count: $(cat run.out)"
  [ -s merger/merger_0001.png ] || fail "merger frame 1: $(ls merger)"
fi
finish
