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
} galaxy;

/* A generated particle, before it goes into a chunk. */
typedef struct particle {
    orr_vec3 pos, vel;
    float mass;
    uint8_t type;
    float r;  /* distance from its galaxy's centre at generation (0 for markers) */
    float e0; /* specific binding energy in its galaxy at generation, (km/s)^2 (0 for markers) */
} particle;

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

/* The spherically averaged potential at radius r, (km/s)^2. */
double orr_model_galaxy_potential(const galaxy *g, double r);
/* v_c^2 in the disc plane at radius R. */
double orr_model_galaxy_disc_vc2(const galaxy *g, double R);

/* A disc particle's, a bulge or halo (comp) particle's position and
 * velocity drawn from r. */
void orr_model_galaxy_sample_disc(const galaxy *g, orr_rng *r, particle *p);
void orr_model_galaxy_sample_sphere(const galaxy *g, int comp, orr_rng *r, particle *p);

#endif
