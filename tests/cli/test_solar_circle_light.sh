# scripts/solar_circle_light.py (docs/nbody.md, "The sky's light from many
# Suns"): against the light of continuous rings of stars, seen from their
# plane, and a disc turning rigidly at the circle's angular speed, whose
# observers, riding round with it, see no change; then its refusals.
source "$(dirname "$0")/lib.sh"

# rings.hdf5: rings of 3600 stars in the plane z = 0 (disc stars of radius
# 3.5 and 8 kpc, bulge stars of radius 2) turning at 200 km/s about +z, and
# two heavy clumps of 50 stars at (9 kpc, 30 deg) and (9 kpc, 210 deg) turning
# with the 8 kpc ring (25 km/s/kpc). turned.hdf5: the same 0.02 time units
# later, everything turned by 0.5 rad; still.hdf5: turned, but at the first
# snapshot's time. close.hdf5 and after.hdf5 turn on, Andromeda's black
# hole 50 kpc away in the first, 500 again in the second.
"$py" - <<'PY' || fail "making the snapshots"
import h5py
import numpy as np

def ring(radius, n, speed, phase=0.0):
    a = phase + 2 * np.pi * np.arange(n) / n
    x = np.stack([radius * np.cos(a), radius * np.sin(a), np.zeros(n)], 1)
    v = np.stack([-speed * np.sin(a), speed * np.cos(a), np.zeros(n)], 1)
    return x, v

def clump(phase):
    rng = np.random.default_rng(7)
    a = phase + 0.05 * rng.standard_normal(50)
    r = 9 + 0.1 * rng.standard_normal(50)
    x = np.stack([r * np.cos(a), r * np.sin(a), 0.05 * rng.standard_normal(50)], 1)
    v = 25.0 * np.stack([-x[:, 1], x[:, 0], np.zeros(50)], 1)
    return x, v

def write(path, time, turn, m31=500.0):
    c, s = np.cos(turn), np.sin(turn)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    parts = {2: [ring(3.5, 3600, 200), ring(8, 3600, 200), clump(np.pi / 6), clump(7 * np.pi / 6)],
             3: [ring(2, 3600, 200)]}
    masses = {2: [1e-5, 2e-5, 2e-4, 2e-4], 3: [3e-5]}
    with h5py.File(path, "w") as f:
        f.create_group("Header").attrs["Time"] = time
        ids = 10
        for t, pieces in parts.items():
            x = np.concatenate([p[0] for p in pieces]) @ rot.T
            v = np.concatenate([p[1] for p in pieces]) @ rot.T
            m = np.concatenate([np.full(len(p[0]), mm) for p, mm in zip(pieces, masses[t])])
            g = f.create_group(f"PartType{t}")
            g["Coordinates"], g["Velocities"], g["Masses"] = x, v, m
            g["ParticleIDs"] = np.arange(ids, ids + len(m))
            ids += len(m)
        g = f.create_group("PartType5")
        g["Coordinates"] = np.array([[0, 0, 0], [m31, 0, 0]])
        g["Velocities"] = np.zeros((2, 3))
        g["Masses"] = np.array([1e-4, 1e-4])
        g["ParticleIDs"] = np.array([1, 2])

write("rings.hdf5", 1.0, 0.0)
write("turned.hdf5", 1.02, 0.5)
write("still.hdf5", 1.0, 0.5)
write("close.hdf5", 1.04, 1.0, m31=50.0)
write("after.hdf5", 1.06, 1.5)
PY

script="$SRC/scripts/solar_circle_light.py"
"$py" "$script" rings.hdf5 turned.hdf5 >turn.out 2>turn.err || fail "two snapshots: $(cat turn.err)"
"$py" "$script" rings.hdf5 still.hdf5 >still.out 2>still.err || fail "the still snapshot: $(cat still.err)"
# The summary stops at the first snapshot with Andromeda within --near.
"$py" "$script" rings.hdf5 turned.hdf5 close.hdf5 after.hdf5 >near.out 2>near.err || fail "Andromeda near: $(cat near.err)"
grep -q "^64 observers, 1 steps before Andromeda is within 100 kpc" near.out || fail "the summary's steps: $(cat near.out)"
[ "$(grep -c "hdf5 .*|" near.out)" -eq 3 ] || fail "every step's line: $(cat near.out)"
"$py" - <<'PY' || fail "the light of the rings or the turn: $(cat turn.out still.out)"
import numpy as np

