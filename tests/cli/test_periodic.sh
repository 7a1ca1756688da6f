# Periodic boxes (docs/periodic.md): the fly-through scene of the page, on
# the shared GADGET-4 box, renders a few frames with the copies around the
# camera; culling does not change the pixels; bad keys fail clearly.
source "$(dirname "$0")/lib.sh"
DATA=${ORRERY_SHARED_DATA:-$SRC/../shared/data}
if [ ! -d "$DATA" ]; then
  echo "shared data not found at $DATA: skipped"
  exit 77
fi
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# The page's YAML example with the box in it, pointed at this data folder.
awk '/^```yaml/ { inblock = 1; text = ""; next }
     /^```/ && inblock { inblock = 0; if (text ~ /kind: line/) { printf "%s", text; exit } next }
     inblock { text = text $0 "\n" }' "$SRC/docs/periodic.md" |
  sed "s|\.\./\.\./shared/data|$DATA|" >fly.yaml
grep -q "replicas: 3" fly.yaml || fail "no fly-through example found in docs/periodic.md"

small=(--set image.width=192 --set image.height=108)
if ! "$ORRERY" render fly.yaml "${small[@]}" --frames 0:2 -o out >log.txt 2>&1; then
  fail "the fly-through example failed: $(cat log.txt)"
fi
for f in 0000 0001 0002; do
  [ -s out/fly_$f.fits ] && [ -s out/fly_$f.png ] || fail "frame $f not written"
done
# Frame 0 sits at (5000, 26000, 24000) in a 50000 box: of the 27 copies
# around it, the 19 whose cell comes within the sphere's radius (one box
# side, the default with 3 copies) are drawn; looking along +x the copies
# behind (x < 0) go whole at least.
grep -q "periodic box drawn 19 times" log.txt || fail "no periodic line in the report: $(cat log.txt)"
skipped=$(awk '/periodic box drawn/ { for (i = 1; i <= NF; i++) if ($i == "whole:") { print $(i + 1); exit } }' log.txt)
[ "${skipped:-0}" -ge 9 ] || fail "expected at least 9 copies skipped whole, got '$skipped'"

# Culling changes nothing: the pixels with ORRERY_NO_CULL=1 are the same.
"$ORRERY" render fly.yaml "${small[@]}" --set animation.frames=1 --set output.name=cull -o out >/dev/null 2>&1 ||
  fail "render with culling"
ORRERY_NO_CULL=1 "$ORRERY" render fly.yaml "${small[@]}" --set animation.frames=1 --set output.name=nocull -o out \
  >nocull.txt 2>&1 || fail "render without culling"
grep -q "skipped: 0 of" nocull.txt || fail "ORRERY_NO_CULL=1 still culled: $(cat nocull.txt)"
"$py" - out/cull.fits out/nocull.fits <<'PY' || fail "culling changed the pixels"
import sys
from astropy.io import fits
a, b = (fits.getdata(p) for p in sys.argv[1:3])
h = fits.getheader(sys.argv[1])
ok = (a == b).all() and a.sum() > 0 and h["NREPLIC"] == 19 and h["PERBOX"] == 50000 and h["NBLKCULL"] > 0
sys.exit(0 if ok else 1)
PY

# Bad input names the key and what is wrong.
expect_fail 2 "input.periodic.replicas.*odd" bad -- render fly.yaml --set input.periodic.replicas=4 -o bad
expect_fail 2 "input.periodic.centre" bad -- render fly.yaml --set input.periodic.centre=middle -o bad
# The sphere around the camera: within the copies' reach, its fade no
# wider than it, numbers; nothing written.
expect_fail 2 "input.periodic.radius 60000 is larger than the replicated volume allows" bad -- \
  render fly.yaml --set input.periodic.radius=60000 -o bad
expect_fail 2 "input.periodic.fade 30000 is wider than the radius 20000" bad -- \
  render fly.yaml --set input.periodic.radius=20000 --set input.periodic.fade=30000 -o bad
expect_fail 2 "input.periodic.fade 60000 is wider than the radius 50000" bad -- \
  render fly.yaml --set input.periodic.fade=60000 -o bad
expect_fail 2 "input.periodic.radius" bad -- render fly.yaml --set input.periodic.radius=nan -o bad
expect_fail 2 "input.periodic.fade" bad -- render fly.yaml --set input.periodic.fade=nan -o bad
expect_fail 2 "input.periodic.radius applies to input.periodic.centre: camera" bad -- \
  render fly.yaml --set input.periodic.centre=origin --set input.periodic.radius=100 -o bad
printf 'x y z mass\n1 2 3 1\n' >table.txt
write_scene nobox.yaml table.txt
sed -i 's|  file: table.txt|  file: table.txt\n  periodic: {replicas: 3}|' nobox.yaml
expect_fail 2 "BoxSize.*input.periodic.box" bad -- render nobox.yaml -o bad
finish
