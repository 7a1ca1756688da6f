/* End to end: run the orrery command on a scene, read its FITS back with
 * cfitsio and its PNG with libpng, and check against values computed here. */
#include <fitsio.h>
#include <png.h>
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "source/models/model.h"

static char tmpdir[] = "/tmp/orrery-e2e-XXXXXX";

static void path_in_tmp(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", tmpdir, name);
}

static int run_orrery(const char *args)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s' %s > run.log 2>&1", tmpdir, ORRERY_CLI, args);
    int rc = system(cmd);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/* Reads the primary image of a FITS file; returns the pixels (caller frees). */
static float *read_fits(const char *path, long *w, long *h, double *wimage, double *woutside, long *npart)
{
    fitsfile *f;
    int status = 0, naxis = 0;
    long size[2] = {0, 0};
    fits_open_file(&f, path, READONLY, &status);
    fits_get_img_dim(f, &naxis, &status);
    fits_get_img_size(f, 2, size, &status);
    CHECK(status == 0 && naxis == 2);
    if (status)
        return NULL;
    float *data = malloc((size_t)size[0] * (size_t)size[1] * sizeof *data);
    int anynul = 0;
    fits_read_img(f, TFLOAT, 1, size[0] * size[1], NULL, data, &anynul, &status);
    fits_read_key(f, TDOUBLE, "WIMAGE", wimage, NULL, &status);
    fits_read_key(f, TDOUBLE, "WOUTSIDE", woutside, NULL, &status);
    fits_read_key(f, TLONG, "NPART", npart, NULL, &status);
    char extname[FLEN_VALUE] = "";
    fits_read_key(f, TSTRING, "EXTNAME", extname, NULL, &status);
    CHECK(strcmp(extname, "mass") == 0);
    fits_close_file(f, &status);
    CHECK(status == 0);
    *w = size[0];
    *h = size[1];
    return data;
}

static double sum_pixels(const float *d, long n)
{
    double s = 0;
    for (long i = 0; i < n; i++)
        s += d[i];
    return s;
}

static void test_text_table_mass_in_view(void)
{
    /* 64 x 48 pixels over 10 x 7.5 units: 6.4 pixels per unit. Particles
     * well inside and well outside, so the expected sum is unambiguous. */
    char table[600], scene[600];
    path_in_tmp(table, sizeof table, "cloud.txt");
    path_in_tmp(scene, sizeof scene, "cloud.yaml");
    FILE *fp = fopen(table, "w");
    fprintf(fp, "x y z mass\n");
    double inside = 0, outside = 0;
    srand(5);
    for (int i = 0; i < 2000; i++) {
        double x = rand() / (double)RAND_MAX * 9 - 4.5, y = rand() / (double)RAND_MAX * 6.6 - 3.3;
        double m = 0.5 + rand() / (double)RAND_MAX;
        int out = i % 4 == 0;
        if (out)
            x += x > 0 ? 6 : -6;
        fprintf(fp, "%.6f %.6f %.3f %.6f\n", x, y, (double)(i % 7) - 3, m);
        *(out ? &outside : &inside) += (float)m;
    }
    fclose(fp);
    fp = fopen(scene, "w");
    fprintf(fp, "input:\n  file: cloud.txt\ncamera:\n  projection: orthographic\n  width: 10\n"
                "image:\n  width: 64\n  height: 48\ndeposit: cic\noutput:\n  dir: out\n");
    fclose(fp);
    CHECK(run_orrery("render cloud.yaml") == 0);
    char fits[600];
    path_in_tmp(fits, sizeof fits, "out/cloud.fits");
    long w = 0, h = 0, npart = 0;
    double wimage = 0, woutside = 0;
    float *d = read_fits(fits, &w, &h, &wimage, &woutside, &npart);
    CHECK(w == 64 && h == 48);
    CHECK(npart == 2000);
    /* Pixels hold mass per unit area: times a pixel's area, (10 / 64)^2. */
    const double area = (10.0 / 64) * (10.0 / 64);
    if (d)
        CHECK_NEAR(sum_pixels(d, w * h) * area, inside, 1e-5 * inside);
    CHECK_NEAR(wimage, inside, 1e-6 * inside);
    CHECK_NEAR(woutside, outside, 1e-6 * outside);
    free(d);
}

