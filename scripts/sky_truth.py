#!/usr/bin/env python3
"""Measures a rendered sky against the real one (issue 40): the figures of
a sky map and the list of the stars drawn on it, beside the real sky's.

    scripts/sky_truth.py SKY.fits STARS.fits [--plane Y] [--band-map CAR.fits]
                         [--reference TABLE.tsv] [--resolved TABLE.tsv] [--json OUT.json] [--check]

SKY.fits: a sky map with a GLON/GLAT WCS (equirectangular or Hammer-Aitoff)
whose plane (HDU named by --plane, default the one named Y, else the
primary) holds V-band surface brightness in S10 units: the light of V = 10
stars per square degree (Leinert et al. 1998, A&AS 127, 1, sect. 2; times
--scale if it holds something else).
STARS.fits: a binary table with columns L, B (deg), V (apparent magnitude),
BV and PARTICLE (int64): the stars drawn on it.

Figures (the real sky's from data/sky/star_counts.tsv, made from the
Hipparcos/Tycho-2 catalogues by scripts/gen_sky_counts.py):

- the whole sky's integrated V: 10 - 2.5 log10(sum of pixel x solid angle in deg^2);
- the share of that light in the 20 brightest listed stars, the number of
  stars brighter than V = 6.5 and their share, the share of those brighter
  than 10.5;
- N(< V) for V = 0 .. 8 over the real sky's (to the list's own limit);
- the band's smoothness (on an equirectangular map, the plane itself or
  --band-map): inside |b| < 8, 30 < |l| < 150 deg, each pixel over its
  Gaussian-smoothed mean (sigma 1 deg, wrapping in l), the median and the
  90th/10th percentile ratio;
- the surface brightness around the Galactic poles and (l, b) = (0, 0),
  (90, 0), (180, 0): the mean within --radius deg, without the listed
  stars brighter than --exclude-brighter (their light is taken off), in
  S10, V mag/arcsec^2 and W m^-2 sr^-1 um^-1, beside a reference table's
  values if --reference gives one (columns name, l, b, S10; Leinert et
  al. 1998's integrated starlight: data/sky/leinert1998_isl.tsv);
- the resolved starlight: the light of the listed stars 6.5 <= V < 10.5
  per square degree within 5 deg of the poles and of four points in the
  plane, and in zones of |b|, over the real sky's (data/sky/resolved_light.tsv,
  from the same catalogues; --resolved). It needs a list complete to
  V = 10.5: one drawn with stars.limit >= 10.5 (the list's own limit is
  its faintest MV + 5 log10(DIST / 10 pc), V before the dust).

--check exits 1 if a measured figure is outside issue 40's bars (listed in
BARS below); a figure that cannot be measured is said so and not checked.
"""
import argparse
import json
import os
import sys

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests", "cli"))
from gen_sky_counts import RESOLVED_V, read_resolved, read_table, resolved_light  # noqa: E402
from solid_angle import solid_angles  # noqa: E402

DEFAULT_COUNTS = os.path.join(HERE, "..", "data", "sky", "star_counts.tsv")
DEFAULT_RESOLVED = os.path.join(HERE, "..", "data", "sky", "resolved_light.tsv")
DEG2_PER_SR = (180 / np.pi) ** 2
# V = 0 in f_lambda: 363.1e-11 erg cm^-2 s^-1 A^-1 (Bessell, Castelli & Plez 1998, A&A 333, 231,
# table A2) = 3.631e-8 W m^-2 um^-1; one S10 spreads a V = 10 star over a square degree.
S10_W_M2_SR_UM = 3.631e-8 * 1e-4 * DEG2_PER_SR
S10_MAG_ARCSEC2 = 10 + 2.5 * np.log10(3600.0 ** 2)  # S10 = 1 is V = 27.78 mag/arcsec^2
WHOLE_SKY_V = -6.6  # issue 40's whole-sky integrated starlight
POINTS = {"NGP": (0.0, 90.0), "SGP": (0.0, -90.0), "l=0": (0.0, 0.0), "l=90": (90.0, 0.0), "l=180": (180.0, 0.0)}
COUNT_MAGS = np.arange(0, 9)
# Issue 40's bars: figure -> (low, high)
BARS = {
    "V_total": (WHOLE_SKY_V - 0.3, WHOLE_SKY_V + 0.3),
    "share_20_brightest": (0.03, 0.06),
    "n_brighter_6.5": (6000, 12000),
    "share_brighter_6.5": (0.15, 0.30),
    "share_brighter_10.5": (0.35, 0.65),
    "count_ratio": (1 / 1.5, 1.5),
    "band_median": (0.85, np.inf),
    "band_p90_p10": (0, 3.0),
    "reference_ratio": (0.5, 2.0),
    "resolved_ratio": (0.5, 2.0),
}


