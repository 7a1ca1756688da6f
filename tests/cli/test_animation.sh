# Runs of frames from the command line: per-frame names, frame-parallel
# jobs, resumption after an interruption, and --frames / --jobs errors.
source "$(dirname "$0")/lib.sh"

printf 'x y z mass\n0 0 0 1\n1 1 0 2\n-2 1 0 1\n' >t.txt
write_scene s.yaml t.txt "animation:" "  frames: 5" "  fps: 24"

# Two jobs render every frame once between them.
"$ORRERY" render s.yaml --jobs 2 >run.out 2>run.err || fail "render --jobs 2: $(cat run.err)"
for f in 0 1 2 3 4; do
  [ -s out/s_000$f.png ] && [ -s out/s_000$f.fits ] || fail "frame $f missing: $(ls out)"
done
[ "$(ls out | wc -l)" -eq 10 ] || fail "expected 10 files: $(ls out)"
grep -q "rendered 5, skipped 0" run.out || fail "summary: $(cat run.out)"
for f in 0 1 2 3 4; do grep -q "frame $f done" run.err || fail "progress of frame $f: $(cat run.err)"; done

# Resumption: an interrupted run leaves complete frames and no partial file
# under a final name; here frame 3 is truncated and frame 4 lost.
truncate -s 7 out/s_0003.fits
rm out/s_0004.png
"$ORRERY" render s.yaml >run.out 2>run.err || fail "resume: $(cat run.err)"
grep -q "rendered 2, skipped 3" run.out || fail "resume summary: $(cat run.out)"
grep -q "frame 1 already complete, skipped" run.err || fail "resume progress: $(cat run.err)"
[ "$(stat -c %s out/s_0003.fits)" -gt 7 ] || fail "truncated frame not redone"
[ -s out/s_0004.png ] || fail "lost frame not redone"

# The issue's resume attack: frames 0-1 of a 4-frame anaglyph orbit at
# 320x180, then the whole run at 640x360 in grey: all four frames must be
# the new run's (size, colours), and the first redo names what changed.
scene="$2/configs/anaglyph-orbit.yaml"
py=/usr/bin/python3 # Debian's, with Pillow
[ -x "$py" ] || py=python3
small=(--set input.model.particles=3000 --set animation.frames=4 --set output.fits=false)
"$ORRERY" render "$scene" -o orbit "${small[@]}" --frames 0:1 --set image.width=320 --set image.height=180 \
  >run.out 2>run.err || fail "orbit frames 0-1: $(cat run.err)"
"$ORRERY" render "$scene" -o orbit "${small[@]}" --set image.width=640 --set image.height=360 \
  --set stereo.anaglyph=grey >run.out 2>run.err || fail "orbit, whole run: $(cat run.err)"
grep -q "rendered 4, skipped 0" run.out || fail "orbit resume summary: $(cat run.out)"
grep -q "frame 0 of an earlier run rendered again: image.width changed from 320 to 640" run.err \
  || fail "orbit: the change is not named: $(cat run.err)"
"$ORRERY" render "$scene" -o fresh "${small[@]}" --set image.width=640 --set image.height=360 \
  --set stereo.anaglyph=grey --frames 0 >/dev/null 2>run.err || fail "fresh frame 0: $(cat run.err)"
"$py" - orbit/anaglyph-orbit_000{0,1,2,3}.png fresh/anaglyph-orbit_0000.png <<'PY' || fail "orbit frames are not all the new run's"
import sys
from PIL import Image
ims = [Image.open(p) for p in sys.argv[1:]]
assert all(im.size == (640, 360) for im in ims), [im.size for im in ims]
assert list(ims[0].getdata()) == list(ims[-1].getdata()), "frame 0 differs from a fresh render of it"
PY
# The same scene again: nothing to do. A longer run moves every camera.
"$ORRERY" render "$scene" -o orbit "${small[@]}" --set image.width=640 --set image.height=360 \
  --set stereo.anaglyph=grey >run.out 2>run.err || fail "orbit again: $(cat run.err)"
