#!/usr/bin/env python3
"""Writes data/sky/star_counts.tsv: the real sky's cumulative star counts
N(< V) and the summed light of those stars, for V = -1.5 ... 10.5 in steps
of 0.5, from the Hipparcos/Tycho-2 star catalogues Debian's stellarium-data
package ships (read by scripts/stellarium_stars.py, which says how).

    apt-get install stellarium-data
    scripts/gen_sky_counts.py > data/sky/star_counts.tsv
    scripts/gen_sky_counts.py --check data/sky/star_counts.tsv   # exit 1 if it differs
    scripts/gen_sky_counts.py --star-list real_sky.fits   # the catalogues as a star list
    scripts/gen_sky_counts.py --resolved > data/sky/resolved_light.tsv
    scripts/gen_sky_counts.py --resolved --check data/sky/resolved_light.tsv

--resolved writes the real sky's resolved starlight by region instead: the
light of the stars 6.5 <= V < 10.5 (those the naked eye does not see, but
the catalogues hold completely) per square degree, in S10, within 5 deg of
the Galactic poles and of four points in the plane, and in zones of |b|.
Issue 40 asks for the band's surface brightness beside Leinert et al.'s
(1998) integrated starlight; their tables are not at hand, so this is the
part of it the catalogues measure: about a third of all the starlight, and
the stars that set how the light climbs from the poles to the band.

The catalogue stores each V as the lower edge of its 0.05-mag step, and
the table's limits are multiples of 0.05, so N(< V) counts exactly the
stars whose catalogue V is below the limit. Each star's light is taken at
the middle of its step (its V + 0.025), in units of a V = 0 star.
"""
import argparse
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stellarium_stars  # noqa: E402

LIMITS = np.arange(-1.5, 10.5 + 1e-9, 0.5)
COMPLETE_TO = 10.5  # the shipped files hold the stars brighter than this (stars_0 .. stars_3)
# The resolved light's stars and regions: caps (name, l, b) of CAP_RADIUS
# degrees, and zones of |b| (both hemispheres together), degrees.
RESOLVED_V = (6.5, 10.5)
CAP_RADIUS = 5.0
CAPS = (("NGP", 0.0, 90.0), ("SGP", 0.0, -90.0), ("l=0", 0.0, 0.0), ("l=90", 90.0, 0.0),
        ("l=180", 180.0, 0.0), ("l=270", 270.0, 0.0))
ZONES = ((0, 5), (5, 10), (10, 20), (20, 30), (30, 60), (60, 90))
DEG2_PER_SR = (180 / np.pi) ** 2


def package_version():
    """stellarium-data's Debian version, or 'unknown' without dpkg."""
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "stellarium-data"],
                             capture_output=True, text=True, check=True)
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def count_rows(edges, middles):
    """(limit, N(< limit), summed flux in V = 0 units) for each limit."""
    order = np.argsort(edges, kind="stable")
    edges, flux = edges[order], 10 ** (-0.4 * middles[order])
    cumulative = np.concatenate([[0.0], np.cumsum(flux)])
    rows = []
    for limit in LIMITS:
        n = int(np.searchsorted(edges, limit - 1e-6, side="right"))
        rows.append((limit, n, cumulative[n]))
    return rows