static void test_pixel_orientation(void)
{
    /* One particle at the centre of pixel (i, j) = (40, 10) from the top-left:
     * world x = (40.5 - 32) / 6.4, y = (24 - 10.5) / 6.4 (the xy plane seen
     * face-on: +y is up). FITS stores rows bottom-up: row 48 - 10 = 38. */
    char table[600], scene[600];
    path_in_tmp(table, sizeof table, "one.txt");
    path_in_tmp(scene, sizeof scene, "one.yaml");
    FILE *fp = fopen(table, "w");
    fprintf(fp, "x y z mass\n%.9f %.9f 0 3\n", (40.5 - 32) / 6.4, (24 - 10.5) / 6.4);
    fclose(fp);
    fp = fopen(scene, "w");
    fprintf(fp, "input:\n  file: one.txt\ncamera:\n  projection: orthographic\n  width: 10\n"
                "image:\n  width: 64\n  height: 48\ndeposit: ngp\noutput:\n  dir: out\n");
    fclose(fp);
    CHECK(run_orrery("render one.yaml --set output.png=false") == 0);
    char fits[600], png[600];
    path_in_tmp(fits, sizeof fits, "out/one.fits");
    path_in_tmp(png, sizeof png, "out/one.png");
    CHECK(access(png, F_OK) != 0); /* output.png=false was honoured */
    long w = 0, h = 0, npart = 0;
    double wimage = 0, woutside = 0;
    float *d = read_fits(fits, &w, &h, &wimage, &woutside, &npart);
    if (d) {
        long fits_row = 48 - 10;     /* 1-based FITS row of image row 10 */
        const double area = 1 / 6.4 / 6.4; /* a pixel's, in scene units: it holds mass per unit area */
        CHECK_NEAR(d[(fits_row - 1) * w + 40] * area, 3.0, 1e-6);
        CHECK_NEAR(sum_pixels(d, w * h) * area, 3.0, 1e-6);
    }
    free(d);
}

static void test_builtin_model_scene(void)
{
    /* Stars only (disc and bulge), a view wide enough to hold both galaxies'
     * stars: the image holds exactly their mass. */
    char scene[600];
    path_in_tmp(scene, sizeof scene, "model.yaml");
    FILE *fp = fopen(scene, "w");
    fprintf(fp, "input:\n  model:\n    name: mw-m31\n    particles: 20000\n    separation: 120\n"
                "  types: [2, 3]\ncamera:\n  projection: orthographic\n  width: 2000\n"
                "image:\n  width: 256\n  height: 256\noutput:\n  dir: out\n  png_bits: 16\n");
    fclose(fp);
    CHECK(run_orrery("render model.yaml") == 0);

    orr_model_params mp = {20000, 1, 120.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_source *src;
    orr_error err = {0};
    double stars = 0;
    long nstars = 0;
    CHECK(orr_model_source_open(&mp, 4096, &src, &err) == ORR_OK);
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t i = 0; i < c->n; i++)
            if (c->type[i] == ORR_MODEL_TYPE_DISC || c->type[i] == ORR_MODEL_TYPE_BULGE)
                stars += c->mass[i], nstars++;
    orr_source_close(src);

    char fits[600], png[600];
    path_in_tmp(fits, sizeof fits, "out/model.fits");
    path_in_tmp(png, sizeof png, "out/model.png");
    long w = 0, h = 0, npart = 0;
    double wimage = 0, woutside = 0;
    float *d = read_fits(fits, &w, &h, &wimage, &woutside, &npart);
    /* Only the drawn types are generated, and the three markers. */
    CHECK(npart == nstars + 3);
    const double area = (2000.0 / 256) * (2000.0 / 256); /* a pixel's: it holds mass per unit area */
    if (d)
        CHECK_NEAR(sum_pixels(d, w * h) * area, stars, 1e-5 * stars);
    CHECK_NEAR(woutside, 0, 0);
    free(d);

    /* The PNG is a 16-bit RGB image of the same size, readable by libpng. */
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    CHECK(png_image_begin_read_from_file(&img, png) != 0);
    CHECK(img.width == 256 && img.height == 256);
    CHECK(img.format & PNG_FORMAT_FLAG_COLOR);
    png_image_free(&img);
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    RUN(test_text_table_mass_in_view);
    RUN(test_pixel_orientation);
    RUN(test_builtin_model_scene);
    if (check_failures) {
        char log[600];
        path_in_tmp(log, sizeof log, "run.log");
        FILE *fp = fopen(log, "r");
        char line[512];
        while (fp && fgets(line, sizeof line, fp))
            fputs(line, stderr);
        if (fp)
            fclose(fp);
    }
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    return check_summary();
}
