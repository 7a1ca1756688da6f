"""The PEP 517 build backend of `pip install .` (pyproject.toml names it).

It needs nothing but Python's standard library, so `pip install .` works
without fetching a build backend from an index (offline, or with
--no-build-isolation): it builds liborrery with CMake, as
scripts/build.sh does, and packs the wheel itself. The wheel holds the
package python/orrery, the library beside it (orrery/liborrery.so.0, found
by the _paths.py written here) and the metadata that gives
`pip show orrery` and `orrery.__version__`.

ORRERY_CMAKE_BUILD_DIR=DIR builds in DIR (kept, so a second install
rebuilds nothing; an existing build tree of the same sources works) instead
of a temporary folder; ORRERY_CMAKE_ARGS adds arguments to CMake's
configure step of a new build folder.
"""
import base64
import hashlib
import os
import re
import shlex
import subprocess
import sysconfig
import tempfile
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PACKAGE = os.path.join(ROOT, "python", "orrery")
LIBRARY = "liborrery.so.0"  # the soname: CMake's SOVERSION


def project_version():
    """The version of CMakeLists.txt's project(), the one place it is set."""
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        match = re.search(r"project\(orrery VERSION ([0-9.]+)", f.read())
    if not match:
        raise RuntimeError("orrery_build: no `project(orrery VERSION x.y.z` in CMakeLists.txt")
    return match.group(1)


def metadata(version):
    return "\n".join([
        "Metadata-Version: 2.1",
        "Name: orrery",
        f"Version: {version}",
        "Summary: Renders gravitational N-body simulations for domes, full-sky panoramas and flat screens",
        "License: see LICENSE",
        "Requires-Python: >=3.9",
        "Requires-Dist: numpy",
        "",
    ])


def wheel_tag():
    """py3-none-PLATFORM: pure Python over a native library loaded with
    ctypes, so any Python 3 on this platform."""
    return "py3-none-" + re.sub(r"[-.]", "_", sysconfig.get_platform())


def build_library(build_dir):
    """liborrery built by CMake in build_dir: the path of the file."""
    if not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
        # A build tree already configured (a developer's, with its tests) is
        # built as it is: `cmake --build` reconfigures it if it must.
        configure = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=RelWithDebInfo",
                     "-DORRERY_TESTS=OFF", "-DORRERY_WERROR=OFF"]
        configure += shlex.split(os.environ.get("ORRERY_CMAKE_ARGS", ""))
        subprocess.run(configure, check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", build_dir, "--target", "orrery_shared", "--parallel", str(os.cpu_count())],
                   check=True)
    path = os.path.realpath(os.path.join(build_dir, LIBRARY))
    if not os.path.isfile(path):
        raise RuntimeError(f"orrery_build: CMake built no {LIBRARY} in {build_dir}")
    return path


def wheel_files(library, version):
    """{path in the wheel: bytes}: the package, the library, _paths.py."""
    files = {}
    for name in sorted(os.listdir(PACKAGE)):
        if name.endswith(".py") and name != "_paths.py":
            with open(os.path.join(PACKAGE, name), "rb") as f:
                files[f"orrery/{name}"] = f.read()
    with open(library, "rb") as f:
        files[f"orrery/{LIBRARY}"] = f.read()
    files["orrery/_paths.py"] = (
        "# Written by pip's build (python/backend/orrery_build.py): the library in the wheel.\n"
        "import os\n"
        f"LIBRARY = os.path.join(os.path.dirname(os.path.abspath(__file__)), {LIBRARY!r})\n"
        f"VERSION = {version!r}\n").encode()
    return files


def record_line(path, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{path},sha256={digest},{len(data)}"


def write_wheel(directory, files, version):
    dist_info = f"orrery-{version}.dist-info"
    files = dict(files)
    files[f"{dist_info}/METADATA"] = metadata(version).encode()
    files[f"{dist_info}/WHEEL"] = ("Wheel-Version: 1.0\nGenerator: orrery_build\nRoot-Is-Purelib: false\n"
                                   f"Tag: {wheel_tag()}\n").encode()
    with open(os.path.join(ROOT, "LICENSE"), "rb") as f:
        files[f"{dist_info}/LICENSE"] = f.read()
    record = [record_line(path, data) for path, data in files.items()] + [f"{dist_info}/RECORD,,"]
    files[f"{dist_info}/RECORD"] = ("\n".join(record) + "\n").encode()
    name = f"orrery-{version}-{wheel_tag()}.whl"
    with zipfile.ZipFile(os.path.join(directory, name), "w", zipfile.ZIP_DEFLATED) as z:
        for path, data in files.items():
            info = zipfile.ZipInfo(path, date_time=(1980, 1, 1, 0, 0, 0))
            info.external_attr = (0o755 if path.endswith(LIBRARY) else 0o644) << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
    return name


# PEP 517 hooks.

def get_requires_for_build_wheel(config_settings=None):
    return []


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    version = project_version()
    build_dir = os.environ.get("ORRERY_CMAKE_BUILD_DIR")
    if build_dir:
        return write_wheel(wheel_directory, wheel_files(build_library(os.path.abspath(build_dir)), version), version)
    with tempfile.TemporaryDirectory(prefix="orrery-build-") as tmp:
        return write_wheel(wheel_directory, wheel_files(build_library(tmp), version), version)
