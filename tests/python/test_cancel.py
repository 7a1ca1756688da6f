"""A render stopped from its progress callback: returning False raises
orrery.Cancelled, raising stops the render with that exception; either way
the render reads no further chunk, writes no file (not even a temporary
one), and the Scene renders the next frame as if nothing had happened."""
import numpy as np
import pytest

import orrery
from conftest import FLAT

CHUNK = 1000


def scene_writing(tmp_path):
    return orrery.Scene(FLAT, write=True, input={"chunk": CHUNK},
                        output={"dir": str(tmp_path), "png": True, "exr": True})


def test_false_cancels_before_the_next_chunk(tmp_path, particles):
    pos, mass, _ = particles
    scene = scene_writing(tmp_path)
    calls = []

    def stop_at_two(done, total):
        calls.append(done)
        return done < 2 * CHUNK  # True, then False: None or True go on

    with pytest.raises(orrery.Cancelled, match="after 2000 of 5000 particles"):
        scene.render(pos, mass, progress=stop_at_two)
    assert calls == [CHUNK, 2 * CHUNK]  # no chunk read after the False
    assert list(tmp_path.iterdir()) == []  # nothing written, no temporaries left
    assert not isinstance(orrery.Cancelled("x"), Exception)  # `except Exception` does not swallow it
    # The same scene renders the next frame in full, as a fresh one does.
    image = scene.render(pos, mass, progress=lambda done, total: None)[0]
    fresh = orrery.Scene(FLAT, input={"chunk": CHUNK}).render(pos, mass)[0]
    assert np.array_equal(image.data, fresh.data)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["flat_0000.exr", "flat_0000.fits", "flat_0000.png"]


def test_an_exception_stops_the_render(tmp_path, particles):
    pos, mass, _ = particles
    scene = scene_writing(tmp_path)
    calls = []

    def interrupt(done, total):
        calls.append(done)
        raise KeyboardInterrupt("stop")

    with pytest.raises(KeyboardInterrupt, match="stop"):
        scene.render(pos, mass, progress=interrupt)
    assert calls == [CHUNK] and list(tmp_path.iterdir()) == []


def test_false_after_the_last_chunk_still_cancels(tmp_path, particles):
    pos, mass, _ = particles
    scene = scene_writing(tmp_path)
    with pytest.raises(orrery.Cancelled):
        scene.render(pos, mass, progress=lambda done, total: done < total)
    assert list(tmp_path.iterdir()) == []
