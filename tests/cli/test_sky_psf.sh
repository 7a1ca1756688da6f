# A sky map's PSF keeps its angular size across a dome master (check_sky_psf.py);
# the Hubble-like PSF's spikes keep their angle and length (check_sky_spikes.py);
# stars do not twinkle at the automatic core (check_star_shimmer.py, and
# check_star_glide.py at the maps' edges, on flat images and panned).
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" "$(dirname "$0")/check_sky_psf.py" "$ORRERY" "$WORK" || fail "sky PSF size"
# The Hubble-like PSF on sky maps: spikes in angle, flux kept (check_sky_spikes.py).
"$py" "$(dirname "$0")/check_sky_spikes.py" "$ORRERY" "$WORK" || fail "sky PSF spikes"
# Stars gliding across pixels keep their flux and centroid and do not
# twinkle at the automatic core width (check_star_shimmer.py).
"$py" "$(dirname "$0")/check_star_shimmer.py" "$ORRERY" "$WORK" || fail "stars twinkle"
# ... across the panoramas' seam and poles, at the dome's rim, on flat
# images with the default Gaussian PSF, and in a panned star field
# (check_star_glide.py).
"$py" "$(dirname "$0")/check_star_glide.py" "$ORRERY" "$WORK" || fail "stars twinkle at the edges, flat or panned"
finish
