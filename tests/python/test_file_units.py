"""Renders of HDF5 snapshots that state their units (SWIFT's Units group,
Gadget-4's Parameters) carry them into BUNIT and CUNIT, so astropy's
CCDData.read takes the planes with the right unit; the unit is checked
against the file's own cgs numbers by summing the plane back to grams."""
import json

import numpy as np
import pytest

h5py = pytest.importorskip("h5py")
u = pytest.importorskip("astropy.units")
from astropy.io import fits  # noqa: E402
from astropy.nddata import CCDData  # noqa: E402

N, MASS = 300, 0.5  # particles, each of MASS file units
SWIFT_UNITS = {"Unit mass in cgs (U_M)": 1.98841e43, "Unit length in cgs (U_L)": 3.08567758e24}
GADGET_UNITS = {"UnitMass_in_g": 1.989e43, "UnitLength_in_cm": 3.085678e21}


def write_snapshot(path, style, comoving=False, hubble=0.7):
    """A small snapshot of N particles near (5, 5, 5): SWIFT's layout (the
    unit system in Units, each dataset's h and a exponents) or Gadget-4's
    (Parameters, ComovingIntegrationOn and HubbleParam)."""
    pos = np.clip(np.random.default_rng(3).normal(5, 1, (N, 3)), 1, 9).astype(np.float32)
    with h5py.File(path, "w") as f:
        hd = f.create_group("Header")
        for key in ("NumPart_ThisFile", "NumPart_Total"):
            hd.attrs[key] = np.array([0, N, 0, 0, 0, 0], np.uint32)
        hd.attrs["NumPart_Total_HighWord"] = np.zeros(6, np.uint32)
        hd.attrs["MassTable"] = np.zeros(6)
        hd.attrs["Time"] = 1.0
        hd.attrs["NumFilesPerSnapshot"] = 1
        g = f.create_group("PartType1")
        coords = g.create_dataset("Coordinates", data=pos)
        masses = g.create_dataset("Masses", data=np.full(N, MASS, np.float32))
        g.create_dataset("ParticleIDs", data=np.arange(N, dtype=np.uint32))
        if style == "swift":
            units = f.create_group("Units")
            for key, value in SWIFT_UNITS.items():
                units.attrs[key] = [value]
            hd.attrs["Scale-factor"] = [1.0]
            for ds, a_exponent in ((coords, 1.0), (masses, 0.0)):
                ds.attrs["h-scale exponent"] = [0.0]
                ds.attrs["a-scale exponent"] = [a_exponent]
        else:
            params = f.create_group("Parameters")
            for key, value in GADGET_UNITS.items():
                params.attrs[key] = value
            params.attrs["ComovingIntegrationOn"] = int(comoving)
            params.attrs["HubbleParam"] = hubble


def render(cli, tmp_path, snapshot, projection, *sets):
    import subprocess
    camera = {"projection": projection, "position": [5, 5, 20], "look_at": [5, 5, 5]}
    if projection == "orthographic":
        camera["width"] = 10.0
    scene = {"camera": camera, "image": {"width": 40, "height": 40 if projection == "orthographic" else 20},
             "deposit": "ngp", "output": {"name": "o", "png": False}}
    (tmp_path / "s.yaml").write_text(json.dumps(scene))
    args = [cli, "render", str(tmp_path / "s.yaml"), "--set", f"input.file={snapshot}", "-o", str(tmp_path),
            "--quiet"]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True)
    return tmp_path / "o.fits"


@pytest.mark.parametrize("style, mass_g, length_cm, bunit", [
    ("swift", SWIFT_UNITS["Unit mass in cgs (U_M)"], SWIFT_UNITS["Unit length in cgs (U_L)"], "1e10 solMass / Mpc2"),
    ("gadget4", GADGET_UNITS["UnitMass_in_g"], GADGET_UNITS["UnitLength_in_cm"], "1e10 solMass / kpc2"),
])
def test_surface_density_unit_from_file(cli, tmp_path, style, mass_g, length_cm, bunit):
    write_snapshot(tmp_path / "snap.hdf5", style)
    path = render(cli, tmp_path, tmp_path / "snap.hdf5", "orthographic")
    image = CCDData.read(path)
    assert image.unit == u.Unit(bunit)
    header = fits.getheader(path)
    assert header["CUNIT1"] == header["CUNIT2"] == u.Unit(bunit).bases[1].to_string()
    # Summed over the pixels' areas, the plane is the particles' mass, as the
    # file's own cgs numbers give it.
    pixel_area = (10.0 / 40) ** 2 * (length_cm * u.cm) ** 2
    total = (image.data.sum() * image.unit * pixel_area).to(u.g)
    assert total.value == pytest.approx(N * MASS * mass_g, rel=1e-3)


def test_sky_map_unit_from_file(cli, tmp_path):
    write_snapshot(tmp_path / "snap.hdf5", "gadget4")
    image = CCDData.read(render(cli, tmp_path, tmp_path / "snap.hdf5", "equirectangular"))
    assert image.unit == u.Unit("1e10 solMass / sr")


def test_scene_units_win_and_h_scaled_units_stay_unknown(cli, tmp_path):
    write_snapshot(tmp_path / "snap.hdf5", "gadget4")
    path = render(cli, tmp_path, tmp_path / "snap.hdf5", "orthographic", "output.bunit=solMass",
                  "output.length_unit=pc")
    assert fits.getheader(path)["BUNIT"] == "solMass pc-2"
    # A comoving run's masses and lengths are per h (0.7): 1.42e10 solMass,
    # 1.43 kpc, which no FITS unit string says, so no BUNIT rather than a
    # wrong one.
    write_snapshot(tmp_path / "comoving.hdf5", "gadget4", comoving=True)
    header = fits.getheader(render(cli, tmp_path, tmp_path / "comoving.hdf5", "orthographic"))
    assert "BUNIT" not in header and "CUNIT1" not in header
    with pytest.raises(ValueError, match="unit"):
        CCDData.read(tmp_path / "o.fits")
    # With h = 1 the comoving units are the file's own.
    write_snapshot(tmp_path / "h1.hdf5", "gadget4", comoving=True, hubble=1.0)
    assert fits.getheader(render(cli, tmp_path, tmp_path / "h1.hdf5", "orthographic"))["BUNIT"] == \
        "10**10 solMass kpc-2"
