/* Cosmological initial conditions: a Gaussian random density field with a
 * ΛCDM linear power spectrum on an N³ grid, and particles displaced from the
 * grid by the Zel'dovich approximation (docs/dark-universe.md).
 *
 * Units: lengths in Mpc/h (comoving), wavenumbers in h/Mpc, P(k) in
 * (Mpc/h)³, masses in 1e10 Msun/h, velocities in km/s in the Gadget
 * convention (the peculiar velocity divided by sqrt(a)). */
#ifndef ORR_SOURCE_ZELDOVICH_H
#define ORR_SOURCE_ZELDOVICH_H

#include <stdint.h>

#include "core/error.h"

typedef struct orr_cosmology {
    double omega_m;      /* matter density today (CDM + baryons) */
    double omega_lambda; /* cosmological constant; 1 - omega_m - omega_lambda is curvature */
    double omega_b;      /* baryons (only the shape of the transfer function) */
    double h;            /* H0 / (100 km/s/Mpc) */
    double sigma8;       /* rms linear density contrast in spheres of 8 Mpc/h today */
    double n_s;          /* primordial spectral index */
} orr_cosmology;

/* Planck 2018-like values: Ω_m 0.315, Ω_Λ 0.685, Ω_b 0.049, h 0.674,
 * σ8 0.811, n_s 0.965. */
orr_cosmology orr_cosmology_default(void);

/* Checks the parameters (ranges named in the message, e.g.
 * "omega_m 0: expected a value in (0, 2]"). */
orr_status orr_cosmology_check(const orr_cosmology *c, orr_error *err);

/* E(a) = H(a)/H0 for matter, curvature and a cosmological constant. */
double orr_hubble_e(const orr_cosmology *c, double a);
/* The linear growth factor D(a), normalised to D(1) = 1 (growing mode of
 * pressureless matter with Λ and curvature, no radiation). */
double orr_growth_factor(const orr_cosmology *c, double a);
/* The linear growth rate f = d ln D / d ln a. */
double orr_growth_rate(const orr_cosmology *c, double a);

/* The Eisenstein & Hu (1998) "no-wiggle" transfer function at k (h/Mpc):
 * T -> 1 as k -> 0. */
double orr_transfer_eh98(const orr_cosmology *c, double k);

/* The linear power spectrum today, P(k) = A k^n_s T(k)², with A such that
 * sigma(8 Mpc/h) = sigma8. */
typedef struct orr_power {
    orr_cosmology cosmo;
    double amplitude; /* A */
} orr_power;

orr_status orr_power_init(orr_power *p, const orr_cosmology *c, orr_error *err);
/* P(k) at z = 0, (Mpc/h)³; 0 for k <= 0. */
double orr_power_at(const orr_power *p, double k);
/* The rms of the linear density today in spheres of radius r (Mpc/h), from
 * the integral of P(k) with a top-hat window. */
double orr_power_sigma_r(const orr_power *p, double r);

typedef struct orr_zeldovich_params {
    orr_cosmology cosmo;
    int grid;        /* N: N³ particles, even, 2..ORR_ZELDOVICH_GRID_MAX */
    double box;      /* side of the periodic box, Mpc/h */
    double redshift; /* the particles' epoch, >= 0 */
    uint64_t seed;   /* the same seed and grid give the same field */
    double truncate; /* k_t, h/Mpc: P(k) exp(−k²/k_t²), the truncated Zel'dovich
                      * approximation (Coles, Melott & Shandarin 1993); 0: none */
} orr_zeldovich_params;

/* 512³ = 1.3e8 particles take about 5.5 GB; 1024³ would need about 43 GB. */
#define ORR_ZELDOVICH_GRID_MAX 512

/* Particle i (0-based, id i + 1) started at grid point (ix, iy, iz) with
 * i = (ix N + iy) N + iz, at q = ((ix, iy, iz) + ½) box / N, and is now at
 * x = q + D(a) ψ(q) (wrapped into [0, box)), with velocity
 * vel_factor × D(a) ψ(q). */
typedef struct orr_zeldovich {
    int grid;
    int64_t n;             /* grid³ */
    double box, a, redshift;
    double growth;         /* D(a) */
    double rate;           /* f(a) = d ln D / d ln a */
    double hubble;         /* H(a), km/s per Mpc/h */
    double vel_factor;     /* sqrt(a) f(a) H(a): Gadget velocity per unit displacement, km/s per Mpc/h */
    double particle_mass;  /* 1e10 Msun/h: Ω_m ρ_crit (box / N)³ */
    double rms_displacement; /* rms of |D ψ| over the particles, Mpc/h */
    orr_cosmology cosmo;
    float *pos;            /* 3n: x0 y0 z0 x1 ..., Mpc/h */
    float *vel;            /* 3n: km/s, Gadget convention */
} orr_zeldovich;

/* Generates the particles (about 40 bytes per particle at most, plus three
 * FFT grids of 4 bytes per cell). */
orr_status orr_zeldovich_generate(const orr_zeldovich_params *p, orr_zeldovich *z, orr_error *err);
void orr_zeldovich_free(orr_zeldovich *z);

/* The grid point particle i started from, Mpc/h. */
void orr_zeldovich_lagrangian(const orr_zeldovich *z, int64_t i, double q[3]);

#endif
