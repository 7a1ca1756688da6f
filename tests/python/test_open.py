"""orrery.open: files read with orrery's own readers into numpy arrays, a
chunk at a time, equal to what h5py and numpy read; renders report their
progress."""
import os

import numpy as np
import pytest

import orrery
from conftest import FLAT, write_tipsy

DATA = os.environ.get("ORRERY_SHARED_DATA", "")
GADGET4 = os.path.join(DATA, "hdf5", "gadget4_lcdm_gas", "snapshot_004.hdf5")


def test_tipsy_in_chunks(tmp_path, particles):
    pos, mass, _ = particles
    write_tipsy(tmp_path / "p.tipsy", pos, mass, time=0.25)
    with orrery.open(tmp_path / "p.tipsy", chunk_size=1000) as f:
        assert (f.format, f.count, f.time) == ("tipsy", len(pos), 0.25)
        chunks = list(f.chunks())
    assert [len(c["x"]) for c in chunks] == [1000] * 5
    got = {name: np.concatenate([c[name] for c in chunks]) for name in chunks[0]}
    assert np.array_equal(np.stack([got["x"], got["y"], got["z"]], axis=1), pos)
    assert np.array_equal(got["mass"], mass) and np.array_equal(got["id"], np.arange(len(pos)))
    # What it read renders as the file does.
    scene = orrery.Scene(FLAT)
    assert np.array_equal(scene.render((got["x"], got["y"], got["z"]), got["mass"])[0].data,
                          scene.render(pos, mass)[0].data)


def test_gadget4_hdf5_equals_h5py():
    h5py = pytest.importorskip("h5py")
    if not os.path.exists(GADGET4):
        pytest.skip("no shared data")
    data = orrery.open(GADGET4).read()
    with h5py.File(GADGET4, "r") as f:
        gas = f["PartType0"]
        ids = gas["ParticleIDs"][:]
        mine = np.flatnonzero(data["type"] == 0)
        order = np.argsort(data["id"][mine])
        mine = mine[order]
        truth = np.argsort(ids)
        assert np.array_equal(data["id"][mine], ids[truth])
        xyz = np.stack([data[c][mine] for c in "xyz"], axis=1)
        assert np.array_equal(xyz, gas["Coordinates"][:][truth].astype(np.float32))
        # Gadget's SmoothingLength is where the kernel ends; orrery's h half of it.
        assert np.array_equal(data["h"][mine], gas["SmoothingLength"][:][truth].astype(np.float32) * 0.5)
        assert np.array_equal(data["rho"][mine], gas["Density"][:][truth].astype(np.float32))
        assert np.all(data["mass"][mine] == np.float32(f["Header"].attrs["MassTable"][0]))
        count = sum(f[f"PartType{t}"]["ParticleIDs"].shape[0] for t in range(6) if f"PartType{t}" in f)
    assert len(data["x"]) == count


def test_open_errors_name_the_file(tmp_path):
    with pytest.raises(orrery.OrreryError, match="no_such.hdf5"):
        orrery.open(tmp_path / "no_such.hdf5")
    (tmp_path / "junk.bin").write_bytes(b"\x01\x02" * 50)
    with pytest.raises(orrery.OrreryError, match="junk.bin"):
        orrery.open(tmp_path / "junk.bin").read()
    f = orrery.open(GADGET4) if os.path.exists(GADGET4) else None
    if f:
        f.close()
        with pytest.raises(orrery.OrreryError, match="closed"):
            f.read()


def test_progress(particles):
    pos, mass, _ = particles
    scene = orrery.Scene(FLAT, input={"chunk": 1000})
    calls = []
    scene.render(pos, mass, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(k * 1000, len(pos)) for k in range(1, 6)]

    def stop(done, total):
        raise KeyboardInterrupt("stop")

    with pytest.raises(KeyboardInterrupt, match="stop"):
        scene.render(pos, mass, progress=stop)
    with pytest.raises(orrery.OrreryError, match="not from the scene's own render"):
        scene.render(pos, mass, progress=lambda done, total: scene.close())
    assert scene.render(pos, mass)[0].data.sum() > 0  # still open and usable
