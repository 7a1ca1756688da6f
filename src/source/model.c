/* The built-in "mw-m31" model: a Milky Way-like and an Andromeda-like galaxy
 * (exponential disc + Hernquist bulge + truncated Hernquist halo + central
 * black hole each) on an approach orbit, plus a Sun marker; or one of the
 * two alone. Each galaxy is set up near equilibrium: bulge and halo
 * velocities from their Eddington distribution functions in the galaxy's
 * spherically averaged potential, disc velocities from the true circular
 * speed and epicyclic frequency with a Toomre Q profile, asymmetric drift
 * and a vertical dispersion matched to the scale height (the recipe of
 * Hernquist 1993, ApJS 86, 389). docs/model.md gives the numbers, their
 * sources and the approximations made.
 *
 * Every particle is a pure function of (seed, index): particle i is drawn
 * from a counter-based generator keyed by (seed, i), never from a stream
 * shared between particles. Chunk size, rewinds and the order of next()
 * calls therefore cannot change the output. */
#include "source/model.h"
#include "source/model_dust.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "source/galaxy_df.h"
#include "source/galaxy_flat.h"
#include "source/rng.h"

/* Gravitational constant in kpc (km/s)^2 per 1e10 Msun
 * (4.30091e-6 kpc (km/s)^2 / Msun). */
#define MODEL_G 4.30091e4

#define MODEL_PARTICLES_MIN 100
#define MODEL_MARKERS_MAX 3
#define MODEL_FIRST_ID 4 /* the first non-marker particle's id, whatever the markers */
#define MODEL_SEPARATION_MIN 10.0    /* kpc; below this the Sun is inside M31 */
#define MODEL_SEPARATION_MAX 10000.0 /* kpc; keeps float positions precise */

/* The Sun: 8 kpc from the centre on the -x axis, 20 pc above the plane. */
#define SUN_X (-8.0)
#define SUN_Z 0.02
#define SUN_MASS 1e-10 /* one solar mass: a tracer, dynamically irrelevant */

/* Direction of M31 from the Sun (galactic l, b in degrees). */
#define M31_L_DEG 121.17
#define M31_B_DEG (-21.57)
/* Spin axis of M31's disc (galactic l, b in degrees); illustrative, see
 * docs/model.md. It inclines the disc ~78 deg to our line of sight. */
#define M31_SPIN_L_DEG 240.0
#define M31_SPIN_B_DEG (-30.0)
/* Velocity of M31 relative to the MW (km/s): radial (negative = approaching)
 * and tangential (van der Marel et al. 2012). */
#define M31_VRAD (-110.0)
#define M31_VTAN 17.0

/* The radius where the disc's Toomre Q takes the requested value, in disc
 * scale lengths: Hernquist (1993) normalised at the solar radius, 8.5 kpc
 * for his 3.5 kpc scale length. */
#define DISC_Q_RADIUS 2.43
#define DISC_Q_MAX ORR_MODEL_DISC_Q_MAX

/* A halo particle weighs this many star (disc or bulge) particles. Equal
 * masses would leave only ~6% of the particles to the stars; 8 keeps a
 * third of them stars (5e4 disc particles in an isolated Milky Way of 2e5)
 * while cutting the halo particles' heating of the discs (which grows with
 * their mass; Lacey & Ostriker 1985) threefold from the previous 25. */
#define HALO_MASS_RATIO 8.0

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
enum { GAL_MW, GAL_M31, GAL_COUNT };

/* The fixed description of one galaxy (masses in 1e10 Msun, lengths in kpc).
 * Component masses are the masses within the truncation radii: they are what
 * the particles of that component add up to. */
typedef struct galaxy_spec {
    double disc_mass, disc_rd, disc_hz, disc_rmax;
    double bulge_mass, bulge_a, bulge_rmax;
    double halo_mass, halo_a, halo_rmax;
    double bh_mass;
} galaxy_spec;

static const galaxy_spec SPEC[GAL_COUNT] = {
    /* Milky Way */
    {5.0, 3.0, 0.3, 25.0, 1.0, 0.6, 10.0, 100.0, 33.0, 250.0, 4.3e-4},
    /* Andromeda */
    {7.0, 5.0, 0.4, 40.0, 2.5, 1.0, 15.0, 150.0, 35.0, 300.0, 1.4e-2},
};

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

/* A contiguous run of particle indices of one component of one galaxy. */
typedef struct block {
    uint64_t first, count;
    int gal, comp;
    float mass;
    uint8_t type;
} block;

typedef struct model_state {
    orr_model_params params;
    galaxy gal[GAL_COUNT];
    int ngal, gal_index[GAL_COUNT]; /* the galaxies present, in id order */
    int nmarkers;                   /* black holes of the galaxies present, the Sun with the MW */
    uint64_t marker_id[MODEL_MARKERS_MAX];
    block blocks[GAL_COUNT * COMP_COUNT];
    int nblocks;
    uint64_t total, next_index;
    uint64_t dust_first;            /* the first gas particle's index (= total without gas) */
    orr_model_dust dust;            /* the dusty gas discs (model_dust.h) */
} model_state;

/* Extra fields of every particle: velocity, the distance from its own
 * galaxy's centre and its specific binding energy there (for colours that
 * vary with radius or with how deeply bound a star is). */
#define MODEL_FIELDS 5
static const char *const FIELD_NAMES[MODEL_FIELDS] = {"vx", "vy", "vz", "r", "E0"};

typedef struct particle {
    orr_vec3 pos, vel;
    float mass;
    uint8_t type;
    float r;  /* distance from its galaxy's centre at generation (0 for markers) */
    float e0; /* specific binding energy in its galaxy at generation, (km/s)^2 (0 for markers) */
} particle;

/* ---- profiles ---------------------------------------------------------- */

/* Mass fraction of an exponential disc within cylindrical radius R. */
static double disc_cdf(double R, double rd)
{
    double x = R / rd;
    return 1.0 - (1.0 + x) * exp(-x);
}

/* Mass fraction of a Hernquist sphere within radius r. */
static double hernquist_cdf(double r, double a)
{
    double q = r / (r + a);
    return q * q;
}

