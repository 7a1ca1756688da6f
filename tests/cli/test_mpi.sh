# orrery-mpi: 1, 2 and 4 ranks (oversubscribed on a 2-core machine) give the
# same images to float round-off (each rank sums its share of the particles;
# the shares are summed onto rank 0 in a different order), the observer
# particle is found on whichever rank holds it, and --frame-parallel shares
# a run's frames among the ranks.
source "$(dirname "$0")/lib.sh"
MPI=$(dirname "$ORRERY")/orrery-mpi
need_mpi "$MPI"

small="--set input.model.particles=60000 --set input.model.dust_particles=3000 --set input.chunk=5000 -q"
small="$small --set views.dome.image.width=120 --set views.dome.image.height=120"
small="$small --set views.panorama.image.width=160 --set views.panorama.image.height=80"
# A narrow PSF core: the automatic one is 3.2 pixels of these small maps,
# about 4 degrees, so every pixel sums hundreds of float kernels, whose
# order differs between rank counts by up to 5e-5 of the image's peak;
# 6 arcminutes keeps each star in a pixel or two, and the test on the
# ranks' reduction to the tolerance below.
small="$small --set psf.fwhm_arcmin=6"
for np in 1 2 4; do
  mpirun -np $np "$MPI" render "$SRC/configs/futuresky.yaml" -o np$np $small >mpi$np.log 2>&1 \
    || fail "mpirun -np $np: $(tail -5 mpi$np.log)"
done
"$ORRERY" render "$SRC/configs/futuresky.yaml" -o serial $small || fail "serial render"

"$py" - <<'PY' || fail "images differ between rank counts"
import numpy as np
from astropy.io import fits
bad = 0
for view in ("dome", "panorama"):
    ref = fits.open(f"serial/futuresky-{view}.fits")
    for np_ in (1, 2, 4):
        got = fits.open(f"np{np_}/futuresky-{view}.fits")
        for a, b in zip(ref, got):
            x, y = np.nan_to_num(a.data.astype(float)), np.nan_to_num(b.data.astype(float))
            tol = 1e-5 * np.abs(x).max()
            if np_ == 1 and not np.array_equal(x, y):
                print(f"{view} {a.name}: 1 rank differs from the serial render"); bad += 1
            if np.abs(x - y).max() > tol or abs(x.sum() - y.sum()) > 1e-6 * abs(x.sum()):
                print(f"{view} {a.name}, {np_} ranks: max diff {np.abs(x - y).max()} > {tol}"); bad += 1
        if got[0].header["NPART"] != ref[0].header["NPART"]:
            print(f"{view}: NPART {got[0].header['NPART']} != {ref[0].header['NPART']}"); bad += 1
raise SystemExit(bad)
PY

# Snapshot files: each rank reads only its share (a multi-file snapshot split
# by file, more ranks than files as well; a single file by ranges of each
# block), and the images agree with one process as the model's do.
DATA=${ORRERY_SHARED_DATA:-$SRC/../shared/data}
if [ -d "$DATA/gadget2" ]; then
  file_scene() { # NAME FILE CENTRE WIDTH DEPOSIT-LINES...
    local name=$1 file=$2 centre=$3 width=$4
    shift 4
    { echo "input: {file: $file}"
      echo "camera: {position: $centre, projection: orthographic, width: $width}"
      echo "image: {width: 96, height: 96}"
      for line in "$@"; do echo "$line"; done
      echo "output: {name: $name, png: false}"; } >"$name.yaml"
  }
  file_scene multi "$DATA/gadget2/gadgetreader_format2/test_g2_snap" "[1500, 1500, 4000]" 3000 \
    "deposit: sph" "smoothing: {lengths: file}"
  file_scene single "$DATA/gadget2/gadget2_examples/galaxy_littleendian.dat" "[0, 0, 400]" 400 "deposit: cic"
  for scene in multi single; do
    "$ORRERY" render "$scene.yaml" -o "$scene-serial" -q || fail "$scene: serial render"
    for np in 1 2 3; do
      mpirun -np $np "$MPI" render "$scene.yaml" -o "$scene-np$np" -q >"$scene$np.log" 2>&1 \
        || fail "$scene, mpirun -np $np: $(tail -5 "$scene$np.log")"
    done
  done
  "$py" - <<'PY' || fail "snapshot images differ between rank counts"
import numpy as np
from astropy.io import fits
bad = 0
for scene in ("multi", "single"):
    ref = fits.open(f"{scene}-serial/{scene}.fits")[0]
    x = ref.data.astype(float)
    for np_ in (1, 2, 3):
        got = fits.open(f"{scene}-np{np_}/{scene}.fits")[0]
        y = got.data.astype(float)
        if np.abs(x - y).max() > 1e-5 * np.abs(x).max() or got.header["NPART"] != ref.header["NPART"]:
            print(f"{scene}, {np_} ranks: max diff {np.abs(x - y).max()}, NPART {got.header['NPART']}"); bad += 1
raise SystemExit(bad)
PY
fi

# Frame-parallel: 5 frames on 2 ranks, each frame once.
mpirun -np 2 "$MPI" render "$SRC/configs/first-light.yaml" -o frames --frame-parallel \
  --set animation.frames=5 --set image.width=32 --set image.height=32 --set input.model.particles=2000 -q \
  >fp.log 2>&1 || fail "frame-parallel: $(cat fp.log)"
[ "$(ls frames/*.png 2>/dev/null | wc -l)" -eq 5 ] || fail "frame-parallel frames: $(ls frames)"

# A missing observer is an error on every rank, and a non-zero exit.
mpirun -np 2 "$MPI" render "$SRC/configs/futuresky.yaml" -o bad $small --set observer.id=999999999 >bad.log 2>&1 \
  && fail "missing observer accepted"
grep -q "observer particle id 999999999" bad.log || fail "missing observer message: $(cat bad.log)"
finish
