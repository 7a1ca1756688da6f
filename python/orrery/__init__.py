"""orrery from Python: render numpy arrays of particles with liborrery's
scenes (dome masters, panoramas, flat cameras) into numpy images.

    import numpy as np, orrery
    pos = np.random.default_rng(1).normal(size=(100000, 3)).astype(np.float32)
    image = orrery.render({"camera": {"projection": "orthographic", "width": 8}}, pos, 1.0)

docs/python.md says more.
"""
from . import _paths
from ._reader import File, open
from .scene import Cancelled, Image, OrreryError, Scene, parse_header, render

# CMakeLists.txt's project() version, written into _paths.py by the build
# (CMake's, or pip's: python/backend/orrery_build.py).
__version__ = _paths.VERSION

# (orrery.open is not in __all__: `from orrery import *` would hide the builtin open.)
__all__ = ["__version__", "Cancelled", "File", "Image", "OrreryError", "Scene", "parse_header", "render"]
