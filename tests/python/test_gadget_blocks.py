"""Gadget SnapFormat 2 blocks beyond the standard ones as named fields: the
reader infers from each block's length in every part which particle types
it covers (stars-only AGE, gas-and-stars Z with 3 values each, gas-only
TEMP, all-types ACCE), reads LABEL or LABEL[k], lists them in `orrery info`,
and says when it cannot tell. Files are written here with numpy; the values
the CLI reads from them must equal, bit for bit, a render of the same values
passed as arrays to the Python package."""
import json
import subprocess

import numpy as np
import pytest

import orrery
from conftest import cli_render

fits = pytest.importorskip("astropy.io.fits")


def record(payload):
    n = np.array([len(payload)], dtype="<u4").tobytes()
    return n + payload + n


def block(label, payload):
    return record(label.ljust(4).encode() + np.array([len(payload) + 8], dtype="<u4").tobytes()) + record(payload)


def header(npart, massarr, num_files, total, time=0.5):
    h = np.array(npart, dtype="<i4").tobytes() + np.array(massarr, dtype="<f8").tobytes()
    h += np.array([time, 0.0], dtype="<f8").tobytes() + np.zeros(2, dtype="<i4").tobytes()
    h += np.array(total, dtype="<u4").tobytes() + np.array([0, num_files], dtype="<i4").tobytes()
    h += np.array([100.0, 0.3, 0.7, 0.7], dtype="<f8").tobytes()
    return h.ljust(256, b"\0")


def write_part(path, npart, massarr, pos, mass, ids, named, num_files=1, total=None, time=0.5):
    """One SnapFormat 2 file: HEAD POS VEL ID MASS, then the named blocks
    {label: float32 array} in order."""
    with open(path, "wb") as f:
        f.write(block("HEAD", header(npart, massarr, num_files, total or npart, time)))
        f.write(block("POS", pos.astype("<f4").tobytes()))
        f.write(block("VEL", np.zeros_like(pos, dtype="<f4").tobytes()))
        f.write(block("ID", ids.astype("<u4").tobytes()))
        f.write(block("MASS", mass.astype("<f4").tobytes()))
        for label, values in named.items():
            f.write(block(label, np.asarray(values, dtype="<f4").tobytes()))


GRID = 16  # particles on a 16 x 16 grid of pixel centres: one per pixel


