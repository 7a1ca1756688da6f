# orrery path: every example scene of docs/paths.md runs; the table has one
# row per printed frame; -o writes a PNG of the requested size; bad scenes
# and bad keyframe files fail with the file, line and key named and leave
# no picture behind.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

png_size() {
  "$py" -c 'import sys; from PIL import Image; im = Image.open(sys.argv[1]); im.load(); print("%dx%d %s" % (im.size[0], im.size[1], im.mode))' "$1"
}

# The docs' examples: each ```yaml block is a scene, the ```csv block is keys.csv.
awk -v dir="$WORK" '
  /^```yaml$/ { n++; out = sprintf("%s/doc-%d.yaml", dir, n); inside = 1; next }
  /^```csv$/  { out = dir "/keys.csv"; inside = 1; next }
  /^```$/     { inside = 0; next }
  inside      { print > out }
' "$SRC/docs/paths.md"
count=$(ls doc-*.yaml | wc -l)
[ "$count" -ge 6 ] || fail "expected at least 6 YAML examples in docs/paths.md, found $count"
for scene in doc-*.yaml; do
  if ! "$ORRERY" path "$scene" --set input.model.particles=2000 --frames 30 -o "${scene%.yaml}.png" --size 64x48 >out.txt 2>err.txt; then
    fail "orrery path $scene (from docs/paths.md) failed: $(cat err.txt)"
  elif [ "$(png_size "${scene%.yaml}.png")" != "64x48 RGB" ]; then
    fail "$scene: overview is $(png_size "${scene%.yaml}.png"), expected 64x48 RGB"
  fi
done

# scene FILE CAMERA-LINES... [-- OTHER-LINES...]: a particle table with the
# given camera: block (and more top-level lines).
scene() {
  local file=$1
  shift
  { echo "input: {file: particles.txt}"; echo "camera:"; echo "  projection: perspective"
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do echo "$1"; shift; done
    [ $# -gt 0 ] && shift
    for line in "$@"; do echo "$line"; done; } >"$file"
}
mkdir -p out pics
printf 'x y z mass\n0 0 0 1\n1 0 0 1\n0 1 0 1\n-3 -2 1 1\n' >particles.txt

# An orbit: 12 frames, every row printed, constant distance from the centre.
scene orbit.yaml "  path: {kind: orbit, centre: [1, 2, 0], radius: 5, turns: 0.5}"
"$ORRERY" path orbit.yaml --frames 12 -o pics/orbit.png --size 120x80 >out.txt 2>err.txt || fail "orbit: $(cat err.txt)"
rows=$(grep -cE '^ +[0-9]+ ' out.txt)
[ "$rows" -eq 12 ] || fail "orbit: expected 12 rows, got $rows: $(cat out.txt)"
[ "$(png_size pics/orbit.png)" = "120x80 RGB" ] || fail "orbit: picture is $(png_size pics/orbit.png)"
awk '$1 ~ /^[0-9]+$/ && NF == 8 { d = sqrt(($3 - 1)^2 + ($4 - 2)^2 + $5^2); if (d < 4.9999 || d > 5.0001) bad++ }
     END { exit bad > 0 }' out.txt || fail "orbit: a row is not 5 from the centre: $(cat out.txt)"
# Half a turn: the last frame is opposite the first (x = 1 - 5).
last_x=$(awk '$1 == "11" { print $3 }' out.txt)
[ "$last_x" = "-4" ] || fail "orbit: last frame x = $last_x, expected -4"

# Many frames: about 50 rows, always the last; --every chooses.
"$ORRERY" path orbit.yaml --frames 1000 >out.txt || fail "1000 frames"
rows=$(grep -cE '^ +[0-9]+ ' out.txt)
[ "$rows" -le 51 ] && [ "$rows" -ge 45 ] || fail "1000 frames: $rows rows"
grep -qE '^ +999 ' out.txt || fail "1000 frames: the last frame is not printed"
"$ORRERY" path orbit.yaml --frames 12 --every 5 >out.txt || fail "--every"
[ "$(grep -cE '^ +[0-9]+ ' out.txt)" -eq 4 ] || fail "--every 5 of 12: expected frames 0 5 10 11: $(cat out.txt)"

# Contradictions and bad values name the key.
scene fixed.yaml "  position: [0, 0, 3]" "  path: {kind: orbit, radius: 5}"
expect_fail 2 "fixed.yaml:4: camera.position is not allowed with camera.path.kind: orbit" out -- path fixed.yaml -o out/x.png
scene obs.yaml "  path: {kind: orbit, radius: 5}" -- "observer: {id: 1, reference_id: 2}"
expect_fail 2 "camera.path.kind and observer.id are both set" out -- path obs.yaml -o out/x.png
scene plain.yaml "  width: 10"
expect_fail 2 "plain.yaml: no camera path: set camera.path.kind" out -- path plain.yaml -o out/x.png
expect_fail 2 "--frames 0: expected a whole number" out -- path orbit.yaml --frames 0
expect_fail 2 "--size: expected WxH" out -- path orbit.yaml --size 10x5000000

# Keyframes from CSV: a bad row names the file and line.
printf 'frame,x,y,z,look_x,look_y,look_z\n0,5,0,0,0,0,0\n10,0,5\n' >bad.csv
scene csv.yaml "  path: {kind: keyframes, file: bad.csv}"
expect_fail 1 "bad.csv:3: 3 values, expected 7" out -- path csv.yaml -o out/x.png
printf 'frame,x,y,z,look_x,look_y,look_z\n0,5,0,0,0,0,0\n10,0,5,2,0,0,0\n' >good.csv
scene csv.yaml "  path: {kind: keyframes, file: good.csv}"
"$ORRERY" path csv.yaml --frames 11 >out.txt 2>err.txt || fail "good CSV: $(cat err.txt)"
grep -qE '^ +10 +1\.00000 +0 +5 +2 ' out.txt || fail "good CSV: frame 10 is not at the last keyframe: $(cat out.txt)"

finish
