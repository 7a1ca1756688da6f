/* One galaxy of the mw-m31 model (model_galaxy.h): the equilibrium recipe
 * of model.c's opening comment, profile by profile. */
#include "source/models/model_galaxy.h"

#include <math.h>

/* ---- profiles ---------------------------------------------------------- */

/* Mass fraction of an exponential disc within cylindrical radius R. */
static double disc_cdf(double R, double rd)
{
    double x = R / rd;
    return 1.0 - (1.0 + x) * exp(-x);
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
    return disc_sphere_mass(g, r) + orr_model_spheroid_mass(g, r);
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
#pragma omp parallel for schedule(dynamic, 1) /* nodes are independent */
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
    const double *v = g->disc_v2;
    return orr_model_catmull_rom(v[i > 0 ? i - 1 : 0], v[i], v[i + 1], v[i + 2 < DISC_TAB_N ? i + 2 : i + 1], t - i);
}

/* v_c^2 in the disc plane: the thick disc's own plus the spherical
 * components'. This is the circular speed the disc must rotate at; the
 * spherical approximation of the disc is ~10% off near 2 Rd, the thin-disc
 * formula 5-15% in v^2 within 3 Rd. */
double orr_model_galaxy_disc_vc2(const galaxy *g, double R)
{
    return disc_own_vc2(g, R) + MODEL_G * orr_model_spheroid_mass(g, R) / R;
}

/* kappa^2 = R d(Omega^2)/dR + 4 Omega^2 = (dv_c^2/dR) / R + 2 v_c^2 / R^2
 * (Binney & Tremaine 2008 eq. 3.80), the derivative by central difference. */
double orr_model_galaxy_disc_kappa2(const galaxy *g, double R)
{
    double h = 1e-3 * R;
    double dv2 = (orr_model_galaxy_disc_vc2(g, R + h) - orr_model_galaxy_disc_vc2(g, R - h)) / (2.0 * h);
    return dv2 / R + 2.0 * orr_model_galaxy_disc_vc2(g, R) / (R * R);
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
    g->sigma_r_ref = q * 3.36 * disc_surface_density_g(g, rref) / sqrt(orr_model_galaxy_disc_kappa2(g, rref));
}

/* Outside R_ref, Hernquist's profile. Inside, where it would make Q rise
 * steeply (sigma_R reaching 80-130 km/s, half of v_c, within 3 kpc of the
 * Milky Way: a disc far too hot for the epicyclic Gaussians, which puffed
 * up and spread within 25 Myr, taking the bulge with it), Q is held at q:
 * sigma_R = q 3.36 G Sigma / kappa, which is continuous at R_ref and about
 * sigma_z there (cf. Springel, Di Matteo & Hernquist 2005, MNRAS 361, 776,
 * who take sigma_R = sigma_z). The smaller of the two is used. */
double orr_model_galaxy_disc_sigma_r(const galaxy *g, double R)
{
    double hern = g->sigma_r_ref * exp(-(R - DISC_Q_RADIUS * g->s.disc_rd) / (2.0 * g->s.disc_rd));
    if (R >= DISC_Q_RADIUS * g->s.disc_rd)
        return hern;
    double flat_q = g->disc_q * 3.36 * disc_surface_density_g(g, R) / sqrt(orr_model_galaxy_disc_kappa2(g, R));
    return fmin(hern, flat_q);
}

/* d ln(Sigma sigma_R^2) / d ln R, by central difference: the pressure term
 * of the radial Jeans equation (-2 R / Rd for Hernquist's sigma_R^2 ~ Sigma). */
