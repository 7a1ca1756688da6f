#include "source/models/model_dust.h"

#include <math.h>
#include <string.h>

#include "source/models/rng.h"

/* Stream of the generator, apart from the stars' (model.c uses 0). */
#define GAS_STREAM 0x6761730000000001ULL

/* The galaxies' gas (masses in 1e10 Msun, lengths in kpc):
 * - Milky Way: ~7e9 Msun of interstellar gas (atomic ~ 5-6e9 plus
 *   molecular ~1e9: Kalberla & Kerp 2009, ARA&A 47, 27; Heyer & Dame 2015,
 *   ARA&A 53, 583), which with the usual dust-to-gas ratio 0.01 gives the
 *   Milky Way's ~7e7 Msun of dust.
 * - M31: ~6e9 Msun (HI 5.2e9, Braun et al. 2009, ApJ 695, 937, plus
 *   ~0.4e9 of H2, Nieten et al. 2006).
 * Scale lengths 1.5 times the stellar discs' (3 and 5 kpc in model.c): dust
 * discs are radially more extended than the stars (Xilouris et al. 1999,
 * A&A 344, 868: 1.4; Casasola et al. 2017, A&A 605, A18: about 1.8);
 * exponential scale height 0.1 kpc, that of the Milky Way's dust layer
 * (Drimmel & Spergel 2001, ApJ 556, 181: 0.134 kpc; Marshall et al. 2006:
 * 0.125 kpc); cut at the stellar discs' truncation radii. */
static const struct {
    double gas_mass, rd, hz, rmax;
} GAS[2] = {
    {0.7, 4.5, 0.1, 25.0},
    {0.6, 7.5, 0.1, 40.0},
};

/* Stream of the clumping field's waves. */
#define CLUMP_STREAM 0x636c756d70000001ULL
/* The clouds' wavelengths, kpc: from a giant molecular cloud complex to
 * the lanes between spiral arms, equal power per octave. */
#define CLUMP_LAMBDA_MIN 0.1
#define CLUMP_LAMBDA_MAX 2.0

/* The field's plane waves: directions uniform on the sphere, but squeezed
 * into the disc plane (the vertical wave number times 1/3), since clouds are
 * flatter than they are wide; wave numbers log-uniform between the
 * wavelengths; phases uniform. A pure function of the seed. */
static void clumping_waves(orr_model_dust *d)
{
    orr_rng rng = orr_rng_seed(d->seed, 0, CLUMP_STREAM);
    for (int j = 0; j < ORR_MODEL_DUST_WAVES; j++) {
        double u = 2.0 * orr_rng_uniform(&rng) - 1.0, phi = 6.283185307179586 * orr_rng_uniform(&rng);
        double s = sqrt(1.0 - u * u);
        double lambda = CLUMP_LAMBDA_MIN * pow(CLUMP_LAMBDA_MAX / CLUMP_LAMBDA_MIN, orr_rng_uniform(&rng));
        double k = 6.283185307179586 / lambda;
        d->wave[j][0] = k * s * cos(phi);
        d->wave[j][1] = k * s * sin(phi);
        d->wave[j][2] = k * u / 3.0;
        d->wave[j][3] = 6.283185307179586 * orr_rng_uniform(&rng);
    }
}

void orr_model_dust_init(orr_model_dust *d, uint64_t total, uint64_t seed, double clumping)
{
    memset(d, 0, sizeof *d);
    d->total = total;
    d->seed = seed;
    d->clumping = clumping;
    if (clumping > 0)
        clumping_waves(d);
}

/* The clumping factor at x, y, z of the disc frame (kpc): exp(sigma g -
 * sigma^2 / 2), g = sqrt(2 / N) sum cos(k . x + phase), of zero mean and
 * unit variance, so the factor's mean is 1 and the gas mass is kept on
 * average. */
