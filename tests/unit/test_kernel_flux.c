/* The flux from light spread over a particle's kernel (stars/kernel_flux.h)
 * against independent truths: Dawson's integral's closed form (the
 * integral summed here by Simpson's rule), a brute-force sum over the sky
 * of the kernel's column density, 1/r^2 far away and 1/sigma^2 at the
 * centre; and the glow's dimming (stars/stars.h) against the stars
 * actually drawn: over many particles, what the stars bring plus what the
 * glow brings is the whole kernel's flux, L E[1/s^2]. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "test_chunk.h"
#include "stars/kernel_flux.h"
#include "stars/stars.h"

static const double pi = 3.14159265358979323846;

/* Dawson's integral D(x) = exp(-x^2) int_0^x exp(t^2) dt
 * = int_0^x exp(-u (2x - u)) du (u = x - t), by Simpson's rule on 20 000
 * intervals of [0, min(x, 40/x)]: beyond, the integrand is below exp(-40). */
static double dawson_simpson(double x)
{
    const int n = 20000;
    const double top = x < 40.0 / x ? x : 40.0 / x, h = top / n;
    double sum = 1.0 + exp(-top * (2 * x - top));
    for (int k = 1; k < n; k++) {
        const double u = k * h;
        sum += (k % 2 ? 4.0 : 2.0) * exp(-u * (2 * x - u));
    }
    return sum * h / 3.0;
}

/* E[1/s^2] in closed form: sqrt(2) / (sigma mu) D(mu / (sqrt(2) sigma)). */
static double closed_form(double mu, double sigma)
{
    return sqrt(2.0) / (sigma * mu) * dawson_simpson(mu / (sqrt(2.0) * sigma));
}

/* The same, as the observer sees it: the flux of a unit of light spread
 * over the kernel is the sky's integral of its column density,
 * int dOmega int_0^inf rho(s n) ds (the shell's s^2 cancels the flux's
 * 1/s^2). The kernel is symmetric about the axis to its centre: a sum over
 * the angle theta from that axis and the distance s, midpoints. */
static double sky_sum(double mu, double sigma)
{
    const int nt = 1500, ns = 3000;
    const double smax = mu + 9 * sigma, ds = smax / ns, dt = pi / nt;
    const double norm = pow(2 * pi * sigma * sigma, -1.5);
    double total = 0;
    for (int a = 0; a < nt; a++) {
        const double theta = (a + 0.5) * dt, c = cos(theta);
        double column = 0;
        for (int b = 0; b < ns; b++) {
            const double s = (b + 0.5) * ds;
            column += exp(-(s * s - 2 * s * mu * c + mu * mu) / (2 * sigma * sigma));
        }
        total += 2 * pi * sin(theta) * dt * column * ds * norm;
    }
    return total;
}

static double one(double s, const void *user)
{
    (void)s, (void)user;
    return 1.0;
}

/* The quadrature's own light: the kernel's whole light, at any distance. */
static void test_quadrature_holds_the_light(void)
{
    const double sigma = 0.139;
    const double mus[] = {0.0, 0.02, 0.139, 0.5, 1.1, 3.0, 30.0};
    for (size_t k = 0; k < sizeof mus / sizeof *mus; k++) {
        orr_kernel_part p = orr_kernel_weighted(mus[k], sigma, 0.0, HUGE_VAL, -1.0, one, NULL);
        CHECK_NEAR(p.light, 1.0, 1e-9);
        /* ... and with w = 1 its flux is E[1/s^2] */
        CHECK_NEAR(p.flux / orr_kernel_inv_r2(mus[k], sigma), 1.0, 1e-9);
    }
}

static void test_closed_form(void)
{
    const double sigma = 0.139;
    CHECK_NEAR(orr_kernel_inv_r2(0.0, sigma) * sigma * sigma, 1.0, 1e-9);
    const double ratios[] = {1e-3, 0.1, 0.26, 0.5, 1.0, 2.0, 4.0, 7.99, 8.01, 12.0, 40.0, 300.0};
    for (size_t k = 0; k < sizeof ratios / sizeof *ratios; k++) {
        const double mu = ratios[k] * sigma;
        const double got = orr_kernel_inv_r2(mu, sigma), want = closed_form(mu, sigma);
        if (fabs(got / want - 1) > 1e-8)
            printf("  mu/sigma %g: %.12g against %.12g\n", ratios[k], got, want);
        CHECK_NEAR(got / want, 1.0, 1e-8);
    }
}