/* Mass of the spherical components (black hole, bulge, halo) inside r. */
static double spheroid_mass(const galaxy *g, double r)
{
    const galaxy_spec *s = &g->s;
    double m = s->bh_mass;
    m += r >= s->bulge_rmax ? s->bulge_mass
                            : s->bulge_mass * hernquist_cdf(r, s->bulge_a) / g->bulge_frac;
    m += r >= s->halo_rmax ? s->halo_mass : s->halo_mass * hernquist_cdf(r, s->halo_a) / g->halo_frac;
    return m;
}

/* Disc mass within cylindrical radius R (the truncated exponential). */
static double disc_cylinder_mass(const galaxy *g, double R)
{
    const galaxy_spec *s = &g->s;
    return R >= s->disc_rmax ? s->disc_mass : s->disc_mass * disc_cdf(R, s->disc_rd) / g->disc_frac;
}

/* Disc mass within the sphere of radius r, for the layer's exponential
 * vertical profile: integral over |z| < r of exp(-|z|/h)/(2h) times the
 * mass within cylindrical radius sqrt(r^2 - z^2); with u = 1 - exp(-z/h)
 * the weight is du, so a 48-point midpoint rule in u is smooth. For a thin
 * disc this is the cylinder mass; for h = 0.3 kpc it is 17% less at 1 kpc,
 * which the bulge must not be made too hot for. */
static double disc_sphere_mass(const galaxy *g, double r)
{
    const int n = 48;
    double h = g->s.disc_hz, top = 1.0 - exp(-r / h), sum = 0.0;
    for (int k = 0; k < n; k++) {
        double u = (k + 0.5) / n * top, z = -h * log(1.0 - u);
        sum += disc_cylinder_mass(g, sqrt(fmax(0.0, r * r - z * z)));
    }
    return sum * top / n;
}

/* Mass inside radius r with the disc's mass in that sphere: the monopole
 * (spherical average) the bulge and halo feel, and the potential E0 is
 * measured in. */
static double enclosed_mass(const galaxy *g, double r)
{
    return disc_sphere_mass(g, r) + spheroid_mass(g, r);
}

static double gm_enclosed(double r, const void *ctx)
{
    return MODEL_G * enclosed_mass(ctx, r);
}

static double gm_disc_sphere(double r, const void *ctx)
{
    return MODEL_G * disc_sphere_mass(ctx, r);
}

/* ---- disc dynamics ------------------------------------------------------ */

/* The disc's own v_c^2 for its thickness (gdf_thick_disc_vc2; the
 * truncation ignored: 0.2% of its mass lies beyond), tabulated once. */
static void build_disc_table(galaxy *g)
{
    g->disc_ln_r0 = log(DISC_TAB_RMIN);
    g->disc_dln = (log(DISC_TAB_ROUT * g->s.disc_rmax) - g->disc_ln_r0) / (DISC_TAB_N - 1);
    for (int i = 0; i < DISC_TAB_N; i++)
        g->disc_v2[i] = gdf_thick_disc_vc2(exp(g->disc_ln_r0 + i * g->disc_dln), g->s.disc_rd, g->s.disc_hz,
                                           g->g_sigma0);
}

/* Catmull-Rom interpolation in ln R, so the derivative (kappa) is
 * continuous; v^2 ~ R^2 inside the table (a finite central density), the
 * thin disc's outside (the thickness no longer matters there). */
static double disc_own_vc2(const galaxy *g, double R)
{
    if (R <= DISC_TAB_RMIN)
        return g->disc_v2[0] * (R / DISC_TAB_RMIN) * (R / DISC_TAB_RMIN);
    double t = (log(R) - g->disc_ln_r0) / g->disc_dln;
    if (t >= DISC_TAB_N - 1)
        return gdf_freeman_vc2(R, g->s.disc_rd, g->g_sigma0);
    int i = (int)t;
    double f = t - i, f2 = f * f, f3 = f2 * f;
    const double *v = g->disc_v2;
    double p0 = v[i > 0 ? i - 1 : 0], p1 = v[i], p2 = v[i + 1], p3 = v[i + 2 < DISC_TAB_N ? i + 2 : i + 1];
    return 0.5 * (2.0 * p1 + (p2 - p0) * f + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * f2 +
                  (3.0 * p1 - p0 - 3.0 * p2 + p3) * f3);
}

/* v_c^2 in the disc plane: the thick disc's own plus the spherical
 * components'. This is the circular speed the disc must rotate at; the
 * spherical approximation of the disc is ~10% off near 2 Rd, the thin-disc
 * formula 5-15% in v^2 within 3 Rd. */
static double disc_vc2(const galaxy *g, double R)
{
    return disc_own_vc2(g, R) + MODEL_G * spheroid_mass(g, R) / R;
}

/* kappa^2 = R d(Omega^2)/dR + 4 Omega^2 = (dv_c^2/dR) / R + 2 v_c^2 / R^2
 * (Binney & Tremaine 2008 eq. 3.80), the derivative by central difference. */
static double disc_kappa2(const galaxy *g, double R)
{
    double h = 1e-3 * R;
    double dv2 = (disc_vc2(g, R + h) - disc_vc2(g, R - h)) / (2.0 * h);
    return dv2 / R + 2.0 * disc_vc2(g, R) / (R * R);
}

static double disc_surface_density_g(const galaxy *g, double R)
{
    return g->g_sigma0 * exp(-R / g->s.disc_rd); /* G Sigma(R) */
}

/* Hernquist (1993): sigma_R^2 proportional to Sigma, i.e. sigma_R =
 * sigma_ref exp(-(R - R_ref) / (2 Rd)), normalised so that Toomre's
 * Q = sigma_R kappa / (3.36 G Sigma) equals q at R_ref = 2.43 Rd. */
static void set_disc_dispersion(galaxy *g, double q)
{
    double rref = DISC_Q_RADIUS * g->s.disc_rd;
    g->disc_q = q;
    g->sigma_r_ref = q * 3.36 * disc_surface_density_g(g, rref) / sqrt(disc_kappa2(g, rref));
}

