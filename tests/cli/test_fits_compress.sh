# output.fits_compress: lossless tile compression read back by astropy and
# fitsverify (tests/cli/check_fits_compress.py).
source "$(dirname "$0")/lib.sh"
python_with astropy python3-astropy
"$py" "$(dirname "$0")/check_fits_compress.py" "$ORRERY" "$WORK" || fail "FITS compression check"
finish