grep -q "rendered 0, skipped 4" run.out || fail "orbit again: $(cat run.out)"
"$ORRERY" render "$scene" -o orbit "${small[@]}" --set image.width=640 --set image.height=360 \
  --set stereo.anaglyph=grey --set animation.frames=6 >run.out 2>run.err || fail "orbit of 6: $(cat run.err)"
grep -q "rendered 6, skipped 0" run.out || fail "6 frames after 4 must all be new: $(cat run.out)"

# Interrupted: SIGTERM (a batch system's kill; SIGINT and SIGHUP alike,
# but a shell starts background jobs with SIGINT ignored) while a large
# frame is being written leaves no temporary file, and the run dies of the
# signal.
printf 'x y z mass\n0 0 0 1\n' >one.txt
write_scene big.yaml one.txt
# start_big_render: a 6000x6000 frame (two FITS of 144 MB) in the
# background, in $pid, returning once its temporary files are being written.
start_big_render() {
  "$ORRERY" render big.yaml -o big --set image.width=6000 --set image.height=6000 --set output.png=false \
    --set output.raw=true >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 1 600); do
    ls -a big 2>/dev/null | grep -q '^\.orrery-tmp-' && return
    sleep 0.05
  done
  fail "no temporary file seen while writing"
}
start_big_render
kill -TERM $pid
wait $pid
code=$?
[ $code -eq 143 ] || fail "SIGTERM: exit status $code, expected 143"
! ls -a big | grep -q 'tmp' || fail "SIGTERM left a temporary file: $(ls -a big)"
[ ! -e big/big.fits ] || fail "SIGTERM left a FITS under its final name"
# A killed run's leftovers (same host, process gone) go with the next run.
start_big_render
kill -KILL $pid
wait $pid 2>/dev/null
ls -a big | grep -q '^\.orrery-tmp-' || fail "SIGKILL: expected a leftover to test with"
"$ORRERY" render big.yaml -o big --set output.png=false >/dev/null 2>run.err || fail "render after a kill: $(cat run.err)"
! ls -a big | grep -q 'tmp' || fail "a killed run's temporary was not removed: $(ls -a big)"

# animation.white_smoothing: each frame's automatic white level (Nightfall's
# rises and jumps as the camera spirals in) is replaced by the geometric
# mean of the levels of the 7 frames around it, read from the markers; the
# pictures are re-graded from the FITS planes, and a resumed run leaves
# them as they are.
nf=(--set animation.frames=12 --set image.width=160 --set image.height=90 --set colour.synthesis.white=auto -q)
"$ORRERY" render "$2/configs/nightfall.yaml" -o each "${nf[@]}" --jobs 2 2>run.err || fail "nightfall: $(cat run.err)"
"$ORRERY" render "$2/configs/nightfall.yaml" -o smooth "${nf[@]}" --set animation.white_smoothing=7 --jobs 2 \
  2>run.err || fail "nightfall smoothed: $(cat run.err)"
