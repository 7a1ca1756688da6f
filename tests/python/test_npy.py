"""orrery's .npy reader: np.save's files, in every layout numpy writes, read
by the CLI to the same pixels as the Python package given the same arrays;
and bad files refused with what is wrong."""

import numpy as np
import pytest

import orrery
from conftest import FLAT, cli_flat_plane as cli_plane, cli_refused as refused


def structured(pos, mass, ids, extra):
    """A structured array as a simulation might save it: mixed precisions
    and byte orders, integer ids and types, a field of its own."""
    a = np.zeros(len(pos), dtype=[("x", "<f8"), ("y", ">f4"), ("z", "<f4"), ("mass", ">f8"), ("id", "<i8"),
                                  ("type", "u1"), ("age", "<f4")])
    a["x"], a["y"], a["z"] = pos[:, 0], pos[:, 1], pos[:, 2]
    a["mass"], a["id"], a["type"], a["age"] = mass, ids, 4, extra
    return a


def test_structured_npy_equals_python(tmp_path, cli, particles):
    pos, mass, ids = particles
    age = np.linspace(0, 13, len(pos)).astype(np.float32)
    a = structured(pos, mass, ids, age)
    np.save(tmp_path / "stars.npy", a)
    scene = orrery.Scene(FLAT)
    expected = scene.render((a["x"], a["y"], a["z"]), a["mass"], a["id"])[0].data
    assert cli_plane(cli, tmp_path, tmp_path / "stars.npy").tobytes() == expected.tobytes()
    by_age = orrery.Scene(FLAT, input={"weight": "age"}).render(pos, mass, fields={"age": age})[0].data
    assert cli_plane(cli, tmp_path, tmp_path / "stars.npy", "input.weight=age").tobytes() == by_age.tobytes()


@pytest.mark.parametrize("layout", ["C float32", "Fortran float64", "version 2"])
def test_plain_positions(tmp_path, cli, particles, layout):
    pos = particles[0].astype(np.float64 if "64" in layout else np.float32)
    path = tmp_path / "pos.npy"
    if layout == "version 2":
        with open(path, "wb") as f:
            np.lib.format.write_array(f, pos, version=(2, 0))
    else:
        np.save(path, np.asfortranarray(pos) if "Fortran" in layout else pos)
    expected = orrery.Scene(FLAT).render(pos, 1.0)[0].data
    assert cli_plane(cli, tmp_path, path).tobytes() == expected.tobytes()


def test_bad_npy_files(tmp_path, cli, particles):
    pos, mass, ids = particles
    cases = {
        "four.npy": (np.zeros((5, 4)), "must have shape (N, 3)"),
        "ints.npy": (np.zeros((5, 3), dtype=np.int32), "must hold floats"),
        "complex.npy": (np.zeros(5, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<c8")]), "dtype '<c8'"),
        "noz.npy": (np.zeros(5, dtype=[("x", "<f4"), ("y", "<f4")]), "no field 'z'"),
        "sub.npy": (np.zeros(5, dtype=[("pos", "<f4", (3,))]), "field 'pos' is a sub-array"),
        "fid.npy": (np.zeros(5, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("id", "<f4")]), "ids are integers"),
    }
    for name, (array, message) in cases.items():
        np.save(tmp_path / name, array)
        assert message in refused(cli, tmp_path, tmp_path / name), name
    a = structured(pos[:10], mass[:10], ids[:10], 0)
    a["id"][3] = -7
    np.save(tmp_path / "negid.npy", a)
    assert "row 3: id -7 is negative" in refused(cli, tmp_path, tmp_path / "negid.npy")
    a["id"][3], a["mass"][5] = 1, -1
    np.save(tmp_path / "negmass.npy", a)
    assert "row 5: mass -1" in refused(cli, tmp_path, tmp_path / "negmass.npy")
    good = (tmp_path / "pos.npy")
    np.save(good, pos[:10])
    data = good.read_bytes()
    (tmp_path / "short.npy").write_bytes(data[:-5])
    assert "truncated" in refused(cli, tmp_path, tmp_path / "short.npy")
    (tmp_path / "long.npy").write_bytes(data + b"\0")
    assert "bytes after the array" in refused(cli, tmp_path, tmp_path / "long.npy")
    (tmp_path / "dict.npy").write_bytes(data.replace(b"'shape'", b"'shap' "))
    assert "lacks 'descr', 'fortran_order' or 'shape'" in refused(cli, tmp_path, tmp_path / "dict.npy")