# The mean of 1 / (d^2 + s^2) round a ring of radius a, seen from radius R
# in its plane: 1 / sqrt((R^2 + a^2 + s^2)^2 - 4 R^2 a^2).
R, s = 8.0, 0.25
ring = lambda a: 1 / np.sqrt((R * R + a * a + s * s) ** 2 - 4 * R * R * a * a)
rings = 3600 * (1e-5 * ring(3.5) + 2e-5 * ring(8) + 3e-5 * ring(2))

def rows(path):
    lines = open(path).read().splitlines()
    return [l.split() for l in lines if l.endswith(".hdf5") or ".hdf5 " in l], lines[-1]

turn, summary = rows("turn.out")
mean, spread = float(turn[0][2]), float(turn[0][3])
# The clumps (2 x 50 stars, 1 kpc outside the circle) light their side.
assert mean > rings and spread > 5, (mean, rings, spread)
largest = float(turn[1][-2])
assert largest < 0.05, f"observers riding with a rigid turn saw the light change by {largest} %"
assert "64 of 64 within 15 % at every step" in summary, summary
# The disc's m = 2 amplitudes: the ring of 3.5 kpc is round (0.000); at
# 6-10 kpc the two clumps, opposite each other, against the 8 kpc ring.
import h5py
with h5py.File("rings.hdf5", "r") as f:
    x, m = f["PartType2/Coordinates"][:], f["PartType2/Masses"][:]
R, phi = np.hypot(x[:, 0], x[:, 1]), np.arctan2(x[:, 1], x[:, 0])
ring = (R >= 6) & (R < 10)
a2 = abs(np.sum(m[ring] * np.exp(2j * phi[ring]))) / np.sum(m[ring])
assert 0.15 < a2 < 0.3, a2
for row in turn:
    assert row[6] == "0.000" and abs(float(row[7]) - a2) < 6e-4, (row, a2)
still, summary = rows("still.out")
assert float(still[1][-2]) > 10, f"observers left behind by the turn saw only {still[1][-2]} %"
PY

# The rings alone: their light is the formula's to 1e-6 for every observer.
"$py" - <<'PY' || fail "rings alone"
import h5py, numpy as np
with h5py.File("rings.hdf5", "r") as f, h5py.File("bare.hdf5", "w") as g:
    for k in f:
        f.copy(k, g)
    d = g["PartType2"]
    keep = 7200
    for name in ("Coordinates", "Velocities", "Masses", "ParticleIDs"):
        data = d[name][:keep]
        del d[name]
        d[name] = data
PY
"$py" "$script" --observers 16 bare.hdf5 >bare.out 2>bare.err || fail "rings alone: $(cat bare.err)"
"$py" - <<'PY' || fail "rings alone against the formula: $(cat bare.out)"
import numpy as np
R, s = 8.0, 0.25
ring = lambda a: 1 / np.sqrt((R * R + a * a + s * s) ** 2 - 4 * R * R * a * a)
rings = 3600 * (1e-5 * ring(3.5) + 2e-5 * ring(8) + 3e-5 * ring(2))
row = open("bare.out").read().splitlines()[1].split()
mean, spread, lo, hi = map(float, row[2:6])
assert abs(mean / rings - 1) < 2e-4 and spread < 0.05 and lo == 1.0 and hi == 1.0, (mean, rings, row)
PY

# Refusals: each names the file and what is wrong, exit status 1.
refuses() {
  local pattern=$1
  shift
  local got=0
  "$py" "$script" "$@" >refuse.out 2>refuse.err || got=$?
  [ "$got" -eq 1 ] && grep -q -- "$pattern" refuse.err || fail "$* exited $got: $(cat refuse.err)"
}
echo "not HDF5" >text.hdf5
refuses "text.hdf5: cannot read it as HDF5" text.hdf5
"$py" -c 'import h5py; h5py.File("nohole.hdf5", "w").create_group("PartType2")' || fail "making nohole.hdf5"
refuses "nohole.hdf5: no Milky Way black hole (PartType5, id 1)" nohole.hdf5
"$py" - <<'PY' || fail "making notime.hdf5"
import h5py
with h5py.File("rings.hdf5", "r") as f, h5py.File("notime.hdf5", "w") as g:
    for k in f:
        if k != "Header":
            f.copy(k, g)
PY
refuses "notime.hdf5: no Header/Time attribute" notime.hdf5
refuses "rings.hdf5: no disc stars within 0.5 kpc of the circle of radius 20 kpc" --radius 20 rings.hdf5
refuses "observers 0: expected at least 1" --observers 0 rings.hdf5
refuses "soften nan: expected a number above 0" --soften nan rings.hdf5
finish
