"""Structural checks of the case studies' outputs (tests/cli/test_case_studies.sh).

  check_case_studies.py band PANORAMA.fits
  check_case_studies.py views FACEON.fits EDGEON.fits FACEON.png
  check_case_studies.py parallax ANAGLYPH.png ANAGLYPH.fits
  check_case_studies.py cameras MODEL.txt SCENE.yaml VIEW:DX,DY,DZ ...

Each prints what it measured and exits 1 when a property does not hold."""
import sys

import numpy as np
from astropy.io import fits
from PIL import Image


def plane(path, name):
    """The first HDU whose name is `name` or starts with it (e.g. "left."),
    with the blank pixels outside a sky map's outline as 0."""
    with fits.open(path) as h:
        for u in h:
            un = u.name.upper()
            if un == name.upper() or (name.endswith(".") and un.startswith(name.upper())):
                return np.nan_to_num(np.asarray(u.data, dtype=float))
    raise SystemExit(f"{path}: no HDU {name}")


def band(path):
    """Future Sky's panorama: the Milky Way band lies along the equator, so
    the brightest rows are the middle ones and most light is near them."""
    y = plane(path, "Y")
    rows = y.sum(axis=1)
    h = len(rows)
    peak = int(np.argmax(rows))
    mid = slice(int(0.4 * h), int(0.6 * h) + 1)
    share = rows[mid].sum() / rows.sum()
    print(f"band: brightest row {peak} of {h}; middle fifth of rows holds {share:.2f} of the light")
    return abs(peak - (h - 1) / 2) <= 0.1 * h and share > 0.5


def lane(dusty, clear):
    """Future Sky with dust against without: a dark lane along the band (the
    rows at the equator keep a smaller share of their light than rows off
    it). Its colour is told, not checked: what light is left at the equator
    comes mostly from near, unreddened stars (each star's reddening is
    checked in tests/unit/test_dust.c)."""
    yd, yc = plane(dusty, "Y"), plane(clear, "Y")
    zd, zc = plane(dusty, "Z"), plane(clear, "Z")
    h = yd.shape[0]
    mid = slice(int(0.45 * h), int(0.55 * h) + 1)
    off = np.r_[int(0.15 * h):int(0.3 * h), int(0.7 * h):int(0.85 * h)]
    kept_mid = yd[mid].sum() / yc[mid].sum()
    kept_off = yd[off].sum() / yc[off].sum()
    red_d, red_c = zd[mid].sum() / yd[mid].sum(), zc[mid].sum() / yc[mid].sum()
    print(f"lane: equator keeps {kept_mid:.3f} of its light, rows off it {kept_off:.3f}; "
          f"Z/Y at the equator {red_d:.3f} with dust, {red_c:.3f} without")
    return kept_mid < 0.7 * kept_off


def moments(img):
    """Second moments (xx, yy) of an image's light about its centroid,
    x along the columns (rightward), y along the rows."""
    yy, xx = np.mgrid[: img.shape[0], : img.shape[1]]
    w = img.sum()
    cx, cy = (img * xx).sum() / w, (img * yy).sum() / w
    return (img * (xx - cx) ** 2).sum() / w, (img * (yy - cy) ** 2).sum() / w, cx, cy


def views(faceon, edgeon, faceon_png):
    """Spiral Metamorphosis: the face-on disc is round, the edge-on one
    flat and horizontal; old red stars gather in the centre."""
    fxx, fyy, _, _ = moments(plane(faceon, "Y"))
    exx, eyy, _, _ = moments(plane(edgeon, "Y"))
    round_ratio, flat_ratio = max(fxx, fyy) / min(fxx, fyy), exx / eyy
    rgb = np.asarray(Image.open(faceon_png).convert("RGB"), dtype=float)
    lum = rgb.sum(axis=2)
    _, _, cx, cy = moments(lum)
    yy, xx = np.mgrid[: lum.shape[0], : lum.shape[1]]
    r = np.hypot(xx - cx, yy - cy)
    scale = 0.5 * lum.shape[1]
    inner, outer = r < 0.03 * scale, (r > 0.08 * scale) & (r < 0.25 * scale)
    rb_in = rgb[inner, 0].sum() / rgb[inner, 2].sum()
    rb_out = rgb[outer, 0].sum() / rgb[outer, 2].sum()
    print(f"views: face-on moment ratio {round_ratio:.2f}; edge-on xx/yy {flat_ratio:.1f}; "
          f"R/B centre {rb_in:.3f}, outside {rb_out:.3f}")
    return round_ratio < 1.3 and flat_ratio > 4 and rb_in > rb_out * 1.05


def parallax(png, fits_path):
    """The anaglyph: the disc's near side (the lower half of the picture,
    the camera being above the disc) is in front of the zero-parallax
    plane, so its red (left-eye) image lies right of its cyan one, and the
    far side (upper half) the other way round (docs/stereo.md)."""
    rgb = np.asarray(Image.open(png).convert("RGB"), dtype=float)
    left, right = plane(fits_path, "left."), plane(fits_path, "right.")
    h = rgb.shape[0]
    ok = True
    for name, rows_png, sign in (("near (lower)", slice(h // 2 + 2, h), +1), ("far (upper)", slice(0, h // 2 - 2), -1)):
        red, cyan = rgb[rows_png, :, 0], rgb[rows_png, :, 1:].sum(axis=2)
        dx_png = moments(red)[2] - moments(cyan)[2]
        # FITS rows run bottom-up: the lower half of the picture is rows 0..h/2.
        rows_fits = slice(0, h // 2 - 2) if sign > 0 else slice(h // 2 + 2, h)
        dx_fits = moments(left[rows_fits])[2] - moments(right[rows_fits])[2]
        print(f"parallax {name}: red - cyan {dx_png:+.2f} px; left eye - right eye {dx_fits:+.2f} px")
        ok = ok and sign * dx_png > 0.2 and sign * dx_fits > 0.2
    return ok


def cameras(model, scene, *expected):
    """Spiral Metamorphosis in-situ: every camera looks at the model's
    centre of mass (mass-weighted mean of all particles, from `orrery model`
    output) and sits at the given offset (kpc) from it. A view named "-" is
    the scene's own camera (no views:)."""
    import yaml

    table = np.loadtxt(model, skiprows=1, usecols=(0, 1, 2, 3))
    com = (table[:, :3] * table[:, 3:4]).sum(axis=0) / table[:, 3].sum()
    with open(scene) as f:
        doc = yaml.safe_load(f)
    ok = True
    for item in expected:
        name, offset = item.split(":")
        cam = doc["camera"] if name == "-" else doc["views"][name]["camera"]
        want = np.array([float(v) for v in offset.split(",")])
        look = np.linalg.norm(np.array(cam["look_at"]) - com)
        place = np.linalg.norm(np.array(cam["position"]) - com - want)
        print(f"cameras {name}: look_at {look:.2f} kpc from the centre of mass {np.round(com, 1)}, "
              f"position {place:.2f} kpc from the centre of mass + {want}")
        ok = ok and look < 2.0 and place < 2.0
    return ok


if __name__ == "__main__":
    checks = {"band": band, "lane": lane, "views": views, "parallax": parallax, "cameras": cameras}
    if len(sys.argv) < 3 or sys.argv[1] not in checks:
        raise SystemExit(__doc__)
    sys.exit(0 if checks[sys.argv[1]](*sys.argv[2:]) else 1)
