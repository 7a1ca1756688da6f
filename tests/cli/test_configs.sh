# Every scene in configs/ that README.md and docs/gallery.md render renders
# at a tiny size to a picture that is neither blank nor saturated: at least
# 1 % of its pixels brighter than 10/255, at most 5 % clipped at white.
# (The Dark Universe short command once gave frames 100 % white.) A run of
# frames renders one frame from the middle of it; the in-situ scenes are
# tested with the N-body example (test_case_studies.sh).
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
C=$SRC/configs
# The Dark Universe box as README.md makes it (evolved by the particle mesh), smaller.
"$ORRERY" ics --zeldovich --grid 32 --box 100 --evolve --pm-steps 10 -o box.hdf5 >/dev/null 2>err.txt ||
  fail "ics: $(cat err.txt)"

# smoke NAME SCENE [options...]: renders into NAME/.
smoke() {
  local name=$1 scene=$2
  shift 2
  "$ORRERY" render "$C/$scene" -o "$name" -q "$@" 2>err.txt || fail "$scene: $(cat err.txt)"
  grep -q "AddressSanitizer\|runtime error" err.txt && fail "$scene: sanitizer report: $(cat err.txt)"
}
model="--set input.model.particles=100000"
dust="--set input.model.dust_particles=5000" # the configs with dust: a few gas particles
smoke fs futuresky.yaml $model $dust --set views.dome.image.width=200 --set views.dome.image.height=200 \
  --set views.panorama.image.width=256 --set views.panorama.image.height=128
smoke eq futuresky.yaml $model $dust --set views.panorama.camera.projection=equirectangular \
  --set views.dome.image.width=128 --set views.dome.image.height=128 \
  --set views.panorama.image.width=256 --set views.panorama.image.height=128
smoke fl first-light.yaml --set image.width=256 --set image.height=256
smoke tt text-table-perspective.yaml --set image.width=256 --set image.height=192
smoke ao anaglyph-orbit.yaml $model --set image.width=320 --set image.height=180 --frames 60
smoke sm spiral-metamorphosis.yaml $model $dust --set image.width=200 --set image.height=200
smoke sa spiral-metamorphosis-anaglyph.yaml $model --set image.width=320 --set image.height=180
smoke nf nightfall.yaml --set image.width=240 --set image.height=135 --frames 18
smoke du dark-universe.yaml --set input.file="$PWD/box.hdf5" --set animation.frames=48 --frames 24 \
  --set image.width=256 --set image.height=135 --set psf.fwhm=1
# Stellar ages (configs/stellar-ages.yaml) on the toy galaxy its example writes.
if "$py" -c "import h5py" 2>/dev/null; then
  "$py" "$SRC/examples/python/aged_galaxy.py" --out . >/dev/null 2>err.txt || fail "aged_galaxy.py: $(cat err.txt)"
  smoke ages stellar-ages.yaml --set input.file="$PWD/aged_galaxy.hdf5" --set image.width=200 --set image.height=150
fi

"$py" - */*.png <<'PY' || fail "a picture is blank or saturated"
import sys
import numpy as np
from PIL import Image
bad = 0
for path in sys.argv[1:]:
    rgb = np.asarray(Image.open(path).convert("RGB")).astype(float)
    lum = rgb.max(axis=2)
    lit, clipped = (lum > 10).mean(), (lum >= 254).mean()
    ok = lit >= 0.01 and clipped <= 0.05
    print(f"{'ok  ' if ok else 'FAIL'} {path}: {100 * lit:.2f} % lit, {100 * clipped:.2f} % clipped")
    bad += not ok
sys.exit(1 if bad or len(sys.argv) < 11 else 0)
PY
finish
