#!/bin/bash
# Motion blur (animation.shutter, docs/animation.md#motion-blur): stars
# moving at known velocities, a turning camera and a moving observer give
# streaks of the predicted length that hold the star's flux and have no
# gaps; the result does not depend on the threads; bad settings are
# refused by name with nothing written.
. "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
check="$SRC/tests/cli/check_motion_blur.py"

# Two stars: A slow (vx 12: a 12-pixel streak), B fast (vy 100: 100 pixels).
cat >stars.txt <<'T'
x y z mass vx vy vz
0.1 0.2 0 1 12 0 0
-3.3 -2.0 0 1 0 100 0
T
cat >line.yaml <<'Y'
input:
  file: stars.txt
camera:
  projection: orthographic
  width: 10
image:
  width: 200
  height: 200
deposit: cic
animation:
  shutter: 0.5
  frame_interval: 0.1
output:
  name: line
  dir: out
Y
"$ORRERY" render line.yaml -q || fail "render line.yaml"
$py "$check" line out/line.fits || fail "streaks of moving stars"

# One thread or two: the same bits.
OMP_NUM_THREADS=1 "$ORRERY" render line.yaml -q --set output.dir=one || fail "render on one thread"
$py "$check" same out/line.fits one/line.fits || fail "thread count changed the streaks"

# A camera turning 30 degrees over 10 frame intervals past a star that is
# in the centre of frame 5 (the rotate path turns about +y).
cat >pan.yaml <<'Y'
input:
  file: star.txt
camera:
  position: [0, 0, 0]
  look_at: [0, 0, -1]
  up: [0, 1, 0]
  projection: perspective
  fov: 60
  near: 0.01
  path:
    kind: rotate
    axis: [0, 1, 0]
    angle: 30
image:
  width: 400
  height: 300
deposit: cic
animation:
  frames: 11
  shutter: 0.5
output:
  name: pan
  dir: out
Y
$py -c "import math; a=math.radians(15); print('x y z mass'); print(-50*math.sin(a), 0, -50*math.cos(a), 1)" >star.txt
"$ORRERY" render pan.yaml -q --frames 5 || fail "render pan.yaml"
$py "$check" pan out/pan_0005.fits || fail "streak of a turning camera"

# An observer (id 0) moving at 4 along x past a star (id 2) 10 units away
# along y; the reference (id 1) far along x fixes the frame.
cat >obs.txt <<'T'
x y z mass vx vy vz id
0 0 0 1 4 0 0 0
1000 0 0 1 0 0 0 1
0 10 0 1 0 0 0 2
T
cat >dome.yaml <<'Y'
input:
  file: obs.txt
observer:
  id: 0
  reference_id: 1
  normal: [0, 0, 1]
  dim: false
camera:
  projection: dome
  zenith: [90, 0]
  front: [0, 0]
image:
  width: 400
  height: 400
deposit: cic
animation:
  shutter: 0.5
  frame_interval: 0.1
output:
  name: dome
  dir: out
Y
"$ORRERY" render dome.yaml -q || fail "render dome.yaml"
$py "$check" dome out/dome.fits || fail "streak of a moving observer"

# Bad settings: named, nothing written.
expect_fail 2 "animation.shutter" bad -- render line.yaml --set animation.shutter=1.5 --set output.dir=bad
expect_fail 2 "animation.frame_interval" bad -- render line.yaml --set animation.frame_interval=-1 --set output.dir=bad
head -1 stars.txt | cut -d' ' -f1-4 >novel.txt
echo "0 0 0 1" >>novel.txt
expect_fail 2 "has no field vx" bad -- render line.yaml --set input.file=novel.txt --set output.dir=bad
printf 'x y z mass vx vy vz\n0 0 0 1 nan 0 0\n' >nanvel.txt
expect_fail 1 "non-finite velocity" bad -- render line.yaml --set input.file=nanvel.txt --set output.dir=bad
finish
