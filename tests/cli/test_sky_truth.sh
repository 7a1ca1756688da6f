#!/bin/bash
# scripts/sky_truth.py, issue 40's measure of a sky against the real one,
# checked against truth (check_sky_truth.py): the real sky's star list
# inside the bars, synthetic skies with analytic figures, bad input, and
# data/sky/star_counts.tsv against stellarium-data's catalogues when the
# package is installed.
. "$(dirname "$0")/lib.sh"
python_with astropy python3-astropy
python_with scipy python3-scipy
"$py" "$SRC/tests/cli/check_sky_truth.py" "$SRC" "$WORK" >"$WORK/log" 2>&1 || fail "sky_truth: $(cat "$WORK/log")"
finish
