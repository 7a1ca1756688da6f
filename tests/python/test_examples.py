"""The examples in examples/python run on the shared reference data and make
their pictures (skipped without the data, h5py or yt)."""
import os
import subprocess
import sys

import pytest

SOURCE = os.environ.get("ORRERY_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SHARED = os.environ.get("ORRERY_SHARED_DATA", os.path.join(SOURCE, "..", "shared", "data"))


@pytest.mark.parametrize("script, module, picture", [
    ("gadget4_h5py.py", "h5py", "gadget4_gas.png"),
    ("swift_h5py.py", "h5py", "swift_b2.png"),
    ("yt_particles.py", "yt", "yt_dm.png"),
])
def test_example(tmp_path, script, module, picture):
    pytest.importorskip(module)
    pytest.importorskip("PIL")
    if not os.path.isdir(os.path.join(SHARED, "hdf5")):
        pytest.skip(f"no shared reference data in {SHARED}")
    path = os.path.join(SOURCE, "examples", "python", script)
    run = subprocess.run([sys.executable, path, "--data", SHARED, "--out", str(tmp_path)],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / picture).stat().st_size > 1000
    assert "32768" in run.stdout
