/* Spike stars on a sky map (post/sky_psf.h): each star's PSF stamped from
 * its tiles' corners (sky_psf_stamp.c) against the same stamp with every
 * sample mapped to the sky exactly; flux kept to 1e-6; and the same bits
 * on any number of threads. The maps' own checks of the spikes' angles and
 * lengths are tests/cli/check_sky_spikes.py's. */
#include <omp.h>
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "post/view_psf.h"
#include "splat/sph.h"

typedef struct sky {
    orr_projection p;
    orr_kernel k;
    orr_sph sph;
    orr_sky_psf sp;
    orr_plane fast, exact;
    double weight; /* the stars' total */
} sky;

static orr_image_kernel hst_psf(void)
{
    orr_psf_settings ps;
    orr_psf_settings_defaults(&ps);
    ps.kind = ORR_PSF_HST;
    orr_image_kernel psf = {0};
    orr_error err = {0};
    CHECK(orr_view_psf_kernel(&ps, NULL, &psf, &err) == ORR_OK);
    return psf;
}

/* Stars at the given directions (camera frame), one unit away, weights
 * 1, 2, 3, ..., each drawn first as the splat draws it: its core. */
static void sky_setup(sky *s, orr_projection p, const orr_image_kernel *psf, const orr_vec3 *dirs, int n)
{
    orr_error err = {0};
    memset(s, 0, sizeof *s);
    s->p = p;
    CHECK(orr_kernel_init(&s->k, ORR_KERNEL_CUBIC, &err) == ORR_OK);
    CHECK(orr_sph_init(&s->sph, &s->k, &s->p, &err) == ORR_OK);
    CHECK(orr_plane_alloc(&s->fast, s->p.width, s->p.height, "w", "", &err) == ORR_OK);
    CHECK(orr_plane_alloc(&s->exact, s->p.width, s->p.height, "w", "", &err) == ORR_OK);
    const double fwhm = ORR_SKY_CORE_PIXELS / s->p.focal;
    orr_image_kernel copy;
    CHECK(orr_image_kernel_alloc(&copy, psf->width, psf->height, &err) == ORR_OK);
    memcpy(copy.data, psf->data, sizeof(float) * (size_t)psf->width * psf->height);
    CHECK(orr_sky_psf_init(&s->sp, &copy, fwhm, n, 0.0, 0, &err) == ORR_OK);
    s->sp.stars = calloc((size_t)n, sizeof *s->sp.stars);
    s->sp.nstars = n;
    for (int i = 0; i < n; i++) {
        orr_sky_star *st = &s->sp.stars[i];
        orr_vec3 d = orr_v3_normalize(dirs[i]);
        st->x = (float)d.x, st->y = (float)d.y, st->z = (float)d.z;
        uint8_t vis;
        orr_project_batch(&s->p, 1, &st->x, &st->y, &st->z, &st->px, &st->py, &st->scale, &vis);
        CHECK(vis);
        st->h = (float)(2.0 * sin(0.25 * fwhm) / orr_kernel_half_max_q(&s->k));
        st->key = st->w[0] = (float)(n - i);
        s->weight += st->w[0];
    }
}

static void draw(sky *s, orr_plane *plane, int exact)
{
    memset(plane->data, 0, sizeof(float) * (size_t)plane->width * plane->height);
    const uint8_t visible = 1;
    for (int i = 0; i < s->sp.nstars; i++) {
        const orr_sky_star *st = &s->sp.stars[i];
        orr_sph_block b = {1, &st->x, &st->y, &st->z, &st->px, &st->py, &st->scale, &visible, &st->h, &st->w[0]};
        orr_deposit_stats stats = {0};
        orr_sph_deposit(&s->sph, &b, plane, &stats);
    }
    orr_error err = {0};
    s->sp.exact = exact;
    CHECK(orr_sky_psf_draw(&s->sp, &s->sph, plane, 1, &err) == ORR_OK);
    CHECK(s->sp.stars_drawn == s->sp.nstars);
}

static void sky_free(sky *s)
{
    orr_sky_psf_free(&s->sp);
    orr_sph_free(&s->sph);
    orr_kernel_free(&s->k);
    orr_plane_free(&s->fast);
    orr_plane_free(&s->exact);
}

static double plane_sum(const orr_plane *p)
{
    double sum = 0;
    for (size_t i = 0; i < (size_t)p->width * p->height; i++)
        sum += p->data[i];
    return sum;
}