/* Two cases of the short Future Sky run: the particle 36 pc from the Sun
 * in frame 7 (1/r^2 would be 772 kpc^-2, the kernel gives 51), and one at
 * 0.3 kpc; and one far enough for the series. */
static void test_sky_sum(void)
{
    const double cases[][2] = {{0.036, 0.139}, {0.3, 0.139}, {1.5, 0.139}};
    for (size_t k = 0; k < 3; k++) {
        const double mu = cases[k][0], sigma = cases[k][1];
        CHECK_NEAR(orr_kernel_inv_r2(mu, sigma) / sky_sum(mu, sigma), 1.0, 5e-5); /* (the grid's own error) */
    }
}

/* 1/mu^2 far away, to the series' first term; 1/sigma^2 at the centre and
 * never more; falling with distance; no step where the series takes over. */
static void test_limits(void)
{
    const double sigma = 0.085;
    for (double mu = 1.0; mu <= 100.0; mu *= 10.0) {
        const double x = sigma * sigma / (mu * mu);
        CHECK_NEAR(orr_kernel_inv_r2(mu, sigma) * mu * mu, 1.0 + x + 3 * x * x, 20 * x * x * x + 1e-14);
    }
    double last = orr_kernel_inv_r2(0.0, sigma);
    CHECK_NEAR(last * sigma * sigma, 1.0, 1e-9);
    for (double mu = 0.001; mu < 2.0; mu *= 1.1) {
        const double k = orr_kernel_inv_r2(mu, sigma);
        CHECK(k < last);
        last = k;
    }
    const double edge = 8.0 * sigma;
    CHECK_NEAR(orr_kernel_inv_r2(edge * (1 - 1e-12), sigma) / orr_kernel_inv_r2(edge, sigma), 1.0, 1e-9);
}

static orr_stars stars_to(double limit)
{
    orr_stars_settings set;
    orr_stars_defaults(&set);
    set.enabled = 1;
    set.limit = limit;
    set.types = 1u << 2;
    orr_stars st;
    orr_error err = {0};
    CHECK(orr_stars_prepare(&st, &set, "test.yaml", &err) == ORR_OK);
    return st;
}

/* n disc particles of light `light` (solar V) at (r, 0, 0) kpc, ids from first. */
static orr_chunk particles_at(size_t n, double r, float light, uint64_t first, float *xyz[3])
{
    orr_chunk c = test_chunk(n, NULL, 0);
    for (size_t i = 0; i < n; i++) {
        c.x[i] = (float)r, c.y[i] = 0.0f, c.z[i] = 0.0f;
        c.mass[i] = 9.35e-5f; /* the short run's disc particle: sigma 139 pc */
        c.type[i] = 2;
        c.id[i] = first + i;
        xyz[0][i] = light, xyz[1][i] = light, xyz[2][i] = light;
    }
    return c;
}

/* The share of a particle's light in the stars the draw shows, if they
 * lie at s pc, by the draw's rule (stars/stars.h): of the stars brighter
 * than m_lim (the faintest that could be seen from its nearest search
 * distance, max(r - 3 sigma, 10 pc)) those whose apparent V from s reaches
 * the limit. */
static double shown_share(const orr_stars *st, double r_pc, double sigma_pc, double s_pc)
{
    const double nearest = fmax(r_pc - 3 * sigma_pc, 10.0);
    const double m_lim = st->set.limit - 5 * log10(nearest / 10.0);
    const double seen = st->set.limit - 5 * log10(s_pc / 10.0);
    return orr_lf_light_brighter(&st->lf, fmin(seen, m_lim)) / orr_lf_light_per_mass(&st->lf);
}

