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
