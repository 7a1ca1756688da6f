"""The package installed as users install it: `pip install .` into a fresh
virtual environment (offline: the build backend is in the tree), and
`cmake --install`. Each gives metadata and orrery.__version__, the version
of CMakeLists.txt's project(), and renders."""
import os
import re
import subprocess
import sys

import pytest

SOURCE = os.environ.get("ORRERY_SOURCE_DIR")

# Run by the installed package, away from the build tree's copy.
CHECK = """
import importlib.metadata, numpy as np, orrery
print(orrery.__version__, importlib.metadata.version("orrery"), orrery._paths.LIBRARY)
image = orrery.render({"camera": {"projection": "orthographic", "width": 4}, "image": {"width": 8, "height": 8},
                       "deposit": "ngp"}, np.zeros((1, 3)), 2.0)
print(float(image.data.sum()) * 0.25)
"""


def project_version():
    with open(os.path.join(SOURCE, "CMakeLists.txt")) as f:
        return re.search(r"project\(orrery VERSION ([0-9.]+)", f.read()).group(1)


@pytest.fixture
def build_dir(cli):
    if not SOURCE:
        pytest.skip("ORRERY_SOURCE_DIR not set")
    return os.path.dirname(cli)  # the CLI is built at the top of the build tree


def tool_env(**env):
    """The environment for pip and cmake: without the sanitizer runtimes
    run.sh preloads for Python (cmake hangs with them preloaded)."""
    return {**{k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}, **env}


def run_check(python, cwd, **env):
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "ORRERY_LIBRARY")}
    run = subprocess.run([python, "-c", CHECK], cwd=cwd, env={**environment, **env}, capture_output=True,
                         text=True)
    assert run.returncode == 0, run.stderr
    version, metadata_version, library, mass = run.stdout.split()
    assert version == metadata_version == project_version()
    assert float(mass) == pytest.approx(2.0)
    return library


def test_pip_install_in_a_fresh_venv(tmp_path, build_dir):
    """pip install . --no-build-isolation --no-index: nothing fetched. The
    backend builds in the test's build tree (up to date: nothing compiled)."""
    pytest.importorskip("pip")
    venv = tmp_path / "venv"
    # Debian's pip, seen through --system-site-packages, spares the venv its own copy (3 s).
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True)
    pip = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-build-isolation", "--no-index",
                          "-q", SOURCE], env=tool_env(ORRERY_CMAKE_BUILD_DIR=build_dir), capture_output=True, text=True,
                         timeout=600)
    assert pip.returncode == 0, pip.stdout + pip.stderr
    library = run_check(str(venv / "bin" / "python"), tmp_path)
    assert library.startswith(str(venv))  # the library in the wheel, not the build tree's


def test_cmake_install(tmp_path, build_dir):
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", build_dir, "--prefix", str(prefix)], check=True, capture_output=True,
                   env=tool_env(), timeout=300)
    packages = [os.path.dirname(p) for p, _, files in os.walk(prefix) if "orrery" in p.split(os.sep)[-1:]
                and "__init__.py" in files]
    assert len(packages) == 1
    library = run_check(sys.executable, tmp_path, PYTHONPATH=packages[0])
    assert library.startswith(str(prefix))
