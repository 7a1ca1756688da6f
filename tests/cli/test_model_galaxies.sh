# `orrery model --galaxies pair|mw|m31 --disc-q Q --m31-weight W` (docs/cli.md):
# the scene keys input.model.galaxies, .disc_q and .m31_weight on the command line.
# Which markers each choice holds (model.h's ids: 1 the Milky Way's black
# hole, 2 M31's, 3 the Sun), where its particles are, that Toomre's Q sets
# the discs' radial dispersion (sigma_R proportional to Q, sigma_z not), that
# the table renders exactly as the scene keys' model does, and bad values;
# scripts/model_ez.py on the table.
source "$(dirname "$0")/lib.sh"

"$ORRERY" model --help >help.txt || fail "model --help"
grep -q -- "--galaxies WHICH" help.txt && grep -q -- "--disc-q Q" help.txt && grep -q -- "--m31-weight W" help.txt ||
  fail "help: $(cat help.txt)"

for g in pair mw m31; do
  "$ORRERY" model -o $g.txt --particles 3000 --galaxies $g >out.txt 2>&1 || fail "--galaxies $g: $(cat out.txt)"
done
"$ORRERY" model -o q3.txt --particles 3000 --galaxies mw --disc-q 3 >out.txt 2>&1 || fail "--disc-q 3: $(cat out.txt)"
"$ORRERY" model -o w4.txt --particles 3000 --m31-weight 4 >out.txt 2>&1 || fail "--m31-weight 4: $(cat out.txt)"
PYTHONPATH="$SRC/tests/cli" "$py" - <<'PY' || fail "model tables"
import numpy as np
from expect import check, done
def load(name):
    return np.loadtxt(name, skiprows=1)  # x y z mass id type vx vy vz r E0 ez
markers = {"pair": {1, 2, 3}, "mw": {1, 3}, "m31": {2}}
for g, want in markers.items():
    d = load(f"{g}.txt")
    check(len(d) == 3000, f"{g}: {len(d)} rows")
    ids = set(d[d[:, 5] >= 4, 4].astype(int))
    check(ids == want, f"{g}: marker ids {sorted(ids)}, expected {sorted(want)}")
    r = np.sqrt((d[:, :3] ** 2).sum(axis=1))
    if g != "pair":  # alone, at rest at the origin: no particle 780 kpc away
        check(np.median(r) < 100 and r.max() < 500, f"{g}: median r {np.median(r)}, max {r.max()}")
    else:
        check(r.max() > 600, f"pair: farthest particle {r.max()} kpc, expected M31 ~780 kpc away")
def dispersions(d):
    d = d[d[:, 5] == 2]
    R = np.hypot(d[:, 0], d[:, 1])
    m = (R > 5) & (R < 10)
    vR = (d[m, 0] * d[m, 6] + d[m, 1] * d[m, 7]) / R[m]
    return vR.std(), d[m, 8].std()
(sr1, sz1), (sr3, sz3) = dispersions(load("mw.txt")), dispersions(load("q3.txt"))
check(abs(sr3 / sr1 - 2) < 0.02, f"sigma_R {sr1} at Q = 1.5, {sr3} at Q = 3: expected twice")
check(abs(sz3 / sz1 - 1) < 0.02, f"sigma_z {sz1} at Q = 1.5, {sz3} at Q = 3: expected the same")
# --m31-weight 4: M31's star particles (ids after the Milky Way's halo) weigh
# four times the Milky Way's, each galaxy's stars keep their mass, and the
# Milky Way gets more of the 3000 particles.
def star_masses(d):
    d = d[d[:, 4] > 3]
    mw = np.arange(len(d)) < np.flatnonzero((d[1:, 5] == 2) & (d[:-1, 5] == 1))[0] + 1
    stars = d[:, 5] != 1
    return d[mw & stars, 3], d[~mw & stars, 3], mw.sum()
(mw1, m311, n1), (mw4, m314, n4) = star_masses(load("pair.txt")), star_masses(load("w4.txt"))
check(abs(np.median(m314) / np.median(mw4) - 4) < 0.02, f"--m31-weight 4: star masses {np.median(mw4)}, {np.median(m314)}")
check(abs(mw4.sum() / mw1.sum() - 1) < 1e-5 and abs(m314.sum() / m311.sum() - 1) < 1e-5, "--m31-weight 4 moved stellar mass")
check(n4 > 1.6 * n1, f"--m31-weight 4: the Milky Way has {n4} particles, {n1} without")
done()
PY