/* Outside R_ref, Hernquist's profile. Inside, where it would make Q rise
 * steeply (sigma_R reaching 80-130 km/s, half of v_c, within 3 kpc of the
 * Milky Way: a disc far too hot for the epicyclic Gaussians, which puffed
 * up and spread within 25 Myr, taking the bulge with it), Q is held at q:
 * sigma_R = q 3.36 G Sigma / kappa, which is continuous at R_ref and about
 * sigma_z there (cf. Springel, Di Matteo & Hernquist 2005, MNRAS 361, 776,
 * who take sigma_R = sigma_z). The smaller of the two is used. */
static double disc_sigma_r(const galaxy *g, double R)
{
    double hern = g->sigma_r_ref * exp(-(R - DISC_Q_RADIUS * g->s.disc_rd) / (2.0 * g->s.disc_rd));
    if (R >= DISC_Q_RADIUS * g->s.disc_rd)
        return hern;
    double flat_q = g->disc_q * 3.36 * disc_surface_density_g(g, R) / sqrt(disc_kappa2(g, R));
    return fmin(hern, flat_q);
}

/* d ln(Sigma sigma_R^2) / d ln R, by central difference: the pressure term
 * of the radial Jeans equation (-2 R / Rd for Hernquist's sigma_R^2 ~ Sigma). */
static double disc_pressure_slope(const galaxy *g, double R)
{
    double h = 1e-3 * R;
    double lo = disc_sigma_r(g, R - h), hi = disc_sigma_r(g, R + h);
    double p_lo = disc_surface_density_g(g, R - h) * lo * lo, p_hi = disc_surface_density_g(g, R + h) * hi * hi;
    return (log(p_hi) - log(p_lo)) / (log(R + h) - log(R - h));
}

/* The spheroids' (black hole, bulge, halo) vertical pull at (R, z'):
 * G M_sph(<r) z' / r^3, r = sqrt(R^2 + z'^2), with r held at least the
 * disc's scale height so the black hole's pull stays finite on the axis
 * (the N-body code softens it too). */
static double spheroid_pull_z(const galaxy *g, double R, double zp)
{
    double r = fmax(sqrt(R * R + zp * zp), g->s.disc_hz);
    return MODEL_G * spheroid_mass(g, r) * zp / (r * r * r);
}

#define SIGMA_Z_NODES 24

/* Vertical dispersion at (R, z) from the vertical Jeans equation
 * d(rho sigma_z^2)/dz = -rho dPhi/dz for the model's exponential layer
 * rho ~ exp(-|z|/h) (so the dispersion keeps the layer at its scale
 * height): sigma_z^2(z) = integral_|z|^inf exp(-(z' - |z|)/h) K(z') dz',
 * K the vertical pull. With u = exp(-(z' - |z|)/h) that is
 * h integral_0^1 K(|z| - h ln u) du. The pull, after Poisson's equation
 * near the plane, d^2Phi/dz^2 = 4 pi G rho - (1/R) d(R F_R)/dR:
 *  - the layer's own density, 2 pi G Sigma(<|z'|), gives
 *    2 pi G Sigma h (1 - exp(-|z|/h) / 2);
 *  - less the disc's own radial term (1/R) d(v_disc^2)/dR times z', which
 *    the infinite-sheet approximation drops and which weakens the pull by
 *    10-15% inside 2 Rd where the disc's rotation rises: h (|z| + h) times it;
 *  - the spheroids' pull at each height, integrated in u (24-point
 *    midpoint rule). The first version took it as linear in z' with the
 *    slope at z' = h; inside 2 kpc, where the bulge's M(<r) / r^3 falls
 *    quickly with height, that overestimated it and the inner disc was
 *    about 20% too hot vertically (<v_z^2> / <-z a_z> = 1.2-1.3 with the
 *    N-body forces) and puffed up within 15 Myr.
 * Clipped at a small positive floor should the sum turn negative. */
static double disc_sigma_z2(const galaxy *g, double R, double z)
{
    double h = g->s.disc_hz, az = fabs(z);
    double sheet = 2.0 * ORR_PI * disc_surface_density_g(g, R) * h * (1.0 - 0.5 * exp(-az / h));
    double dR = 1e-3 * R;
    double radial = (disc_own_vc2(g, R + dR) - disc_own_vc2(g, R - dR)) / (2.0 * dR * R);
    double sph = 0.0;
    for (int k = 0; k < SIGMA_Z_NODES; k++) {
        double u = (k + 0.5) / SIGMA_Z_NODES;
        sph += spheroid_pull_z(g, R, az - h * log(u));
    }
    sph *= h / SIGMA_Z_NODES;
    return fmax(1.0, sheet + sph - radial * h * (az + h));
}

/* ---- spherical components' distribution functions ---------------------- */

typedef struct sphere_ctx {
    double a;
} sphere_ctx;

/* The untruncated Hernquist shape (its constant cancels in f's shape). */
static double hernquist_rho(double r, const void *ctx)
{
    double a = ((const sphere_ctx *)ctx)->a, ra = r + a;
    return 1.0 / (r * ra * ra * ra);
}

static double hernquist_dlnrho(double r, const void *ctx)
{
    double a = ((const sphere_ctx *)ctx)->a;
    return -1.0 - 3.0 * r / (r + a);
}

/* The bulge's and the halo's speed tables from Eddington's formula for
 * their (untruncated) Hernquist densities in the whole galaxy's spherically
 * averaged potential (disc monopole, black hole and the truncated
 * components included), and the bulge's equivalent radii in the disc's
 * flattened potential (galaxy_flat.h; the halo, mostly far from the disc,
 * stays spherical). Returns 0 on allocation failure. */
