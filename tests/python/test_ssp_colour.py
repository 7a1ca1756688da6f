"""Stellar ages and metallicities colouring stars through the CMD/PARSEC
simple-stellar-population table (colour: {ssp: ...}, docs/colour.md):
a synthetic EAGLE/AREPO-style snapshot whose StellarFormationTime holds
formation scale factors. The truth is independent of orrery's code: the
formation scale factors of stars 125.9 Myr and 7.943 Gyr old come from
astropy's cosmology, and the expected brightness ratio from the V
magnitudes of those two grid points, quoted from the table's source file.
The snapshot is written SWIFT style (7 types, Time a 1-element array) with
EAGLE's dataset names."""
import json

import numpy as np
import pytest

import orrery
from conftest import cli_render
from test_hdf5_fields import write_stars  # a SWIFT-style snapshot of stars: Time, PartType4

h5py = pytest.importorskip("h5py")
cosmology = pytest.importorskip("astropy.cosmology")
units = pytest.importorskip("astropy.units")
fits = pytest.importorskip("astropy.io.fits")

# pynbody/analysis/default_ssp.txt (CMD 3.7), lines 534 and 558: Z = 0.01471,
# ages 1.259e8 and 7.943e9 yr; columns B and V.
YOUNG_AGE, YOUNG_B, YOUNG_V = 1.259e8, 3.254, 3.095
OLD_AGE, OLD_B, OLD_V = 7.943e9, 7.634, 6.741

SCENE = {"camera": {"projection": "orthographic", "width": 4, "position": [0, 0, 10], "look_at": [0, 0, 0],
                    "up": [0, 1, 0]},
         "image": {"width": 40, "height": 40}, "deposit": "ngp", "output": {"name": "stars", "png": False},
         "colour": {"populations": [
             {"name": "stars", "select": {"types": [4]},
              "colour": {"ssp": {"field": "StellarFormationTime", "clock": "scale_factor",
                                 "metallicity_field": "Metallicities", "h": 0.7, "omega_m": 0.3}},
              "luminance": {"ssp": 1.0}}]}}


def formation_scale_factor(age_yr):
    """a at which a star now (a = 1) age_yr old formed, flat LCDM h = 0.7,
    omega_m = 0.3 without radiation (orrery's convention)."""
    c = cosmology.FlatLambdaCDM(H0=70, Om0=0.3, Tcmb0=0)
    z = cosmology.z_at_value(c.age, c.age(0) - age_yr * units.yr)
    return float(1 / (1 + z))


def render(cli, tmp_path, scene, snapshot):
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(scene))
    cli_render(cli, scene_file, snapshot, tmp_path / "out")
    with fits.open(tmp_path / "out" / "stars.fits") as f:
        return [np.flipud(h.data).astype(np.float64) for h in f]


@pytest.fixture
def stars():
    """Young stars (125.9 Myr) on the left half, old ones (7.943 Gyr) on the
    right; the old ones with Z = 0.03, beyond the table's 0.01471, which is
    clamped to it. Equal masses."""
    rng = np.random.default_rng(25)
    n = 4000
    pos = rng.uniform(-1.9, 1.9, size=(n, 3)).astype(np.float32)
    young = pos[:, 0] < 0
    birth = np.where(young, formation_scale_factor(YOUNG_AGE), formation_scale_factor(OLD_AGE))
    metals = np.where(young, 0.01471, 0.03)
    return pos, np.full(n, 1e-3, dtype=np.float32), birth.astype(np.float32), metals.astype(np.float32), young


def test_young_blue_old_red_and_brighter(tmp_path, cli, stars):
    pos, mass, birth, metals, young = stars
    write_stars(tmp_path / "stars.hdf5", pos, mass, birth, metals)
    x, y, z = render(cli, tmp_path, SCENE, tmp_path / "stars.hdf5")
    left, right = slice(0, 19), slice(21, 40)
    xy = lambda s: (x[:, s].sum() / (x[:, s] + y[:, s] + z[:, s]).sum())
    assert xy(left) < 0.30 < 0.32 < xy(right)  # B-V 0.16 (8100 K) against 0.89 (5100 K)
    # The V light per star: 10^(-0.4 V) of each age, times the star counts.
    expected = 10 ** (-0.4 * (YOUNG_V - OLD_V))
    in_left = (pos[:, 0] >= -2.0) & (pos[:, 0] < -0.1)
    in_right = (pos[:, 0] >= 0.1) & (pos[:, 0] < 2.0)
    assert in_left.sum() > 1000 and in_right.sum() > 1000
    measured = (y[:, left].sum() / np.count_nonzero(in_left)) / (y[:, right].sum() / np.count_nonzero(in_right))
    assert measured == pytest.approx(expected, rel=1e-6)
    # The Python package, given the same arrays and time, gives the same planes.
    image = orrery.Scene(SCENE).render(pos, mass, np.arange(1, len(pos) + 1),
                                       fields={"StellarFormationTime": birth, "Metallicities": metals},
                                       types=np.full(len(pos), 4), time=1.0)[0]
    assert [image.planes[k].astype(np.float64).tobytes() for k in "XYZ"] == [p.tobytes() for p in (x, y, z)]


def test_time_clock_and_snapshot_time(tmp_path, cli, stars):
    """Formation times in Gyr with the snapshot's own Time as "now" give the
    same picture as the scale factors."""
    pos, mass, birth, metals, young = stars
    write_stars(tmp_path / "a.hdf5", pos, mass, birth, metals)
    by_a = render(cli, tmp_path, SCENE, tmp_path / "a.hdf5")
    now = 13.0
    born = np.where(young, now - YOUNG_AGE / 1e9, now - OLD_AGE / 1e9).astype(np.float32)
    write_stars(tmp_path / "t.hdf5", pos, mass, born, metals, time=now)
    scene = json.loads(json.dumps(SCENE))
    scene["colour"]["populations"][0]["colour"]["ssp"] = {
        "field": "StellarFormationTime", "clock": "time", "unit_yr": 1e9, "metallicity_field": "Metallicities"}
    by_t = render(cli, tmp_path, scene, tmp_path / "t.hdf5")
    for p, q in zip(by_a, by_t):
        np.testing.assert_allclose(p, q, rtol=2e-3, atol=1e-9 * p.max())


def test_bad_ssp_keys(tmp_path, cli, stars):
    import subprocess
    pos, mass, birth, metals, young = stars
    write_stars(tmp_path / "stars.hdf5", pos, mass, birth, metals)
    for ssp, message in [({"clock": "age"}, "needs field"),
                         ({"field": "StellarFormationTime", "clock": "redshift"},
                          "expected one of: age time scale_factor, got 'redshift'"),
                         ({"field": "StellarFormationTime", "metallicity_field": "Metals"},
                          "no group read has a dataset Metals (PartType4 has: Coordinates"),
                         ({"field": "StellarFormationTime", "clock": "scale_factor", "omega_m": 1.5}, "omega_m")]:
        scene = json.loads(json.dumps(SCENE))
        scene["colour"]["populations"][0]["colour"]["ssp"] = ssp
        scene_file = tmp_path / "scene.yaml"
        scene_file.write_text(json.dumps(scene))
        run = subprocess.run([cli, "render", str(scene_file), "--set", f"input.file={tmp_path / 'stars.hdf5'}",
                              "-o", str(tmp_path / "bad")], capture_output=True, text=True)
        assert run.returncode != 0 and message in run.stderr, (ssp, run.stderr)
        assert not (tmp_path / "bad" / "stars.fits").exists()
