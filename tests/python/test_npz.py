"""orrery's .npz reader: archives np.savez and np.savez_compressed write,
read by the CLI to the same pixels as the same arrays saved as .npy (and
given to the Python package); bad archives refused naming the member."""
import subprocess
import zipfile

import numpy as np
import pytest

import orrery
from conftest import FLAT, cli_flat_plane as cli_plane, cli_refused as refused


def as_npy(tmp_path, pos, mass, ids, **fields):
    """The same particles as a structured .npy (its reader is tested
    against the Python package in test_npy.py)."""
    dtype = [("x", pos.dtype), ("y", pos.dtype), ("z", pos.dtype), ("mass", mass.dtype), ("id", ids.dtype)]
    dtype += [(k, v.dtype) for k, v in fields.items()]
    a = np.zeros(len(pos), dtype=dtype)
    a["x"], a["y"], a["z"], a["mass"], a["id"] = pos[:, 0], pos[:, 1], pos[:, 2], mass, ids
    for k, v in fields.items():
        a[k] = v
    np.save(tmp_path / "same.npy", a)
    return tmp_path / "same.npy"


@pytest.mark.parametrize("save", [np.savez, np.savez_compressed])
def test_npz_equals_npy_and_python(tmp_path, cli, particles, save):
    pos, mass, ids = particles
    mass = mass.astype(np.float64)
    age = np.linspace(0, 13, len(pos)).astype(np.float32)
    path = tmp_path / "stars.npz"
    save(path, pos=pos, mass=mass, id=ids, age=age, time=np.float64(2.5))
    with zipfile.ZipFile(path) as z:  # the archive is what the test says it is
        method = zipfile.ZIP_DEFLATED if save is np.savez_compressed else zipfile.ZIP_STORED
        assert {i.compress_type for i in z.infolist()} == {method}
    npy = as_npy(tmp_path, pos, mass, ids, age=age)
    by_mass = cli_plane(cli, tmp_path, path)
    assert by_mass.sum() > 0
    assert by_mass.tobytes() == cli_plane(cli, tmp_path, npy).tobytes()
    expected = orrery.Scene(FLAT).render(pos, mass, ids)[0].data
    assert by_mass.tobytes() == expected.tobytes()
    by_age = cli_plane(cli, tmp_path, path, "input.weight=age")
    assert by_age.tobytes() == cli_plane(cli, tmp_path, npy, "input.weight=age").tobytes()
    # Streamed: chunks of 700 particles, a read block smaller than a member.
    assert cli_plane(cli, tmp_path, path, "input.chunk=700").tobytes() == by_mass.tobytes()


@pytest.mark.parametrize("save", [np.savez, np.savez_compressed])
def test_npz_columns_and_layouts(tmp_path, cli, particles, save):
    """x, y, z as members of their own, positions in Fortran order, and a
    component of a 2-D member as a weight (vel[1])."""
    pos, mass, ids = particles
    vel = np.random.default_rng(1).uniform(0.1, 1.0, size=(len(pos), 3))
    split = tmp_path / "split.npz"
    save(split, x=pos[:, 0], y=pos[:, 1].astype(">f8"), z=pos[:, 2], m=mass, vel=vel)
    fortran = tmp_path / "fortran.npz"
    save(fortran, pos=np.asfortranarray(pos), mass=mass, vel=np.asfortranarray(vel))
    plain = tmp_path / "plain.npz"
    save(plain, pos=pos, mass=mass, vel=vel)
    ref = cli_plane(cli, tmp_path, plain)
    assert cli_plane(cli, tmp_path, split).tobytes() == ref.tobytes()
    assert cli_plane(cli, tmp_path, fortran, "input.chunk=999").tobytes() == ref.tobytes()
    vy = vel[:, 1].astype(np.float32)
    expected = orrery.Scene(FLAT, input={"weight": "vy"}).render(pos, mass, fields={"vy": vy})[0].data
    for path in (split, fortran, plain):
        got = cli_plane(cli, tmp_path, path, "input.weight=vel[1]")
        assert got.tobytes() == expected.tobytes(), path.name


def test_npz_info(tmp_path, cli, particles):
    pos, mass, ids = particles
    path = tmp_path / "snap.npz"
    np.savez_compressed(path, pos=pos[:10], mass=mass[:10], time=np.float32(0.75), box=np.int64(100))
    out = subprocess.run([cli, "info", str(path)], capture_output=True, text=True, check=True).stdout
    assert "npz" in out and "10" in out
    assert "box" in out and "100" in out
    assert "0.75" in out


def test_bad_npz_files(tmp_path, cli, particles):
    pos, mass, ids = particles
    n = 50
    cases = {
        "ragged.npz": (dict(pos=pos[:n], mass=mass[:n - 1]), "member 'mass.npy' has 49 rows but member 'pos.npy' has 50"),
        "nopos.npz": (dict(mass=mass[:n]), "no member 'x' (positions are a member pos of shape (N, 3)"),
        "fid.npz": (dict(pos=pos[:n], id=np.zeros(n, np.float32)), "member 'id' holds floats; ids are integers"),
        "three.npz": (dict(pos=pos[:n], v=np.zeros((n, 2, 2))), "member 'v.npy': an array must have shape"),
        "twice.npz": (dict(pos=pos[:n], x=pos[:n, 0]), "a second x column"),
    }
    for name, (arrays, message) in cases.items():
        np.savez(tmp_path / name, **arrays)
        assert message in refused(cli, tmp_path, tmp_path / name), name
    ok = dict(pos=pos[:n], mass=mass[:n])
    bad_mass = mass[:n].copy()
    bad_mass[7] = -1
    np.savez_compressed(tmp_path / "negmass.npz", pos=pos[:n], mass=bad_mass)
    assert "member 'mass.npy': row 7: mass -1 is negative" in refused(cli, tmp_path, tmp_path / "negmass.npz")
    np.savez_compressed(tmp_path / "good.npz", **ok)
    data = (tmp_path / "good.npz").read_bytes()
    (tmp_path / "short.npz").write_bytes(data[:-30])
    assert "no ZIP end of central directory record" in refused(cli, tmp_path, tmp_path / "short.npz")
    # A flipped byte inside the deflated positions: zlib or the CRC catches it.
    with zipfile.ZipFile(tmp_path / "good.npz") as z:
        info = z.getinfo("pos.npy")
    at = info.header_offset + 30 + len(info.filename) + len(info.extra) + info.compress_size // 2
    damaged = bytearray(data)
    damaged[at] ^= 0x55
    (tmp_path / "damaged.npz").write_bytes(bytes(damaged))
    err = refused(cli, tmp_path, tmp_path / "damaged.npz")
    assert "member 'pos.npy'" in err and ("damaged" in err or "CRC-32" in err or "ends before" in err), err
    with zipfile.ZipFile(tmp_path / "bz2.npz", "w", compression=zipfile.ZIP_BZIP2) as z:
        with z.open("pos.npy", "w") as f:
            np.lib.format.write_array(f, pos[:n])
    assert "member 'pos.npy' is compressed with ZIP method 12" in refused(cli, tmp_path, tmp_path / "bz2.npz")