class InputError(ValueError):
    """Input that cannot be measured, with the file and the field named."""


def v_flux(v):
    """Flux in units of a V = 0 star."""
    return 10 ** (-0.4 * np.asarray(v, dtype=float))


def read_plane(path, plane=None):
    """(data, header) of the named image HDU; default the one named Y, else
    the primary. NaN (off the map) reads as 0."""
    try:
        hdul = fits.open(path)
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: not a readable FITS file ({e})")
    with hdul:
        names = [h.name.upper() for h in hdul]
        if plane is None:
            index = names.index("Y") if "Y" in names else 0
        elif plane.upper() in names:
            index = names.index(plane.upper())
        else:
            raise InputError(f"{path}: no HDU named {plane!r} (there are {names})")
        hdu = hdul[index]
        if hdu.data is None or hdu.data.ndim != 2:
            raise InputError(f"{path}: HDU {names[index]!r} is not a 2-D image")
        header = hdu.header.copy()
        for key in ("CTYPE1", "CTYPE2"):
            if not str(header.get(key, "")).startswith(("GLON", "GLAT")):
                raise InputError(f"{path}: HDU {names[index]!r} {key} = {header.get(key)!r}, not GLON/GLAT")
        return np.nan_to_num(np.asarray(hdu.data, dtype=float)), header


def read_stars(path):
    """The star list: dict of arrays L, B, V, BV, PARTICLE."""
    try:
        hdul = fits.open(path)
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: not a readable FITS file ({e})")
    with hdul:
        tables = [h for h in hdul if isinstance(h, fits.BinTableHDU)]
        if not tables:
            raise InputError(f"{path}: no binary table")
        data = tables[0].data
        have = [c.upper() for c in tables[0].columns.names]
        stars = {}
        for col in ("L", "B", "V", "BV", "PARTICLE"):
            if col not in have:
                raise InputError(f"{path}: the star table has no column {col} (it has {have})")
            stars[col] = np.asarray(data.field(have.index(col)))
        for col in ("MV", "DIST"):  # orrery's lists have them; a catalogue need not
            if col in have:
                stars[col] = np.asarray(data.field(have.index(col)), dtype=float)
    if not np.all(np.isfinite(stars["V"])):
        raise InputError(f"{path}: column V holds a value that is not finite")
    return stars


def list_limit(stars):
    """The faintest V before the dust the list holds (orrery lists every
    star to stars.limit, dimmed or not), or None when the list has no MV
    and DIST (a catalogue: complete to its own limit)."""
    if "MV" not in stars or "DIST" not in stars or len(stars["V"]) == 0:
        return None
    dist = np.maximum(stars["DIST"], 1e-3)
    return float(np.max(stars["MV"] + 5 * np.log10(dist / 10.0)))


def list_reaches(limit, v):
    """Whether a list drawn to limit (None: a catalogue) holds every star
    brighter than v (to the 0.01 mag the limit is read to)."""
    return limit is None or limit >= v - 0.01


def resolved_figures(stars, table_path):
    """The listed stars' resolved light by region over the real sky's, or
    (None, why) when the list stops short of RESOLVED_V[1]."""
    limit = list_limit(stars)
    if not list_reaches(limit, RESOLVED_V[1]):
        return None, (f"the list stops at V = {limit:.2f} (before the dust); "
                      f"render with stars.limit >= {RESOLVED_V[1]:g}")
    real = read_resolved(table_path)
    mine = resolved_light(stars["L"], stars["B"], stars["V"], stars["V"])
    out = {}
    for name, (s10, n) in mine.items():
        if name not in real:
            raise InputError(f"{table_path}: no row for region {name!r}")
        out[name] = {"S10": s10, "stars": n, "real_S10": real[name],
                     "ratio": s10 / real[name] if real[name] > 0 else None}
    return out, None


