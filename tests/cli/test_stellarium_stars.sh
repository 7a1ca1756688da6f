#!/bin/bash
# scripts/stellarium_stars.py, the reader of Stellarium's star catalogues
# behind data/sky/, on small catalogues written from the format
# (check_stellarium_stars.py); the real catalogues are read by
# test_sky_truth.sh where stellarium-data is installed.
. "$(dirname "$0")/lib.sh"
python_with numpy python3-numpy
run_checker "stellarium_stars" check_stellarium_stars.py
finish