def table_text(stars_dir):
    cat = stellarium_stars.read_all(stars_dir)
    files = cat["files"]
    rows = count_rows(cat["V"], cat["V_mid"])
    names = ", ".join(f"{os.path.basename(f)} ({os.path.getsize(f)} bytes)" for f in files)
    lines = [
        "# The real sky's star counts: N(< V) over the whole sky and the summed light of those stars.",
        "# Source: the star catalogues of Debian's stellarium-data package, version " + package_version() + ",",
        "#   files " + names + ";",
        "#   built by Stellarium (util/MakeCombinedCatalogue.C, util/ParseHip.C) from Hipparcos (ESA 1997,",
        "#   CDS I/239) and Tycho-2 (Hog et al. 2000, A&A 355, L27; CDS I/259). Read by scripts/stellarium_stars.py,",
        "#   written by scripts/gen_sky_counts.py (do not edit by hand).",
        "# V is Johnson V: Hipparcos's V (field H5) where given, else V = VT - 0.090 (BT - VT)",
        "#   (ESA 1997, vol. 1, sect. 1.3, eq. 1.3.20), stored in steps of 0.05 mag (the lower edge);",
        "#   a star's light is taken at the middle of its step.",
        f"# Complete to V = {COMPLETE_TO}: the shipped files hold every catalogue star brighter than that",
        "#   (fainter ones are in stars_4 .. stars_8, not packaged); Tycho-2 itself is about 99 % complete",
        "#   to V ~ 11.0 and 90 % to V ~ 11.5 (Hog et al. 2000). Close doubles it does not resolve count once.",
        "# Columns: V_lim, N(< V_lim), flux(< V_lim) in units of a V = 0 star, that flux as a magnitude.",
        "V_lim\tN_brighter\tflux_V0\tV_sum",
    ]
    for limit, n, flux in rows:
        v_sum = f"{-2.5 * np.log10(flux):.4f}" if flux > 0 else "inf"
        lines.append(f"{limit:.1f}\t{n}\t{flux:.6g}\t{v_sum}")
    return "\n".join(lines) + "\n"


def read_table(path):
    """The committed table: arrays V_lim, N, flux (comment lines skipped)."""
    rows = []
    try:
        with open(path) as f:
            lines = f.readlines()
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text table")
    for line in lines:
        if line.startswith("#") or line.startswith("V_lim"):
            continue
        w = line.split("\t")
        try:
            rows.append((float(w[0]), int(w[1]), float(w[2])))
        except (ValueError, IndexError):
            raise ValueError(f"{path}: expected V_lim, N, flux, V_sum separated by tabs: {line.strip()!r}")
    if not rows:
        raise ValueError(f"{path}: no rows")
    v, n, flux = (np.array(c) for c in zip(*rows))
    return {"V_lim": v, "N": n, "flux": flux}


def resolved_regions():
    """[(name, kind, a, b)]: caps ('cap', l, b) and zones ('zone', |b| from, to)."""
    return [(n, "cap", l, b) for n, l, b in CAPS] + [(f"|b| {lo}-{hi}", "zone", lo, hi) for lo, hi in ZONES]


def region_area_deg2(kind, a, b):
    if kind == "cap":
        return 2 * np.pi * (1 - np.cos(np.radians(CAP_RADIUS))) * DEG2_PER_SR
    return 2 * 2 * np.pi * (np.sin(np.radians(b)) - np.sin(np.radians(a))) * DEG2_PER_SR


def in_region(l, b, kind, a, c):
    """Mask of the stars at (l, b) (deg) inside the region."""
    l, b = np.asarray(l, dtype=float), np.asarray(b, dtype=float)
    if kind == "zone":
        return (np.abs(b) >= a) & ((np.abs(b) < c) | (c >= 90))
    cos_d = (np.sin(np.radians(b)) * np.sin(np.radians(c))
             + np.cos(np.radians(b)) * np.cos(np.radians(c)) * np.cos(np.radians(l - a)))
    return cos_d >= np.cos(np.radians(CAP_RADIUS))


def resolved_light(l, b, v_select, v_light):
    """{region name: (S10, stars)}: the light of the stars RESOLVED_V[0] <=
    v_select < RESOLVED_V[1] (their light from v_light) per square degree
    of each region, in V = 10 stars per square degree."""
    chosen = (v_select >= RESOLVED_V[0]) & (v_select < RESOLVED_V[1])
    l, b = np.asarray(l)[chosen], np.asarray(b)[chosen]
    flux10 = 10 ** (-0.4 * (np.asarray(v_light, dtype=float)[chosen] - 10))
    out = {}
    for name, kind, a, c in resolved_regions():
        inside = in_region(l, b, kind, a, c)
        out[name] = (float(flux10[inside].sum() / region_area_deg2(kind, a, c)), int(inside.sum()))
    return out


