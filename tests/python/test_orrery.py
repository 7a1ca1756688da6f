"""The Python package: numpy in, numpy images out, the same pixels as the
CLI's FITS, and errors as exceptions naming what was wrong."""
import json

import numpy as np
import pytest
from astropy.io import fits

import orrery
from conftest import FLAT, cli_render, write_tipsy

DOME = {"camera": {"projection": "dome", "position": [0, 0, -12], "look_at": [0, 0, 0], "up": [0, 1, 0]},
        "image": {"width": 128, "height": 128}, "deposit": "cic", "output": {"name": "dome"}}


@pytest.mark.parametrize("scene", [FLAT, DOME], ids=["orthographic", "dome"])
def test_equals_cli_fits(tmp_path, cli, particles, scene):
    """A Python render equals, bit for bit, the FITS the CLI writes for the
    same particles and scene (FITS rows are stored bottom-up)."""
    pos, mass, ids = particles
    scene_file = tmp_path / "scene.yaml"
    scene_file.write_text(json.dumps(scene))
    write_tipsy(tmp_path / "p.tipsy", pos, mass)
    cli_render(cli, scene_file, tmp_path / "p.tipsy", tmp_path / "cli")
    name = scene["output"]["name"]
    with fits.open(tmp_path / "cli" / f"{name}.fits") as f:
        expected = np.flipud(f[0].data).astype(np.float32)  # to native byte order
        cli_cards = f[0].header
    image = orrery.Scene(scene_file).render(pos, mass, ids)[0]
    plane = image.planes["mass"]
    assert plane.dtype == np.float32 and plane.shape == expected.shape
    assert plane.tobytes() == expected.tobytes()
    assert image.header["PROJTYPE"] == cli_cards["PROJTYPE"]
    assert image.header["WIMAGE"] == pytest.approx(cli_cards["WIMAGE"], rel=1e-14)  # cfitsio writes fewer digits
    assert image.header["NPART"] == len(pos)


def test_mass_conservation(particles):
    """Every particle inside the view: the plane (mass per unit area) sums
    to the total mass."""
    pos, mass, _ = particles
    inside = (np.abs(pos[:, 0]) < 4.9) & (np.abs(pos[:, 1]) < 3.6)  # clear of the edges by a CIC share
    image = orrery.render(FLAT, pos[inside], mass[inside])
    pixel_area = (10.0 / 80) ** 2
    total = float(mass[inside].astype(np.float64).sum())
    assert image.data.astype(np.float64).sum() * pixel_area == pytest.approx(total, rel=1e-5)
    assert image.header["WOUTSIDE"] == 0


def test_known_pixel():
    """One particle, NGP: its mass / pixel area lands in the pixel under it,
    row 0 at the top."""
    scene = dict(FLAT, deposit="ngp")
    pos = np.array([[1.0 + 1 / 16, 2.0 + 1 / 16, 0.0]])  # the centre of a pixel 1/8 wide
    image = orrery.render(scene, pos, 3.0)
    row, col = np.argwhere(image.data)[0]
    assert (row, col) == (int((3.75 - pos[0, 1]) * 8), int((pos[0, 0] + 5.0) * 8))
    assert image.data[row, col] == pytest.approx(3.0 * 64)
    assert np.count_nonzero(image.data) == 1


def test_dtypes_and_strides_agree(particles):
    """float32 packed, float64, a Fortran-ordered array, a column triple and
    the fields of a structured array (array of structures) give one image."""
    pos, mass, ids = particles
    scene = orrery.Scene(FLAT)
    reference = scene.render(pos, mass, ids)[0].data
    body = np.zeros(len(pos), dtype=[("pos", "f8", 3), ("vel", "f4", 3), ("m", "f4"), ("id", "u8")])
    body["pos"], body["m"], body["id"] = pos, mass, ids
    layouts = [
        (pos.astype(np.float64), mass.astype(np.float64), ids.astype(np.int64)),
        (np.asfortranarray(pos), mass, ids),
        ((pos[:, 0].copy(), pos[:, 1].copy(), pos[:, 2].copy()), mass, ids),
        (body["pos"], body["m"], body["id"]),
        (pos.astype(">f4"), mass.astype(">f4"), ids),  # another byte order: copied once
        (pos[::-1][::-1], mass, ids),
    ]
    for p, m, i in layouts:
        assert np.array_equal(scene.render(p, m, i)[0].data, reference)


def test_field_as_weight_and_colour_planes(particles):
    pos, mass, _ = particles
    lum = (mass * 2).astype(np.float32)
    scene = orrery.Scene(FLAT, input={"weight": "lum"})
    image = scene.render(pos, mass, fields={"lum": lum})[0]
    assert list(image.planes) == ["lum"]
    by_mass = orrery.render(FLAT, pos, mass).data
    assert np.allclose(image.data, 2 * by_mass, rtol=1e-6)
    assert image.rgb.shape == (60, 80, 3) and 0 <= image.rgb.min() and image.rgb.max() <= 1


def test_write_files(tmp_path, particles):
    pos, mass, _ = particles
    scene = orrery.Scene(FLAT, write=True, output={"dir": str(tmp_path), "png": True})
    image = scene.render(pos, mass)[0]
    assert sorted(p.split("/")[-1] for p in scene.outputs) == ["flat_0000.fits", "flat_0000.png"]
    with fits.open(tmp_path / "flat_0000.fits") as f:
        assert np.flipud(f[0].data).astype(np.float32).tobytes() == image.data.tobytes()


def test_bad_key_names_it():
    with pytest.raises(orrery.OrreryError, match="cmaera") as e:
        orrery.Scene(FLAT, cmaera={"fov": 60})
    assert e.value.code == 2 and "camera" in str(e.value)  # the suggestion
    with pytest.raises(orrery.OrreryError, match="camera.fov"):
        orrery.Scene(FLAT, overrides={"camera.fov": 500})
    with pytest.raises(orrery.OrreryError, match="no_such_scene.yaml"):
        orrery.Scene("no_such_scene.yaml")


def test_bad_arrays_name_them(particles):
    pos, mass, ids = particles
    scene = orrery.Scene(FLAT)
    with pytest.raises(TypeError, match="array positions: dtype complex128"):
        scene.render(pos.astype(np.complex128), mass)
    with pytest.raises(ValueError, match=r"array positions: shape \(5000, 2\)"):
        scene.render(pos[:, :2], mass)
    with pytest.raises(ValueError, match="array masses has 4999 particles"):
        scene.render(pos, mass[1:])
    with pytest.raises(ValueError, match="array ids: negative"):
        scene.render(pos, mass, -np.arange(len(pos)))
    bad = pos.copy()
    bad[7, 2] = np.nan
    with pytest.raises(orrery.OrreryError) as e:
        scene.render(bad, mass)
    assert e.value.code == 5 and "non-finite" in str(e.value)
    weighted = orrery.Scene(FLAT, input={"weight": "nosuch"})
    with pytest.raises(orrery.OrreryError, match="nosuch"):
        weighted.render(pos, mass, fields={"lum": mass})
    # The renderer is still usable after errors.
    assert scene.render(pos, mass)[0].data.sum() > 0
