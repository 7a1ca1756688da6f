/* One galaxy of the built-in "mw-m31" model (model.c): its mass profiles,
 * the disc's dynamics, the spherical components' distribution functions
 * and potential (model_galaxy.c), and how one of its particles is drawn.
 * Internal to the model. */
#ifndef ORR_SOURCE_MODEL_GALAXY_H
#define ORR_SOURCE_MODEL_GALAXY_H

#include <stdint.h>

#include "core/vecmath.h"
#include "source/models/galaxy_df.h"
#include "source/models/galaxy_flat.h"
#include "source/models/rng.h"

/* Gravitational constant in kpc (km/s)^2 per 1e10 Msun
 * (4.30091e-6 kpc (km/s)^2 / Msun). */
#define MODEL_G 4.30091e4

/* The radius where the disc's Toomre Q takes the requested value, in disc
 * scale lengths: Hernquist (1993) normalised at the solar radius, 8.5 kpc
 * for his 3.5 kpc scale length. */
#define DISC_Q_RADIUS 2.43

/* The thick disc's midplane v_c^2 is tabulated on DISC_TAB_N radii
 * uniform in ln R from DISC_TAB_RMIN to DISC_TAB_ROUT disc truncation radii
 * (beyond, where no disc star is, the thin-disc formula is within 1%). */
#define DISC_TAB_N 48
#define DISC_TAB_RMIN 0.02
#define DISC_TAB_ROUT 1.2

/* Radii of the spherical potential and distribution-function tables. */
#define DF_R_MIN 1e-4
#define DF_R_OUT 100.0 /* the potential table runs to this many halo truncation radii */

/* Potential table: Phi(r) on a grid uniform in ln r from POT_R_MIN to the
 * halo's truncation radius (the outermost of the galaxy's components). */
#define POT_N 1024
#define POT_R_MIN 1e-3

/* The disc's dynamics tabulated once per galaxy (model_disc_table.c;
 * docs/model.md, "Tables"). Radii on a grid of 2^DISC_NODE_BITS equal cells
 * per octave of R (widths R/1024 to R/512), from DISC_NODE_R0 up 16 octaves (to 64 kpc): a radius's
 * cell and its place in it come from the bits of the double, with no
 * logarithm, and within a cell the interpolation is linear in R. */
#define DISC_NODE_BITS 9
#define DISC_NODE_OCTAVES 16
#define DISC_NODE_R0 (1.0 / 1024.0) /* a power of two, below the kinematics' 1 pc floor */
#define DISC_NODE_CELLS (DISC_NODE_OCTAVES << DISC_NODE_BITS)
/* The spheroids' vertical pull integral on coarser radii (2^PULL_R_BITS
 * cells per octave) times PULL_Z_CELLS equal steps in |z| up to PULL_Z_MAX
 * scale heights (above it, e^-16 of the disc, computed exactly). */
#define PULL_R_BITS 6
#define PULL_R_CELLS (DISC_NODE_OCTAVES << PULL_R_BITS)
#define PULL_Z_CELLS 64
#define PULL_Z_MAX 16.0
#define PULL_R_EXACT 1.0 /* scale heights: the pull is computed exactly nearer the axis */

/* The largest error accepted from a cell's interpolation, relative to
 * each quantity (the drift's to v_c^2, the radial term's to the larger of
 * itself and 2 pi G Sigma / h), checked at the middle of each cell. */
#define DISC_TABLE_TOL 2e-5

/* What a disc star's velocity needs at one radius. */
typedef struct disc_node {
    double vc2;       /* orr_model_galaxy_disc_vc2 */
    double gm_sph;    /* G M_spheroids(<R) / R, the in-plane part of the spheroids' v_c^2 */
    double drift;     /* the asymmetric drift term, sigma_R^2 (1 - kappa^2/(4 Omega^2) + d ln(Sigma sigma_R^2)/d ln R), at most 0 */
    double sigma_r;   /* orr_model_galaxy_disc_sigma_r */
    double sigma_phi; /* sigma_R sqrt(kappa^2 / (4 Omega^2)) */
    double radial;    /* orr_model_galaxy_disc_radial */
} disc_node;

typedef struct disc_table {
    disc_node node[DISC_NODE_CELLS + 1];
    /* 1 for a cell where interpolation is off by more than DISC_TABLE_TOL
     * somewhere (a kink of the exact functions: docs/model.md, "Tables"):
     * its stars are computed exactly. */
    unsigned char exact[DISC_NODE_CELLS];
    /* orr_model_galaxy_spheroid_pull at |z| = (m - 1) PULL_Z_MAX h / PULL_Z_CELLS:
     * one node below 0 and one above the top, for the cubic in |z| */
    double pull[PULL_R_CELLS + 1][PULL_Z_CELLS + 3];
} disc_table;

