"""Shared pieces of the Python package's tests: the CLI, the shared data
and a scene file, from the environment ctest sets (tests/CMakeLists.txt)."""
import json
import os
import subprocess

import numpy as np
import pytest

import orrery


@pytest.fixture
def cli():
    path = os.environ.get("ORRERY_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("ORRERY_CLI (the orrery command) not set")
    return path


def write_tipsy(path, pos, mass, time=0.0):
    """A standard (big-endian, padded header) Tipsy file of dark particles:
    a format whose header gives the count, as the in-memory arrays do (the
    splat's lanes follow the count, and with them the order of the sums)."""
    n = len(pos)
    header = np.array([(time, n, 3, 0, n, 0, 0)],
                      dtype=[("t", ">f8"), ("nb", ">i4"), ("nd", ">i4"), ("ns", ">i4"), ("ndk", ">i4"),
                             ("nst", ">i4"), ("pad", ">i4")])
    dark = np.zeros((n, 9), dtype=">f4")  # mass, pos[3], vel[3], eps, phi
    dark[:, 0], dark[:, 1:4] = mass, pos
    with open(path, "wb") as f:
        f.write(header.tobytes())
        f.write(dark.tobytes())


def cli_render(cli, scene, table, outdir, *sets):
    args = [cli, "render", str(scene), "--set", f"input.file={table}", "-o", str(outdir), "--quiet"]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True)


@pytest.fixture
def particles():
    rng = np.random.default_rng(25)
    n = 5000
    pos = rng.normal(scale=2.0, size=(n, 3)).astype(np.float32)
    mass = rng.uniform(0.5, 2.0, size=n).astype(np.float32)
    ids = np.arange(100, 100 + n, dtype=np.uint64)
    return pos, mass, ids


FLAT = {"camera": {"projection": "orthographic", "width": 10.0}, "image": {"width": 80, "height": 60},
        "deposit": "cic", "output": {"name": "flat"}}


def cli_flat_plane(cli, tmp_path, path, *sets):
    """The CLI's FLAT render of the particle file path (with --set sets):
    its plane, rows top-down as the Python package returns them."""
    from astropy.io import fits

    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(FLAT))
    out = tmp_path / ("cli-" + path.name)
    cli_render(cli, scene_file, path, out, *sets)
    with fits.open(out / "flat.fits") as f:
        return np.flipud(f[0].data).astype(np.float32)


def cli_refused(cli, tmp_path, path):
    """The CLI's FLAT render of path, which must be refused cleanly (non-zero,
    no Python traceback or sanitizer report): its error text."""
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(FLAT))
    run = subprocess.run([cli, "render", str(scene_file), "--set", f"input.file={path}", "-o", str(tmp_path)],
                         capture_output=True, text=True)
    assert run.returncode != 0
    assert "Traceback" not in run.stderr and "Sanitizer" not in run.stderr
    return run.stderr
