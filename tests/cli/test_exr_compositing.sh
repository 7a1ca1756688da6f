# The linear OpenEXR as compositors read it (tests/cli/check_exr_compositing.py,
# through OpenImageIO's Python bindings): R, G, B, A, the xyz layer,
# chromaticities, alpha 0 and no NaN off the dome's circle.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
if ! "$py" -c 'import OpenImageIO' 2>/dev/null; then
  echo "skipped: no OpenImageIO Python bindings (python3-openimageio)"
  exit 77
fi
"$py" "$(dirname "$0")/check_exr_compositing.py" "$ORRERY" "$WORK" || fail "EXR compositing check"
finish
