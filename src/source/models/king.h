/* The built-in "king" model: a globular cluster as a King (1966) model
 * (lowered isothermal sphere, f(E) ~ exp(-E/sigma^2) - 1), every star with an
 * absolute V magnitude and a B-V colour from a globular cluster's
 * colour-magnitude diagram (gc_cmd.h). Units: pc, solar masses, km/s.
 * Particle i is a pure function of (seed, i). docs/nightfall.md. */
#ifndef ORR_SOURCE_KING_H
#define ORR_SOURCE_KING_H

#include <stdint.h>

#include "source/source.h"

#define ORR_KING_W0_MIN 0.5
#define ORR_KING_W0_MAX 15.0

/* The solution of King's Poisson equation in dimensionless form: radius in
 * units of the King radius r0 = sqrt(9 sigma^2 / (4 pi G rho0)), W = the
 * potential relative to the tidal radius over sigma^2, mu(r) = integral of
 * rho/rho0 r^2 dr (the enclosed mass is 4 pi rho0 r0^3 mu). */
typedef struct orr_king_profile {
    double w0;
    int n;            /* table entries, r[0] = 0 to r[n - 1] = rt */
    double *r, *w, *mu;
    double rt;        /* tidal radius / r0 */
    double mu_total;  /* mu(rt) */
} orr_king_profile;

/* Density over the central density's shape: rho(W) ~ e^W erf(sqrt W) -
 * sqrt(4W/pi) (1 + 2W/3), not normalised (0 for W <= 0). */
double orr_king_rho_shape(double w);

/* Integrates W'' + 2W'/r = -9 rho(W)/rho(W0) from W(0) = W0, W'(0) = 0
 * outwards (RK4 in ln r) to W = 0, the tidal radius. */
orr_status orr_king_solve(double w0, orr_king_profile *out, orr_error *err);
void orr_king_free(orr_king_profile *p);

/* Interpolated from the table; r in units of r0, clamped to [0, rt]. */
double orr_king_w_at(const orr_king_profile *p, double r);
double orr_king_mass_fraction(const orr_king_profile *p, double r);
/* The radius enclosing a fraction (0..1) of the mass. */
double orr_king_radius_of_mass(const orr_king_profile *p, double fraction);

/* Gravitational constant in pc (km/s)^2 / Msun. */
#define ORR_KING_G 4.30091e-3

typedef struct orr_king_params {
    long long particles;  /* at least 100 */
    uint64_t seed;
    double w0;            /* central potential W0, ORR_KING_W0_MIN..MAX */
    double core_radius;   /* King radius r0, pc */
    double mass;          /* total mass, Msun */
} orr_king_params;

/* The physical scales of a model: sigma (the distribution function's
 * velocity parameter, km/s) and the tidal radius (pc). */
void orr_king_scales(const orr_king_params *params, const orr_king_profile *p, double *sigma, double *rt_pc);

/* The source: x, y, z (pc, the cluster centre at the origin), mass (Msun,
 * all stars equal), id = index + 1, type = the star's phase (orr_gc_phase),
 * and fields vx, vy, vz (km/s), r (pc from the centre), V (absolute
 * magnitude M_V) and BV (intrinsic B-V). */
orr_status orr_king_source_open(const orr_king_params *params, size_t chunk_size, orr_source **out,
                                orr_error *err);

#endif