static int build_sphere_dfs(galaxy *g)
{
    gdf_potential_build(&g->sph, DF_R_MIN, DF_R_OUT * g->s.halo_rmax, gm_enclosed, g);
    gdf_potential_build(&g->disc_mono, DF_R_MIN, DF_R_OUT * g->s.halo_rmax, gm_disc_sphere, g);
    sphere_ctx bulge = {g->s.bulge_a}, halo = {g->s.halo_a};
    gdf_flat_disc disc = {g->s.disc_rd, g->s.disc_hz, g->g_sigma0, &g->sph, &g->disc_mono};
    gdf_flat_build(&g->bulge_flat, &disc, 1e-2, g->s.bulge_rmax, hernquist_rho, &bulge);
    return gdf_speeds_build(&g->speeds[COMP_BULGE], &g->sph, 1e-3, g->s.bulge_rmax, hernquist_rho,
                            hernquist_dlnrho, &bulge) &&
           gdf_speeds_build(&g->speeds[COMP_HALO], &g->sph, 1e-3, g->s.halo_rmax, hernquist_rho,
                            hernquist_dlnrho, &halo);
}

/* ---- potential table -------------------------------------------------- */

/* The galaxy's spherically averaged potential from its own enclosed mass:
 *   Phi(r) = -G M(rmax) / rmax - G integral_r^rmax M(r') / r'^2 dr',
 * with rmax the halo's truncation radius (all the mass is inside it).
 * Integrated inward with the trapezoid rule in ln r (dr = r d ln r), as the
 * Jeans tables are. */
static void build_potential_table(galaxy *g)
{
    double rmax = g->s.halo_rmax;
    double ln_lo = log(POT_R_MIN), dln = (log(rmax) - ln_lo) / (POT_N - 1);
    double integrand[POT_N];
    for (int j = 0; j < POT_N; j++) {
        double r = exp(ln_lo + j * dln);
        integrand[j] = MODEL_G * enclosed_mass(g, r) / r;
    }
    double phi = -MODEL_G * enclosed_mass(g, rmax) / rmax;
    g->pot[POT_N - 1] = phi;
    for (int j = POT_N - 2; j >= 0; j--) {
        phi -= 0.5 * (integrand[j] + integrand[j + 1]) * dln;
        g->pot[j] = phi;
    }
    g->pot_ln_rmin = ln_lo;
    g->pot_dln = dln;
}

/* Phi(r) by linear interpolation in ln r. Outside the truncation radius the
 * galaxy is a point mass; inside POT_R_MIN (1 pc) the value at 1 pc is kept
 * (the black hole's -G M / r would diverge). */
static double potential(const galaxy *g, double r)
{
    if (r >= g->s.halo_rmax)
        return -MODEL_G * enclosed_mass(g, r) / r;
    if (r <= POT_R_MIN)
        return g->pot[0];
    double t = (log(r) - g->pot_ln_rmin) / g->pot_dln;
    int j = (int)t;
    if (j >= POT_N - 1)
        return g->pot[POT_N - 1];
    double f = t - j;
    return g->pot[j] + f * (g->pot[j + 1] - g->pot[j]);
}

/* ---- geometry ---------------------------------------------------------- */

/* Unit vector towards galactic longitude l, latitude b (degrees) in the
 * model frame: +x to l = 0, +y to l = 90, +z to the north galactic pole. */
static orr_vec3 galactic_direction(double l_deg, double b_deg)
{
    double l = l_deg * ORR_PI / 180.0, b = b_deg * ORR_PI / 180.0;
    return orr_v3(cos(b) * cos(l), cos(b) * sin(l), sin(b));
}

/* A right-handed disc frame (e1, e2, spin) for a given spin axis. */
static void set_disc_frame(galaxy *g, orr_vec3 spin, orr_vec3 hint)
{
    g->spin = orr_v3_normalize(spin);
    g->e1 = orr_v3_normalize(orr_v3_cross(hint, g->spin));
    g->e2 = orr_v3_cross(g->spin, g->e1);
}

/* M31's centre: along the direction of M31 seen from the Sun, at the
 * distance D from the Sun for which |sun + D d| = separation (the positive
 * root of D^2 + 2 D (sun.d) + |sun|^2 - sep^2 = 0). */
static orr_vec3 m31_centre(double separation)
{
    orr_vec3 sun = orr_v3(SUN_X, 0.0, SUN_Z);
    orr_vec3 d = galactic_direction(M31_L_DEG, M31_B_DEG);
    double sd = orr_v3_dot(sun, d);
    double dist = -sd + sqrt(sd * sd - orr_v3_dot(sun, sun) + separation * separation);
    return orr_v3_add(sun, orr_v3_scale(d, dist));
}

static double galaxy_mass(const galaxy_spec *s)
{
    return s->disc_mass + s->bulge_mass + s->halo_mass + s->bh_mass;
}

/* Places M31 and gives both galaxies bulk velocities with zero total
 * momentum. The tangential direction is illustrative (the measured
 * tangential velocity has no well-constrained direction): it makes the
 * orbital angular momentum prograde with respect to the Milky Way's spin. */
static void set_orbit(model_state *m)
{
    galaxy *mw = &m->gal[GAL_MW], *m31 = &m->gal[GAL_M31];
    mw->centre = orr_v3(0, 0, 0);
    m31->centre = m31_centre(m->params.separation_kpc);
    orr_vec3 rhat = orr_v3_normalize(m31->centre);
    orr_vec3 that = orr_v3_normalize(orr_v3_cross(mw->spin, rhat));
    orr_vec3 vrel = orr_v3_add(orr_v3_scale(rhat, M31_VRAD), orr_v3_scale(that, M31_VTAN));
    double m_mw = galaxy_mass(&mw->s), m_m31 = galaxy_mass(&m31->s), mt = m_mw + m_m31;
    mw->velocity = orr_v3_scale(vrel, -m_m31 / mt);
    m31->velocity = orr_v3_scale(vrel, m_mw / mt);
}

static void init_galaxy(galaxy *g, const galaxy_spec *s, double q)
{
    g->s = *s;
    g->disc_frac = disc_cdf(s->disc_rmax, s->disc_rd);
    g->bulge_frac = hernquist_cdf(s->bulge_rmax, s->bulge_a);
    g->halo_frac = hernquist_cdf(s->halo_rmax, s->halo_a);
    /* Sigma0 of the untruncated profile whose mass within disc_rmax is disc_mass. */
    g->g_sigma0 = MODEL_G * s->disc_mass / (2.0 * ORR_PI * s->disc_rd * s->disc_rd * g->disc_frac);
    build_disc_table(g);
    set_disc_dispersion(g, q);
}

