#!/usr/bin/env python3
"""Writes small Gadget-2 (SnapFormat 1, little endian) and Tipsy (big endian,
padded header) snapshots for the command-line tests, with the Python
standard library only, so that crafted values (a NaN time, a negative or
underflowing mass) can be put where the tests want them.

usage: make_snapshot.py gadget|tipsy OUT [--time T] [--masses M,M,...] [--double]

Particles sit on a line, x = 0, 1, 2, ...; their masses are the list given
(default 1,1,1). Gadget files hold them as gas (massarr[0] = 0, so the
masses are in the MASS block; --double writes POS and MASS as doubles, so a
mass like 1e-300 reaches the reader as it is). Tipsy files hold them as dark
particles (floats)."""
import argparse
import struct


def record(payload):
    """A Fortran record: the payload between two 4-byte length markers."""
    return struct.pack("<I", len(payload)) + payload + struct.pack("<I", len(payload))


def gadget(path, time, masses, double):
    n = len(masses)
    header = struct.pack("<6i", n, 0, 0, 0, 0, 0)
    header += struct.pack("<6d", 0, 0, 0, 0, 0, 0)  # massarr: gas masses in MASS
    header += struct.pack("<dd", time, 0.0)  # time, redshift
    header += struct.pack("<ii", 0, 0)  # flag_sfr, flag_feedback
    header += struct.pack("<6I", n, 0, 0, 0, 0, 0)  # npartTotal
    header += struct.pack("<ii", 0, 1)  # flag_cooling, num_files
    header += struct.pack("<4d", 100.0, 0.3, 0.7, 0.7)
    header = header.ljust(256, b"\0")
    real = "<d" if double else "<f"
    pos = b"".join(struct.pack(real, v) for i in range(n) for v in (float(i), 0.0, 0.0))
    vel = b"".join(struct.pack("<f", 0.0) for _ in range(3 * n))
    ids = b"".join(struct.pack("<I", i + 1) for i in range(n))
    mass = b"".join(struct.pack(real, m) for m in masses)
    with open(path, "wb") as f:
        for block in (header, pos, vel, ids, mass):
            f.write(record(block))


def tipsy(path, time, masses):
    n = len(masses)
    with open(path, "wb") as f:
        f.write(struct.pack(">diiiiii", time, n, 3, 0, n, 0, 0))
        for i, m in enumerate(masses):
            # mass, x y z, vx vy vz, eps, phi
            f.write(struct.pack(">9f", m, float(i), 0.0, 0.0, 0.0, 0.0, 0.0, 0.01, 0.0))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("format", choices=["gadget", "tipsy"])
    p.add_argument("out")
    p.add_argument("--time", type=float, default=0.5)
    p.add_argument("--masses", default="1,1,1")
    p.add_argument("--double", action="store_true")
    a = p.parse_args()
    masses = [float(m) for m in a.masses.split(",")]
    if a.format == "gadget":
        gadget(a.out, a.time, masses, a.double)
    else:
        tipsy(a.out, a.time, masses)


if __name__ == "__main__":
    main()