def pixel_areas_deg2(header):
    """Each pixel's solid angle in deg^2, as orrery takes it (frame/projection.h,
    orr_pixel_measure): a band of latitude on an equirectangular map, the
    same for every pixel of an equal-area Hammer-Aitoff map (a pixel the
    rim cuts counts whole: the light of its part off the map is folded onto
    it), else from the WCS alone (tests/cli/solid_angle.py, 2 x 2 cells a
    pixel)."""
    wcs = WCS(header)
    w, h = header["NAXIS1"], header["NAXIS2"]
    projection = header["CTYPE1"][-3:]
    if projection == "CAR":
        _, b_edges = wcs.all_pix2world(np.zeros(h + 1), np.arange(h + 1) - 0.5, 0)
        dl = abs(wcs.pixel_scale_matrix[0, 0])
        rows = np.radians(dl) * np.abs(np.diff(np.sin(np.radians(np.clip(b_edges, -90, 90))))) * DEG2_PER_SR
        return np.repeat(rows[:, None], w, axis=1)
    if projection == "AIT":
        return np.full((h, w), abs(np.linalg.det(wcs.pixel_scale_matrix)))
    return solid_angles(header, n=2) * DEG2_PER_SR


def pixel_directions(header):
    """(l, b) in degrees of each pixel's centre (NaN off the map)."""
    w, h = header["NAXIS1"], header["NAXIS2"]
    jj, ii = np.mgrid[0:h, 0:w]
    l, b = WCS(header).all_pix2world(ii, jj, 0)
    return l, b


def angular_distance(l1, b1, l2, b2):
    l1, b1, l2, b2 = (np.radians(x) for x in (l1, b1, l2, b2))
    c = np.sin(b1) * np.sin(b2) + np.cos(b1) * np.cos(b2) * np.cos(l1 - l2)
    return np.degrees(np.arccos(np.clip(c, -1, 1)))


def star_shares(v, total_v0, limit=None):
    """The star list's figures against the sky's total light (V = 0 units);
    the share brighter than 10.5 None when the list stops short of it."""
    v = np.sort(np.asarray(v, dtype=float))
    flux = v_flux(v)
    naked = v < 6.5
    return {
        "share_20_brightest": float(flux[:20].sum() / total_v0),
        "n_brighter_6.5": int(naked.sum()),
        "share_brighter_6.5": float(flux[naked].sum() / total_v0),
        "share_brighter_10.5": float(flux[v < 10.5].sum() / total_v0) if list_reaches(limit, 10.5) else None,
    }


def count_ratios(v, table, limit=None):
    """N(< V) of the list over the real sky's, V = 0 .. 8; None past the
    list's own limit (it does not hold those stars)."""
    out = {}
    for m in COUNT_MAGS:
        real = table["N"][np.isclose(table["V_lim"], m)]
        if real.size == 0:
            raise InputError(f"the counts table has no row V_lim = {m}")
        if not list_reaches(limit, m):
            out[f"{m:g}"] = {"model": None, "real": int(real[0]), "ratio": None}
            continue
        mine = int(np.sum(np.asarray(v) < m))
        out[f"{m:g}"] = {"model": mine, "real": int(real[0]), "ratio": mine / real[0] if real[0] else None}
    return out


def band_smoothness(data, header):
    """Issue 40's band statistic on an equirectangular map covering all
    longitudes; None (with the reason) for any other map."""
    from scipy.ndimage import gaussian_filter

    if not (header["CTYPE1"].endswith("-CAR") and header["CTYPE2"].endswith("-CAR")):
        return None, "needs an equirectangular (CAR) map: pass --band-map"
    wcs = WCS(header)
    dl, db = (abs(float(x)) for x in np.diag(wcs.pixel_scale_matrix))
    if abs(header["NAXIS1"] * dl - 360) > 1e-6 * 360:
        return None, f"the map spans {header['NAXIS1'] * dl:g} deg of longitude, not 360 (the smoothing wraps in l)"
    smooth = gaussian_filter(data, sigma=(1.0 / db, 1.0 / dl), mode=("nearest", "wrap"), truncate=4.0)
    l, b = pixel_directions(header)
    lw = (l + 180) % 360 - 180
    inside = (np.abs(b) < 8) & (np.abs(lw) > 30) & (np.abs(lw) < 150) & (smooth > 0)
    if not inside.any():
        return None, "no lit pixel in |b| < 8, 30 < |l| < 150"
    r = data[inside] / smooth[inside]
    p10, p90 = np.percentile(r, [10, 90])
    return {"median": float(np.median(r)), "p90_p10": float(p90 / p10) if p10 > 0 else float("inf"),
            "pixel_deg": [dl, db], "pixels": int(inside.sum())}, None


