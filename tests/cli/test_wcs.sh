# Sky maps carry a FITS WCS that an independent library (astropy's wcslib)
# reads back: particles at known (l, b) are in the pixels the header says.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" "$(dirname "$0")/check_wcs.py" "$ORRERY" "$WORK" || fail "WCS check"
finish
