# A run of frames over a snapshot sequence: each frame's particles are
# interpolated at its time (animation.time, or the sequence's own range),
# matched by id, so a particle moving at constant velocity lands where it
# should in every frame, and the galactic frame of an observer particle
# follows it through the sequence.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# Three Gadget-1 snapshots at t = 0, 1, 2 of 3 particles moving in x at
# 2 units per time (ids listed in a different order in each file), and an
# observer (id 10) and reference (id 11) moving along.
"$py" - <<'PY' || fail "writing snapshots"
import struct
import numpy as np
def record(f, b):
    f.write(struct.pack("<i", len(b))); f.write(b); f.write(struct.pack("<i", len(b)))
x0 = np.array([-6.0, -4.0, -2.0, 0.0, 1.0]); v = 2.0
ids = np.array([1, 2, 3, 10, 11], dtype="<u4")
for k, t in enumerate((0.0, 1.0, 2.0)):
    order = np.roll(np.arange(5), k)
    pos = np.zeros((5, 3)); pos[:, 0] = x0 + v * t; pos[3:, 1] = 5.0
    vel = np.zeros((5, 3)); vel[:, 0] = v
    n = 5
    head = bytearray(256)
    struct.pack_into("<6i", head, 0, 0, n, 0, 0, 0, 0)
    struct.pack_into("<6d", head, 24, 0, 1.0, 0, 0, 0, 0)
    struct.pack_into("<d", head, 72, t)
    struct.pack_into("<6I", head, 96, 0, n, 0, 0, 0, 0)
    struct.pack_into("<i", head, 124, 1)
    with open(f"snap_{k:03d}", "wb") as f:
        record(f, bytes(head))
        record(f, pos[order].astype("<f4").tobytes())
        record(f, vel[order].astype("<f4").tobytes())
        record(f, ids[order].tobytes())
PY

cat >seq.yaml <<'Y'
input:
  sequence: {pattern: snap_%03d, first: 0, last: 2}
camera: {projection: orthographic, width: 40, position: [0, 0, 10]}
image: {width: 40, height: 4}
deposit: ngp
animation: {frames: 5}
output: {dir: out, png: false}
Y
"$ORRERY" render seq.yaml -q || fail "render the sequence"
"$py" - <<'PY' || fail "particles not where constant velocity puts them"
import numpy as np
from astropy.io import fits
bad = 0
for f in range(5):
    h = fits.open(f"out/seq_{f:04d}.fits")[0]
    t = 2.0 * f / 4
    cols = sorted(set(np.nonzero(h.data.sum(axis=0))[0]))
    # x = -20 .. 20 over 40 columns: column = floor(x + 20)
    want = sorted(set(int(np.floor(x + 2.0 * t + 20)) for x in (-6.0, -4.0, -2.0)))
    if cols != want or abs(h.header["SIMTIME"] - t) > 1e-9:
        print(f"frame {f}: columns {cols}, expected {want}; SIMTIME {h.header['SIMTIME']}, expected {t}"); bad += 1
raise SystemExit(bad)
PY

# animation.time picks part of the range; an observer moves with the run.
"$ORRERY" render seq.yaml -q -o part --set 'animation.time=[0.5, 1.5]' --set animation.frames=2 || fail "animation.time"
"$py" -c "
from astropy.io import fits
assert abs(fits.getheader('part/seq_0001.fits')['SIMTIME'] - 1.5) < 1e-9
" || fail "animation.time: last frame not at t = 1.5"
cat >sky.yaml <<'Y'
input:
  sequence: {files: [snap_000, snap_001, snap_002]}
  types: [1]
observer: {id: 10, reference_id: 11}
camera: {projection: hammer-aitoff}
image: {width: 64, height: 32}
animation: {frames: 5}
output: {dir: sky, name: seq, png: false}
Y
"$ORRERY" render sky.yaml -q 2>sky.err || fail "observer over a sequence: $(cat sky.err)"
"$py" -c "
from astropy.io import fits
a, b = fits.getheader('sky/seq_0000.fits'), fits.getheader('sky/seq_0004.fits')
assert abs(a['CAMPOSX'] - 0.0) < 1e-5 and abs(b['CAMPOSX'] - 4.0) < 1e-5, (a['CAMPOSX'], b['CAMPOSX'])
" || fail "the observer did not follow the sequence"

# A time outside the sequence is an error naming it.
expect_fail 2 "animation.time \\[0, 5\\] reaches outside the sequence's snapshots, times 0 to 2" bad -- render seq.yaml -o bad --set 'animation.time=[0, 5]'
finish
