#!/usr/bin/env python3
"""Checks scripts/stellarium_stars.py, the reader of Stellarium's star
catalogues behind data/sky/ (docs/sky.md), on small catalogues written
here from the format its docstring gives (header, zone counts, records;
the bits packed by Python integers, not by the reader's numpy code), so
it is checked where stellarium-data is not installed too:

- both record types (28-byte Hipparcos, 10-byte Tycho with its 20-bit
  signed offsets), with every other field (ids, proper motions, trailing
  bytes) all ones, so a misplaced shift or mask shows;
- V = (zero + step * range / steps) / 1000 with a negative zero, and
  B-V = bV * 4 / 127 - 0.5;
- the geometry of the gnomonic offsets: stars at (+-a, 0) and (0, +-a)
  lie symmetrically about the zone's centre, the two axes are at right
  angles (cos of the angle between the (a, 0) and (0, a) stars is the
  square of the cos of either's angle to the centre), (a, 0) is east of
  the centre and (0, a) north of it, and every star is inside its zone;
- bad files (another magic, an unknown record type, counts that say more
  than the file holds, a file shorter than the header, no catalogue in
  a folder) refused with a CatalogueError naming the file.

usage: check_stellarium_stars.py SOURCE_DIR WORK_DIR
"""
import os
import struct
import sys

import numpy as np

SRC, WORK = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SRC, "scripts"))
import stellarium_stars as ss  # noqa: E402

LEVEL, ZONE = 1, 37
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what, file=sys.stderr)


def hipparcos(x0, x1, bv, mag):
    """A 28-byte Star1 record: hip:24 and componentIds:8 (all ones), x0, x1
    (int32), bV, mag (uint8), then 14 more bytes (all ones)."""
    return struct.pack("<Iii", 0xFFFFFFFF, x0, x1) + bytes([bv, mag]) + b"\xff" * 14


def tycho(x0, x1, bv, mag):
    """A 10-byte Star2 record, 80 bits from the least significant: x0:20,
    x1:20, dx0:14, dx1:14 (both all ones), bV:7, mag:5."""
    bits = (x0 & 0xFFFFF) | (x1 & 0xFFFFF) << 20 | 0x3FFF << 40 | 0x3FFF << 54 | bv << 68 | mag << 75
    return bits.to_bytes(10, "little")


def catalogue(path, kind, records, zero=-2000, mag_range=12800, steps=256, magic=ss.MAGIC, zone=ZONE, extra=0):
    """A catalogue of level LEVEL with all records in one zone."""
    counts = [0] * (20 * 4 ** LEVEL)
    counts[zone] = len(records) + extra
    head = struct.pack("<8I", magic, kind, 0, 1, LEVEL, zero & 0xFFFFFFFF, mag_range, steps)
    with open(path, "wb") as f:
        f.write(head + struct.pack(f"<{len(counts)}I", *counts) + b"".join(records))


def offsets(a):
    return [(0, 0), (a, 0), (-a, 0), (0, a), (0, -a)]


def radec(v):
    return np.degrees(np.arctan2(v[1], v[0])) % 360, np.degrees(np.arcsin(v[2]))


def check_geometry(name, xyz):
    c, east, west, north, south = xyz
    check(np.allclose(ss._normalise(east + west), c, atol=1e-12) and
          np.allclose(ss._normalise(north + south), c, atol=1e-12),
          f"{name}: stars at +-a are not symmetric about the centre (a sign misread?)")
    cos_r = east @ c
    check(abs(north @ c - cos_r) < 1e-12 and abs(east @ north - cos_r ** 2) < 1e-12,
          f"{name}: the offsets' axes are not at right angles with one scale")
    (ra_c, dec_c), (ra_e, _), (_, dec_n) = radec(c), radec(east), radec(north)
    check(0 < (ra_e - ra_c) % 360 < 180 and dec_n > dec_c, f"{name}: (a, 0) is not east or (0, a) not north")


