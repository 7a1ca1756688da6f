"""Reads the star catalogues Debian's stellarium-data package ships
(/usr/share/stellarium/stars/default/stars_N_*.cat, Stellarium 0.22): every
star's V magnitude, B - V and J2000 direction, as numpy arrays.

The format, learnt from Stellarium's source (src/core/modules/ZoneArray.cpp
and Star.hpp; the writer util/MakeCombinedCatalogue.C, the magnitudes
util/ParseHip.v5.C), little-endian throughout:

- a header of eight 32-bit integers: magic 0x835f040a, record type
  (0: 28-byte Hipparcos records, 1: 10-byte Tycho records), major and
  minor version, level (the geodesic grid's subdivision), the magnitude
  scale's zero in millimag, its range in millimag and its number of steps;
- 20 * 4**level 32-bit star counts, one per triangular zone of the
  level's geodesic grid (an icosahedron subdivided level times);
- the zones' stars, zone after zone.

A record's magnitude is the header's zero + mag * range / steps, the lower
edge of the 0.05-mag step the star's V fell in (the writer floors). Its
direction is the zone's centre plus x0, x1 along the zone's two tangent
axes, scaled by the level's largest corner offset over the integer range
(a gnomonic projection about the zone's centre).

V is Johnson V: the Hipparcos catalogue's V (field H5) where there is one,
else V = VT - 0.090 (BT - VT) from the Tycho magnitudes (ESA 1997, The
Hipparcos and Tycho Catalogues, vol. 1, sect. 1.3, eq. 1.3.20), as
ParseHip writes it.
"""
import glob
import os
import struct

import numpy as np

STARS_DIR = "/usr/share/stellarium/stars/default"
MAGIC = 0x835F040A
HEADER = struct.Struct("<8I")
# Record type -> (bytes per record, largest integer offset along an axis)
RECORD = {0: (28, 0x7FFFFFFF), 1: (10, (1 << 19) - 1)}


class CatalogueError(ValueError):
    """A catalogue file that is not what the format says."""


def catalogue_files(stars_dir=None):
    """The shipped star catalogues, brightest level first."""
    stars_dir = stars_dir or STARS_DIR
    files = sorted(glob.glob(os.path.join(stars_dir, "stars_[0-9]_*.cat")))
    if not files:
        raise CatalogueError(f"{stars_dir}: no stars_N_*.cat catalogue (apt-get install stellarium-data)")
    return files