/* Which galaxies are present, and the marker particles: each present
 * galaxy's black hole, then the Sun when the Milky Way is there. Marker ids
 * are the well-known ones (1, 2, 3) whichever are present. */
static void choose_galaxies(model_state *m)
{
    int mode = m->params.galaxies;
    m->ngal = 0;
    m->nmarkers = 0;
    if (mode != ORR_MODEL_M31)
        m->gal_index[m->ngal++] = GAL_MW;
    if (mode != ORR_MODEL_MW)
        m->gal_index[m->ngal++] = GAL_M31;
    for (int k = 0; k < m->ngal; k++)
        m->marker_id[m->nmarkers++] = m->gal_index[k] == GAL_MW ? ORR_MODEL_ID_MW_BH : ORR_MODEL_ID_M31_BH;
    if (mode != ORR_MODEL_M31)
        m->marker_id[m->nmarkers++] = ORR_MODEL_ID_SUN;
}

/* Returns 0 on allocation failure. */
static int init_galaxies(model_state *m)
{
    double q = m->params.disc_q > 0 ? m->params.disc_q : ORR_MODEL_DISC_Q_DEFAULT;
    init_galaxy(&m->gal[GAL_MW], &SPEC[GAL_MW], q);
    init_galaxy(&m->gal[GAL_M31], &SPEC[GAL_M31], q);
    /* The Milky Way's angular momentum points to -z (clockwise seen from the
     * north galactic pole): the Sun at -x moves towards +y. */
    set_disc_frame(&m->gal[GAL_MW], orr_v3(0, 0, -1), orr_v3(0, 1, 0));
    set_disc_frame(&m->gal[GAL_M31], galactic_direction(M31_SPIN_L_DEG, M31_SPIN_B_DEG),
                   orr_v3(0, 0, 1));
    choose_galaxies(m);
    if (m->ngal == 2) {
        set_orbit(m);
    } else { /* alone: at rest at the origin, for isolation tests */
        galaxy *g = &m->gal[m->gal_index[0]];
        g->centre = orr_v3(0, 0, 0);
        g->velocity = orr_v3(0, 0, 0);
    }
    for (int k = 0; k < m->ngal; k++) {
        galaxy *g = &m->gal[m->gal_index[k]];
        build_potential_table(g);
        if (!build_sphere_dfs(g))
            return 0;
    }
    return 1;
}

/* ---- particle split ---------------------------------------------------- */

static double comp_mass(const galaxy_spec *s, int comp)
{
    return comp == COMP_DISC ? s->disc_mass : comp == COMP_BULGE ? s->bulge_mass : s->halo_mass;
}

static uint8_t comp_type(int comp)
{
    return comp == COMP_DISC ? ORR_MODEL_TYPE_DISC
           : comp == COMP_BULGE ? ORR_MODEL_TYPE_BULGE
                                : ORR_MODEL_TYPE_HALO;
}

/* A component's claim on particles: its mass in units of its particle
 * mass (star particles 1, halo particles HALO_MASS_RATIO). */
static double comp_weight(const galaxy_spec *s, int comp)
{
    return comp_mass(s, comp) / (comp == COMP_HALO ? HALO_MASS_RATIO : 1.0);
}

/* Every block gets at least one particle: an empty one takes one from the
 * largest (N >= 100 leaves the largest far above one). */
static void ensure_nonempty(model_state *m)
{
    for (int b = 0; b < m->nblocks; b++) {
        if (m->blocks[b].count)
            continue;
        int big = 0;
        for (int k = 1; k < m->nblocks; k++)
            if (m->blocks[k].count > m->blocks[big].count)
                big = k;
        m->blocks[big].count--;
        m->blocks[b].count = 1;
    }
}

/* Blocks in id order: MW disc, bulge, halo, then M31 disc, bulge, halo (the
 * galaxies present). Counts are the cumulative rounding of the weights, so
 * they add up to exactly N minus the markers and particle masses are
 * equal within each kind up to one particle's rounding. */
static void split_particles(model_state *m)
{
    uint64_t rest = m->total - (uint64_t)m->nmarkers;
    double wsum = 0.0;
    for (int k = 0; k < m->ngal; k++)
        for (int c = 0; c < COMP_COUNT; c++)
            wsum += comp_weight(&SPEC[m->gal_index[k]], c);
    double cum = 0.0;
    uint64_t prev = 0;
    m->nblocks = 0;
    for (int k = 0; k < m->ngal; k++) {
        for (int c = 0; c < COMP_COUNT; c++) {
            int gi = m->gal_index[k];
            cum += comp_weight(&SPEC[gi], c);
            uint64_t upto = (uint64_t)floor((double)rest * cum / wsum + 0.5);
            if (upto > rest)
                upto = rest;
            block *b = &m->blocks[m->nblocks++];
            b->count = upto - prev;
            b->gal = gi;
            b->comp = c;
            b->type = comp_type(c);
            prev = upto;
        }
    }
    m->blocks[m->nblocks - 1].count += rest - prev;
    ensure_nonempty(m);
    uint64_t first = (uint64_t)m->nmarkers;
    for (int b = 0; b < m->nblocks; b++) {
        block *bl = &m->blocks[b];
        bl->first = first;
        bl->mass = (float)(comp_mass(&SPEC[bl->gal], bl->comp) / (double)bl->count);
        first += bl->count;
    }
}

/* ---- sampling ---------------------------------------------------------- */

/* How much the spheroids' part of v_c^2 = R dPhi/dR is smaller at height z
 * than in the plane: G M_sph(<r) R^2 / r^3 - G M_sph(<R) / R, r^2 = R^2 + z^2.
 * Inside ~3 scale heights of the centre, where the bulge dominates, a star
 * one scale height up feels a radial pull 10% (R = 1 kpc) to 25% (0.5 kpc)
 * weaker than in the plane; given the plane's rotation, the inner disc had
 * too much angular momentum and lost a third of its mass inside 1 kpc in
 * 25 Myr, taking the bulge (which sat in its potential) out with it. The
 * disc's own pull is kept at its midplane value (it changes little within
 * the layer, whose mass is mostly farther out than its thickness). */