static double clumping_factor(const orr_model_dust *d, double x, double y, double z)
{
    double g = 0.0;
    for (int j = 0; j < ORR_MODEL_DUST_WAVES; j++)
        g += cos(d->wave[j][0] * x + d->wave[j][1] * y + d->wave[j][2] * z + d->wave[j][3]);
    g *= sqrt(2.0 / ORR_MODEL_DUST_WAVES);
    return exp(d->clumping * g - 0.5 * d->clumping * d->clumping);
}

orr_model_dust_disc *orr_model_dust_add(orr_model_dust *d, int galaxy)
{
    orr_model_dust_disc *g = &d->disc[d->ndisc++];
    memset(g, 0, sizeof *g);
    g->gas_mass = GAS[galaxy].gas_mass;
    g->rd = GAS[galaxy].rd;
    g->hz = GAS[galaxy].hz;
    g->rmax = GAS[galaxy].rmax;
    return g;
}

void orr_model_dust_split(orr_model_dust *d)
{
    double sum = 0;
    for (int k = 0; k < d->ndisc; k++)
        sum += d->disc[k].gas_mass;
    uint64_t first = 0;
    for (int k = 0; k < d->ndisc; k++) {
        orr_model_dust_disc *g = &d->disc[k];
        g->first = first;
        g->count = k == d->ndisc - 1 ? d->total - first : (uint64_t)floor((double)d->total * g->gas_mass / sum + 0.5);
        g->mass = g->count ? (float)(g->gas_mass / (double)g->count) : 0.0f;
        first += g->count;
    }
}

/* A radius of the exponential disc Sigma ~ exp(-R/rd), cut at rmax: the
 * surface density times 2 pi R is a Gamma(2) law, the sum of two
 * exponential deviates; draws beyond rmax are redrawn. */
static double disc_radius(orr_rng *r, double rd, double rmax)
{
    for (;;) {
        double R = -rd * log(orr_rng_uniform(r) * orr_rng_uniform(r));
        if (R <= rmax)
            return R;
    }
}

static double circular_speed(const orr_model_dust_disc *g, double R)
{
    double u = R / g->rmax * (ORR_MODEL_DUST_VC_N - 1);
    int i = (int)u;
    if (i >= ORR_MODEL_DUST_VC_N - 1)
        return g->vc[ORR_MODEL_DUST_VC_N - 1];
    return g->vc[i] + (u - i) * (g->vc[i + 1] - g->vc[i]);
}

void orr_model_dust_make(const orr_model_dust *d, uint64_t k, orr_vec3 *pos, orr_vec3 *vel, float *mass, float *r)
{
    int gi = 0;
    while (gi < d->ndisc - 1 && k >= d->disc[gi].first + d->disc[gi].count)
        gi++;
    const orr_model_dust_disc *g = &d->disc[gi];
    orr_rng rng = orr_rng_seed(d->seed, k, GAS_STREAM);
    const double R = disc_radius(&rng, g->rd, g->rmax);
    const double phi = 6.283185307179586 * orr_rng_uniform(&rng);
    /* exponential in |z|: an exponential deviate with a random sign */
    const double zabs = -g->hz * log(orr_rng_uniform(&rng));
    const double z = orr_rng_uniform(&rng) < 0.5 ? -zabs : zabs;
    const double c = cos(phi), s = sin(phi);
    orr_vec3 rhat = orr_v3_add(orr_v3_scale(g->e1, c), orr_v3_scale(g->e2, s));
    orr_vec3 off = orr_v3_add(orr_v3_scale(rhat, R), orr_v3_scale(g->spin, z));
    *pos = orr_v3_add(g->centre, off);
    /* cold gas on circular orbits, in the sense of the disc's spin */
    *vel = orr_v3_add(g->velocity, orr_v3_scale(orr_v3_cross(g->spin, rhat), circular_speed(g, R)));
    *mass = d->clumping > 0 ? (float)(g->mass * clumping_factor(d, R * c, R * s, z)) : g->mass;
    *r = (float)orr_v3_norm(off);
}
