"""A toy disc galaxy whose stars carry formation scale factors and
metallicities, written as an EAGLE/AREPO-style HDF5 snapshot (PartType4 with
Coordinates, Masses, ParticleIDs, StellarFormationTime = the scale factor
at birth, Metallicities = metal mass fraction; Header/Time = 1): the input
of configs/stellar-ages.yaml, which colours each star by the CMD/PARSEC
simple-stellar-population table (docs/colour.md, "Stellar ages").

An old metal-rich bulge (8-12 Gyr), a disc whose stars were born over
13 Gyr (older ones thicker, metallicity falling outward), and two spiral
arms of young stars (0-200 Myr). Times are turned into scale factors with
the flat LCDM cosmology the config names (h = 0.7, omega_m = 0.3, no
radiation): t(a) = 2 / (3 H0 sqrt(L)) asinh(sqrt(L / m) a^1.5), inverted.
Needs numpy and h5py only:

    /usr/bin/python3 examples/python/aged_galaxy.py --out /tmp
    build/orrery render configs/stellar-ages.yaml --set input.file=/tmp/aged_galaxy.hdf5 -o /tmp
"""
import argparse
import os

import numpy as np

H, OMEGA_M = 0.7, 0.3
HUBBLE_TIME_GYR = 977.792 / (100 * H)  # 1/H0 in Gyr


def scale_factor(t_gyr):
    """The scale factor at cosmic time t (Gyr), flat LCDM without radiation."""
    lam = 1 - OMEGA_M
    x = np.sinh(1.5 * np.sqrt(lam) * t_gyr / HUBBLE_TIME_GYR)
    return (np.sqrt(OMEGA_M / lam) * x) ** (2 / 3)


def galaxy(rng, n_bulge=80_000, n_disc=300_000, n_arms=12_000):
    """Positions (kpc), ages (Gyr) and metallicities of the three parts."""
    # Bulge: a Plummer-like sphere of 0.8 kpc, flattened to 0.6.
    r = 0.8 / np.sqrt(rng.uniform(0.0, 0.97, n_bulge) ** (-2 / 3) - 1)
    d = rng.normal(size=(n_bulge, 3))
    bulge = d / np.linalg.norm(d, axis=1)[:, None] * r[:, None] * [1, 1, 0.6]
    bulge_age = rng.uniform(8, 12, n_bulge)
    bulge_z = rng.lognormal(np.log(0.02), 0.3, n_bulge)
    # Disc: exponential, 3 kpc; thickness growing with age (0.1 to 0.8 kpc).
    disc_age = rng.uniform(0.0, 13.0, n_disc)
    rd = rng.gamma(2.0, 3.0, n_disc)
    phi = rng.uniform(0, 2 * np.pi, n_disc)
    zd = rng.laplace(0, 0.1 + 0.055 * disc_age)
    disc = np.column_stack([rd * np.cos(phi), rd * np.sin(phi), zd])
    disc_z = 0.03 * np.exp(-rd / 6) * np.exp(-disc_age / 20) * rng.lognormal(0, 0.2, n_disc)
    # Arms: two logarithmic spirals (pitch 15 degrees) of young stars.
    ra = rng.gamma(3.0, 2.0, n_arms) + 1.5
    arm = rng.integers(0, 2, n_arms)
    pa = np.log(ra / 1.5) / np.tan(np.radians(15)) + np.pi * arm + rng.normal(0, 0.25, n_arms)
    arms = np.column_stack([ra * np.cos(pa), ra * np.sin(pa), rng.normal(0, 0.08, n_arms)])
    arms[:, :2] += rng.normal(0, 0.25, (n_arms, 2))
    arms_age = rng.uniform(0.0, 0.2, n_arms)
    arms_z = 0.025 * np.exp(-ra / 6) * rng.lognormal(0, 0.1, n_arms)
    pos = np.concatenate([bulge, disc, arms])
    age = np.concatenate([bulge_age, disc_age, arms_age])
    metals = np.concatenate([bulge_z, disc_z, arms_z])
    return pos, age, metals


def main():
    import h5py  # only to write the file: the notebook imports galaxy() without it

    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=".", help="folder for aged_galaxy.hdf5")
    args = p.parse_args()
    rng = np.random.default_rng(25)
    pos, age, metals = galaxy(rng)
    now = 13.466  # Gyr: a = 1
    birth_a = scale_factor(now - age)
    n = len(pos)
    path = os.path.join(args.out, "aged_galaxy.hdf5")
    with h5py.File(path, "w") as f:
        h = f.create_group("Header")
        h.attrs["NumPart_ThisFile"] = np.array([0, 0, 0, 0, n, 0], dtype=np.int64)
        h.attrs["NumPart_Total"] = np.array([0, 0, 0, 0, n, 0], dtype=np.int64)
        h.attrs["MassTable"] = np.zeros(6)
        h.attrs["Time"] = 1.0
        h.attrs["NumFilesPerSnapshot"] = 1
        g = f.create_group("PartType4")
        g["Coordinates"] = pos.astype(np.float32)
        g["Masses"] = np.full(n, 1e-4, dtype=np.float32)  # 1e10 Msun units: 1e6 Msun each
        g["ParticleIDs"] = np.arange(1, n + 1, dtype=np.uint64)
        g["StellarFormationTime"] = birth_a.astype(np.float32)
        g["Metallicities"] = metals.astype(np.float32)
    print(f"wrote {path}: {n} stars, ages {age.min():.3f}-{age.max():.2f} Gyr, "
          f"formation a {birth_a.min():.3f}-{birth_a.max():.4f}")


if __name__ == "__main__":
    main()