static double spheroid_vc2_drop(const galaxy *g, double R, double z)
{
    double r = sqrt(R * R + z * z);
    return MODEL_G * (spheroid_mass(g, r) * R * R / (r * r * r) - spheroid_mass(g, R) / R);
}

/* A disc star's velocity at (R, z) from three unit Gaussians, in the
 * epicyclic approximation (Hernquist 1993 sec. 2.2.3; Binney & Tremaine
 * 2008 eqs. 3.100, 4.228): sigma_R from the Q profile, sigma_phi^2 =
 * sigma_R^2 kappa^2 / (4 Omega^2), and the mean rotation lagging the
 * circular speed by the asymmetric drift,
 *   vphi_mean^2 = v_c^2 + sigma_R^2 (1 - kappa^2 / (4 Omega^2) + d ln(Sigma sigma_R^2) / d ln R)
 * (the last term is -2 R / Rd where sigma_R^2 ~ Sigma), v_c^2 being the
 * circular speed at the star's height (spheroid_vc2_drop). The drift term
 * is never let lift the mean above v_c: inside ~2 kpc, where the constant-Q
 * sigma_R rises outward, the formula asks for 3-8 km/s more than v_c, but
 * the Gaussians there are no equilibrium and that extra angular momentum
 * carried 12% of the disc's mass inside 1 kpc outward in 25 Myr (3% with
 * the mean held at v_c). The mean is clipped at 0 where the drift would
 * exceed the rotation (near the centre). */
static void disc_velocity(const galaxy *g, double R, double z, double gr, double gt, double gz, double *vr,
                          double *vphi, double *vz)
{
    double Rs = R > 1e-3 ? R : 1e-3; /* the kinematics are finite at the centre */
    double vc2 = disc_vc2(g, Rs), kappa2 = disc_kappa2(g, Rs);
    double ratio = kappa2 * Rs * Rs / (4.0 * vc2); /* kappa^2 / (4 Omega^2) */
    double sr = disc_sigma_r(g, Rs);
    double drift = fmin(0.0, sr * sr * (1.0 - ratio + disc_pressure_slope(g, Rs)));
    double mean2 = vc2 + spheroid_vc2_drop(g, Rs, z) + drift;
    *vr = sr * gr;
    *vphi = sqrt(fmax(0.0, mean2)) + sr * sqrt(ratio) * gt;
    *vz = sqrt(disc_sigma_z2(g, Rs, z)) * gz;
}

/* Exponential surface density: R = -Rd ln(u1 u2) samples the Gamma(2)
 * distribution R e^(-R/Rd) exactly; radii beyond the truncation are redrawn
 * from further values of the particle's own sequence (rare: 0.2% for the
 * MW). Vertical: exponential profile, z = -/+ hz ln(2u) on each side. */
static void sample_disc(const galaxy *g, orr_rng *r, particle *p)
{
    const galaxy_spec *s = &g->s;
    double R;
    do
        R = -s->disc_rd * log(orr_rng_uniform(r) * orr_rng_uniform(r));
    while (R > s->disc_rmax);
    double phi = 2.0 * ORR_PI * orr_rng_uniform(r);
    double u = orr_rng_uniform(r);
    double z = u < 0.5 ? s->disc_hz * log(2.0 * u) : -s->disc_hz * log(2.0 * (1.0 - u));

    orr_vec3 rhat = orr_v3_add(orr_v3_scale(g->e1, cos(phi)), orr_v3_scale(g->e2, sin(phi)));
    orr_vec3 that = orr_v3_cross(g->spin, rhat); /* direction of rotation */
    p->pos = orr_v3_add(g->centre, orr_v3_add(orr_v3_scale(rhat, R), orr_v3_scale(g->spin, z)));

    double gr, gt, gz, unused;
    orr_rng_gauss2(r, &gr, &gt);
    orr_rng_gauss2(r, &gz, &unused);
    double vr, vphi, vz;
    disc_velocity(g, R, z, gr, gt, gz, &vr, &vphi, &vz);
    orr_vec3 v = orr_v3_add(orr_v3_scale(rhat, vr), orr_v3_scale(that, vphi));
    p->vel = orr_v3_add(g->velocity, orr_v3_add(v, orr_v3_scale(g->spin, vz)));
}

/* Hernquist sphere truncated at rmax: the inverse CDF r = a s / (1 - s),
 * s = sqrt(u), with u scaled to (0, F(rmax)) so no redraw is needed.
 * Isotropic direction; the speed from the component's Eddington
 * distribution function at that radius, in an isotropic direction.
 * The bulge takes its f(E) into the disc's flattened potential
 * (galaxy_flat.h): a point drawn so is kept with probability
 * rho(r_eq) / (bound rho(r)) (else drawn again from the particle's own
 * sequence), and its speed is f's at r_eq. */
static void sample_sphere(const galaxy *g, int comp, orr_rng *r, particle *p)
{
    double a = comp == COMP_BULGE ? g->s.bulge_a : g->s.halo_a;
    double frac = comp == COMP_BULGE ? g->bulge_frac : g->halo_frac;
    sphere_ctx shape = {a};
    double rad, req;
    orr_vec3 dir;
    for (;;) {
        double sq = sqrt(orr_rng_uniform(r) * frac);
        rad = a * sq / (1.0 - sq);
        double cost = 2.0 * orr_rng_uniform(r) - 1.0, sint = sqrt(fmax(0.0, 1.0 - cost * cost));
        double phi = 2.0 * ORR_PI * orr_rng_uniform(r);
        dir = orr_v3(sint * cos(phi), sint * sin(phi), cost);
        if (comp != COMP_BULGE) {
            req = rad;
            break;
        }
        req = gdf_flat_req(&g->bulge_flat, rad, orr_v3_dot(dir, g->spin));
        double keep = hernquist_rho(req, &shape) / (g->bulge_flat.bound * hernquist_rho(rad, &shape));
        if (orr_rng_uniform(r) < keep)
            break;
    }
    p->pos = orr_v3_add(g->centre, orr_v3_scale(dir, rad));

    double speed = gdf_speed(&g->speeds[comp], &g->sph, req, orr_rng_uniform(r));
    double vcost = 2.0 * orr_rng_uniform(r) - 1.0, vsint = sqrt(fmax(0.0, 1.0 - vcost * vcost));
    double vphi = 2.0 * ORR_PI * orr_rng_uniform(r);
    orr_vec3 vdir = orr_v3(vsint * cos(vphi), vsint * sin(vphi), vcost);
    p->vel = orr_v3_add(g->velocity, orr_v3_scale(vdir, speed));
}

