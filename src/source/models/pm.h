/* A particle-mesh (PM) gravity code that evolves Zel'dovich initial
 * conditions (zeldovich.h) in a periodic ΛCDM box to a later epoch, so that
 * filaments and halos form (docs/dark-universe.md, "Particle mesh").
 *
 * Comoving equations of motion (Klypin & Holtzman 1997, astro-ph/9712217,
 * eqs. 2-4), with time in 1/H0 and lengths in Mpc/h: the canonical momentum
 * p = a² dx/dt obeys
 *     dx/da = p / (a³ E(a)),   dp/da = −∇φ / (a E(a)),   ∇²φ = (3/2) Ω_m δ / a.
 * Stepping: kick-drift-kick in a, with the kick and drift factors of FastPM
 * (Feng et al. 2016, MNRAS 463, 2273, §2.3), which make the linear growing
 * mode exact whatever the number of steps. */
#ifndef ORR_SOURCE_PM_H
#define ORR_SOURCE_PM_H

#include "core/error.h"
#include "source/models/zeldovich.h"

/* 1024³ cells take 8.6 GB in the two mesh arrays. */
#define ORR_PM_MESH_MAX 1024
#define ORR_PM_STEPS_MAX 10000

typedef struct orr_pm_params {
    double a_end; /* the scale factor to stop at, above the particles' a, at most 1 */
    int steps;    /* kick-drift-kick steps, evenly spaced in a, 1..ORR_PM_STEPS_MAX */
    int mesh;     /* cells per side of the force mesh, even, 2..ORR_PM_MESH_MAX */
    /* Called after every step (when not NULL): steps done of steps, the
     * scale factor reached, the step's |Σ p| / Σ |p| and the wall-clock
     * seconds since the start, for progress lines. */
    void (*progress)(void *user, int done, int steps, double a, double momentum, double seconds);
    void *progress_user;
} orr_pm_params;

typedef struct orr_pm_report {
    double momentum;    /* largest |Σ p| / Σ |p| over the steps (0 for exact conservation) */
    double mesh_mass;   /* largest |Σ mesh − N| / N over the steps (float rounding of the deposit) */
    double wall_seconds;
} orr_pm_report;

/* Evolves z's particles from z->a to p->a_end in place: positions (wrapped
 * into [0, box)) and velocities (still Gadget's u = v_pec / sqrt(a), km/s);
 * z's epoch fields (a, redshift, growth, rate, hubble, vel_factor,
 * rms_displacement) describe the new epoch. The result is the same bit for
 * bit for any number of OpenMP threads. Memory: 16 bytes per particle and
 * two meshes of about 4 M³ bytes each. */
orr_status orr_pm_evolve(orr_zeldovich *z, const orr_pm_params *p, orr_pm_report *report, orr_error *err);

/* FastPM's factors for one cosmology (exposed for the tests): the drift
 * moves x by p × drift(a0, a1, ar), the kick moves p by −∇φ(ar) ×
 * kick(a0, a1, ar), ar being the epoch at which p or ∇φ is taken. */
double orr_pm_drift_factor(const orr_cosmology *c, double a0, double a1, double ar);
double orr_pm_kick_factor(const orr_cosmology *c, double a0, double a1, double ar);

#endif