def surface_brightness(data, areas, header, stars, radius, cut):
    """Mean S10 around each of POINTS, the listed stars brighter than cut
    taken off."""
    l, b = pixel_directions(header)
    bright = stars["V"] < cut
    out = {}
    for name, (l0, b0) in POINTS.items():
        near = np.isfinite(l) & (angular_distance(l, b, l0, b0) <= radius) & (areas > 0)
        if not near.any():
            out[name] = None
            continue
        light = float(np.sum(data[near] * areas[near]))
        in_cap = bright & (angular_distance(stars["L"], stars["B"], l0, b0) <= radius)
        taken = float(np.sum(v_flux(stars["V"][in_cap] - 10.0)))
        s10 = (light - taken) / float(np.sum(areas[near]))
        out[name] = {"S10": s10, "stars_taken_off": int(in_cap.sum()),
                     "mag_arcsec2": S10_MAG_ARCSEC2 - 2.5 * np.log10(s10) if s10 > 0 else None,
                     "W_m2_sr_um": s10 * S10_W_M2_SR_UM}
    return out


def read_reference(path):
    """{name: S10} from a table with columns name, l, b, S10 ('#' comments)."""
    ref = {}
    with open(path) as f:
        for line in f:
            w = line.split("\t")
            if line.startswith("#") or w[0] == "name" or not line.strip():
                continue
            if len(w) < 4 or w[0] not in POINTS:
                raise InputError(f"{path}: expected name (one of {list(POINTS)}), l, b, S10: {line.strip()!r}")
            ref[w[0]] = float(w[3])
    return ref


def measure(sky, stars, counts, plane=None, scale=1.0, band_map=None, band_plane=None,
            radius=3.0, cut=6.5, reference=None, resolved=DEFAULT_RESOLVED):
    """All the figures, as a dict."""
    data, header = read_plane(sky, plane)
    data = data * scale
    areas = pixel_areas_deg2(header)
    total_s10 = float(np.sum(data * areas))
    if not total_s10 > 0:
        raise InputError(f"{sky}: the plane's light sums to {total_s10}, not a positive number")
    total_v0 = total_s10 * 1e-4
    list_ = read_stars(stars)
    table = read_table(counts)
    fig = {"sky": sky, "stars": stars, "BUNIT": str(header.get("BUNIT", "")), "scale": scale,
           "V_total": 10 - 2.5 * np.log10(total_s10), "n_stars": int(len(list_["V"]))}
    fig["list_limit"] = list_limit(list_)
    fig.update(star_shares(list_["V"], total_v0, fig["list_limit"]))
    fig["counts"] = count_ratios(list_["V"], table, fig["list_limit"])
    if band_map:
        bdata, bheader = read_plane(band_map, band_plane)
        fig["band"], why = band_smoothness(bdata * scale, bheader)
    else:
        fig["band"], why = band_smoothness(data, header)
    if why:
        fig["band_not_measured"] = why
    fig["surface"] = surface_brightness(data, areas, header, list_, radius, cut)
    fig["surface_radius_deg"], fig["surface_exclude_brighter"] = radius, cut
    fig["resolved"], why = resolved_figures(list_, resolved)
    if why:
        fig["resolved_not_measured"] = why
    if reference:
        ref = read_reference(reference)
        for name, s in fig["surface"].items():
            if s and name in ref:
                s["reference_S10"] = ref[name]
                s["ratio"] = s["S10"] / ref[name]
    return fig


def failures(fig):
    """The measured figures outside BARS, as strings."""
    bad = []

    def bar(key, value, label=None):
        lo, hi = BARS[key]
        if value is None or not (lo <= value <= hi):
            bad.append(f"{label or key} = {value} outside [{lo:g}, {hi:g}]")

    for key in ("V_total", "share_20_brightest", "n_brighter_6.5", "share_brighter_6.5", "share_brighter_10.5"):
        if fig[key] is not None:
            bar(key, fig[key])
    for m, c in fig["counts"].items():
        if c["model"] is not None:
            bar("count_ratio", c["ratio"], f"N(<{m}) ratio")
    if fig["band"]:
        bar("band_median", fig["band"]["median"])
        bar("band_p90_p10", fig["band"]["p90_p10"])
    for name, s in fig["surface"].items():
        if s and "ratio" in s:
            bar("reference_ratio", s["ratio"], f"{name} surface brightness over the reference")
    for name, r in (fig["resolved"] or {}).items():
        bar("resolved_ratio", r["ratio"], f"{name} resolved light over the real sky's")
    return bad


def count_text(m, c):
    if c["model"] is None:
        return f"{m}: past the list"
    return f"{m}: {c['model']}/{c['real']}" + (f"={c['ratio']:.2f}" if c["ratio"] is not None else "")


