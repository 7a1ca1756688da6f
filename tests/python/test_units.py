"""Numbers with units: astropy Quantities and unyt arrays converted to the
scene's units (output.length_unit, output.bunit), or refused naming the
unit; the same particles in Mpc and in kpc give the same image."""
import json

import astropy.units as u
import numpy as np
import pytest
import unyt

import orrery
from conftest import FLAT

KPC = dict(FLAT, output={"name": "flat", "length_unit": "kpc", "bunit": "solMass"})


@pytest.fixture
def stars():
    rng = np.random.default_rng(43)
    return rng.normal(scale=2.0, size=(4000, 3)), rng.uniform(0.5, 2.0, size=4000)


def test_lengths_converted(tmp_path, stars):
    pos, mass = stars
    scene = orrery.Scene(KPC)
    reference = scene.render(pos, mass)[0].data
    for given in (pos * u.kpc, (pos * u.kpc).to(u.Mpc), unyt.unyt_array(pos / 1000, "Mpc"),
                  unyt.unyt_array(pos * 1000, "pc")):
        assert np.allclose(scene.render(given, mass)[0].data, reference, rtol=1e-5, atol=0)
    columns = tuple((pos[:, k] * u.kpc).to(u.lyr) for k in range(3))
    assert np.allclose(scene.render(columns, mass)[0].data, reference, rtol=1e-5, atol=0)
    # The same scene from a file: its keys read there.
    path = tmp_path / "kpc.yaml"
    path.write_text(json.dumps(KPC))
    assert np.allclose(orrery.Scene(path).render(pos * u.Mpc / 1000, mass)[0].data, reference, rtol=1e-5, atol=0)
    assert orrery.Scene(path).units["length"] == "kpc"


def test_masses_and_smoothing_converted(stars):
    pos, mass = stars
    scene = orrery.Scene(dict(KPC, deposit="sph"))
    h = np.full(len(pos), 0.3)
    reference = scene.render(pos, mass, h=h)[0].data
    image = scene.render(pos, (mass * u.M_sun).to(u.kg), h=(h * u.kpc).to(u.pc))[0].data
    assert np.allclose(image, reference, rtol=1e-5, atol=1e-6 * reference.max())
    as_weight = orrery.Scene(KPC, input={"weight": "lum"}).render(pos, 1.0, fields={"lum": mass * 1e3 * u.solMass})
    assert np.allclose(as_weight[0].data, 1e3 * orrery.Scene(KPC).render(pos, mass)[0].data, rtol=1e-5)


def test_refused_naming_the_unit(stars):
    pos, mass = stars
    with pytest.raises(ValueError, match=r"positions: in kpc, but the scene states no unit for it "
                                         r"\(output.length_unit\)"):
        orrery.Scene(FLAT).render(pos * u.kpc, mass)
    with pytest.raises(ValueError, match=r"positions: in s, which does not convert to the scene's kpc"):
        orrery.Scene(KPC).render(pos * u.s, mass)
    with pytest.raises(ValueError, match=r"masses: in kg, but the scene states no unit for it \(output.bunit\)"):
        orrery.Scene(FLAT, output={"length_unit": "kpc"}).render(pos, mass * u.kg)
    with pytest.raises(ValueError, match=r"h: in s, which does not convert"):
        orrery.Scene(KPC).render(pos, mass, h=np.ones(len(pos)) * u.s)
    with pytest.raises(ValueError, match=r"velocities: in km / s, but the scene states no unit for it: pass plain"):
        orrery.Scene(KPC).render(pos, mass, velocities=pos * u.km / u.s)
    with pytest.raises(ValueError, match=r"time: in Gyr, but the scene states no unit"):
        orrery.Scene(KPC).render(pos, mass, time=2 * u.Gyr)
    with pytest.raises(ValueError, match=r"positions: in K"):
        orrery.Scene(KPC).render(unyt.unyt_array(pos, "K"), mass)