def resolved_text(stars_dir):
    cat = stellarium_stars.read_all(stars_dir)
    l, b = stellarium_stars.galactic(cat["xyz"])
    # A star is chosen by its catalogue step's lower edge (as N(< V) counts
    # it) and shines at the step's middle.
    light = resolved_light(l, b, cat["V"] + 1e-6, cat["V_mid"])
    lines = [
        f"# The real sky's resolved starlight: the light of the stars {RESOLVED_V[0]} <= V < {RESOLVED_V[1]}"
        " per square degree, in S10 (V = 10 stars per square degree),",
        f"# within {CAP_RADIUS:g} deg of a point (caps) or in a zone of |b| (both hemispheres).",
        "# Source: the Hipparcos/Tycho-2 catalogues of Debian's stellarium-data package, version "
        + package_version() + ", as data/sky/star_counts.tsv;",
        "#   written by scripts/gen_sky_counts.py --resolved (do not edit by hand).",
        "# Columns: region, kind (cap: l, b of its centre; zone: |b| from, to), a, b, S10, stars.",
        "region\tkind\ta\tb\tS10\tstars",
    ]
    for name, kind, a, c in resolved_regions():
        s10, n = light[name]
        lines.append(f"{name}\t{kind}\t{a:g}\t{c:g}\t{s10:.5g}\t{n}")
    return "\n".join(lines) + "\n"


def read_resolved(path):
    """The committed resolved-light table: {region: S10}."""
    out = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or line.startswith("region") or not line.strip():
                continue
            w = line.rstrip("\n").split("\t")
            try:
                out[w[0]] = float(w[4])
            except (ValueError, IndexError):
                raise ValueError(f"{path}: expected region, kind, a, b, S10, stars separated by tabs: {line.strip()!r}")
    if not out:
        raise ValueError(f"{path}: no rows")
    return out


def write_star_list(stars_dir, path):
    """The catalogues as a star list of sky_truth.py's form (L, B, V, BV,
    PARTICLE = -1): the real sky to measure beside a rendered one."""
    from astropy.io import fits

    cat = stellarium_stars.read_all(stars_dir)
    l, b = stellarium_stars.galactic(cat["xyz"])
    cols = [fits.Column("L", "D", "deg", array=l), fits.Column("B", "D", "deg", array=b),
            fits.Column("V", "E", "mag", array=cat["V_mid"]), fits.Column("BV", "E", "mag", array=cat["BV"]),
            fits.Column("PARTICLE", "K", array=np.full(len(l), -1, dtype=np.int64))]
    hdu = fits.BinTableHDU.from_columns(cols, name="STARS")
    hdu.header["ORIGIN"] = "stellarium-data " + package_version() + " (Hipparcos, Tycho-2)"
    tmp = path + ".tmp"
    hdu.writeto(tmp, overwrite=True)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stars-dir", default=None, help=f"default {stellarium_stars.STARS_DIR}")
    ap.add_argument("--check", metavar="TABLE", help="compare with this committed table; exit 1 if it differs")
    ap.add_argument("--star-list", metavar="FITS", help="write the catalogues as a star list (for sky_truth.py)")
    ap.add_argument("--resolved", action="store_true",
                    help="the resolved starlight by region (data/sky/resolved_light.tsv) instead of the counts")
    args = ap.parse_args()
    try:
        if args.star_list:
            write_star_list(args.stars_dir, args.star_list)
            return
        text = resolved_text(args.stars_dir) if args.resolved else table_text(args.stars_dir)
    except (stellarium_stars.CatalogueError, OSError) as e:
        sys.exit(f"gen_sky_counts: {e}")
    if args.check:
        with open(args.check) as f:
            committed = f.read()
        if committed != text:
            sys.stderr.write(f"gen_sky_counts: {args.check} differs from what the catalogues give:\n{text}")
            sys.exit(1)
        print(f"gen_sky_counts: {args.check} matches the catalogues")
        return
    sys.stdout.write(text)


if __name__ == "__main__":
    main()