enum { COMP_DISC, COMP_BULGE, COMP_HALO, COMP_COUNT };

/* The fixed description of one galaxy (masses in 1e10 Msun, lengths in kpc).
 * Component masses are the masses within the truncation radii: they are what
 * the particles of that component add up to. */
typedef struct galaxy_spec {
    double disc_mass, disc_rd, disc_hz, disc_rmax;
    double bulge_mass, bulge_a, bulge_rmax;
    double halo_mass, halo_a, halo_rmax;
    double bh_mass;
} galaxy_spec;

typedef struct galaxy {
    galaxy_spec s;
    /* Fractions of the untruncated profiles' mass inside the truncation
     * radii: the inverse CDFs and enclosed masses are rescaled by them. */
    double disc_frac, bulge_frac, halo_frac;
    orr_vec3 centre, velocity;
    orr_vec3 e1, e2, spin; /* disc frame: e1 x e2 = spin (angular momentum) */
    double g_sigma0;       /* G times the disc's central surface density */
    double disc_ln_r0, disc_dln;
    double disc_v2[DISC_TAB_N]; /* the thick disc's own v_c^2 in its plane */
    double sigma_r_ref;    /* disc radial dispersion at DISC_Q_RADIUS scale lengths */
    double disc_q;         /* Toomre Q at DISC_Q_RADIUS scale lengths, and inside it */
    gdf_potential sph;     /* the spherically averaged potential (the DF's) */
    gdf_speeds speeds[COMP_COUNT]; /* bulge and halo rows used */
    gdf_potential disc_mono;       /* the disc's monopole alone */
    gdf_flat bulge_flat;           /* the bulge's f(E) in the flattened potential */
    double pot_ln_rmin, pot_dln;
    double pot[POT_N]; /* spherically averaged potential, (km/s)^2 */
    disc_table disc;   /* orr_model_galaxy_build_disc_table */
} galaxy;

/* A generated particle, before it goes into a chunk. */
typedef struct particle {
    orr_vec3 pos, vel;
    float mass;
    uint8_t type;
    float r;  /* distance from its galaxy's centre at generation (0 for markers) */
    float e0; /* specific binding energy in its galaxy at generation, (km/s)^2 (0 for markers) */
    float ez; /* a disc star's vertical energy in its local sigma_z^2 (orr_model_disc_ez; 0 for the others) */
} particle;

/* A disc star's vertical energy in units of its local vertical dispersion,
 * ez = v_z^2 / (2 sigma_z^2) + |z| / h = gz^2 / 2 + |z| / h, from the unit
 * Gaussian gz that set v_z = sigma_z(R, z) gz and the height az = |z| drawn
 * from the exponential layer of scale height h (docs/model.md, "Vertical
 * energy ez"). One formula for the exact recipe, the tables and the batches. */
static inline float orr_model_disc_ez(double gz, double az, double h)
{
    return (float)(0.5 * gz * gz + az / h);
}

/* The Catmull-Rom spline through p0..p3 at f (0 to 1) between p1 and p2:
 * continuous first derivatives across nodes. */
static inline double orr_model_catmull_rom(double p0, double p1, double p2, double p3, double f)
{
    double f2 = f * f, f3 = f2 * f;
    return 0.5 * (2.0 * p1 + (p2 - p0) * f + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * f2 +
                  (3.0 * p1 - p0 - 3.0 * p2 + p3) * f3);
}

/* The Milky Way's and M31's descriptions, in that order (model.c). */
extern const galaxy_spec orr_model_galaxy_specs[2];

/* Mass fraction of a Hernquist sphere within radius r. */
static inline double orr_model_hernquist_cdf(double r, double a)
{
    double q = r / (r + a);
    return q * q;
}

/* Mass of the spherical components (black hole, bulge, halo) inside r. */
static inline double orr_model_spheroid_mass(const galaxy *g, double r)
{
    const galaxy_spec *s = &g->s;
    double m = s->bh_mass;
    m += r >= s->bulge_rmax ? s->bulge_mass
                            : s->bulge_mass * orr_model_hernquist_cdf(r, s->bulge_a) / g->bulge_frac;
    m += r >= s->halo_rmax ? s->halo_mass : s->halo_mass * orr_model_hernquist_cdf(r, s->halo_a) / g->halo_frac;
    return m;
}

