"""Each pixel's solid angle, from a FITS header's WCS alone (astropy's
wcslib), independently of orrery's own formulas: the pixel is cut into
n x n cells, each the spherical quadrilateral of its corners' world
directions, whose area is that of two spherical triangles (Van Oosterom &
Strackee 1983). orrery's sky maps hold flux per steradian; times these,
flux per pixel."""
import numpy as np
from astropy.wcs import WCS


def unit(l_deg, b_deg):
    l, b = np.radians(l_deg), np.radians(b_deg)
    return np.stack([np.cos(b) * np.cos(l), np.cos(b) * np.sin(l), np.sin(b)], axis=-1)


def triangle_area(a, b, c):
    num = np.abs(np.einsum("...i,...i", a, np.cross(b, c)))
    den = 1 + np.einsum("...i,...i", a, b) + np.einsum("...i,...i", b, c) + np.einsum("...i,...i", c, a)
    return 2 * np.arctan2(num, den)


def grid_areas(wcs, u, v):
    """Areas of the cells of the pixel-coordinate grid u x v (1-D edges);
    NaN for a cell with a corner off the map."""
    uu, vv = np.meshgrid(u, v)
    l, b = wcs.all_pix2world(uu, vv, 0)
    e = unit(l, b)
    a, bb, c, d = e[:-1, :-1], e[:-1, 1:], e[1:, 1:], e[1:, :-1]
    return triangle_area(a, bb, c) + triangle_area(a, c, d)


def whole_pixels(cells, h, w, n):
    """Each pixel's solid angle from its n x n cells. A pixel the map's rim
    cuts counts whole, as orrery takes it (the light of its part off the map
    is folded onto it): its cells on the map, scaled up to n x n."""
    cells = cells.reshape(h, n, w, n)
    on_map = np.isfinite(cells).sum(axis=(1, 3))
    total = np.nansum(cells, axis=(1, 3))
    return np.where(on_map > 0, total * (n * n) / np.maximum(on_map, 1), 0.0)


def pixel_solid_angle(wcs, i, j, n=8):
    """Pixel (i, j)'s solid angle (0-based FITS pixel indices)."""
    cells = grid_areas(wcs, np.linspace(i - 0.5, i + 0.5, n + 1), np.linspace(j - 0.5, j + 0.5, n + 1))
    return float(whole_pixels(cells, 1, 1, n)[0, 0])


def solid_angles(header, n=4):
    """Every pixel's solid angle, in the FITS array's order (row 0 at the
    bottom); 0 off the map."""
    wcs = WCS(header)
    w, h = header["NAXIS1"], header["NAXIS2"]
    cells = grid_areas(wcs, np.linspace(-0.5, w - 0.5, n * w + 1), np.linspace(-0.5, h - 0.5, n * h + 1))
    return whole_pixels(cells, h, w, n)
