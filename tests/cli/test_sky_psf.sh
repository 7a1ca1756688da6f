# A sky map's PSF keeps its angular size across a dome master (check_sky_psf.py);
# the Hubble-like PSF's spikes keep their angle and length (check_sky_spikes.py).
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" "$(dirname "$0")/check_sky_psf.py" "$ORRERY" "$WORK" || fail "sky PSF size"
# The Hubble-like PSF on sky maps: spikes in angle, flux kept (check_sky_spikes.py).
"$py" "$(dirname "$0")/check_sky_spikes.py" "$ORRERY" "$WORK" || fail "sky PSF spikes"
finish
