/* Pixels hold surface brightness: a uniform sky renders uniform on every
 * sky projection and dome profile and in a wide perspective frame. The sky
 * is a Fibonacci lattice of equal particles on a sphere around the camera
 * (as even as points on a sphere get, so no shot noise hides a trend); the
 * render goes through the in-situ API and is read back with cfitsio. Rings
 * of the map (or rows, for the equirectangular one) are compared with the
 * whole map's mean: flat within 0.5 % from centre to edge, where a map of
 * flux per pixel falls to 2/pi (dome rim) or cos b (equirectangular). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "fits_image.h"
#include "orrery.h"
#include "post/brightness.h"
#include "tmpdir.h"

#define NSKY 2000000

static double *sky_x, *sky_y, *sky_z;

/* The golden-angle spiral: point k at height 1 - (2k + 1) / n, turned by
 * the golden angle from the last; each covers 4 pi / n of the sphere. */
static void make_sky(void)
{
    sky_x = malloc(NSKY * sizeof *sky_x);
    sky_y = malloc(NSKY * sizeof *sky_y);
    sky_z = malloc(NSKY * sizeof *sky_z);
    const double golden = 3.14159265358979323846 * (3.0 - sqrt(5.0));
    for (long k = 0; k < NSKY; k++) {
        double z = 1.0 - (2.0 * k + 1.0) / NSKY, r = sqrt(1.0 - z * z), a = golden * k;
        sky_x[k] = 10.0 * r * cos(a);
        sky_y[k] = 10.0 * r * sin(a);
        sky_z[k] = 10.0 * z;
    }
}

/* Renders the sky with the camera at the origin; returns the image (FITS
 * order, row 0 at the bottom), or NULL. */
static float *render_sky(const char *camera, int width, int height, const char *name)
{
    char yaml[1024], msg[1024], path[700];
    snprintf(yaml, sizeof yaml,
             "camera: {position: [0, 0, 0], %s}\nimage: {width: %d, height: %d}\ndeposit: cic\n"
             "output: {name: %s, png: false, dir: %s}\n",
             camera, width, height, name, tmpdir);
    orrery_renderer *r = NULL;
    /* Based in the source tree, whose domes/ holds the profiles. */
    if (orrery_open_yaml(&r, yaml, ORRERY_SOURCE_DIR, NULL, 0, msg, sizeof msg) != ORRERY_OK) {
        fprintf(stderr, "%s: %s\n", name, msg);
        return NULL;
    }
    orr_particle_arrays p = {0};
    p.n = NSKY;
    p.x = (orr_array){sky_x, ORR_F64, 0};
    p.y = (orr_array){sky_y, ORR_F64, 0};
    p.z = (orr_array){sky_z, ORR_F64, 0};
    p.mass_value = 1.0;
    int st = orrery_render(r, &p, 0);
    if (st != ORRERY_OK)
        fprintf(stderr, "%s: %s\n", name, orrery_error(r));
    orrery_close(r);
    snprintf(path, sizeof path, "%s/%s_0000.fits", tmpdir, name); /* in-situ frames are numbered */
    long npix = 0;
    return st == ORRERY_OK ? read_fits_image(path, &npix) : NULL;
}

/* The largest relative difference between the mean of a ring (or row) and
 * the mean over all of them: ring k holds the pixels whose key is k. */
static double worst_ring(const float *img, const int *key, long npix, int nrings, const char *what)
{
    double *sum = calloc((size_t)nrings, sizeof *sum), all = 0;
    long *count = calloc((size_t)nrings, sizeof *count), n = 0;
    for (long i = 0; i < npix; i++)
        if (key[i] >= 0 && isfinite(img[i])) {
            sum[key[i]] += img[i];
            count[key[i]]++;
            all += img[i];
            n++;
        }
    double mean = all / (n > 0 ? n : 1), worst = 0;
    int at = -1;
    for (int k = 0; k < nrings; k++)
        if (count[k] > 0 && fabs(sum[k] / count[k] / mean - 1.0) > worst) {
            worst = fabs(sum[k] / count[k] / mean - 1.0);
            at = k;
        }
    fprintf(stderr, "  %-24s %ld pixels, %d rings: worst ring %d off the mean by %.3f %%\n", what, n, nrings, at,
            100 * worst);
    free(sum);
    free(count);
    return worst;
}

