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

finish
