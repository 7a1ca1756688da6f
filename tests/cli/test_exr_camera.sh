# The camera in the linear OpenEXR (tests/cli/check_exr_camera.py, through
# OpenImageIO's Python bindings): worldToCamera and the screen window put
# known stars on their pixels; output.exr_half; sky maps' own attributes.
source "$(dirname "$0")/lib.sh"
python_with OpenImageIO python3-openimageio
"$py" "$(dirname "$0")/check_exr_camera.py" "$ORRERY" "$WORK" || fail "EXR camera check"
finish