double orr_model_galaxy_disc_pressure_slope(const galaxy *g, double R)
{
    double h = 1e-3 * R;
    double lo = orr_model_galaxy_disc_sigma_r(g, R - h), hi = orr_model_galaxy_disc_sigma_r(g, R + h);
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
    return MODEL_G * orr_model_spheroid_mass(g, r) * zp / (r * r * r);
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
double orr_model_galaxy_disc_sheet(const galaxy *g, double R)
{
    return 2.0 * ORR_PI * disc_surface_density_g(g, R) * g->s.disc_hz;
}

double orr_model_galaxy_disc_radial(const galaxy *g, double R)
{
    double dR = 1e-3 * R;
    return (disc_own_vc2(g, R + dR) - disc_own_vc2(g, R - dR)) / (2.0 * dR * R);
}

double orr_model_galaxy_spheroid_pull(const galaxy *g, double R, double az)
{
    double h = g->s.disc_hz, sph = 0.0;
    for (int k = 0; k < SIGMA_Z_NODES; k++) {
        double u = (k + 0.5) / SIGMA_Z_NODES;
        sph += spheroid_pull_z(g, R, az - h * log(u));
    }
    return sph * (h / SIGMA_Z_NODES);
}

double orr_model_galaxy_disc_sigma_z2(const galaxy *g, double R, double z)
{
    double h = g->s.disc_hz, az = fabs(z);
    double sheet = orr_model_galaxy_disc_sheet(g, R) * (1.0 - 0.5 * exp(-az / h));
    double sph = orr_model_galaxy_spheroid_pull(g, R, az);
    return fmax(1.0, sheet + sph - orr_model_galaxy_disc_radial(g, R) * h * (az + h));
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
int orr_model_galaxy_build_dfs(galaxy *g)
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
void orr_model_galaxy_build_potential(galaxy *g)
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
double orr_model_galaxy_potential(const galaxy *g, double r)
{
    return orr_model_galaxy_potential_ln(g, r, r > POT_R_MIN ? log(r) : 0.0);
}

double orr_model_galaxy_potential_ln(const galaxy *g, double r, double ln_r)
{
    if (r >= g->s.halo_rmax)
        return -MODEL_G * enclosed_mass(g, r) / r;
    if (r <= POT_R_MIN)
        return g->pot[0];
    double t = (ln_r - g->pot_ln_rmin) / g->pot_dln;
    int j = (int)t;
    if (j >= POT_N - 1)
        return g->pot[POT_N - 1];
    double f = t - j;
    return g->pot[j] + f * (g->pot[j + 1] - g->pot[j]);
}

/* ---- setup ------------------------------------------------------------- */

void orr_model_galaxy_init(galaxy *g, const galaxy_spec *s, double q)
{
    g->s = *s;
    g->disc_frac = disc_cdf(s->disc_rmax, s->disc_rd);
    g->bulge_frac = orr_model_hernquist_cdf(s->bulge_rmax, s->bulge_a);
    g->halo_frac = orr_model_hernquist_cdf(s->halo_rmax, s->halo_a);
    /* Sigma0 of the untruncated profile whose mass within disc_rmax is disc_mass. */
    g->g_sigma0 = MODEL_G * s->disc_mass / (2.0 * ORR_PI * s->disc_rd * s->disc_rd * g->disc_frac);
    build_disc_table(g);
    set_disc_dispersion(g, q);
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
    return MODEL_G * (orr_model_spheroid_mass(g, r) * R * R / (r * r * r) - orr_model_spheroid_mass(g, R) / R);
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
void orr_model_galaxy_disc_velocity(const galaxy *g, double R, double z, double gr, double gt, double gz, double *vr,
                                    double *vphi, double *vz)
{
    double Rs = R > 1e-3 ? R : 1e-3; /* the kinematics are finite at the centre */
    double vc2 = orr_model_galaxy_disc_vc2(g, Rs), kappa2 = orr_model_galaxy_disc_kappa2(g, Rs);
    double ratio = kappa2 * Rs * Rs / (4.0 * vc2); /* kappa^2 / (4 Omega^2) */
    double sr = orr_model_galaxy_disc_sigma_r(g, Rs);
    double drift = fmin(0.0, sr * sr * (1.0 - ratio + orr_model_galaxy_disc_pressure_slope(g, Rs)));
    double mean2 = vc2 + spheroid_vc2_drop(g, Rs, z) + drift;
    *vr = sr * gr;
    *vphi = sqrt(fmax(0.0, mean2)) + sr * sqrt(ratio) * gt;
    *vz = sqrt(orr_model_galaxy_disc_sigma_z2(g, Rs, z)) * gz;
}

/* Exponential surface density: R = -Rd ln(u1 u2) samples the Gamma(2)
 * distribution R e^(-R/Rd) exactly; radii beyond the truncation are redrawn
 * from further values of the particle's own sequence (rare: 0.2% for the
 * MW). Vertical: exponential profile, z = -/+ hz ln(2u) on each side. */
void orr_model_galaxy_sample_disc(const galaxy *g, orr_rng *r, particle *p)
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
    orr_model_galaxy_disc_velocity(g, R, z, gr, gt, gz, &vr, &vphi, &vz);
    orr_vec3 v = orr_v3_add(orr_v3_scale(rhat, vr), orr_v3_scale(that, vphi));
    p->vel = orr_v3_add(g->velocity, orr_v3_add(v, orr_v3_scale(g->spin, vz)));
    p->ez = orr_model_disc_ez(gz, fabs(z), s->disc_hz);
}

/* Hernquist sphere truncated at rmax: the inverse CDF r = a s / (1 - s),
 * s = sqrt(u), with u scaled to (0, F(rmax)) so no redraw is needed.
 * Isotropic direction; the speed from the component's Eddington
 * distribution function at that radius, in an isotropic direction.
 * The bulge takes its f(E) into the disc's flattened potential
 * (galaxy_flat.h): a point drawn so is kept with probability
 * rho(r_eq) / (bound rho(r)) (else drawn again from the particle's own
 * sequence), and its speed is f's at r_eq. */
/* sin and cos of 2 pi u: libm's for the exact recipe, orr_sincos_turn's
 * (within a few 1e-16, four times cheaper) for the tabulated model. */
static void turn(double u, int fast, double *s, double *c)
{
    if (fast) {
        orr_sincos_turn(u, s, c);
        return;
    }
    double phi = 2.0 * ORR_PI * u;
    *s = sin(phi);
    *c = cos(phi);
}

/* The position part: radius rad, direction dir, and the equivalent radius
 * req whose f(E) gives the speed. */
static void sphere_point(const galaxy *g, int comp, int fast, orr_rng *r, double *rad_out, double *req_out,
                         orr_vec3 *dir_out)
{
    double a = comp == COMP_BULGE ? g->s.bulge_a : g->s.halo_a;
    double frac = comp == COMP_BULGE ? g->bulge_frac : g->halo_frac;
    sphere_ctx shape = {a};
    double rad, req;
    orr_vec3 dir;
    for (;;) {
        double sq = sqrt(orr_rng_uniform(r) * frac);
        rad = a * sq / (1.0 - sq);
        double cost = 2.0 * orr_rng_uniform(r) - 1.0, sint = sqrt(1.0 - cost * cost); /* |cost| < 1 */
        double sn, cs;
        turn(orr_rng_uniform(r), fast, &sn, &cs);
        dir = orr_v3(sint * cs, sint * sn, cost);
        if (comp != COMP_BULGE) {
            req = rad;
            break;
        }
        req = gdf_flat_req(&g->bulge_flat, rad, orr_v3_dot(dir, g->spin));
        double keep = hernquist_rho(req, &shape) / (g->bulge_flat.bound * hernquist_rho(rad, &shape));
        if (orr_rng_uniform(r) < keep)
            break;
    }
    *rad_out = rad;
    *req_out = req;
    *dir_out = dir;
}

/* The velocity's isotropic direction. */
static orr_vec3 isotropic_direction(orr_rng *r, int fast)
{
    double vcost = 2.0 * orr_rng_uniform(r) - 1.0, vsint = sqrt(1.0 - vcost * vcost), sn, cs; /* |vcost| < 1 */
    turn(orr_rng_uniform(r), fast, &sn, &cs);
    return orr_v3(vsint * cs, vsint * sn, vcost);
}

void orr_model_galaxy_sample_sphere(const galaxy *g, int comp, orr_rng *r, particle *p)
{
    double rad, req;
    orr_vec3 dir;
    sphere_point(g, comp, 0, r, &rad, &req, &dir);
    p->pos = orr_v3_add(g->centre, orr_v3_scale(dir, rad));
    double speed = gdf_speed(&g->speeds[comp], &g->sph, req, orr_rng_uniform(r));
    p->vel = orr_v3_add(g->velocity, orr_v3_scale(isotropic_direction(r, 0), speed));
    p->ez = 0.0f;
}

/* The same, each radius's logarithm taken once for the speed table, the
 * escape speed and the potential (three before), and the angles by
 * orr_sincos_turn; r and e0 from the radius and speed drawn. */
void orr_model_galaxy_sample_sphere_fast(const galaxy *g, int comp, orr_rng *r, particle *p)
{
    double rad, req;
    orr_vec3 dir;
    sphere_point(g, comp, 1, r, &rad, &req, &dir);
    p->pos = orr_v3_add(g->centre, orr_v3_scale(dir, rad));
    double ln_rad = log(rad), ln_req = req == rad ? ln_rad : log(req);
    double speed = gdf_speed_ln(&g->speeds[comp], &g->sph, req, ln_req, orr_rng_uniform(r));
    p->vel = orr_v3_add(g->velocity, orr_v3_scale(isotropic_direction(r, 1), speed));
    p->r = (float)rad;
    p->e0 = (float)(orr_model_galaxy_potential_ln(g, rad, ln_rad) + 0.5 * speed * speed);
    p->ez = 0.0f;
}
