#!/bin/bash
# scripts/box_stats.py, the growth check docs/dark-universe.md quotes, on
# synthetic 16^3 boxes with known answers (check_box_stats.py).
. "$(dirname "$0")/lib.sh"
python_with h5py python3-h5py
python_with scipy python3-scipy
run_checker "box_stats" check_box_stats.py
finish
