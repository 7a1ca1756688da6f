"""HEALPix from Python: a 1-D map in pixel order that healpy reads as it is,
with NSIDE, ORDERING and COORDSYS in the header, for each deposit a HEALPix
scene takes (ngp, sph); particles at known (l, b) in the pixel healpy's
ang2pix names; the map equal to the file the CLI's writer makes."""
import healpy as hp
import numpy as np
import pytest

import orrery

NSIDE = 16
OBSERVER, REFERENCE = np.array([1.0, 2.0, 3.0]), np.array([6.0, 2.0, 3.0])  # l = 0 along +x, b = 90 along +z
POINTS = [(l + 0.37, b + 0.21) for l in range(-150, 180, 60) for b in (-50, -10, 25, 70)]


def sky():
    """The observer (id 1), the reference (id 2) and a particle of mass j + 1
    at each (l, b) of POINTS, 10 units from the observer."""
    pos = [OBSERVER, REFERENCE]
    for l, b in np.radians(POINTS):
        pos.append(OBSERVER + 10 * np.array([np.cos(b) * np.cos(l), np.cos(b) * np.sin(l), np.sin(b)]))
    mass = np.concatenate([[1000.0, 0.5], np.arange(1, len(POINTS) + 1)])
    return np.array(pos), mass, np.arange(1, len(pos) + 1)


def scene(deposit, order, **keys):
    return orrery.Scene({"observer": {"id": 1, "reference_id": 2, "normal": [0, 0, 1], "dim": False},
                         "camera": {"projection": "healpix", "healpix_nside": NSIDE, "healpix_order": order},
                         "deposit": deposit}, **keys)


@pytest.mark.parametrize("deposit", ["ngp", "sph"])
@pytest.mark.parametrize("order", ["ring", "nested"])
def test_map_healpy_reads(tmp_path, deposit, order):
    pos, mass, ids = sky()
    h = np.full(len(pos), 0.02)  # 0.002 rad at 10 units: well inside a pixel of 0.064 rad
    image = scene(deposit, order, write=True, output={"dir": str(tmp_path), "name": "m"}).render(pos, mass, ids,
                                                                                                  h=h)[0]
    m = image.data
    nest = order == "nested"
    assert m.shape == (12 * NSIDE**2,) and hp.get_nside(m) == NSIDE
    assert image.header["NSIDE"] == NSIDE and image.header["ORDERING"] == ("NESTED" if nest else "RING")
    assert image.header["COORDSYS"] == "G" and image.wcs is None
    assert image.rgb.shape == (12 * NSIDE**2, 3)
    area = hp.nside2pixarea(NSIDE)
    for j, (l, b) in enumerate(POINTS):
        pixel = hp.ang2pix(NSIDE, l, b, nest=nest, lonlat=True)
        if deposit == "ngp":
            assert m[pixel] * area == pytest.approx(j + 1, rel=1e-4), (l, b)
        else:  # the kernel (0.004 rad) may reach a neighbour, not further; its pixel holds the most
            around = np.concatenate([[pixel], hp.get_all_neighbours(NSIDE, pixel, nest=nest)])
            assert m[around].sum() * area == pytest.approx(j + 1, rel=1e-4), (l, b)
            assert m[pixel] == m[around].max()
    assert m.sum() * area == pytest.approx(mass[1:].sum(), rel=1e-5)  # the observer is not in its own sky
    from_file = hp.read_map(tmp_path / "m_0000.fits", nest=None)  # as stored, RING or NESTED
    assert np.array_equal(from_file, m)


def test_without_observer_no_coordsys():
    pos, mass, _ = sky()
    image = orrery.render({"camera": {"projection": "healpix", "healpix_nside": 4}, "deposit": "ngp"}, pos, mass)
    assert image.data.shape == (192,) and image.header["ORDERING"] == "RING" and "COORDSYS" not in image.header


def test_deposit_it_cannot_take_is_named():
    """As the CLI: cic (the default) is refused, naming the deposit."""
    with pytest.raises(orrery.OrreryError, match="healpix takes deposit: ngp .* or sph"):
        orrery.Scene({"camera": {"projection": "healpix"}})