/* Sets up galaxy g from its description s with the discs' Toomre Q q: the
 * truncated profiles' fractions, the disc's v_c table and dispersion. Its
 * place (centre, velocity, disc frame) is the model's to set, before the
 * tables below, which depend on it. */
void orr_model_galaxy_init(galaxy *g, const galaxy_spec *s, double q);
/* The spherically averaged potential's table (orr_model_galaxy_potential). */
void orr_model_galaxy_build_potential(galaxy *g);
/* The bulge's and the halo's distribution functions; 0 on allocation
 * failure. */
int orr_model_galaxy_build_dfs(galaxy *g);

/* The spherically averaged potential at radius r, (km/s)^2; the same with
 * ln r given. */
double orr_model_galaxy_potential(const galaxy *g, double r);
double orr_model_galaxy_potential_ln(const galaxy *g, double r, double ln_r);
/* v_c^2 in the disc plane at radius R. */
double orr_model_galaxy_disc_vc2(const galaxy *g, double R);

/* The disc's dynamics computed exactly (model_galaxy.c), from which the
 * tables are built: kappa^2, sigma_R, d ln(Sigma sigma_R^2) / d ln R at R;
 * sigma_z^2 at (R, z) and its parts: 2 pi G Sigma(R) h, the disc's radial
 * term (1/R) d(v_disc^2)/dR, and the spheroids' pull integrated over the
 * layer above |z| (az). */
double orr_model_galaxy_disc_kappa2(const galaxy *g, double R);
double orr_model_galaxy_disc_sigma_r(const galaxy *g, double R);
double orr_model_galaxy_disc_pressure_slope(const galaxy *g, double R);
double orr_model_galaxy_disc_sigma_z2(const galaxy *g, double R, double z);
double orr_model_galaxy_disc_sheet(const galaxy *g, double R);
double orr_model_galaxy_disc_radial(const galaxy *g, double R);
double orr_model_galaxy_spheroid_pull(const galaxy *g, double R, double az);
/* A disc star's velocity (radial, azimuthal, vertical) at (R, z) from three
 * unit Gaussians, all computed exactly. */
void orr_model_galaxy_disc_velocity(const galaxy *g, double R, double z, double gr, double gt, double gz, double *vr,
                                    double *vphi, double *vz);

/* The disc's tables (model_disc_table.c), after orr_model_galaxy_init, and
 * what they give: the node quantities at R (1e-3 <= R <= 64 kpc),
 * interpolated, and 1, or 0 where R lies in a cell the tables do not
 * resolve (the caller computes exactly there); sigma_z^2 at (R, z). */
void orr_model_galaxy_build_disc_table(galaxy *g);
int orr_model_disc_at(const galaxy *g, double R, disc_node *out);
/* sheet = orr_model_galaxy_disc_sheet(g, R) and layer = exp(-|z| / h),
 * which the sampler knows without an exp. */
double orr_model_disc_sigma_z2_at(const galaxy *g, const disc_node *n, double R, double az, double sheet,
                                  double layer);

/* A disc particle's, a bulge or halo (comp) particle's position,
 * velocity and ez drawn from r. */
void orr_model_galaxy_sample_disc(const galaxy *g, orr_rng *r, particle *p);
void orr_model_galaxy_sample_sphere(const galaxy *g, int comp, orr_rng *r, particle *p);
/* The same from the tables (the disc) and with each radius's logarithm
 * taken once (the spheres), r and e0 filled in too: what the model draws;
 * the two above are the exact recipe. */
void orr_model_galaxy_sample_disc_fast(const galaxy *g, orr_rng *r, particle *p);
void orr_model_galaxy_sample_sphere_fast(const galaxy *g, int comp, orr_rng *r, particle *p);

/* Where a batch of particles goes: the chunk's columns from the batch's
 * first slot. */
typedef struct particle_rows {
    float *x, *y, *z, *vx, *vy, *vz, *r, *e0, *ez;
} particle_rows;

/* The most particles orr_model_galaxy_sample_batch draws at once. */
#define ORR_MODEL_BATCH 64

/* Particles first .. first + n - 1 (n <= ORR_MODEL_BATCH) of component
 * comp, each from its own generator orr_rng_seed_keyed(seed_key, index, 0):
 * what the one-particle samplers above draw, several particles at a time
 * in vector registers (model_batch.c), into out's slots 0 .. n - 1. */
void orr_model_galaxy_sample_batch(const galaxy *g, int comp, uint64_t seed_key, uint64_t first, int n,
                                   const particle_rows *out);

#endif