def _normalise(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _icosahedron():
    """The 20 top-level triangles (3 corners each) of Stellarium's grid."""
    g = 0.5 * (1 + np.sqrt(5))
    b = 1 / np.sqrt(1 + g * g)
    a = b * g
    corners = np.array([[a, -b, 0], [a, b, 0], [-a, b, 0], [-a, -b, 0], [0, a, -b], [0, a, b],
                        [0, -a, b], [0, -a, -b], [-b, 0, a], [b, 0, a], [b, 0, -a], [-b, 0, -a]])
    faces = [(1, 0, 10), (0, 1, 9), (0, 9, 6), (9, 8, 6), (0, 7, 10), (6, 7, 0), (7, 6, 3), (6, 8, 3),
             (11, 10, 7), (7, 3, 11), (3, 2, 11), (2, 3, 8), (10, 11, 4), (2, 4, 11), (5, 4, 2),
             (2, 8, 5), (4, 1, 10), (4, 5, 1), (5, 9, 1), (8, 9, 5)]
    return corners[np.array(faces)]


def zone_triangles(level):
    """(20 * 4**level, 3, 3): each zone's corners, in the zones' order:
    triangle i's children are 4i .. 4i+3 (corner 0's, corner 1's, corner
    2's, then the middle one), the corners' midpoints on the sphere."""
    tri = _icosahedron()
    for _ in range(level):
        c0, c1, c2 = tri[:, 0], tri[:, 1], tri[:, 2]
        e0, e1, e2 = _normalise(c1 + c2), _normalise(c2 + c0), _normalise(c0 + c1)
        children = np.stack([np.stack([c0, e2, e1], 1), np.stack([e2, c1, e0], 1),
                             np.stack([e1, e0, c2], 1), np.stack([e0, e1, e2], 1)], 1)
        tri = children.reshape(-1, 3, 3)
    return tri


def zone_frames(level):
    """Each zone's centre and tangent axes (axis0 east-like: north x centre),
    and the level's scale: the largest gnomonic offset of a corner."""
    tri = zone_triangles(level)
    centre = _normalise(tri.sum(axis=1))
    axis0 = _normalise(np.cross([0.0, 0.0, 1.0], centre))
    axis1 = np.cross(centre, axis0)
    d = tri - centre[:, None, :]
    mu0 = np.einsum("zci,zi->zc", d, axis0)
    mu1 = np.einsum("zci,zi->zc", d, axis1)
    f = 1 / np.sqrt(1 - mu0 ** 2 - mu1 ** 2)
    scale = max(np.max(np.abs(mu0) * f), np.max(np.abs(mu1) * f))
    return centre, axis0, axis1, scale


def _signed(field, bits):
    return np.where(field >= 1 << (bits - 1), field - (1 << bits), field)


def _decode(kind, raw):
    """x0, x1, B-V index, magnitude step of each record (raw: (n, size) uint8)."""
    if kind == 0:  # Star1: hip:24, componentIds:8, x0, x1 (int32), bV, mag (uint8), ...
        x0 = raw[:, 4:8].copy().view("<i4")[:, 0].astype(np.int64)
        x1 = raw[:, 8:12].copy().view("<i4")[:, 0].astype(np.int64)
        return x0, x1, raw[:, 12].astype(np.int64), raw[:, 13].astype(np.int64)
    # Star2, 80 bits from the least significant: x0:20, x1:20, dx0:14, dx1:14, bV:7, mag:5
    lo = raw[:, 0:8].copy().view("<u8")[:, 0]
    hi = raw[:, 8:10].copy().view("<u2")[:, 0].astype(np.uint64)
    x0 = _signed((lo & 0xFFFFF).astype(np.int64), 20)
    x1 = _signed(((lo >> np.uint64(20)) & np.uint64(0xFFFFF)).astype(np.int64), 20)
    bv = ((hi >> np.uint64(68 - 64)) & np.uint64(0x7F)).astype(np.int64)
    mag = ((hi >> np.uint64(75 - 64)) & np.uint64(0x1F)).astype(np.int64)
    return x0, x1, bv, mag


def read_catalogue(path):
    """One catalogue file: dict of V (lower edge of its 0.05-mag step),
    BV, the J2000 unit vector xyz (n, 3), each star's zone, the level and
    the magnitude step."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < HEADER.size:
        raise CatalogueError(f"{path}: {len(data)} bytes, shorter than the 32-byte header")
    magic, kind, _major, _minor, level, mag_min, mag_range, mag_steps = HEADER.unpack_from(data)
    if magic != MAGIC:
        raise CatalogueError(f"{path}: magic {magic:#x}, not a Stellarium star catalogue ({MAGIC:#x})")
    if kind not in RECORD:
        raise CatalogueError(f"{path}: record type {kind} is not read here (0 and 1 are)")
    size, max_pos = RECORD[kind]
    nzones = 20 * 4 ** level
    counts = np.frombuffer(data, "<u4", nzones, HEADER.size).astype(np.int64)
    start = HEADER.size + 4 * nzones
    if len(data) != start + size * counts.sum():
        raise CatalogueError(f"{path}: {len(data)} bytes, the zone counts say {start + size * counts.sum()}")
    raw = np.frombuffer(data, np.uint8, size * counts.sum(), start).reshape(-1, size)
    x0, x1, bv, mag = _decode(kind, raw)
    centre, axis0, axis1, scale = zone_frames(level)
    zone = np.repeat(np.arange(nzones), counts)
    k = scale / max_pos
    xyz = _normalise(centre[zone] + (x0 * k)[:, None] * axis0[zone] + (x1 * k)[:, None] * axis1[zone])
    mag_min = struct.unpack("<i", struct.pack("<I", mag_min))[0]
    v = (mag_min + mag * mag_range / mag_steps) / 1000.0
    return {"V": v, "BV": bv * (4.0 / 127.0) - 0.5, "xyz": xyz, "zone": zone, "level": level,
            "step": mag_range / mag_steps / 1000.0}


def read_all(stars_dir=None):
    """Every shipped catalogue, concatenated: V (the step's lower edge),
    V_mid (the step's middle, the star's light), BV, xyz, and the files."""
    files = catalogue_files(stars_dir)
    cats = [read_catalogue(f) for f in files]
    return {"V": np.concatenate([c["V"] for c in cats]),
            "V_mid": np.concatenate([c["V"] + c["step"] / 2 for c in cats]),
            "BV": np.concatenate([c["BV"] for c in cats]),
            "xyz": np.concatenate([c["xyz"] for c in cats]), "files": files}


def galactic(xyz):
    """Galactic (l, b) in degrees of J2000 (ICRS) unit vectors, by astropy."""
    from astropy.coordinates import SkyCoord

    g = SkyCoord(x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2], representation_type="cartesian", frame="icrs").galactic
    return g.spherical.lon.deg, g.spherical.lat.deg
