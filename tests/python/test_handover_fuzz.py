"""A bounded fuzz of the Python/C array hand-over (issue 38): random dtypes,
layouts (steps, reversed, broadcast, misaligned, structured fields,
Fortran order, column triples), lengths, and defects (NaN, a wrong length,
a dtype that does not convert). Every render either equals, bit for bit,
the render of the same values as clean packed arrays, or raises the
exception the defect calls for; nothing crashes (run under the sanitizers
by the sanitizer build's ctest). ORRERY_FUZZ_CASES sets the number of cases."""
import os

import numpy as np
import pytest

import orrery
from conftest import FLAT

CASES = int(os.environ.get("ORRERY_FUZZ_CASES", "100"))
FLOATS = ["<f4", ">f4", "<f8", ">f8", "<f2", ">f2"]
SIGNED = ["i1", "<i2", ">i4", "<i8", ">i8"]
UNSIGNED = ["u1", "<u2", ">u4", "<u8", ">u8"]


def laid_out(rng, values, dtype):
    """values (1-D) as dtype in a random layout holding the same numbers."""
    n = len(values)
    how = rng.integers(6)
    if how == 0:
        return values.astype(dtype)
    if how == 1:  # every k-th element of a larger array
        step = int(rng.integers(2, 5))
        big = np.zeros(n * step, dtype)
        big[::step] = values
        return big[::step]
    if how == 2:  # reversed view
        return values[::-1].astype(dtype)[::-1]
    if how == 3 and n and np.all(values == values[0]):  # one value broadcast
        return np.broadcast_to(np.array(values[0], dtype), (n,))
    if how == 4:  # misaligned: one byte into a buffer
        size = np.dtype(dtype).itemsize
        buf = np.zeros(n * size + 1, np.uint8)
        a = np.frombuffer(buf.data, dtype, count=n, offset=1) if n else np.zeros(0, dtype)
        if n:
            a = a.copy() if not a.flags.writeable else a
            a[...] = values
        return a
    # a field of a structured array, between others
    record = np.zeros(n, [("pad", "u1"), ("v", dtype), ("more", "<f8")])
    record["v"] = values
    return record["v"]


def float_column(rng, values):
    return laid_out(rng, values, FLOATS[rng.integers(len(FLOATS))] if rng.random() < 0.8
                    else SIGNED[rng.integers(len(SIGNED))])


def case(rng):
    """(arguments, clean arguments, the exception expected or None)."""
    n = int(rng.integers(1, 300))
    pos = rng.integers(-4, 5, size=(n, 3)).astype(np.float64)
    mass = rng.integers(1, 4, size=n).astype(np.float64) if rng.random() < 0.7 else np.full(n, 2.0)
    ids = rng.permutation(n).astype(np.uint64) + 10
    types = rng.integers(0, 6, size=n).astype(np.uint8)
    clean = {"positions": pos.astype(np.float32), "masses": mass.astype(np.float32), "ids": ids, "types": types}
    shape = rng.integers(3)
    if shape == 0:
        positions = tuple(float_column(rng, pos[:, k]) for k in range(3))
    elif shape == 1:
        positions = np.asfortranarray(pos.astype(FLOATS[rng.integers(len(FLOATS))]))
    else:
        positions = pos.astype(SIGNED[rng.integers(len(SIGNED))])
    given = {"positions": positions, "masses": float_column(rng, mass) if rng.random() < 0.8 else mass[0],
             "ids": laid_out(rng, ids, UNSIGNED[3 + rng.integers(2)]),
             "types": laid_out(rng, types, (SIGNED + UNSIGNED)[rng.integers(10)])}
    if not np.ndim(given["masses"]):
        clean["masses"] = np.full(n, np.float32(mass[0]))
    defect = rng.integers(8)
    if defect == 0:  # a NaN mass
        m = np.array(mass, np.float32)
        m[rng.integers(n)] = np.nan
        given["masses"] = m
        return given, clean, orrery.OrreryError
    if defect == 1 and n > 1:  # a length that differs
        given["ids"] = given["ids"][:-1]
        return given, clean, ValueError
    if defect == 2:
        given["masses"] = mass.astype(complex)
        return given, clean, TypeError
    return given, clean, None


def test_random_handovers():
    rng = np.random.default_rng(38)
    scene = orrery.Scene(FLAT, input={"types": [0, 1, 2, 3, 4, 5]})
    outcomes = {"equal": 0, "refused": 0}
    for k in range(CASES):
        given, clean, expected = case(rng)
        if expected:
            with pytest.raises(expected):
                scene.render(**given)
            outcomes["refused"] += 1
            continue
        image = scene.render(**given)[0].data
        assert image.tobytes() == scene.render(**clean)[0].data.tobytes(), f"case {k}"
        outcomes["equal"] += 1
    assert outcomes["equal"] > CASES // 2 and outcomes["refused"] > CASES // 10
