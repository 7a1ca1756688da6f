#!/bin/bash
# The glow of unresolved starlight on sky maps (glow.threshold;
# check_glow.py), and its bad settings.
. "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
"$py" "$SRC/tests/cli/check_glow.py" "$ORRERY" "$WORK" || fail "the glow"

printf 'x y z mass id\n0 0 0 1 1\n1000 0 0 1 2\n0 10 0 1 3\n' >stars.txt
cat >sky.yaml <<'Y'
input:
  file: stars.txt
observer:
  id: 1
  reference_id: 2
  normal: [0, 0, 1]
camera:
  projection: hammer-aitoff
image:
  width: 64
  height: 32
psf:
  kind: gaussian
glow:
  threshold: 1
output:
  dir: out
Y
"$ORRERY" render sky.yaml -q || fail "a small glowing sky map"
rm -rf out
expect_fail 2 "glow.threshold.*needs a sky map with a psf.kind" out -- render sky.yaml --set psf.kind=none
expect_fail 2 "glow.threshold.*needs a sky map" out -- render sky.yaml --set camera.projection=perspective \
  --set camera.fov=60
expect_fail 2 "glow.threshold" out -- render sky.yaml --set glow.threshold=-1
expect_fail 2 "glow.max_arcmin" out -- render sky.yaml --set glow.max_arcmin=0
expect_fail 2 "glow.threshold" out -- render sky.yaml --set glow.threshold=nan
finish
