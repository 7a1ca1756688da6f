"""numpy arrays described to liborrery as orr_particle_arrays, read where
they are: a float32 or float64 array with any positive stride (a column of
an (N, 3) array, a field of a structured array) is passed as a pointer and
a stride, without a copy. Only what the library cannot read in place is
copied once: another byte order, integers and float16 (converted: every
value exactly), strides that are negative, zero (a broadcast value) or
shorter than an element (overlapping), misaligned arrays, integer ids and
types of another type. Every refusal names the array."""
import ctypes
import math

import numpy as np

from . import _lib

CHECK_CHUNK = 1 << 20  # elements checked at a time: a bounded temporary for any N


def _float_dtype(name, dtype):
    """The native float dtype orrery reads an array of dtype as: float32 and
    float64 themselves, float16 as float32, integers as float64 (exact to
    2**53); anything else (bool, complex, long double, objects, strings) is
    refused rather than converted with a loss."""
    if dtype.kind == "f" and dtype.itemsize in (4, 8):
        return dtype.newbyteorder("=")
    if dtype.kind == "f" and dtype.itemsize == 2:
        return np.dtype(np.float32)
    if dtype.kind in "iu":
        return np.dtype(np.float64)
    raise TypeError(f"orrery: array {name}: dtype {dtype} does not convert to float32 or float64 without loss "
                    "(float32, float64, float16 and integers do, in either byte order)")


def _as_float(name, a):
    """a as a native float32/float64 array (one copy only when converted)."""
    a = np.asarray(a)
    target = _float_dtype(name, a.dtype)
    return a if a.dtype == target else a.astype(target)


def _strided(a):
    """A 1-D array the library can read through a pointer and a stride: its
    strides are unsigned, 0 means packed, and elements must not overlap; a
    stride that is negative, zero (np.broadcast_to) or shorter than an
    element is copied to a packed array. So is a misaligned one (a field at
    an odd offset of a packed record, a buffer read from an odd offset):
    the library may load its elements as aligned values."""
    if (a.shape[0] > 1 and a.strides[0] < a.itemsize) or not a.flags.aligned:
        return np.array(a, order="C")  # a new, aligned, packed copy
    return a


def _integers(name, a, dtype, high=None):
    """A 1-D integer array as a packed or strided array of dtype (uint64
    ids, uint8 types), its values checked: not negative, at most high."""
    a = np.asarray(a)
    if a.ndim != 1 or a.dtype.kind not in "iu":
        raise TypeError(f"orrery: array {name}: {a.dtype} of shape {a.shape}, not 1-D integers")
    if a.size and a.min() < 0:
        raise ValueError(f"orrery: array {name}: negative value {a.min()}")
    if a.size and high is not None and a.max() > high:
        raise ValueError(f"orrery: array {name}: value {a.max()} outside 0..{high}")
    if a.dtype != dtype:
        a = a.astype(dtype)  # one copy, in range: checked above
    return _strided(a)


def _first_bad(a, bad):
    """The index of the first element of a for which bad(chunk) is true,
    or None; checked a chunk at a time, so the temporary stays small."""
    for start in range(0, a.shape[0], CHECK_CHUNK):
        hit = np.flatnonzero(bad(a[start:start + CHECK_CHUNK]))
        if hit.size:
            return start + int(hit[0])
    return None


def _orr_array(a):
    """The orr_array of a 1-D float array (a stride of 0 would mean packed)."""
    kind = _lib.ORR_F32 if a.dtype.itemsize == 4 else _lib.ORR_F64
    return _lib.OrrArray(a.ctypes.data if a.size else None, kind, a.strides[0] if a.ndim else 0)


