"""liborrery through ctypes: the library found, its public structures
mirrored, and the prototypes of the functions the package calls.

ctypes releases the GIL for the length of every foreign call, so other
Python threads run while orrery renders (orrery itself renders with OpenMP
threads). One Scene must not be used from two threads at once.
"""
import ctypes
import os

from . import _paths

ORR_F32, ORR_F64 = 1, 2
MAX_FIELDS = 8  # ORR_ARRAYS_MAX_FIELDS


class OrrArray(ctypes.Structure):
    """orr_array: one per-particle value, element i at data + i * stride."""
    _fields_ = [("data", ctypes.c_void_p), ("type", ctypes.c_int), ("stride", ctypes.c_size_t)]


class OrrParticleArrays(ctypes.Structure):
    """orr_particle_arrays (src/orrery.h), field for field."""
    _fields_ = [
        ("struct_size", ctypes.c_size_t),
        ("n", ctypes.c_size_t),
        ("x", OrrArray), ("y", OrrArray), ("z", OrrArray),
        ("mass", OrrArray),
        ("mass_value", ctypes.c_double),
        ("id", ctypes.c_void_p),
        ("id_stride", ctypes.c_size_t),
        ("id_offset", ctypes.c_uint64),
        ("type", ctypes.c_void_p),
        ("type_stride", ctypes.c_size_t),
        ("h", OrrArray),
        ("vx", OrrArray), ("vy", OrrArray), ("vz", OrrArray),
        ("nfields", ctypes.c_int),
        ("field_names", ctypes.c_char_p * MAX_FIELDS),
        ("fields", OrrArray * MAX_FIELDS),
        ("time", ctypes.c_double),
    ]


def _candidates():
    """Where liborrery may be, best first: $ORRERY_LIBRARY, the path this
    copy of the package was made for (build tree or install), then the
    dynamic loader's own search."""
    env = os.environ.get("ORRERY_LIBRARY")
    if env:
        return [env]
    return [p for p in (_paths.LIBRARY,) if p and os.path.exists(p)] + ["liborrery.so.0", "liborrery.so"]


def _load():
    errors = []
    for path in _candidates():
        try:
            return ctypes.CDLL(path)
        except OSError as e:
            errors.append(f"{path}: {e}")
    raise ImportError("orrery: cannot load liborrery (set ORRERY_LIBRARY to its path): " + "; ".join(errors))


lib = _load()

_P = ctypes.POINTER
_renderer = ctypes.c_void_p
_reader = ctypes.c_void_p
# orrery_progress_fn: (user, done, total); called from the rendering thread.
PROGRESS_FN = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_uint64, ctypes.c_int64)
_prototypes = {
    "orrery_open": (ctypes.c_int, [_P(_renderer), ctypes.c_char_p, _P(ctypes.c_char_p), ctypes.c_int,
                                   ctypes.c_char_p, ctypes.c_size_t]),
    "orrery_open_yaml": (ctypes.c_int, [_P(_renderer), ctypes.c_char_p, ctypes.c_char_p, _P(ctypes.c_char_p),
                                        ctypes.c_int, ctypes.c_char_p, ctypes.c_size_t]),
    "orrery_render": (ctypes.c_int, [_renderer, _P(OrrParticleArrays), ctypes.c_long]),
    "orrery_error": (ctypes.c_char_p, [_renderer]),
    "orrery_output_count": (ctypes.c_int, [_renderer]),
    "orrery_output": (ctypes.c_char_p, [_renderer, ctypes.c_int]),
    "orrery_render_seconds": (ctypes.c_double, [_renderer]),
    "orrery_close": (None, [_renderer]),
    "orrery_keep_images": (ctypes.c_int, [_renderer, ctypes.c_int]),
    "orrery_image_count": (ctypes.c_int, [_renderer]),
    "orrery_image_size": (ctypes.c_int, [_renderer, ctypes.c_int, _P(ctypes.c_int), _P(ctypes.c_int),
                                         _P(ctypes.c_int)]),
    "orrery_image_plane": (_P(ctypes.c_float), [_renderer, ctypes.c_int, ctypes.c_int, _P(ctypes.c_char_p),
                                                _P(ctypes.c_char_p)]),
    "orrery_image_rgb": (_P(ctypes.c_float), [_renderer, ctypes.c_int]),
    "orrery_image_header": (ctypes.c_char_p, [_renderer, ctypes.c_int]),
    "orrery_particle_arrays_size": (ctypes.c_size_t, []),
    "orrery_set_progress": (ctypes.c_int, [_renderer, PROGRESS_FN, ctypes.c_void_p]),
    "orrery_cancel": (ctypes.c_int, [_renderer]),
    "orrery_reader_open": (ctypes.c_int, [_P(_reader), ctypes.c_char_p, ctypes.c_char_p, ctypes.c_size_t,
                                          _P(ctypes.c_char_p), ctypes.c_int, ctypes.c_char_p, ctypes.c_size_t]),
    "orrery_reader_format": (ctypes.c_char_p, [_reader]),
    "orrery_reader_count": (ctypes.c_longlong, [_reader]),
    "orrery_reader_time": (ctypes.c_double, [_reader]),
    "orrery_reader_has": (ctypes.c_int, [_reader, ctypes.c_char_p]),
    "orrery_reader_h_support": (ctypes.c_double, [_reader]),
    "orrery_reader_field_count": (ctypes.c_int, [_reader]),
    "orrery_reader_field_name": (ctypes.c_char_p, [_reader, ctypes.c_int]),
    "orrery_reader_next": (ctypes.c_int, [_reader, _P(ctypes.c_size_t)]),
    "orrery_reader_field": (_P(ctypes.c_float), [_reader, ctypes.c_char_p]),
    "orrery_reader_ids": (_P(ctypes.c_uint64), [_reader]),
    "orrery_reader_types": (_P(ctypes.c_uint8), [_reader]),
    "orrery_reader_error": (ctypes.c_char_p, [_reader]),
    "orrery_reader_close": (None, [_reader]),
}
for _name, (_restype, _argtypes) in _prototypes.items():
    _f = getattr(lib, _name)
    _f.restype, _f.argtypes = _restype, _argtypes

# The mirror above must be the library's layout: a library built from a
# header with other fields would otherwise read the arrays wrongly.
if lib.orrery_particle_arrays_size() != ctypes.sizeof(OrrParticleArrays):
    raise ImportError(f"orrery: liborrery's orr_particle_arrays is {lib.orrery_particle_arrays_size()} bytes, "
                      f"this package's mirror {ctypes.sizeof(OrrParticleArrays)}: package and library differ")