# The table renders as the scene's own model with the same keys.
view="camera: {projection: orthographic, width: 60, position: [0, 0, 100]}
image: {width: 48, height: 48}
output: {png: false}"
printf 'input: {file: q3.txt}\n%s\n' "$view" >table.yaml
printf 'input: {model: {name: mw-m31, particles: 3000, galaxies: mw, disc_q: 3}}\n%s\n' "$view" >keys.yaml
# (Q moves no particle, only their velocities, checked above; the control is M31.)
printf 'input: {model: {name: mw-m31, particles: 3000, galaxies: m31, disc_q: 3}}\n%s\n' "$view" >m31.yaml
for s in table keys m31; do
  "$ORRERY" render $s.yaml -o $s -q 2>err.txt || fail "render $s: $(cat err.txt)"
done
"$py" - <<'PY' || fail "renders of the table and of the scene keys"
import glob
import numpy as np
from astropy.io import fits
img = {s: fits.open(glob.glob(f"{s}/*.fits")[0])[0].data for s in ("table", "keys", "m31")}
ok = img["table"].max() > 0 and np.array_equal(img["table"], img["keys"]) and not np.array_equal(img["keys"], img["m31"])
print("" if ok else f"max |table - keys| {np.abs(img['table'] - img['keys']).max()}")
raise SystemExit(not ok)
PY

# scripts/model_ez.py (docs/model.md, "Vertical energy ez") on the Milky
# Way's 810 disc stars: the fraction the logistic weights keep and its mean
# |z| near what the recipe predicts (binomial noise 0.017 and about 0.01
# kpc); a bad --select and a table without ez refused by name.
ez=$("$py" "$SRC/scripts/model_ez.py" mw.txt) || fail "model_ez.py: $ez"
echo "$ez" | awk '/^[0-9]+ disc stars: ez mean/ { n = $1; m = $6 + 0; seen = 1 } END { exit !(seen && n > 700 && m > 1.35 && m < 1.65) }' ||
  fail "model_ez.py, the distribution: $ez"
echo "$ez" | awk '/^logistic/ { gsub(/[,()]/, ""); k = $7; z = $10; rk = $14; rz = $15
  if (k - rk > 0.05 || rk - k > 0.05 || z - rz > 0.02 || rz - z > 0.02) bad = 1; n++ } END { exit !(n == 2 && !bad) }' ||
  fail "model_ez.py, the selections against the recipe: $ez"
"$py" "$SRC/scripts/model_ez.py" --select 1 mw.txt >/dev/null 2>err.txt && fail "model_ez.py took --select 1"
grep -q "^model_ez: --select \['1'\]: expected V0,DV" err.txt || fail "model_ez.py --select 1: $(cat err.txt)"
printf 'x y z mass id type vx vy vz r E0\n0 0 0 1 4 2 0 0 0 0 0\n' >old.txt
"$py" "$SRC/scripts/model_ez.py" old.txt >/dev/null 2>err.txt && fail "model_ez.py read a table without ez"
grep -q "^model_ez: old.txt: not a table of .orrery model. (no column ez" err.txt || fail "model_ez.py, no ez: $(cat err.txt)"

expect_fail 2 "^orrery: error: --galaxies andromeda: expected pair, mw or m31" out -- model -o out/m.txt --galaxies andromeda
expect_fail 2 "^orrery: error: --disc-q 0: expected the discs' Toomre Q, above 0" out -- model -o out/m.txt --disc-q 0
expect_fail 2 "^orrery: error: --disc-q -1: expected" out -- model -o out/m.txt --disc-q -1
expect_fail 2 "^orrery: error: --disc-q nan: expected" out -- model -o out/m.txt --disc-q nan
expect_fail 2 "^orrery: error: --disc-q 1000: expected .* at most 100" out -- model -o out/m.txt --disc-q 1000
expect_fail 2 "^orrery: error: --m31-weight 65: expected .* from 0.015625 to 64" out -- model -o out/m.txt --m31-weight 65
expect_fail 2 "^orrery: error: --m31-weight nan: expected" out -- model -o out/m.txt --m31-weight nan
printf 'input: {model: {name: mw-m31, particles: 3000, m31_weight: 0}}\n%s\n' "$view" >w0.yaml
expect_fail 2 "input.model.m31_weight" out -- render w0.yaml -o out/w0
printf 'input: {model: {name: king, particles: 3000, m31_weight: 2}}\n%s\n' "$view" >kw.yaml
expect_fail 2 "input.model.m31_weight does not apply to input.model.name: king" out -- render kw.yaml -o out/kw
finish