/* Brute force over the kernel seen from the observer (sky_sum's grid):
 * the share of the light the stars shown take, and their share of
 * E[1/s^2]; r and sigma in kpc, the flux in kpc^-2. */
static void shown_part(const orr_stars *st, double r, double sigma, double *light, double *flux)
{
    const int nt = 1500, ns = 3000;
    const double smax = r + 9 * sigma, ds = smax / ns, dt = pi / nt;
    const double norm = pow(2 * pi * sigma * sigma, -1.5);
    double *w = malloc(ns * sizeof *w);
    for (int b = 0; b < ns; b++)
        w[b] = shown_share(st, r * 1000, sigma * 1000, (b + 0.5) * ds * 1000);
    *light = *flux = 0;
    for (int a = 0; a < nt; a++) {
        const double theta = (a + 0.5) * dt, c = cos(theta), dome = 2 * pi * sin(theta) * dt * ds * norm;
        for (int b = 0; b < ns; b++) {
            const double s = (b + 0.5) * ds;
            const double column = w[b] * exp(-(s * s - 2 * s * r * c + r * r) / (2 * sigma * sigma)) * dome;
            *flux += column;          /* rho s^2 ds dOmega / s^2 */
            *light += column * s * s; /* rho s^2 ds dOmega */
        }
    }
    free(w);
}

/* The glow's dimming is the mean of 1/s^2 over the stars the draw leaves:
 * (E[1/s^2] - the shown stars' share of it) / (1 - their share of the
 * light), by brute force; and the draw itself leaves that share of the
 * light, over 400 particles (each id its own stars) of 3e5 solar
 * luminosities, as bright as the short run's young disc particles (much
 * fainter ones would be outshone by their own brightest stars, which then
 * share its light, stars.h). */
static void test_glow_dimming_brute_force(void)
{
    orr_stars st = stars_to(6.5);
    const double sigma = orr_stars_kernel_length(&st, 9.35e-5f) / 2; /* (0.1388 kpc) */
    const double rs[] = {0.036, 0.2, 0.5, 1.5};
    enum { N = 100, CHUNKS = 4 };
    float *xyz[3] = {calloc(N, sizeof(float)), calloc(N, sizeof(float)), calloc(N, sizeof(float))};
    float *dimming = calloc(N, sizeof(float));
    orr_star_batch batch = {0};
    orr_error err = {0};
    for (size_t k = 0; k < sizeof rs / sizeof *rs; k++) {
        double light, flux;
        shown_part(&st, rs[k], sigma, &light, &flux);
        const double all = sky_sum(rs[k], sigma), want = (all - flux) / (1 - light);
        double left = 0, left2 = 0;
        for (int ch = 0; ch < CHUNKS; ch++) {
            orr_chunk c = particles_at(N, rs[k], 3e5f, 1 + (uint64_t)ch * N, xyz);
            orr_stars_glow_dimming(&st, (orr_vec3){0, 0, 0}, &c, dimming);
            orr_stars_begin_frame(&st);
            CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, 0, &c, xyz, &batch, &err) == ORR_OK);
            for (size_t i = 0; i < N; i++)
                left += xyz[1][i] / 3e5, left2 += (xyz[1][i] / 3e5) * (xyz[1][i] / 3e5);
            orr_chunk_free(&c);
        }
        const double n = N * CHUNKS, mean = left / n, se = sqrt(fmax(left2 / n - mean * mean, 0) / n);
        printf("  at %.3f kpc: stars shown take %.4f of the light (drawn: %.4f +- %.4f) and %.4f of E[1/s^2] = %.4g; "
               "the glow's dimming %.5g kpc^-2 (brute force %.5g; 1/r^2 %.4g)\n",
               rs[k], light, 1 - mean, se, flux / all, all, (double)dimming[0], want, 1 / (rs[k] * rs[k]));
        CHECK_NEAR(dimming[0] / want, 1.0, 1e-4);
        CHECK(fabs(1 - mean - light) < 4 * se + 1e-3);
    }
    orr_star_batch_free(&batch);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
    free(dimming);
}

