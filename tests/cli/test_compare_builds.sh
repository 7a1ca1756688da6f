#!/bin/bash
# scripts/compare_builds.sh, the check that a refactoring changes no image
# (docs/architecture.md, issue 39), on its smallest scene: the same binary
# twice reports no difference; a "new build" that renders with a wider field
# of view (a wrapper adding --set) is reported as different, exit 1; one
# that fails is reported by name; an unknown scene is refused, exit 2.
. "$(dirname "$0")/lib.sh"
python_with astropy python3-astropy
compare() { # compare NEW_BINARY TAG: runs compare_builds.sh, output in $WORK/TAG.log, sets $got
  got=0
  bash "$SRC/scripts/compare_builds.sh" --only text-table-perspective "$ORRERY" "$1" "$WORK/run-$2" >"$WORK/$2.log" 2>&1 || got=$?
}

compare "$ORRERY" same
[ "$got" -eq 0 ] && grep -q "text-table-perspective: 1 FITS file(s), identical" "$WORK/same.log" ||
  fail "the same binary twice: exit $got, $(cat "$WORK/same.log")"

printf '#!/bin/sh\nexec "%s" "$@" --set camera.fov=41\n' "$ORRERY" >"$WORK/wider"
printf '#!/bin/sh\necho "cannot render: planted failure" >&2\nexit 3\n' >"$WORK/broken"
chmod +x "$WORK/wider" "$WORK/broken"
compare "$WORK/wider" wider
[ "$got" -eq 1 ] && grep -q "plummer.fits\[0\]: data differ" "$WORK/wider.log" ||
  fail "a wider field of view: exit $got, $(cat "$WORK/wider.log")"
compare "$WORK/broken" broken
[ "$got" -eq 1 ] && grep -q "text-table-perspective: new build failed: cannot render: planted failure" "$WORK/broken.log" ||
  fail "a build that fails: exit $got, $(cat "$WORK/broken.log")"

got=0
bash "$SRC/scripts/compare_builds.sh" --only no-such-scene "$ORRERY" "$ORRERY" "$WORK/none" >"$WORK/none.log" 2>&1 || got=$?
[ "$got" -eq 2 ] && grep -q "no scene 'no-such-scene'" "$WORK/none.log" ||
  fail "an unknown scene: exit $got, $(cat "$WORK/none.log")"
cat "$WORK/same.log" "$WORK/wider.log"
finish