/* The markers: the black holes of the galaxies present, then the Sun. */
static void make_marker(const model_state *m, uint64_t index, particle *p)
{
    const galaxy *mw = &m->gal[GAL_MW];
    if (m->marker_id[index] != ORR_MODEL_ID_SUN) {
        const galaxy *g = &m->gal[m->marker_id[index] == ORR_MODEL_ID_MW_BH ? GAL_MW : GAL_M31];
        p->pos = g->centre;
        p->vel = g->velocity;
        p->mass = (float)g->s.bh_mass;
        p->type = ORR_MODEL_TYPE_BH;
        return;
    }
    /* The Sun: on the circular orbit of the MW's true potential in the disc
     * plane (disc_vc2), no random motion. */
    orr_vec3 rhat = orr_v3(-1, 0, 0);
    p->pos = orr_v3(SUN_X, 0.0, SUN_Z);
    p->vel = orr_v3_add(mw->velocity,
                        orr_v3_scale(orr_v3_cross(mw->spin, rhat), sqrt(disc_vc2(mw, -SUN_X))));
    p->mass = (float)SUN_MASS;
    p->type = ORR_MODEL_TYPE_SUN;
}

static const block *find_block(const model_state *m, uint64_t index)
{
    for (int b = 0; b < m->nblocks - 1; b++)
        if (index < m->blocks[b].first + m->blocks[b].count)
            return &m->blocks[b];
    return &m->blocks[m->nblocks - 1];
}

/* A particle's id: the markers' well-known ids, then MODEL_FIRST_ID on (so
 * with both galaxies, id = index + 1). */
static uint64_t particle_id(const model_state *m, uint64_t index)
{
    if (index < (uint64_t)m->nmarkers)
        return m->marker_id[index];
    return index - (uint64_t)m->nmarkers + MODEL_FIRST_ID;
}

/* Particle `index` (0-based), from nothing but the seed and the index. */
static void make_particle(const model_state *m, uint64_t index, particle *p)
{
    if (index < (uint64_t)m->nmarkers) {
        make_marker(m, index, p);
        p->r = 0.0f;
        p->e0 = 0.0f;
        return;
    }
    const block *b = find_block(m, index);
    const galaxy *g = &m->gal[b->gal];
    orr_rng r = orr_rng_seed(m->params.seed, index, 0);
    if (b->comp == COMP_DISC)
        sample_disc(g, &r, p);
    else
        sample_sphere(g, b->comp, &r, p);
    p->mass = b->mass;
    p->type = b->type;
    double rad = orr_v3_norm(orr_v3_sub(p->pos, g->centre));
    orr_vec3 v = orr_v3_sub(p->vel, g->velocity);
    p->r = (float)rad;
    p->e0 = (float)(potential(g, rad) + 0.5 * orr_v3_dot(v, v));
}

/* The dusty gas discs (model_dust.c), appended after every other particle:
 * each galaxy's disc frame and circular speeds handed over. */
static void plan_dust(model_state *m, long long dust_particles)
{
    m->dust_first = m->total;
    orr_model_dust_init(&m->dust, (uint64_t)dust_particles, m->params.seed);
    for (int k = 0; k < m->ngal && dust_particles > 0; k++) {
        const galaxy *g = &m->gal[m->gal_index[k]];
        orr_model_dust_disc *d =
            orr_model_dust_add(&m->dust, m->gal_index[k] == GAL_MW ? ORR_MODEL_DUST_MW : ORR_MODEL_DUST_M31);
        d->centre = g->centre;
        d->velocity = g->velocity;
        d->e1 = g->e1;
        d->e2 = g->e2;
        d->spin = g->spin;
        for (int i = 0; i < ORR_MODEL_DUST_VC_N; i++)
            d->vc[i] = sqrt(disc_vc2(g, d->rmax * i / (ORR_MODEL_DUST_VC_N - 1)));
    }
    orr_model_dust_split(&m->dust);
    m->total += m->dust.total;
}

static void make_gas(const model_state *m, uint64_t index, particle *p)
{
    orr_model_dust_make(&m->dust, index - m->dust_first, &p->pos, &p->vel, &p->mass, &p->r);
    p->type = ORR_MODEL_TYPE_GAS;
    p->e0 = 0.0f;
}

/* ---- the source -------------------------------------------------------- */

static orr_status model_next(orr_source *src, orr_error *err)
{
    (void)err;
    model_state *m = src->state;
    orr_chunk *c = &src->chunk;
    uint64_t left = m->total - m->next_index;
    size_t n = left < c->capacity ? (size_t)left : c->capacity;
    c->first_index = m->next_index;
    for (size_t k = 0; k < n; k++) {
        uint64_t index = m->next_index + k;
        particle p;
        if (index >= m->dust_first)
            make_gas(m, index, &p);
        else
            make_particle(m, index, &p);
        c->x[k] = (float)p.pos.x;
        c->y[k] = (float)p.pos.y;
        c->z[k] = (float)p.pos.z;
        c->mass[k] = p.mass;
        c->id[k] = particle_id(m, index);
        c->type[k] = p.type;
        c->extra[0].data[k] = (float)p.vel.x;
        c->extra[1].data[k] = (float)p.vel.y;
        c->extra[2].data[k] = (float)p.vel.z;
        c->extra[3].data[k] = p.r;
        c->extra[4].data[k] = p.e0;
    }
    c->n = n;
    m->next_index += n;
    return ORR_OK;
}