/* End to end, where the stars' flux has a small scatter: over many
 * particles at r (each id its own draw of stars), the mean flux of the
 * stars drawn plus that of what they leave at the glow's dimming is
 * L E[1/s^2]; with the whole kernel's mean for the glow, the stars drawn
 * on the near side would count twice. */
static void test_glow_keeps_the_flux(void)
{
    orr_stars st = stars_to(6.5);
    enum { N = 100, CHUNKS = 10 };
    const float light = 3e5f;
    const double rs[] = {0.5, 2.0};
    float *xyz[3] = {calloc(N, sizeof(float)), calloc(N, sizeof(float)), calloc(N, sizeof(float))};
    float *dimming = calloc(N, sizeof(float));
    double *star_flux = calloc(N, sizeof(double));
    orr_star_batch batch = {0};
    orr_error err = {0};
    for (size_t k = 0; k < 2; k++) {
        double sum = 0, sum2 = 0, whole = 0;
        const double all = orr_kernel_inv_r2(rs[k], orr_stars_kernel_length(&st, 9.35e-5f) / 2);
        for (int ch = 0; ch < CHUNKS; ch++) {
            orr_chunk c = particles_at(N, rs[k], light, 100000 + (uint64_t)ch * N, xyz);
            orr_stars_glow_dimming(&st, (orr_vec3){0, 0, 0}, &c, dimming);
            orr_stars_begin_frame(&st);
            CHECK(orr_stars_spawn(&st, (orr_vec3){0, 0, 0}, 0, &c, xyz, &batch, &err) == ORR_OK);
            for (size_t i = 0; i < N; i++)
                star_flux[i] = 0;
            for (size_t j = 0; j < batch.stars.n; j++) {
                const double x = batch.stars.x[j], y = batch.stars.y[j], z = batch.stars.z[j];
                const double d2 = fmax(x * x + y * y + z * z, 1e-10); /* (0.01 pc, as the splat) */
                star_flux[batch.stars.id[j] - c.id[0]] += batch.xyz[1][j] / d2;
            }
            for (size_t i = 0; i < N; i++) {
                const double f = (star_flux[i] + xyz[1][i] * (double)dimming[i]) / (light * all);
                sum += f, sum2 += f * f;
                whole += (star_flux[i] + xyz[1][i] * all) / (light * all);
            }
            orr_chunk_free(&c);
        }
        const double n = N * CHUNKS, mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0) / n);
        printf("  at %.1f kpc: stars + glow over L E[1/s^2] %.4f +- %.4f; with the whole kernel's mean for the "
               "glow %.4f\n",
               rs[k], mean, se, whole / n);
        CHECK(se < 0.003);
        CHECK(fabs(mean - 1.0) < 4 * se + 1e-3);
        if (k == 0)
            CHECK(whole / n > 1.0 + 10 * se);
    }
    orr_star_batch_free(&batch);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
    free(dimming), free(star_flux);
}

/* Far from any star the draw could show, the glow is the whole kernel's
 * mean: 1/r^2 and the series' small term. */
static void test_glow_far(void)
{
    orr_stars st = stars_to(6.5);
    float *xyz[3] = {calloc(2, sizeof(float)), calloc(2, sizeof(float)), calloc(2, sizeof(float))};
    float dimming[2] = {-1, -1};
    orr_chunk c = particles_at(2, 6.0, 1e5f, 1, xyz);
    c.type[1] = 3; /* not a spawning type: left alone */
    orr_stars_glow_dimming(&st, (orr_vec3){0, 0, 0}, &c, dimming);
    const double x = 0.139 * 0.139 / 36.0;
    CHECK_NEAR(dimming[0] * 36.0, 1.0 + x, 1e-6);
    CHECK(dimming[1] == -1.0f);
    orr_chunk_free(&c);
    for (int k = 0; k < 3; k++)
        free(xyz[k]);
}

int main(void)
{
    RUN(test_quadrature_holds_the_light);
    RUN(test_closed_form);
    RUN(test_sky_sum);
    RUN(test_limits);
    RUN(test_glow_far);
    RUN(test_glow_dimming_brute_force);
    RUN(test_glow_keeps_the_flux);
    return check_summary();
}
