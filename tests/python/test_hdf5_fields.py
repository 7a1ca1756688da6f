"""Named HDF5 datasets as fields in orrery's own reader: a SWIFT snapshot's
Pressures and one column of its MagneticFluxDensities as the weight, and a
snapshot's StellarFormationTime choosing its stars' colours. The CLI, reading
the file, gives the same pixels as the Python package given the same
datasets through h5py."""
import json
import os
import subprocess

import numpy as np
import pytest
from astropy.io import fits

import orrery
from conftest import cli_render

h5py = pytest.importorskip("h5py")
SHARED = os.environ.get("ORRERY_SHARED_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared",
                                                           "data"))
SWIFT = os.path.join(SHARED, "hdf5", "swift_robertsflow", "g32_randB_withVP.hdf5")
BOX = {"camera": {"projection": "orthographic", "width": 6.4, "position": [3.14, 3.14, 20],
                  "look_at": [3.14, 3.14, 3.14], "up": [0, 1, 0]},
       "image": {"width": 64, "height": 48}, "deposit": "cic", "output": {"name": "box", "png": False}}


def cli_planes(cli, tmp_path, scene, snapshot, *sets):
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(scene))
    cli_render(cli, scene_file, snapshot, tmp_path / "cli", *sets)
    with fits.open(tmp_path / "cli" / f"{scene['output']['name']}.fits") as f:
        return [np.flipud(h.data).astype(np.float32) for h in f if h.name != "SCENE"]  # the planes, not the scene


@pytest.mark.parametrize("field, column", [("Pressures", None), ("MagneticFluxDensities[2]", 2)])
def test_swift_dataset_as_weight(tmp_path, cli, field, column):
    if not os.path.exists(SWIFT):
        pytest.skip(f"no {SWIFT}")
    expected = cli_planes(cli, tmp_path, BOX, SWIFT, f"input.weight={field}")[0]
    with h5py.File(SWIFT, "r") as f:
        gas = f["PartType0"]
        data = gas[field.split("[")[0]][...]
        values = data if column is None else data[:, column]
        image = orrery.Scene(BOX, input={"weight": field}).render(
            gas["Coordinates"][...], gas["Masses"][...], gas["ParticleIDs"][...], fields={field: values})[0]
    assert np.count_nonzero(expected) > 100
    assert image.planes[field].tobytes() == expected.tobytes()


def test_missing_dataset_lists_those_there(tmp_path, cli):
    if not os.path.exists(SWIFT):
        pytest.skip(f"no {SWIFT}")
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(BOX))
    for weight, message in [("Presures", "PartType0 has: Coordinates, Densities"),
                            ("MagneticFluxDensities[3]", "has 3 columns"),
                            ("Coordinates", "NAME[k]")]:
        run = subprocess.run([cli, "render", str(scene_file), "--set", f"input.file={SWIFT}", "--set",
                              f"input.weight={weight}", "-o", str(tmp_path)], capture_output=True, text=True)
        assert run.returncode != 0 and message in run.stderr, run.stderr


def write_stars(path, pos, mass, birth, metals, time=1.0):
    """A SWIFT-style snapshot of stars (PartType4) with their birth times."""
    n = len(pos)
    with h5py.File(path, "w") as f:
        h = f.create_group("Header")
        h.attrs["NumPart_ThisFile"] = np.array([0, 0, 0, 0, n, 0, 0], dtype=np.int64)
        h.attrs["MassTable"] = np.zeros(7)
        h.attrs["Time"] = np.array([time])
        g = f.create_group("PartType4")
        g["Coordinates"] = pos
        g["Masses"] = mass
        g["ParticleIDs"] = np.arange(1, n + 1, dtype=np.uint64)
        g["StellarFormationTime"] = birth
        g["Metallicities"] = metals


STARS = {"camera": {"projection": "orthographic", "width": 4, "position": [0, 0, 10], "look_at": [0, 0, 0],
                    "up": [0, 1, 0]},
         "image": {"width": 40, "height": 40}, "deposit": "ngp", "output": {"name": "stars", "png": False},
         "colour": {"populations": [
             {"name": "young", "select": {"field": {"name": "StellarFormationTime", "min": 0.8}},
              "colour": {"temperature": 15000}},
             {"name": "old", "select": {"field": {"name": "StellarFormationTime", "max": 0.8}},
              "colour": {"temperature": 3500}}]}}


def test_stellar_ages_colour_stars(tmp_path, cli):
    """Stars born late (StellarFormationTime > 0.8, left half) are blue,
    those born early (right half) red: the CIE X/Z ratio of their pixels."""
    rng = np.random.default_rng(4)
    n = 4000
    pos = rng.uniform(-1.9, 1.9, size=(n, 3)).astype(np.float32)
    birth = np.where(pos[:, 0] < 0, rng.uniform(0.85, 1.0, n), rng.uniform(0.1, 0.5, n)).astype(np.float32)
    mass = np.full(n, 1e-3, dtype=np.float32)
    write_stars(tmp_path / "stars.hdf5", pos, mass, birth, np.full(n, 0.02, dtype=np.float32))
    x, y, z = cli_planes(cli, tmp_path, STARS, tmp_path / "stars.hdf5")
    left, right = slice(0, 19), slice(21, 40)
    ratio_young = x[:, left].sum() / z[:, left].sum()
    ratio_old = x[:, right].sum() / z[:, right].sum()
    assert ratio_young < 1.0 < ratio_old
    image = orrery.Scene(STARS).render(pos, mass, np.arange(1, n + 1), fields={"StellarFormationTime": birth},
                                       types=np.full(n, 4), time=1.0)[0]
    assert [image.planes[k].tobytes() for k in "XYZ"] == [p.tobytes() for p in (x, y, z)]