static orr_status model_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    ((model_state *)src->state)->next_index = 0;
    return ORR_OK;
}

static void model_close(orr_source *src)
{
    free(src->state);
    src->state = NULL;
}

/* Every particle is a pure function of its index: skipping costs nothing. */
static orr_status model_skip_chunk(orr_source *src, orr_error *err)
{
    (void)err;
    model_state *m = src->state;
    uint64_t left = m->total - m->next_index;
    m->next_index += left < src->chunk.capacity ? left : src->chunk.capacity;
    return ORR_OK;
}

static const orr_source_ops MODEL_OPS = {
    .next = model_next, .rewind = model_rewind, .close = model_close, .skip_chunk = model_skip_chunk};

static orr_status check_params(const orr_model_params *params, size_t chunk_size, orr_error *err)
{
    if (!params)
        return orr_fail(err, ORR_ERR_USAGE, "model: no parameters given");
    if (params->particles < MODEL_PARTICLES_MIN || params->particles > ORR_MODEL_PARTICLES_MAX)
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: %lld particles requested; the mw-m31 model needs %d to %lld "
                        "(3 of them are the Sun and black-hole markers)",
                        params->particles, MODEL_PARTICLES_MIN, (long long)ORR_MODEL_PARTICLES_MAX);
    if (params->galaxies == ORR_MODEL_PAIR && !(params->separation_kpc >= MODEL_SEPARATION_MIN && params->separation_kpc <= MODEL_SEPARATION_MAX))
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: separation %g kpc is out of range (%g to %g kpc; 780 is today's "
                        "Milky Way-Andromeda distance)",
                        params->separation_kpc, MODEL_SEPARATION_MIN, MODEL_SEPARATION_MAX);
    if (params->galaxies != ORR_MODEL_PAIR && params->galaxies != ORR_MODEL_MW && params->galaxies != ORR_MODEL_M31)
        return orr_fail(err, ORR_ERR_USAGE, "model: galaxies = %d is not one of pair (0), mw (1), m31 (2)",
                        params->galaxies);
    /* 0 selects the default; anything else must be a positive finite Q. */
    if (params->disc_q != 0.0 && !(params->disc_q > 0.0 && params->disc_q <= DISC_Q_MAX))
        return orr_fail(err, ORR_ERR_USAGE,
                        "model: disc_q (the discs' Toomre Q) is %g; it must be above 0 (stable discs "
                        "need Q > 1; at most %g)",
                        params->disc_q, DISC_Q_MAX);
    if (chunk_size == 0)
        return orr_fail(err, ORR_ERR_USAGE, "model: chunk size must be at least 1 particle");
    return ORR_OK;
}

static void fill_info(orr_source_info *info, const orr_model_params *params)
{
    snprintf(info->format, sizeof info->format, "model:mw-m31");
    double q = params->disc_q > 0 ? params->disc_q : ORR_MODEL_DISC_Q_DEFAULT;
    if (params->galaxies == ORR_MODEL_PAIR)
        snprintf(info->path, sizeof info->path,
                 "built-in model mw-m31 (N=%lld, seed=%llu, separation=%g kpc, disc Q=%g)", params->particles,
                 (unsigned long long)params->seed, params->separation_kpc, q);
    else
        snprintf(info->path, sizeof info->path, "built-in model mw-m31 (N=%lld, seed=%llu, %s alone, disc Q=%g)",
                 params->particles, (unsigned long long)params->seed,
                 params->galaxies == ORR_MODEL_MW ? "Milky Way" : "M31", q);
    info->count = params->particles;
    info->time = 0.0;
    info->has_h = 0;
    info->has_id = 1;
    info->has_type = 1;
    info->nextra = MODEL_FIELDS;
    for (int i = 0; i < MODEL_FIELDS; i++)
        snprintf(info->extra_names[i], sizeof info->extra_names[i], "%s", FIELD_NAMES[i]);
}

orr_status orr_model_source_open(const orr_model_params *params, size_t chunk_size, orr_source **out,
                                 orr_error *err)
{
    return orr_model_source_open_dust(params, 0, chunk_size, out, err);
}

orr_status orr_model_source_open_dust(const orr_model_params *params, long long dust_particles, size_t chunk_size,
                                      orr_source **out, orr_error *err)
{
    *out = NULL;
    orr_status st = check_params(params, chunk_size, err);
    if (!st && (dust_particles < 0 || dust_particles > ORR_MODEL_PARTICLES_MAX - params->particles))
        st = orr_fail(err, ORR_ERR_USAGE, "model: dust_particles = %lld: 0 (no dusty gas discs) to %lld",
                      dust_particles, (long long)ORR_MODEL_PARTICLES_MAX - params->particles);
    if (st != ORR_OK)
        return st;
    orr_source *src = orr_source_new("model", "", &MODEL_OPS, sizeof(model_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    model_state *m = src->state;
    m->params = *params;
    m->total = (uint64_t)params->particles;
    if (!init_galaxies(m)) {
        orr_source_close(src);
        return orr_fail(err, ORR_ERR_NOMEM, "model: out of memory building the distribution functions");
    }
    split_particles(m);
    plan_dust(m, dust_particles);
    fill_info(&src->info, params);
    src->info.count = (int64_t)m->total;

    size_t cap = (uint64_t)chunk_size < m->total ? chunk_size : (size_t)m->total;
    st = orr_chunk_alloc(&src->chunk, cap, 0, FIELD_NAMES, MODEL_FIELDS, err);
    if (st != ORR_OK) {
        orr_source_close(src);
        return st;
    }
    *out = src;
    return ORR_OK;
}

const orr_named orr_model_galaxies_names[] = {
    {"pair", ORR_MODEL_PAIR}, {"mw", ORR_MODEL_MW}, {"m31", ORR_MODEL_M31}, {NULL, 0}};

int orr_model_galaxies_named(const char *word)
{
    int g;
    return orr_named_value(orr_model_galaxies_names, word, &g) ? g : -1;
}
