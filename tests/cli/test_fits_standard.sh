# FITS outputs as astropy and fitsverify take them: units, checksums, WCS on
# every view (tests/cli/check_fits_standard.py); bad unit keys are refused.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" "$(dirname "$0")/check_fits_standard.py" "$ORRERY" "$WORK" || fail "FITS standard check"

printf 'x y z mass\n0 0 5 1\n' > p.txt
printf 'input:\n  file: p.txt\noutput:\n  dir: bad\n' > bad.yaml
expect_fail 2 "output.bunit: 'mass/sr' divides with '/'" bad -- render bad.yaml --set "output.bunit=mass/sr"
expect_fail 2 "output.bunit: 'Msun: solar' is not a FITS unit string \(it has ':'\)" bad -- \
  render bad.yaml --set "output.bunit='Msun: solar'"
expect_fail 2 "output.length_unit: 'kpc h-1' is not a single FITS unit symbol" bad -- \
  render bad.yaml --set "output.length_unit=kpc h-1"
finish