/* Fast against exact: the flux, every pixel against the brightest (the
 * stars' cores), and the relative error of the pixels that show: above
 * 1e-4 of the brightest, about 9 magnitudes down, where a log stretch
 * still draws the halo. The difference is the tiles' interpolation,
 * which may move a sample by TILE_TOL = 0.02 PSF pixel: a few percent
 * where the rings and spikes are steepest (measured 3.9 % and 1.0 %;
 * 1.2e-3 and 6.4e-4 of the brightest). */
static void compare(sky *s, const char *name, double max_abs, double max_rel)
{
    draw(s, &s->fast, 0);
    draw(s, &s->exact, 1);
    const size_t n = (size_t)s->p.width * s->p.height;
    double peak = 0, worst = 0, worst_rel = 0;
    for (size_t i = 0; i < n; i++)
        peak = fmax(peak, s->exact.data[i]);
    for (size_t i = 0; i < n; i++) {
        const double d = fabs((double)s->fast.data[i] - s->exact.data[i]);
        worst = fmax(worst, d / peak);
        if (s->exact.data[i] > 1e-4 * peak)
            worst_rel = fmax(worst_rel, d / s->exact.data[i]);
    }
    fprintf(stderr, "  %s: flux %.9g and %.9g of %.9g; worst pixel %.2e of the brightest, %.2e of itself\n", name,
            plane_sum(&s->fast), plane_sum(&s->exact), s->weight, worst, worst_rel);
    CHECK_NEAR(plane_sum(&s->fast), s->weight, 1e-6 * s->weight);
    CHECK_NEAR(plane_sum(&s->exact), s->weight, 1e-6 * s->weight);
    CHECK(worst <= max_abs);
    CHECK(worst_rel <= max_rel);
}

static void test_dome(void)
{
    orr_image_kernel psf = hst_psf();
    /* The zenith, 30 and 60 degrees from it, and by the rim (85 degrees,
     * part of the PSF beyond the horizon, folded back onto the map). */
    const orr_vec3 dirs[] = {{0.001, 0.002, 1}, {0.5, 0, 0.866}, {0, -0.866, 0.5}, {-0.70, 0.70, 0.15},
                             {0.996, 0.03, 0.087}};
    sky s;
    sky_setup(&s, PLANNED(.kind = ORR_PROJ_DOME, .width = 1201, .height = 1201, .dome_fov_deg = 180),
              &psf, dirs, 5);
    compare(&s, "dome 1201^2", 2e-3, 0.05);
    sky_free(&s);
    orr_image_kernel_free(&psf);
}

static void test_hammer_aitoff(void)
{
    orr_image_kernel psf = hst_psf();
    /* The centre, by the l = 180 seam, and near a pole. */
    const orr_vec3 dirs[] = {{0.01, 0.02, 1}, {0.017, 0.1, -0.99}, {0.1, -0.98, 0.17}};
    sky s;
    sky_setup(&s, PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 1600, .height = 800), &psf, dirs, 3);
    compare(&s, "hammer-aitoff 1600x800", 2e-3, 0.05);
    sky_free(&s);
    orr_image_kernel_free(&psf);
}

/* Stamps are made and added on the threads: one, two and three give the
 * same bits. */
static void test_threads(void)
{
    orr_image_kernel psf = hst_psf();
    orr_vec3 dirs[40];
    for (int i = 0; i < 40; i++) /* overlapping stars, more than one batch */
        dirs[i] = (orr_vec3){0.3 * cos(0.7 * i), 0.3 * sin(1.3 * i), 1};
    sky s;
    sky_setup(&s, PLANNED(.kind = ORR_PROJ_DOME, .width = 801, .height = 801, .dome_fov_deg = 180), &psf,
              dirs, 40);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    draw(&s, &s.exact, 0);
    for (int t = 2; t <= 3; t++) {
        omp_set_num_threads(t);
        draw(&s, &s.fast, 0);
        CHECK(memcmp(s.fast.data, s.exact.data, sizeof(float) * 801 * 801) == 0);
    }
    omp_set_num_threads(threads);
    sky_free(&s);
    orr_image_kernel_free(&psf);
}

int main(void)
{
    RUN(test_dome);
    RUN(test_hammer_aitoff);
    RUN(test_threads);
    return check_summary();
}
