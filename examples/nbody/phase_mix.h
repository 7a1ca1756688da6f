/* Discs phase-mixed before a run (--phase-mix T, docs/nbody.md).
 *
 * Why: the model draws a disc star's velocity from Gaussians about the
 * Jeans equations' moments at its place (Hernquist 1993). That is not a
 * steady state: in the first tens of Myr the disc moves out and back
 * together at each radius, at the local epicyclic frequency, and the
 * ring around the Sun breathes at the Sun's own frequency. A tracer Sun
 * started on a circular orbit is then forced at resonance: its radial
 * swing grows steadily (0.5 kpc in 0.6 Gyr in the hot disc, Q = 3). The
 * same disc relaxed by the N-body code for 0.6 Gyr forces it five times
 * less (docs/nbody.md, "What pumps the Sun's epicycle").
 *
 * So each disc star is first moved along its own orbit in its galaxy's
 * axisymmetric, Plummer-softened pull (as the tree softens it) for a time
 * drawn uniformly from [0, T] (from its id alone, so the same on any
 * number of threads or processes): stars of one place and one orbital
 * frequency no longer share a phase, and the disc starts as the time
 * average of its orbits, a steady state of that pull.
 *
 * The pull: every particle of the galaxy binned as rings about its axis
 * (a lattice in u = R / (R + S_R), v = z / (|z| + S_Z), fine near the
 * centre and the plane, reaching to infinity), each bin's ring acting by
 * the exact field of a softened ring (complete elliptic integrals), on a
 * lattice of probe points in (R, |z|) read by bilinear interpolation
 * (beyond the probes, R > 40 kpc or |z| > 4 kpc, the pull at their edge:
 * the model's discs hardly reach there). */
#ifndef NBODY_PHASE_MIX_H
#define NBODY_PHASE_MIX_H

#include <stddef.h>
#include <stdint.h>

#define PM_SCALE_R 10.0 /* kpc: u = R / (R + PM_SCALE_R) */
#define PM_SCALE_Z 1.0  /* kpc: v = z / (|z| + PM_SCALE_Z) */
#define PM_BINS_U 128   /* ring bins over u in [0, 1) */
#define PM_BINS_V 96    /* ring bins over v in (-1, 1) */
#define PM_PROBES_U 81  /* probes over u in [0, PM_PROBE_U_MAX]: R to 40 kpc */
#define PM_PROBES_V 41  /* probes over v in [0, PM_PROBE_V_MAX]: |z| to 4 kpc */
#define PM_PROBE_U_MAX 0.8
#define PM_PROBE_V_MAX 0.8
#define PM_BIN_SUMS 4 /* m, m R, m z, m eps^2 */
#define PM_DT 0.0005  /* the orbits' leapfrog step, time units (0.49 Myr) */

/* A galaxy's particles as rings: per bin the sums m, m R, m z, m eps^2. */
typedef struct pm_rings {
    double sum[PM_BINS_U * PM_BINS_V * PM_BIN_SUMS];
} pm_rings;

/* The axisymmetric pull (F_R, F_z) at the probes, z >= 0. */
typedef struct pm_field {
    double fr[PM_PROBES_U * PM_PROBES_V], fz[PM_PROBES_U * PM_PROBES_V];
} pm_field;

/* The pull of a ring of mass m, radius a at height z0, Plummer-softened
 * with eps2 (> 0), at (R, z): into fr, fz (G = 1). Exact, by the complete
 * elliptic integrals. */
void pm_ring_pull(double m, double a, double z0, double eps2, double R, double z, double *fr, double *fz);

/* Adds a particle at (R, z) in its galaxy's frame, of mass m and softening
 * eps, to the rings. */
void pm_rings_add(pm_rings *r, double R, double z, double m, double eps);

/* The pull of the rings (G times it) at every probe, on particles of
 * softening eps (a pair is softened with (eps^2 + eps_j^2) / 2, as the
 * tree does). Threaded over probes; the same bits on any thread count. */
void pm_field_build(pm_field *f, const pm_rings *r, double G, double eps);

/* The field's pull at (x, y, z) in the galaxy's frame: a[3]. */
void pm_field_pull(const pm_field *f, const double x[3], double a[3]);

/* How long particle id is mixed: T times a number in [0, 1) from id
 * alone. */
double pm_mix_time(uint64_t id, double T);

/* Moves x, v (the galaxy's frame) along the field's orbit for time t, by
 * leapfrog steps of at most PM_DT. */
void pm_follow(const pm_field *f, double x[3], double v[3], double t);

#endif