def grid_positions(n):
    i = np.arange(n)
    return np.column_stack([(i % GRID) + 0.5, (i // GRID) + 0.5, np.zeros(n)]).astype(np.float32)


SCENE = {"camera": {"projection": "orthographic", "width": GRID, "position": [GRID / 2, GRID / 2, 10],
                    "look_at": [GRID / 2, GRID / 2, 0], "up": [0, 1, 0]},
         "image": {"width": GRID, "height": GRID}, "deposit": "ngp", "output": {"name": "blocks", "png": False}}

NPART = [31, 40, 0, 0, 19, 0]  # gas, dark matter, stars: no two sets of types with the same count
MASSARR = [0, 0.5, 0, 0, 0, 0]


@pytest.fixture
def snapshot(tmp_path):
    """A snapshot of gas, dark matter and stars with AGE (stars), Z (gas and
    stars, 3 each), TEMP (gas), ACCE (all, 3 each); also per particle the
    value each field should have (0 for types a block does not cover)."""
    rng = np.random.default_rng(25)
    n = sum(NPART)
    types = np.repeat(np.arange(6), NPART)
    gas, stars = types == 0, types == 4
    age = rng.uniform(0.1, 13, NPART[4])
    z = rng.uniform(0, 0.04, (NPART[0] + NPART[4], 3))
    temp = rng.uniform(1e3, 1e7, NPART[0])
    acce = rng.normal(size=(n, 3))
    pos = grid_positions(n)
    mass = rng.uniform(0.1, 1, NPART[0] + NPART[4])
    write_part(tmp_path / "snap", NPART, MASSARR, pos, mass, np.arange(1, n + 1),
               {"AGE": age, "Z": z, "TEMP": temp, "ACCE": acce})
    expect = {"AGE": np.zeros(n), "TEMP": np.zeros(n)}
    expect["AGE"][stars] = age
    expect["TEMP"][gas] = temp
    for k in range(3):
        expect[f"Z[{k}]"] = np.zeros(n)
        expect[f"Z[{k}]"][gas | stars] = z[:, k]
        expect[f"ACCE[{k}]"] = acce[:, k]
    masses = np.full(n, 0.5)
    masses[gas | stars] = mass
    return tmp_path / "snap", pos, masses, types, expect


def cli_plane(cli, tmp_path, snap, field):
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(SCENE))
    cli_render(cli, scene_file, snap, tmp_path / "out", f"input.weight={field}")
    with fits.open(tmp_path / "out" / "blocks.fits") as f:
        return np.flipud(f[0].data).astype(np.float32)


@pytest.mark.parametrize("field", ["AGE", "TEMP", "Z[0]", "Z[2]", "ACCE[1]"])
def test_named_block_values(tmp_path, cli, snapshot, field):
    snap, pos, masses, types, expect = snapshot
    plane = cli_plane(cli, tmp_path, snap, field)
    covered = np.count_nonzero(expect[field])
    assert np.count_nonzero(plane) == covered > 0
    image = orrery.Scene(SCENE, input={"weight": field}).render(
        pos, masses.astype(np.float32), np.arange(1, len(pos) + 1), fields={field: expect[field].astype(np.float32)},
        types=types)[0]
    assert image.planes[field].tobytes() == plane.tobytes()


def test_info_lists_named_blocks(cli, snapshot):
    snap = snapshot[0]
    out = subprocess.run([cli, "info", str(snap)], capture_output=True, text=True, check=True).stdout
    assert "AGE                      type 4, 1 float each: field AGE" in out
    assert "Z                        types 0 4, 3 floats each: fields Z[0..2]" in out
    assert "TEMP                     type 0, 1 float each: field TEMP" in out
    assert "ACCE                     types 0 1 4, 3 floats each: fields ACCE[0..2]" in out


def render_error(cli, tmp_path, snap, field):
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(SCENE))
    run = subprocess.run([cli, "render", str(scene_file), "--set", f"input.file={snap}", "--set",
                          f"input.weight={field}", "-o", str(tmp_path / "bad")], capture_output=True, text=True)
    assert run.returncode != 0
    assert not (tmp_path / "bad" / "blocks.fits").exists()
    return run.stderr


@pytest.mark.parametrize("field, message", [
    ("AGEX", "field AGEX: no block AGEX (other blocks: AGE Z TEMP ACCE)"),
    ("StellarFormationTime", "no block StellarFormationTime"),
    ("Z", "block Z holds 3 values per particle: name one as Z[k], k from 0"),
    ("Z[3]", "block Z holds 3 values per particle: no column 3"),
    ("AGE[1]", "block AGE holds 1 value per particle: no column 1"),
    ("Z[x]", "field Z[x]: not a block label"),
])
def test_field_errors(tmp_path, cli, snapshot, field, message):
    assert message in render_error(cli, tmp_path, snapshot[0], field)


def test_multi_file_layouts(tmp_path, cli):
    """Part 0 has stars and their AGE block; part 1 has none, and no AGE
    block. In part 0 alone, 20 AGE values could be the 20 gas particles' or
    the 20 stars': part 1 (10 gas, 5 stars, 5 AGE values) settles it."""
    rng = np.random.default_rng(7)
    parts = [([20, 8, 0, 0, 20, 0], {"AGE": rng.uniform(1, 2, 20)}),
             ([10, 8, 0, 0, 5, 0], {"AGE": rng.uniform(1, 2, 5)}),
             ([12, 8, 0, 0, 0, 0], {})]
    total = [sum(p[0][t] for p in parts) for t in range(6)]
    first = 1
    for i, (npart, named) in enumerate(parts):
        n = sum(npart)
        write_part(tmp_path / f"multi.{i}", npart, MASSARR, grid_positions(n) + [0, 0, i],
                   np.full(npart[0] + npart[4], 0.25), np.arange(first, first + n), named, 3, total)
        first += n
    out = subprocess.run([cli, "info", str(tmp_path / "multi")], capture_output=True, text=True, check=True).stdout
    assert "AGE                      type 4, 1 float each: field AGE" in out
    # Each star of part 0 and 1 has its AGE (pixels 1 x 1: a pixel holds the sum of its weights).
    plane = cli_plane(cli, tmp_path, tmp_path / "multi", "AGE")
    ages = np.concatenate([p[1]["AGE"] for p in parts[:2]]).astype(np.float32)
    assert np.count_nonzero(plane) == 25  # no two stars share a pixel
    assert plane.sum() == pytest.approx(ages.sum(), rel=1e-5)
    # Only part 0 (20 and 20): the reader cannot tell, and says which layouts fit.
    write_part(tmp_path / "single", parts[0][0], MASSARR, grid_positions(48), np.full(40, 0.25),
               np.arange(1, 49), parts[0][1])
    message = render_error(cli, tmp_path, tmp_path / "single", "AGE")
    assert ("block AGE: cannot tell which particles it covers: 1 float per particle of type 0, or 1 float per "
            "particle of type 4") in message
    # A length that fits no set of types.
    write_part(tmp_path / "odd", parts[0][0], MASSARR, grid_positions(48), np.full(40, 0.25),
               np.arange(1, 49), {"ODD": np.zeros(7)})
    assert ("block ODD: 28 bytes (part 0, npart 20 8 0 0 20 0) are no whole number of floats per particle of any "
            "set of the snapshot's types in every part") in render_error(cli, tmp_path, tmp_path / "odd", "ODD")


def test_snapformat1_has_no_labels(tmp_path, cli):
    import os
    import sys
    make = os.path.join(os.environ.get("ORRERY_SOURCE_DIR", "."), "tests", "cli", "make_snapshot.py")
    subprocess.run([sys.executable, make, "gadget", str(tmp_path / "f1")], check=True)
    assert "a SnapFormat 1 file has no block labels" in render_error(cli, tmp_path, tmp_path / "f1", "AGE")


def test_gadget_ages_colour_stars(tmp_path, cli):
    """A SnapFormat 2 snapshot at a = 1 whose AGE block holds the stars'
    formation scale factors (Gadget-2 with its stellar-age flag): through
    the SSP colours, stars born at a = 0.99 (left) are blue, those born at
    a = 0.3 (right) red."""
    n_gas, n_stars = 7, 200
    npart = [n_gas, 0, 0, 0, n_stars, 0]
    rng = np.random.default_rng(3)
    pos = np.zeros((n_gas + n_stars, 3), dtype=np.float32)
    pos[:, :2] = rng.uniform(0.5, GRID - 0.5, (n_gas + n_stars, 2))
    left = pos[n_gas:, 0] < GRID / 2
    birth = np.where(left, 0.99, 0.3)
    write_part(tmp_path / "stars", npart, [0] * 6, pos, np.full(n_gas + n_stars, 0.01),
               np.arange(1, n_gas + n_stars + 1), {"AGE": birth}, time=1.0)
    scene = dict(SCENE, colour={"populations": [
        {"name": "stars", "select": {"types": [4]},
         "colour": {"ssp": {"field": "AGE", "clock": "scale_factor", "metallicity": 0.0152}},
         "luminance": {"ssp": 1.0}}]})
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(scene))
    cli_render(cli, scene_file, tmp_path / "stars", tmp_path / "out")
    with fits.open(tmp_path / "out" / "blocks.fits") as f:
        x, y, z = (h.data.astype(np.float64) for h in f)
    half = GRID // 2
    xy = lambda s: x[:, s].sum() / (x[:, s] + y[:, s] + z[:, s]).sum()
    assert xy(slice(0, half)) < 0.30 < 0.33 < xy(slice(half, GRID))
