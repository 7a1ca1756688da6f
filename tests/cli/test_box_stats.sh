#!/bin/bash
# scripts/box_stats.py, the growth check docs/dark-universe.md quotes, on
# synthetic 16^3 boxes with known answers (check_box_stats.py).
. "$(dirname "$0")/lib.sh"
python_with h5py python3-h5py
python_with scipy python3-scipy
if "$py" "$SRC/tests/cli/check_box_stats.py" "$SRC" "$WORK" >"$WORK/log" 2>&1; then
  cat "$WORK/log"
else
  fail "box_stats: $(cat "$WORK/log")"
fi
finish
