#!/bin/bash
# scripts/collision_tails.py, the first pericentre and tails docs/gallery.md
# quotes, on 12 synthetic snapshots with known answers
# (check_collision_tails.py).
. "$(dirname "$0")/lib.sh"
python_with h5py python3-h5py
run_checker "collision_tails" check_collision_tails.py
finish
