# The scene stored in every FITS output, read back by astropy and PyYAML,
# verified by fitsverify and rendered again (tests/cli/check_fits_scene.py).
source "$(dirname "$0")/lib.sh"
python_with yaml python3-yaml
python_with astropy python3-astropy
command -v fitsverify >/dev/null || { echo "skipped: no fitsverify"; exit 77; }
"$py" "$(dirname "$0")/check_fits_scene.py" "$ORRERY" "$WORK" || fail "FITS scene check"
finish
