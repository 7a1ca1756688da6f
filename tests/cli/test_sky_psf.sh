# A sky map's PSF keeps its angular size across a dome master (check_sky_psf.py);
# the Hubble-like PSF's spikes keep their angle and length (check_sky_spikes.py);
# stars do not twinkle at the automatic core (check_star_shimmer.py).
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" "$(dirname "$0")/check_sky_psf.py" "$ORRERY" "$WORK" || fail "sky PSF size"
# The Hubble-like PSF on sky maps: spikes in angle, flux kept (check_sky_spikes.py).
"$py" "$(dirname "$0")/check_sky_spikes.py" "$ORRERY" "$WORK" || fail "sky PSF spikes"
# Stars gliding across pixels keep their flux and centroid and do not
# twinkle at the automatic core width (check_star_shimmer.py).
"$py" "$(dirname "$0")/check_star_shimmer.py" "$ORRERY" "$WORK" || fail "stars twinkle"
finish