md5sum smooth/*.png >before.md5
"$py" - <<'PY' || fail "smoothed white levels"
import glob, math, re
from PIL import Image
def y0(folder):
    return [float(re.search(r"Y0 ([0-9.e+-]+)", Image.open(p).info["Description"]).group(1))
            for p in sorted(glob.glob(f"{folder}/nightfall_*.png"))]
each, smooth = y0("each"), y0("smooth")
marked = [float(re.search(r"^white (\S+)$", open(p).read(), re.M).group(1))
          for p in sorted(glob.glob("smooth/.orrery-frames/nightfall_*.done"))]
assert len(each) == len(smooth) == len(marked) == 12
assert all(abs(a / b - 1) < 1e-5 for a, b in zip(each, marked)), "markers keep each frame's own level"  # %g: 6 digits
for f in range(12):
    window = [math.log(each[g]) for g in range(max(0, f - 3), min(12, f + 4))]
    want = math.exp(sum(window) / len(window))
    assert abs(smooth[f] / want - 1) < 1e-5, (f, smooth[f], want)
jump = lambda w: max(abs(math.log(b / a)) for a, b in zip(w, w[1:]))
print(f"largest step between frames: each frame's own white x{math.exp(jump(each)):.2f}, smoothed x{math.exp(jump(smooth)):.2f}")
assert jump(smooth) < 0.5 * jump(each)
PY
"$ORRERY" render "$2/configs/nightfall.yaml" -o smooth "${nf[@]}" --set animation.white_smoothing=7 >run.out 2>&1 \
  || fail "nightfall smoothed again: $(cat run.out)"
md5sum -c --quiet before.md5 || fail "a resumed smoothed run changed its pictures"
expect_fail 2 "animation.white_smoothing averages the automatic white level, but colour.synthesis.white is fixed" \
  none -- render "$2/configs/nightfall.yaml" --set animation.white_smoothing=5
expect_fail 2 "animation.white_smoothing re-grades each frame from its FITS planes: it needs output.fits: true" \
  none -- render "$2/configs/nightfall.yaml" --set animation.white_smoothing=5 --set colour.synthesis.white=auto \
  --set output.fits=false

# A film of a still scene: every frame the same bits as the still. Each
# frame after the first clears the view's planes, the first's come zeroed
# from their allocation (render/plan_view.c); the Future Sky views splat
# their kernels in four lanes at this size, summed into those planes.
fs=(--set input.model.particles=100000 --set input.model.dust_particles=5000
    --set views.dome.image.width=200 --set views.dome.image.height=200
    --set views.panorama.image.width=256 --set views.panorama.image.height=128 --set output.png=false -q)
"$ORRERY" render "$2/configs/futuresky.yaml" -o still "${fs[@]}" >/dev/null 2>run.err || fail "still: $(cat run.err)"
"$ORRERY" render "$2/configs/futuresky.yaml" -o film "${fs[@]}" --set animation.frames=3 >/dev/null 2>run.err \
  || fail "film of a still: $(cat run.err)"
"$py" - still film <<'PY' || fail "a film of a still scene changes from frame to frame"
import sys
import numpy as np
from astropy.io import fits
still, film = sys.argv[1:]
for view in ("futuresky-dome", "futuresky-panorama"):
    with fits.open(f"{still}/{view}.fits") as a:  # the X, Y, Z planes (not the scene, which differs)
        want = [h.data.tobytes() for h in a if h.is_image and h.data is not None and h.data.ndim == 2]
        assert len(want) == 3 and np.nansum(a[0].data) > 0, view
    for k in range(3):
        with fits.open(f"{film}/{view}_{k:04d}.fits") as b:
            got = [h.data.tobytes() for h in b if h.is_image and h.data is not None and h.data.ndim == 2]
        same = got == want
        if not same:
            sys.exit(f"{view}: frame {k} differs from the still")
print("a film of a still: 3 frames of both views, the still's bits")
PY

# --frames and --force.
"$ORRERY" render s.yaml --frames 1:2 --force >run.out 2>&1 || fail "--frames 1:2 --force"
grep -q "rendered 2, skipped 0" run.out || fail "--frames 1:2 summary: $(cat run.out)"

expect_fail 2 "frame 9 asked for" none -- render s.yaml --frames 9
expect_fail 2 "expected A:B" none -- render s.yaml --frames 3:1
expect_fail 2 "expected A:B" none -- render s.yaml --frames x
expect_fail 2 "--jobs 0: expected a whole number" none -- render s.yaml --jobs 0
expect_fail 2 "views.a.animation: a view may not set animation" none -- render s.yaml --set 'views={a: {animation: {frames: 2}}}'
expect_fail 2 "animation.frames" none -- render s.yaml --set animation.frames=0

finish
