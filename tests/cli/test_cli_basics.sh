# --help and --version tell the truth; info reads a table; exit codes.
source "$(dirname "$0")/lib.sh"

"$ORRERY" --version | grep -Eq '^orrery [0-9]+\.[0-9]+\.[0-9]+$' || fail "--version"
"$ORRERY" --help | grep -q "render SCENE.yaml" || fail "--help lists render"
for cmd in render info model; do
  "$ORRERY" $cmd --help | grep -q "usage: orrery $cmd" || fail "$cmd --help"
done
"$ORRERY" >/dev/null 2>&1; [ $? -eq 2 ] || fail "no arguments should exit 2"

printf 'x y z mass type\n-1 2 3 0.5 1\n4 -5 6 1.5 2\n0 0 -9 2 2\n' >t.txt
"$ORRERY" info t.txt >info.out || fail "info failed"
grep -q "particles:  3" info.out || fail "info count: $(cat info.out)"
grep -q "type 2:   2 particles, mass 3.5" info.out || fail "info per type: $(cat info.out)"
grep -q "x range:    \[-1, 4\]" info.out || fail "info x range: $(cat info.out)"
grep -q "z range:    \[-9, 6\]" info.out || fail "info z range: $(cat info.out)"
grep -q "mass:       total 4" info.out || fail "info mass: $(cat info.out)"

# The model command writes a table that info reads back with the same count.
"$ORRERY" model -o m.txt --particles 1000 --seed 3 >/dev/null || fail "model failed"
"$ORRERY" info m.txt | grep -q "particles:  1000" || fail "model table count"
"$ORRERY" model -o m.txt --particles 5 >/dev/null 2>&1; [ $? -eq 2 ] || fail "model --particles 5 should exit 2"

# --timings: the stage table, even with --quiet (nothing else then); for a
# run, a line a frame and the run's sum.
"$ORRERY" render --help | grep -q -- "--timings" || fail "render --help lists --timings"
printf 'input: {file: t.txt}\ncamera: {projection: orthographic, width: 30}\nimage: {width: 40, height: 30}\n' >tim.yaml
"$ORRERY" render tim.yaml -q --timings -o tim >tim.out || fail "render --timings failed"
for stage in setup source gather+project deposit colour/post fits png commit "stages summed" total; do
  grep -q "^  $stage " tim.out || fail "--timings lists no $stage: $(cat tim.out)"
done
grep -q "^timings (one frame" tim.out || fail "--timings header: $(cat tim.out)"
grep -q "wrote" tim.out && fail "--quiet --timings printed the report too"
"$ORRERY" render tim.yaml -q -o tim --force >tim.out || fail "render -q failed"
[ -s tim.out ] && fail "render -q without --timings printed: $(cat tim.out)"
"$ORRERY" render tim.yaml -q --timings -o timrun --set animation.frames=2 >tim.out || fail "run --timings failed"
[ "$(grep -c '^timings: frame [01]: ' tim.out)" = 2 ] || fail "--timings frame lines: $(cat tim.out)"
grep -q "^timings (the run's 2 frames" tim.out || fail "--timings run sum: $(cat tim.out)"
"$ORRERY" compose tim.yaml --timings >/dev/null 2>&1; [ $? -eq 2 ] || fail "compose --timings should exit 2"

finish
