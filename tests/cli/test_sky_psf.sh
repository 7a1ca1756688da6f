# A sky map's PSF keeps its angular size across a dome master (check_sky_psf.py).
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" "$(dirname "$0")/check_sky_psf.py" "$ORRERY" "$WORK" || fail "sky PSF size"
finish