/* A dome master (or a perspective frame): rings of 8 pixels around the
 * centre, up to `reach` pixels out (to a pixel short of the rim, whose
 * pixels the rim cuts). */
static void check_rings(const char *camera, int size, double reach, const char *name)
{
    float *img = render_sky(camera, size, size, name);
    CHECK(img != NULL);
    if (!img)
        return;
    long npix = (long)size * size;
    int *key = malloc((size_t)npix * sizeof *key), nrings = (int)(reach / 8) + 1;
    for (int j = 0; j < size; j++)
        for (int i = 0; i < size; i++) {
            double r = hypot(i + 0.5 - 0.5 * size, j + 0.5 - 0.5 * size);
            key[(long)j * size + i] = r < reach ? (int)(r / 8) : -1;
        }
    CHECK(worst_ring(img, key, npix, nrings, name) < 0.005);
    free(key);
    free(img);
}

static void test_domes_are_uniform(void)
{
    const int size = 360;
    check_rings("projection: dome, dome_fov: 180", size, 0.5 * size - 1.5, "dome 180");
    check_rings("projection: dome, dome: fisheye-210, dome_fov: 210", size, 0.5 * size - 1.5, "dome 210");
    check_rings("projection: dome, dome: fisheye-230, dome_fov: 230", size, 0.5 * size - 1.5, "dome 230");
    check_rings("projection: dome, dome: tilted-30", size, 0.5 * size - 1.5, "dome tilted 30");
    /* A 90-degree perspective frame: the corners are 55 degrees out, where
     * a pixel covers cos^3 of the centre's solid angle (0.19). */
    check_rings("projection: perspective, fov: 90, near: 0.001", size, 0.5 * size * sqrt(2.0) - 1.5,
                "perspective 90");
}

static void test_panoramas_are_uniform(void)
{
    const int w = 720, h = 360;
    long npix = (long)w * h;
    int *key = malloc((size_t)npix * sizeof *key);
    /* Equirectangular: every row but the poles' own. A CIC point shares
     * its flux with the next row in proportion to pixel area, not solid
     * angle, and a pole row covers a third of the solid angle of the row
     * next to it, so it gains from that row (8 % here). */
    float *img = render_sky("projection: equirectangular", w, h, "equirectangular");
    CHECK(img != NULL);
    for (long i = 0; i < npix; i++)
        key[i] = i / w == 0 || i / w == h - 1 ? -1 : (int)(i / w);
    if (img)
        CHECK(worst_ring(img, key, npix, h, "equirectangular rows") < 0.005);
    free(img);
    /* Hammer-Aitoff: rings of the ellipse, u^2 + v^2 = rho^2, in 24 steps
     * of rho to a pixel short of the rim. */
    img = render_sky("projection: hammer-aitoff", w, h, "hammer-aitoff");
    CHECK(img != NULL);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double u = (i + 0.5 - 0.5 * w) / (0.5 * w), v = (j + 0.5 - 0.5 * h) / (0.5 * h);
            double rho = sqrt(u * u + v * v);
            key[(long)j * w + i] = rho < 1.0 - 1.5 / (0.5 * h) ? (int)(rho * 24) : -1;
        }
    if (img)
        CHECK(worst_ring(img, key, npix, 24, "hammer-aitoff rings") < 0.005);
    free(img);
    free(key);
}

/* Equal light, equal value: a map of flux per pixel would not be uniform,
 * so the tests above would fail without the division; and the measure the
 * division uses adds up to the whole sphere on the full-sky maps. */
static void test_measures_add_up(void)
{
    const orr_projection maps[2] = {PLANNED(.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 360, .height = 180),
                                    PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 360, .height = 180)};
    for (int m = 0; m < 2; m++) {
        double sum = 0;
        for (int j = 0; j < maps[m].height; j++)
            for (int i = 0; i < maps[m].width; i++)
                if (orr_projection_pixel_in_map(&maps[m], i, j))
                    sum += orr_pixel_measure(&maps[m], i, j);
        /* Equirectangular exactly; the ellipse's pixels whole, so their
         * count over pi W H / 4 (within a rim's width). */
        CHECK_NEAR(sum / (4 * 3.14159265358979323846), 1.0, m == 0 ? 1e-12 : 0.01);
    }
    /* A perspective frame's pixels add up to the frame's solid angle:
     * 4 asin(sin a sin b) for half-angles a and b. */
    orr_projection p = PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 200, .height = 100, .fov_deg = 90, .near = 0.1);
    double sum = 0, a = atan(1.0), b = atan(0.5);
    for (int j = 0; j < p.height; j++)
        for (int i = 0; i < p.width; i++)
            sum += orr_pixel_measure(&p, i, j);
    CHECK_NEAR(sum, 4 * asin(sin(a) * sin(b)), 1e-12);
}

