# The linear OpenEXR as compositors read it (tests/cli/check_exr_compositing.py,
# through OpenImageIO's Python bindings): R, G, B, A, the xyz layer,
# chromaticities, alpha 0 and no NaN off the dome's circle.
source "$(dirname "$0")/lib.sh"
python_with OpenImageIO python3-openimageio
"$py" "$(dirname "$0")/check_exr_compositing.py" "$ORRERY" "$WORK" || fail "EXR compositing check"
finish
