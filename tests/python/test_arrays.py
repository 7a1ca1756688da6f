"""Arrays handed to the library: any strides and the dtypes that convert
without loss give the image of the plain float64 arrays; everything else,
and bad values, are refused naming the argument (never a crash); a Scene
used from two threads, or closed under a render, raises instead of
crashing."""
import threading

import numpy as np
import pytest
from numpy.lib.stride_tricks import as_strided

import orrery
from conftest import FLAT

N = 3000


@pytest.fixture
def small():
    rng = np.random.default_rng(38)
    pos = rng.integers(-30, 30, size=(N, 3)).astype(np.float64) / 8  # exact in float16 and as integers / 8
    mass = rng.integers(1, 4, size=N).astype(np.float64)
    return pos, mass


def test_zero_and_overlapping_strides_are_copied(small):
    """np.broadcast_to gives a zero stride, which the C API would take as
    packed (issue 38 item 1: a heap overflow for types, a SEGV for ids)."""
    pos, mass = small
    scene = orrery.Scene(FLAT, input={"types": [1]})
    reference = scene.render(pos, mass, ids=np.arange(N), types=np.ones(N, np.uint8))[0].data
    one = np.broadcast_to(np.uint8(1), (N,))
    assert one.strides == (0,)
    assert np.array_equal(scene.render(pos, mass, ids=np.arange(N), types=one)[0].data, reference)
    same_id = np.broadcast_to(np.uint64(7), (N,))  # every particle id 7: no observer, so allowed
    assert np.array_equal(scene.render(pos, mass, ids=same_id, types=one)[0].data, reference)
    broadcast_mass = np.broadcast_to(np.float32(2.0), (N,))
    assert np.array_equal(scene.render(pos, broadcast_mass, types=one)[0].data,
                          scene.render(pos, 2.0, types=one)[0].data)
    # Overlapping elements: a stride of 2 bytes through float32 data.
    raw = np.arange(N + 1, dtype=np.float32)
    overlapping = as_strided(raw, shape=(N,), strides=(2,))
    assert np.array_equal(scene.render(pos, overlapping, types=one)[0].data,
                          scene.render(pos, overlapping.copy(), types=one)[0].data)


@pytest.mark.parametrize("dtype", ["i2", "<i8", ">i4", "f2", ">f2", ">f4", ">f8"])
def test_dtypes_converted(small, dtype):
    pos, mass = small
    scene = orrery.Scene(FLAT)
    reference = scene.render(pos, mass)[0].data
    scale = 8 if np.dtype(dtype).kind in "iu" else 1  # integer positions: the same points, 8 times as far
    wide = dict(FLAT, camera=dict(FLAT["camera"], width=FLAT["camera"]["width"] * scale))
    masses = mass.astype("u2" if scale > 1 else dtype)  # (unsigned: masses are positive)
    image = orrery.Scene(wide).render((pos * scale).astype(dtype), masses)[0].data
    assert np.array_equal(image * scale**2, reference)


@pytest.mark.parametrize("dtype", [bool, complex, np.longdouble, object, "U3"])
def test_dtypes_refused_by_name(small, dtype):
    pos, mass = small
    with pytest.raises(TypeError, match=r"array positions: dtype .* does not convert"):
        orrery.render(FLAT, pos.astype(dtype), mass)
    with pytest.raises(TypeError, match=r"array masses: dtype .* does not convert"):
        orrery.render(FLAT, pos, mass.astype(dtype))


def test_bad_values_named(small):
    """Issue 38 item 9."""
    pos, mass = small
    scene = orrery.Scene(FLAT)
    with pytest.raises(ValueError, match="array positions: no particles"):
        scene.render(np.zeros((0, 3)), 1.0)
    with pytest.raises(ValueError, match=r"frame: 9223372036854775808 is outside 0\.\."):
        scene.render(pos, mass, frame=2**63)
    with pytest.raises(ValueError, match="frame: -1 is outside"):
        scene.render(pos, mass, frame=-1)
    with pytest.raises(TypeError, match="frame: 1.5 is not an integer"):
        scene.render(pos, mass, frame=1.5)
    for t in (np.nan, np.inf, -np.inf):
        with pytest.raises(ValueError, match=f"time: {t} is not finite"):
            scene.render(pos, mass, time=t)
    with pytest.raises(ValueError, match="field name 'lu\\\\x00m' holds a NUL"):
        scene.render(pos, mass, fields={"lu\0m": mass})
    for bad in (np.nan, -0.5, np.inf):
        h = np.full(N, 0.1)
        h[1234] = bad
        with pytest.raises(ValueError, match=rf"array h: h\[1234\] = {bad}: smoothing lengths must be finite"):
            scene.render(pos, mass, h=h)
    with pytest.raises(ValueError, match="array types: value 6 outside 0..5"):
        scene.render(pos, mass, types=np.full(N, 6))
    assert scene.render(pos, mass, h=np.zeros(N), frame=2**62)[0].data.sum() > 0  # still usable


def test_closed_scene_raises(small):
    pos, mass = small
    scene = orrery.Scene(FLAT)
    scene.close()
    scene.close()
    with pytest.raises(orrery.OrreryError, match="the scene is closed"):
        scene.render(pos, mass)


def test_one_scene_from_threads(small):
    """Two threads render one Scene until a third closes it: each render
    gives the right image or raises OrreryError (busy in the other thread,
    or closed), and the process survives (issue 38 item 2: a use-after-free
    before)."""
    pos, mass = small
    big = np.tile(pos, (10, 1))
    scene = orrery.Scene(FLAT)
    reference = scene.render(big, 1.0)[0].data
    counts, lock, rendered = {"right": 0, "wrong": 0, "busy": 0, "closed": 0}, threading.Lock(), threading.Event()

    def count(what):
        with lock:
            counts[what] += 1
            if counts["right"] >= 4:
                rendered.set()

    def renders():
        for _ in range(2000):
            try:
                count("right" if np.array_equal(scene.render(big, 1.0)[0].data, reference) else "wrong")
            except orrery.OrreryError as e:
                if "closed" in str(e):
                    return count("closed")
                assert "already rendering in another thread" in str(e)
                count("busy")
                threading.Event().wait(0.001)

    def closes():
        rendered.wait(60)
        scene.close()

    threads = [threading.Thread(target=f) for f in (renders, renders, closes)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert counts["closed"] == 2 and counts["wrong"] == 0 and counts["right"] >= 4 and counts["busy"] > 0, counts