/* A row's measures and its twin row's are each pixel's own, bit for bit:
 * the division by rows gives the same planes as pixel by pixel. */
static void test_measure_rows_are_exact(void)
{
    const orr_projection maps[] = {
        PLANNED(.kind = ORR_PROJ_DOME, .width = 101, .height = 101, .dome_fov_deg = 180),
        PLANNED(.kind = ORR_PROJ_DOME, .width = 100, .height = 100, .dome_fov_deg = 210),
        PLANNED(.kind = ORR_PROJ_DOME, .width = 120, .height = 90, .dome_fov_deg = 180),
        PLANNED(.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 64, .height = 32),
        PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 64, .height = 32),
        PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 40, .height = 30, .fov_deg = 60, .near = 0.1)};
    int twins = 0;
    for (size_t m = 0; m < sizeof maps / sizeof maps[0]; m++) {
        double row[128];
        int mismatches = 0;
        for (int j = 0; j < maps[m].height; j++) {
            orr_pixel_measure_row(&maps[m], j, row);
            int twin = orr_pixel_measure_twin_row(&maps[m], j);
            twins += twin >= 0;
            for (int i = 0; i < maps[m].width; i++) {
                mismatches += row[i] != orr_pixel_measure(&maps[m], i, j);
                mismatches += twin >= 0 && row[i] != orr_pixel_measure(&maps[m], i, twin);
            }
        }
        CHECK(mismatches == 0);
    }
    CHECK(twins == 101 - 1 + 100 + 90); /* every dome row but the centre one has a twin */
}

/* A row's run of pixels on the map is exactly those the pixel test takes
 * (the coarse glow's passes visit only it), and the measures of a span are
 * the row's, bit for bit, with the pixels outside it left alone. */
static void test_row_spans_are_the_pixel_test(void)
{
    const orr_projection maps[] = {
        PLANNED(.kind = ORR_PROJ_DOME, .width = 101, .height = 101, .dome_fov_deg = 180),
        PLANNED(.kind = ORR_PROJ_DOME, .width = 100, .height = 100, .dome_fov_deg = 210),
        PLANNED(.kind = ORR_PROJ_DOME, .width = 120, .height = 90, .dome_fov_deg = 180),
        PLANNED(.kind = ORR_PROJ_DOME, .width = 7, .height = 128, .dome_fov_deg = 180),
        PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 64, .height = 32),
        PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 127, .height = 61),
        PLANNED(.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 64, .height = 32),
        PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 40, .height = 30, .fov_deg = 60, .near = 0.1)};
    for (size_t m = 0; m < sizeof maps / sizeof maps[0]; m++) {
        const orr_projection *p = &maps[m];
        double row[128], span[128];
        int wrong = 0, empty = 0;
        for (int j = -1; j <= p->height; j++) {
            int i0, i1;
            const int n = orr_projection_row_in_map(p, j, &i0, &i1);
            wrong += n != i1 - i0 || i0 < 0 || i1 > p->width;
            empty += n == 0;
            for (int i = -2; i < p->width + 2; i++)
                wrong += orr_projection_pixel_in_map(p, i, j) != (i >= i0 && i < i1);
            if (j < 0 || j >= p->height)
                continue;
            orr_pixel_measure_row(p, j, row);
            for (int i = 0; i < p->width; i++)
                span[i] = -1.0;
            orr_pixel_measure_span(p, j, i0, i1, span);
            for (int i = 0; i < p->width; i++)
                wrong += span[i] != (i >= i0 && i < i1 ? row[i] : -1.0);
        }
        CHECK(wrong == 0);
        CHECK(empty >= 2); /* the rows above and below the image */
    }
}

int main(void)
{
    make_tmpdir();
    test_measure_rows_are_exact();
    test_row_spans_are_the_pixel_test();
    make_sky();
    test_measures_add_up();
    test_domes_are_uniform();
    test_panoramas_are_uniform();
    free(sky_x);
    free(sky_y);
    free(sky_z);
    remove_tmpdir();
    return check_summary();
}