def report(fig):
    lines = []
    if "S10" not in fig["BUNIT"].upper() and fig["scale"] == 1.0:
        lines.append(f"warning: the plane's BUNIT is {fig['BUNIT']!r}, not S10; the figures take it as S10"
                     " (--scale converts)")
    lines += [f"whole sky: V = {fig['V_total']:.3f} (real {WHOLE_SKY_V})   stars listed: {fig['n_stars']}",
             f"20 brightest: {100 * fig['share_20_brightest']:.2f} % of the light",
             f"brighter than 6.5: {fig['n_brighter_6.5']} stars, {100 * fig['share_brighter_6.5']:.2f} %",
             "brighter than 10.5: " + (f"{100 * fig['share_brighter_10.5']:.2f} %"
                                       if fig["share_brighter_10.5"] is not None else "past the list"),
             "N(<V): " + "  ".join(count_text(m, c) for m, c in fig["counts"].items())]
    if fig["band"]:
        lines.append(f"band: median {fig['band']['median']:.3f}, p90/p10 {fig['band']['p90_p10']:.2f}"
                     f" ({fig['band']['pixels']} pixels)")
    else:
        lines.append(f"band: not measured ({fig['band_not_measured']})")
    for name, s in fig["surface"].items():
        if s is None:
            lines.append(f"{name}: not on the map")
            continue
        mag = f"{s['mag_arcsec2']:.2f} mag/arcsec^2" if s["mag_arcsec2"] is not None else "no light"
        ref = f", reference {s['reference_S10']:g}, ratio {s['ratio']:.2f}" if "ratio" in s else ""
        lines.append(f"{name}: {s['S10']:.1f} S10 = {mag} = {s['W_m2_sr_um']:.3g} W m^-2 sr^-1 um^-1"
                     f" ({s['stars_taken_off']} stars taken off{ref})")
    lo, hi = RESOLVED_V
    if fig["resolved"]:
        lines.append(f"resolved light ({lo:g} <= V < {hi:g}), S10, listed / real sky = ratio:")
        for name, r in fig["resolved"].items():
            ratio = f"{r['ratio']:.2f}" if r["ratio"] is not None else "-"
            lines.append(f"  {name}: {r['S10']:.2f} / {r['real_S10']:.2f} = {ratio}")
    else:
        lines.append(f"resolved light ({lo:g} <= V < {hi:g}): not measured ({fig['resolved_not_measured']})")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sky")
    ap.add_argument("stars")
    ap.add_argument("--plane", help="HDU name of the luminance plane (default: Y, else the primary)")
    ap.add_argument("--scale", type=float, default=1.0, help="factor taking the plane to S10 (default 1)")
    ap.add_argument("--band-map", help="an equirectangular map for the band's smoothness (default: SKY if CAR)")
    ap.add_argument("--band-plane", help="its HDU name (default as --plane)")
    ap.add_argument("--counts", default=DEFAULT_COUNTS, help="the real sky's counts (data/sky/star_counts.tsv)")
    ap.add_argument("--radius", type=float, default=3.0, help="radius in deg of the surface-brightness caps")
    ap.add_argument("--exclude-brighter", type=float, default=6.5,
                    help="listed stars brighter than this are taken off the caps' light (default 6.5)")
    ap.add_argument("--reference", help="reference surface brightness: TSV name, l, b, S10 "
                    "(Leinert et al. 1998: data/sky/leinert1998_isl.tsv)")
    ap.add_argument("--resolved", default=DEFAULT_RESOLVED,
                    help="the real sky's resolved light by region (data/sky/resolved_light.tsv)")
    ap.add_argument("--json", help="also write the figures here")
    ap.add_argument("--check", action="store_true", help="exit 1 if a measured figure is outside issue 40's bars")
    args = ap.parse_args(argv)
    try:
        fig = measure(args.sky, args.stars, args.counts, args.plane, args.scale, args.band_map,
                      args.band_plane or args.plane, args.radius, args.exclude_brighter, args.reference,
                      args.resolved)
    except (InputError, OSError, ValueError) as e:
        sys.exit(f"sky_truth: {e}")
    print(report(fig))
    bad = failures(fig)
    fig["outside_bars"] = bad
    if args.json:
        tmp = args.json + ".tmp"
        with open(tmp, "w") as f:
            json.dump(fig, f, indent=1, default=float)
        os.replace(tmp, args.json)
    if args.check:
        for b in bad:
            print("OUTSIDE: " + b)
        if bad:
            sys.exit(1)
        print("sky_truth: every measured figure is inside issue 40's bars")


if __name__ == "__main__":
    main()