def test_records():
    d = os.path.join(WORK, "stars")
    os.makedirs(d)
    hip_mags, hip_bvs = [0, 1, 100, 200, 255], [0, 127, 64, 1, 100]
    tyc_mags, tyc_bvs = [0, 1, 15, 30, 31], [127, 0, 3, 90, 64]
    a_hip, a_tyc = ss.RECORD[0][1] // 3, ss.RECORD[1][1] // 3
    catalogue(os.path.join(d, "stars_0_0v0_8.cat"), 0,
              [hipparcos(x0, x1, b, m) for (x0, x1), b, m in zip(offsets(a_hip), hip_bvs, hip_mags)])
    catalogue(os.path.join(d, "stars_3_1v0_4.cat"), 1,
              [tycho(x0, x1, b, m) for (x0, x1), b, m in zip(offsets(a_tyc), tyc_bvs, tyc_mags)],
              zero=9000, mag_range=1550, steps=31)
    hip, tyc = (ss.read_catalogue(os.path.join(d, f)) for f in ("stars_0_0v0_8.cat", "stars_3_1v0_4.cat"))
    check(np.allclose(hip["V"], [(-2000 + m * 12800 / 256) / 1000 for m in hip_mags], atol=1e-12),
          f"Hipparcos V {hip['V']}")
    check(np.allclose(tyc["V"], [9 + m * 0.05 for m in tyc_mags], atol=1e-12), f"Tycho V {tyc['V']}")
    for name, c, bvs in (("Hipparcos", hip, hip_bvs), ("Tycho", tyc, tyc_bvs)):
        check(np.allclose(c["BV"], [b * 4 / 127 - 0.5 for b in bvs], atol=1e-12), f"{name} B-V {c['BV']}")
        check((c["zone"] == ZONE).all() and c["level"] == LEVEL, f"{name}: zones {c['zone']}, level {c['level']}")
        check_geometry(name, c["xyz"])
        tri = ss.zone_triangles(LEVEL)[ZONE]
        sides = np.array([np.cross(tri[k], tri[(k + 1) % 3]) @ c["xyz"].T for k in range(3)])
        check((sides > 0).all() or (sides < 0).all(), f"{name}: a star outside its zone")
    # The same offsets of both types land on the same points: a third of the largest offset each.
    check(np.allclose(hip["xyz"], tyc["xyz"], atol=1e-5), "Hipparcos and Tycho offsets of a third disagree")
    every = ss.read_all(d)
    check(len(every["V"]) == 10 and np.allclose(every["V_mid"][5:] - every["V"][5:], 0.025),
          f"read_all: {len(every['V'])} stars, V_mid - V = {every['V_mid'][5:] - every['V'][5:]}")
    print(f"Hipparcos V {hip['V']}, Tycho V {tyc['V']}; angle to the centre "
          f"{np.degrees(np.arccos(hip['xyz'][1] @ hip['xyz'][0])):.4f} deg")


def refused(path, pattern):
    try:
        ss.read_catalogue(path)
        check(False, f"{path} read without an error (expected {pattern!r})")
    except ss.CatalogueError as e:
        check(str(e).startswith(path + ": ") and pattern in str(e), f"{path}: {e} (expected {pattern!r})")


def test_bad_files():
    d = os.path.join(WORK, "bad")
    os.makedirs(d)
    one = [tycho(0, 0, 10, 10)]
    catalogue(os.path.join(d, "magic.cat"), 1, one, magic=0x12345678)
    refused(os.path.join(d, "magic.cat"), "magic 0x12345678, not a Stellarium star catalogue")
    catalogue(os.path.join(d, "kind.cat"), 2, one)
    refused(os.path.join(d, "kind.cat"), "record type 2 is not read here")
    catalogue(os.path.join(d, "short.cat"), 1, one, extra=2)
    refused(os.path.join(d, "short.cat"), "the zone counts say")
    with open(os.path.join(d, "tiny.cat"), "wb") as f:
        f.write(b"\x0a\x04\x5f\x83")
    refused(os.path.join(d, "tiny.cat"), "4 bytes, shorter than the 32-byte header")
    try:
        ss.catalogue_files(d)
        check(False, "a folder without stars_N_*.cat gave catalogues")
    except ss.CatalogueError as e:
        check("no stars_N_*.cat catalogue" in str(e) and d in str(e), f"no catalogues: {e}")


for test in (test_records, test_bad_files):
    test()
sys.exit(1 if failures else 0)
