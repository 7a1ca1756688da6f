#!/usr/bin/env bash
# Future Sky, short: 25 frames of the Milky Way-Andromeda collision seen from
# the Sun over 4.8 Gyr, past the galaxies' first pericentre, evolved by the
# example N-body code (500 000 particles, 600 block steps of 8 Myr, each
# particle on its own step down to 2 Myr, softening
# 0.2 kpc for stars and 0.4 for dark matter: fewer particles heat the Milky
# Way's disc into a thick glow before Andromeda arrives, docs/nbody.md,
# "The band and the particle number") and rendered in-situ with configs/futuresky-sequence.yaml at a quarter of
# its size: a 1024x1024 dome master and a 1024x512 panorama per frame, then
# a film of each when ffmpeg is there. docs/gallery.md gives the time it
# took here; the full-length run is the config's own command.
#
# For a sky whose light holds from frame to frame (frames are 196 Myr apart,
# most of the Sun's orbit): M31's particles weigh 4 times the Milky Way's
# (--m31-weight 4: 98 000 disc particles about the Sun instead of 53 500),
# the discs start with Toomre's Q = 3, their stars spread along their orbits
# (--disc-q 3 --phase-mix 0.5: quieter spirals, though twice the real old
# disc's radial speeds), and each disc particle's stars and glow spread over
# 0.2 kpc, about the particles' spacing at the Sun (stars.spread).
# docs/nbody.md, "A quieter disc for the short film". Block steps (--eta 0.2
# --dt-min 0.002, the Sun always on the shortest) take 0.76 of the global
# 2 Myr step's CPU in this disc, with a steadier sky and a smaller energy error.
#
#   examples/futuresky-short.sh [OUT_DIR [SNAPSHOT_DIR]]   (default out/futuresky-short)
#
# With SNAPSHOT_DIR, a snapshot every 5 steps (39 Myr, 40 MB each; frame k is
# snapshot 5k) goes
# there too, for scripts/collision_tails.py (first pericentre, tails) and
# configs/collision-snapshots.yaml (the collision from outside).
#
# Pixels hold surface brightness (per steradian), so the config's white
# levels grade the smaller frames like the full-size ones.
#
# The N-body code prints a progress line on stderr every 10 s (step, time,
# energy error, particle-steps per second, time left), even with --quiet.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${ORRERY_BUILD:-$here/build}
out=${1:-out/futuresky-short}
scene=$here/configs/futuresky-sequence.yaml
snapshots=()
[ $# -ge 2 ] && snapshots=(--snapshot-every 5 --snapshot-dir "$2")
"$build/examples/orrery-nbody" --particles 500000 --m31-weight 4 --disc-q 3 --phase-mix 0.5 \
  --steps 600 --render-every 25 --dt 0.008 --eta 0.2 --dt-min 0.002 --eps 0.2 --tracer-ring 32 --tracer-mirror --quiet \
  --scene "$scene" --set output.dir="$out" --set animation.frames=25 --set stars.spread=0.2 \
  --set views.dome.image.width=1024 --set views.dome.image.height=1024 \
  --set views.panorama.image.width=1024 --set views.panorama.image.height=512 "${snapshots[@]}"
if command -v ffmpeg >/dev/null; then
  "$build/orrery" video "$scene" --force --set output.dir="$out" --set animation.frames=25
fi
