"""orrery.open: a particle file read with orrery's own readers (every
format `orrery render` reads), into numpy arrays by field, a chunk at a
time."""
import ctypes
import os
import threading

import numpy as np

from ._lib import lib
from .scene import OrreryError

DTYPES = {"id": np.uint64, "type": np.uint8}  # every other field float32


class File:
    """A particle file open for reading. .format, .count (-1: unknown until
    read), .time, .fields (the names each chunk has); chunks() yields
    {field: array} a chunk at a time, read() the whole file. Positions,
    masses, h and the other fields are float32, "id" uint64, "type" uint8;
    "h" is in orrery's convention (kernel support 2h: the file's own
    smoothing lengths scaled, so they can go straight to Scene.render).
    The file is read once, front to back."""

    def __init__(self, path, format=None, fields=None, chunk_size=1 << 20):
        self._lock = threading.Lock()  # one thread reads at a time; close waits for a read
        self._rd = ctypes.c_void_p()
        self.path = os.fspath(path)
        wanted = None
        if fields is not None:
            names = [str(f) for f in fields]
            if any("\0" in f for f in names):
                raise ValueError(f"orrery.open: a field name holds a NUL character: {names!r}")
            wanted = (ctypes.c_char_p * max(len(names), 1))(*[f.encode() for f in names])
        msg = ctypes.create_string_buffer(2048)
        st = lib.orrery_reader_open(ctypes.byref(self._rd), self.path.encode(), (format or "auto").encode(),
                                    int(chunk_size), wanted, len(fields) if fields is not None else 0, msg, len(msg))
        if st != 0:
            raise OrreryError(msg.value.decode(errors="replace"), st)
        self.format = lib.orrery_reader_format(self._rd).decode()
        self.count = lib.orrery_reader_count(self._rd)
        self.time = lib.orrery_reader_time(self._rd)
        self.has = {what: bool(lib.orrery_reader_has(self._rd, what.encode())) for what in ("h", "id", "type")}
        # h as orrery takes it: the file's kernel ends at h_support * h, orrery's at 2 h.
        self._h_scale = np.float32(lib.orrery_reader_h_support(self._rd) / 2)
        extra = [lib.orrery_reader_field_name(self._rd, i).decode()
                 for i in range(lib.orrery_reader_field_count(self._rd))]
        self.fields = ["x", "y", "z", "mass"] + (["h"] if self.has["h"] else []) + ["id", "type"] + extra

    def _next(self):
        """The next chunk as copies, or None at the end."""
        if not self._lock.acquire(blocking=False):
            raise OrreryError(f"orrery.open: {self.path}: already being read in another thread", 2)
        try:
            if not self._rd:
                raise OrreryError(f"orrery.open: {self.path}: the file is closed", 2)
            n = ctypes.c_size_t()
            st = lib.orrery_reader_next(self._rd, ctypes.byref(n))
            if st != 0:
                raise OrreryError(lib.orrery_reader_error(self._rd).decode(errors="replace"), st)
            if n.value == 0:
                return None
            return {name: self._field(name, n.value) for name in self.fields}
        finally:
            self._lock.release()

    def _field(self, name, n):
        if name == "id":
            return np.ctypeslib.as_array(lib.orrery_reader_ids(self._rd), shape=(n,)).copy()
        if name == "type":
            return np.ctypeslib.as_array(lib.orrery_reader_types(self._rd), shape=(n,)).copy()
        values = np.ctypeslib.as_array(lib.orrery_reader_field(self._rd, name.encode()), shape=(n,)).copy()
        if name == "h" and self._h_scale != 1:
            values *= self._h_scale
        return values

    def chunks(self):
        """Yields each chunk of the file as {field: array}, copies the caller
        keeps (the library's buffer is refilled by the next chunk)."""
        while (chunk := self._next()) is not None:
            yield chunk

    def read(self):
        """The rest of the file as {field: array}, every chunk joined."""
        parts = {name: [] for name in self.fields}
        for chunk in self.chunks():
            for name, values in chunk.items():
                parts[name].append(values)
        return {name: np.concatenate(p) if p else np.empty(0, DTYPES.get(name, np.float32))
                for name, p in parts.items()}

    def close(self):
        with self._lock:
            if self._rd:
                lib.orrery_reader_close(self._rd)
                self._rd = ctypes.c_void_p()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        if hasattr(self, "_lock"):
            self.close()

    def __repr__(self):
        return f"<orrery.File {self.path!r} {self.format}, {self.count} particles, fields {self.fields}>"


def open(path, format=None, fields=None, chunk_size=1 << 20):  # noqa: A001 (orrery.open, as io.open)
    """Opens a particle file with orrery's readers: an orrery.File.
    format: None detects it (or "gadget2", "hdf5", "tipsy", ...); fields:
    the other fields to read (datasets, blocks, columns; None: every one);
    chunk_size: particles per chunk."""
    return File(path, format, fields, chunk_size)
