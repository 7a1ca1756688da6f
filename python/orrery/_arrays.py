"""numpy arrays described to liborrery as orr_particle_arrays, read where
they are: a float32 or float64 array with any positive stride (a column of
an (N, 3) array, a field of a structured array) is passed as a pointer and
a stride, without a copy. Only what the library cannot read in place is
copied once: another byte order, negative strides, integer ids of another
type. Every refusal names the array."""
import ctypes

import numpy as np

from . import _lib


def _as_float(name, a):
    """a as a native float32/float64 array the library can stride through."""
    a = np.asarray(a)
    if a.dtype.kind != "f" or a.dtype.itemsize not in (4, 8):
        raise TypeError(f"orrery: array {name}: dtype {a.dtype}, not float32 or float64")
    if not a.dtype.isnative:
        a = a.astype(a.dtype.newbyteorder("="))  # one copy: orrery reads native floats only
    if any(s <= 0 for s in a.strides) and a.size > 1:
        # One copy: orrery's strides are unsigned, and 0 means packed (numpy's
        # 0 is a broadcast value).
        a = np.ascontiguousarray(a)
    return a


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
        ids = np.asarray(ids)
        if ids.ndim != 1 or ids.dtype.kind not in "iu":
            raise TypeError(f"orrery: array ids: {ids.dtype} of shape {ids.shape}, not 1-D integers")
        self._length("ids", ids.shape[0])
        if ids.dtype.kind == "i" and ids.size and ids.min() < 0:
            raise ValueError("orrery: array ids: negative ids")
        if ids.dtype != np.uint64 or not ids.dtype.isnative or ids.strides[0] < 0:
            ids = ids.astype(np.uint64)  # one copy: orrery reads uint64 ids
        self.keep.append(ids)
        self.c.id, self.c.id_stride = ids.ctypes.data, ids.strides[0]

    def types(self, types):
        types = np.asarray(types)
        if types.ndim != 1 or types.dtype.kind not in "iu":
            raise TypeError(f"orrery: array types: {types.dtype} of shape {types.shape}, not 1-D integers")
        self._length("types", types.shape[0])
        if types.size and (types.min() < 0 or types.max() > 5):
            raise ValueError("orrery: array types: values outside 0..5")
        if types.dtype != np.uint8 or types.strides[0] < 0:
            types = types.astype(np.uint8)
        self.keep.append(types)
        self.c.type, self.c.type_stride = types.ctypes.data, types.strides[0]

    def smoothing(self, h):
        self.c.h = self._column("h", h)

    def fields(self, fields):
        if len(fields) > _lib.MAX_FIELDS:
            raise ValueError(f"orrery: {len(fields)} fields, at most {_lib.MAX_FIELDS}")
        for k, (name, a) in enumerate(fields.items()):
            if not isinstance(name, str) or not name:
                raise TypeError(f"orrery: field name {name!r} is not a string")
            encoded = name.encode()
            self.keep.append(encoded)
            self.c.field_names[k] = encoded
            self.c.fields[k] = self._column(f"fields[{name!r}]", a)
        self.c.nfields = len(fields)


def describe(positions, masses, ids=None, h=None, fields=None, types=None, velocities=None, time=0.0):
    """The Arrays of one render, every argument checked."""
    arrays = Arrays()
    arrays.positions(positions)
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
    return arrays
