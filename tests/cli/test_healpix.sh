# The healpix projection: a standard HEALPix FITS map that healpy reads
# (tests/cli/check_healpix.py), its SPH kernels against healpy
# (check_healpix_kernels.py), and the keys it refuses.
source "$(dirname "$0")/lib.sh"
python_with healpy python3-healpy
"$py" "$(dirname "$0")/check_healpix.py" "$ORRERY" "$WORK" || fail "HEALPix check"
"$py" "$(dirname "$0")/check_healpix_kernels.py" "$ORRERY" "$WORK" || fail "HEALPix kernel check"

printf 'x y z mass\n0 0 5 1\n' >p.txt
printf 'input:\n  file: p.txt\ncamera:\n  projection: healpix\ndeposit: ngp\noutput:\n  dir: bad\n' >bad.yaml
expect_fail 2 "healpix takes deposit: ngp .* or sph .*, not cic" bad -- \
  render bad.yaml --set deposit=cic
expect_fail 2 "camera.healpix_nside: .*12" bad -- render bad.yaml --set camera.healpix_nside=12
expect_fail 2 "image.width: not with camera.projection: healpix" bad -- render bad.yaml --set image.width=64
expect_fail 2 "output.png: not with camera.projection: healpix" bad -- render bad.yaml --set output.png=true
expect_fail 2 "output.exr: not with camera.projection: healpix" bad -- render bad.yaml --set output.exr=true
expect_fail 2 "output.raw: not with camera.projection: healpix" bad -- render bad.yaml --set output.raw=true
# Pictures turned off ask for nothing the map cannot give (the Python package sets them).
"$ORRERY" render bad.yaml --quiet --set output.dir=off --set output.exr=false --set output.raw=false \
  --set output.png=false >off.log 2>&1 || fail "pictures turned off refused: $(cat off.log)"
[ -f off/bad.fits ] || fail "pictures turned off: no map written"
expect_fail 2 "camera.lon_flip: not with camera.projection: healpix" bad -- render bad.yaml --set camera.lon_flip=true
expect_fail 2 "camera.healpix_order: expected one of: ring nested" bad -- \
  render bad.yaml --set camera.healpix_order=nest
expect_fail 2 "camera.healpix_nside: only with camera.projection: healpix" bad -- \
  render bad.yaml --set camera.projection=dome --set camera.healpix_nside=8
# deposit: sph from among the particles at a fine nside would take hours
# (each kernel covers the sky: 12 nside^2 samples): refused at once, with
# the figures, instead of running silently past 300 s. Two threads, so the
# limit (2e9 samples a thread) is the same on any machine.
awk 'BEGIN { srand(5); print "x y z mass h"; for (i = 0; i < 50000; i++) print rand() - 0.5, rand() - 0.5, rand() - 0.5, 1, 5 }' >near.txt
printf 'input:\n  file: near.txt\ncamera:\n  projection: healpix\n  position: [0, 0, 0]\n  healpix_nside: 1024\ndeposit: sph\noutput:\n  dir: bad\n' >near.yaml
OMP_NUM_THREADS=2 expect_fail 2 "near.yaml: camera.healpix_nside 1024 with deposit: sph: the frame's kernels need more than the limit of 4e\+09 kernel samples .*6.29e\+11 foreseen from the first 50000 of 50000 particles" \
  bad -- render near.yaml
finish
