#!/bin/bash
# scripts/collision_tails.py, the first pericentre and tails docs/gallery.md
# quotes, on 12 synthetic snapshots with known answers
# (check_collision_tails.py).
. "$(dirname "$0")/lib.sh"
python_with h5py python3-h5py
if "$py" "$SRC/tests/cli/check_collision_tails.py" "$SRC" "$WORK" >"$WORK/log" 2>&1; then
  cat "$WORK/log"
else
  fail "collision_tails: $(cat "$WORK/log")"
fi
finish
