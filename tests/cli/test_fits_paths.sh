# FITS files are opened by their names as given: a raw-plane file or a PSF
# whose path holds '[' is not cfitsio's extended file-name syntax (which
# read "run[1]/x.fits" as a filter and failed with "parse error in input file
# URL"), so what `render` writes, `compose` and psf.file read back.
source "$(dirname "$0")/lib.sh"

cat >scene.yaml <<'EOT'
input:
  model:
    name: mw-m31
    particles: 5000
camera:
  projection: orthographic
  width: 60
image:
  width: 64
  height: 48
output:
  dir: run[1]
  name: sky[a]
  raw: true
EOT
"$ORRERY" render --quiet scene.yaml 2>err.txt || fail "render into run[1]: $(cat err.txt)"
[ -f "run[1]/sky[a].raw.fits" ] || fail "no raw planes in run[1]: $(ls -R)"
"$ORRERY" compose --quiet scene.yaml 2>err.txt || fail "compose from run[1]: $(cat err.txt)"

# The raw planes as a PSF (its own pixels: psf.arcsec_per_pixel 0).
mkdir -p "psf[2]"
cp "run[1]/sky[a].raw.fits" "psf[2]/star[0].fits"
"$ORRERY" render --quiet scene.yaml --set output.dir=out --set output.raw=false --set psf.kind=file \
  --set "psf.file=psf[2]/star[0].fits" --set psf.arcsec_per_pixel=0 --set psf.size=9 2>err.txt ||
  fail "render with psf.file psf[2]/star[0].fits: $(cat err.txt)"
[ -f "out/sky[a].png" ] || fail "no image rendered with the bracketed PSF"

# A scale far beyond the PSF image is refused by name, with its range.
nicmos="${ORRERY_SHARED_DATA:-}/psf/nic2_f160w_4xsub00.fits"
if [ -f "$nicmos" ]; then
  expect_fail 2 "psf.arcsec_per_pixel = 1e\+06 is out of range for this PSF: it must be above 0 and at most 9.9792 arcsec" \
    bad -- render scene.yaml --set output.dir=bad --set psf.kind=file --set "psf.file=$nicmos" \
    --set psf.arcsec_per_pixel=1000000
fi

finish