class Arrays:
    """The particles of one render: the ctypes structure, and the numpy
    arrays it points into, kept alive for as long as the structure."""

    def __init__(self):
        self.c = _lib.OrrParticleArrays()
        self.c.struct_size = ctypes.sizeof(self.c)  # what the library checks (src/orrery.h)
        self.keep = []  # every array and name the structure points at
        self.n = None

    def _length(self, name, n):
        if self.n is None:
            self.n = n
        elif n != self.n:
            raise ValueError(f"orrery: array {name} has {n} particles, the positions {self.n}")

    def _column(self, name, a):
        """A 1-D per-particle float array, checked and kept."""
        a = _as_float(name, a)
        if a.ndim != 1:
            raise ValueError(f"orrery: array {name}: shape {a.shape}, not (N,)")
        self._length(name, a.shape[0])
        a = _strided(a)
        self.keep.append(a)
        return _orr_array(a)

    def positions(self, pos, name="positions", targets=("x", "y", "z")):
        """(N, 3) positions (or velocities), or three 1-D arrays."""
        if isinstance(pos, (tuple, list)) and len(pos) == 3:
            columns = [np.asarray(c) for c in pos]
        else:
            pos = _as_float(name, pos)
            if pos.ndim != 2 or pos.shape[1] != 3:
                raise ValueError(f"orrery: array {name}: shape {pos.shape}, not (N, 3)")
            columns = [pos[:, k] for k in range(3)]  # views: the same memory, the row stride
        for k, target in enumerate(targets):
            setattr(self.c, target, self._column(f"{name}[:, {k}]", columns[k]))

    def masses(self, m):
        if np.ndim(m) == 0:  # one mass for every particle
            self.c.mass_value = float(m)
            return
        self.c.mass = self._column("masses", m)

    def ids(self, ids):
        ids = _integers("ids", ids, np.dtype(np.uint64))
        self._length("ids", ids.shape[0])
        self.keep.append(ids)
        self.c.id, self.c.id_stride = ids.ctypes.data, ids.strides[0]

    def types(self, types):
        types = _integers("types", types, np.dtype(np.uint8), 5)
        self._length("types", types.shape[0])
        self.keep.append(types)
        self.c.type, self.c.type_stride = types.ctypes.data, types.strides[0]

    def smoothing(self, h):
        self.c.h = self._column("h", h)
        bad = _first_bad(self.keep[-1], lambda c: ~(c >= 0) | np.isinf(c))  # NaN fails c >= 0
        if bad is not None:
            raise ValueError(f"orrery: array h: h[{bad}] = {self.keep[-1][bad]}: smoothing lengths must be "
                             "finite and not negative (0: a particle without one)")

    def fields(self, fields):
        if len(fields) > _lib.MAX_FIELDS:
            raise ValueError(f"orrery: {len(fields)} fields, at most {_lib.MAX_FIELDS}")
        for k, (name, a) in enumerate(fields.items()):
            if not isinstance(name, str) or not name:
                raise TypeError(f"orrery: field name {name!r} is not a string")
            if "\0" in name:
                raise ValueError(f"orrery: field name {name!r} holds a NUL character")
            encoded = name.encode()
            self.keep.append(encoded)
            self.c.field_names[k] = encoded
            self.c.fields[k] = self._column(f"fields[{name!r}]", a)
        self.c.nfields = len(fields)


def describe(positions, masses, ids=None, h=None, fields=None, types=None, velocities=None, time=0.0):
    """The Arrays of one render, every argument checked."""
    arrays = Arrays()
    arrays.positions(positions)
    if arrays.n == 0:
        raise ValueError("orrery: array positions: no particles (0 rows); a render needs at least one")
    arrays.masses(masses)
    if ids is not None:
        arrays.ids(ids)
    if types is not None:
        arrays.types(types)
    if h is not None:
        arrays.smoothing(h)
    if velocities is not None:
        arrays.positions(velocities, "velocities", ("vx", "vy", "vz"))
    arrays.fields(dict(fields or {}))
    arrays.c.n = arrays.n
    arrays.c.time = float(time)
    if not math.isfinite(arrays.c.time):
        raise ValueError(f"orrery: time: {time} is not finite")
    return arrays
