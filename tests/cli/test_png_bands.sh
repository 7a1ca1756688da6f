# PNG bands deflated on every thread (encode/png_idat.h): the same bytes on
# one thread and two, read back alike by PIL and OpenImageIO
# (tests/cli/check_png_bands.py).
source "$(dirname "$0")/lib.sh"
python_with PIL python3-pil
python_with OpenImageIO python3-openimageio
"$py" "$(dirname "$0")/check_png_bands.py" "$ORRERY" "$WORK" || fail "PNG bands check"
finish
