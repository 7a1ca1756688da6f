"""`orrery info` on the shared HDF5 snapshots lists every numeric dataset of
the particle groups with its units, checked against the attributes as h5py
reads them; a dataset it lists as a field renders as input.weight."""
import json
import os
import subprocess

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")

DATA = os.environ.get("ORRERY_SHARED_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
FILES = ["hdf5/swift_robertsflow/g32_randB_withVP.hdf5", "hdf5/gadget4_lcdm_gas/snapshot_004.hdf5"]


def info_entries(cli, path):
    out = subprocess.run([cli, "info", path], capture_output=True, text=True, check=True).stdout
    entries = {}
    for line in out.splitlines():
        if line.startswith("  ") and not line.startswith("  type "):
            key, _, value = line.strip().partition(" ")
            entries[key] = value.strip()
    return entries


def expected_units(ds):
    """The units as the file states them, formatted independently."""
    a = ds.attrs
    if "Expression for physical CGS units" in a:
        expr = a["Expression for physical CGS units"]
        expr = " ".join((expr.decode() if isinstance(expr, bytes) else str(expr)).split())
        key = "Conversion factor to CGS (not including cosmological corrections)"
        return f"{expr} (to cgs {float(np.ravel(a[key])[0]):.10g})" if key in a else expr
    if "to_cgs" in a and "a_scaling" in a and "h_scaling" in a:
        return f"a^{float(a['a_scaling']):g} h^{float(a['h_scaling']):g} (to cgs {float(a['to_cgs']):.10g})"
    return ""


@pytest.mark.parametrize("rel", FILES)
def test_info_lists_every_dataset_with_units(cli, rel):
    path = os.path.join(DATA, rel)
    if not os.path.exists(path):
        pytest.skip(f"{path} not found")
    entries = info_entries(cli, path)
    checked = 0
    with h5py.File(path, "r") as f:
        groups = [g for g in f if g.startswith("PartType")]
        for g in groups:
            for name, ds in f[g].items():
                if name == "ParticleIDs" or ds.dtype.kind not in "fiu":
                    continue
                assert name in entries, f"{g}/{name} not in orrery info"
                units = expected_units(ds)
                assert entries[name].endswith(units), (name, entries[name], units)
                checked += 1
    assert checked >= 5


def test_listed_field_renders(cli, tmp_path):
    path = os.path.join(DATA, FILES[0])
    if not os.path.exists(path):
        pytest.skip(f"{path} not found")
    entries = info_entries(cli, path)
    assert "fields MagneticFluxDensities[0..2]" in entries["MagneticFluxDensities"]
    assert "field Pressures" in entries["Pressures"]
    scene = {"camera": {"projection": "orthographic", "width": 6.6, "look_at": [3.14, 3.14, 3.14],
                        "position": [3.14, 3.14, 16.4]},
             "image": {"width": 32, "height": 32}, "deposit": "ngp", "output": {"name": "b"}}
    (tmp_path / "s.yaml").write_text(json.dumps(scene))
    for field in ("MagneticFluxDensities[2]", "Pressures"):
        run = subprocess.run([cli, "render", str(tmp_path / "s.yaml"), "--set", f"input.file={path}",
                              "--set", f"input.weight={field}", "-o", str(tmp_path), "--quiet"],
                             capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
