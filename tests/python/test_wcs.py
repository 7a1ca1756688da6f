"""Image.header's WCS describes Image.data as returned (row 0 at the top):
single particles placed at known sky coordinates (l, b), or positions, are
found by astropy where the image has them, to 0.1 pixel."""
import numpy as np
import pytest
from astropy.io import fits

import orrery

AT_ORIGIN = {"position": [0, 0, 0], "look_at": [1, 0, 0], "up": [0, 0, 1]}
SKY = {
    "equirectangular": ({"projection": "equirectangular", **AT_ORIGIN}, (180, 90)),
    "hammer-aitoff": ({"projection": "hammer-aitoff", **AT_ORIGIN}, (180, 90)),
    "dome": ({"projection": "dome", **AT_ORIGIN}, (128, 128)),  # the zenith at l = b = 0
    "perspective": ({"projection": "perspective", "position": [0, 0, 0], "look_at": [1, 0.2, 0.1], "up": [0, 0, 1],
                     "fov": 60}, (96, 72)),
}
# (l, b) in degrees inside every view above; none symmetric about b = 0, so a
# flipped y would show.
LB = [(10, 20), (20, 8), (5, 22), (-10, 25), (17, -9)]


def direction(l, b, distance=10.0):
    """The position at (l, b) from the origin in the scene's axes (no
    observer: l = 0 along +x, l = 90 along +y, b = 90 along +z)."""
    l, b = np.radians(l), np.radians(b)
    return np.array([[np.cos(b) * np.cos(l), np.cos(b) * np.sin(l), np.sin(b)]]) * distance


def centroid(data):
    """(column, row) of the light in data: a CIC deposit's bilinear shares
    put it at the particle's projected position (the pixels' areas differ
    too little over 2 x 2 pixels to move it by 0.01 pixel here)."""
    w = np.nan_to_num(data)
    rows, cols = np.indices(w.shape)
    return (w * cols).sum() / w.sum(), (w * rows).sum() / w.sum()


@pytest.mark.parametrize("projection", list(SKY))
def test_particles_at_known_lb_found_by_astropy(projection):
    camera, (width, height) = SKY[projection]
    scene = orrery.Scene({"camera": camera, "image": {"width": width, "height": height}, "deposit": "cic"})
    for l, b in LB:
        image = scene.render(direction(l, b), 1.0)[0]
        assert isinstance(image.header, fits.Header)
        x, y = image.wcs.world_to_pixel_values(l, b)
        assert np.hypot(*(np.array(centroid(image.data)) - (x, y))) < 0.1, (l, b)
        found_l, found_b = image.wcs.pixel_to_world_values(*centroid(image.data))
        assert abs((found_l - l + 180) % 360 - 180) < 0.1 and abs(found_b - b) < 0.1


def test_orthographic_positions_found_by_astropy():
    """Linear axes: the offsets along the camera's right (+x here) and up (+y)."""
    camera = {"projection": "orthographic", "width": 8.0, "position": [0, 0, 10], "look_at": [0, 0, 0],
              "up": [0, 1, 0]}
    scene = orrery.Scene({"camera": camera, "image": {"width": 64, "height": 48}, "deposit": "cic"})
    for x, y in [(1.3, 2.2), (-3.1, 0.7), (2.0, -1.4)]:
        image = scene.render(np.array([[x, y, 0.0]]), 1.0)[0]
        assert np.allclose(image.wcs.pixel_to_world_values(*centroid(image.data)), (x, y), atol=0.1 * 8 / 64)


def test_header_wcs_is_the_files_flipped(tmp_path):
    """The file keeps FITS's bottom-up rows and its own WCS: the same sky
    position falls on the file's row and on the array's mirrored row."""
    camera, (width, height) = SKY["dome"]
    scene = orrery.Scene({"camera": camera, "image": {"width": width, "height": height}}, write=True,
                         output={"dir": str(tmp_path), "name": "d"})
    image = scene.render(direction(10, 20), 1.0)[0]
    from astropy.wcs import WCS

    file_header = fits.getheader(tmp_path / "d_0000.fits")
    x_file, y_file = WCS(file_header).world_to_pixel_values(10, 20)
    x, y = image.wcs.world_to_pixel_values(10, 20)
    assert x == pytest.approx(x_file) and y == pytest.approx(height - 1 - y_file)
