/* The splat gives the same planes, bit for bit, and the same report sums on
 * 1, 2 and 4 OpenMP threads (render.c's lanes: a fixed assignment of blocks
 * to lanes and a fixed-order reduction; for point deposits into large
 * images, bands), for every kind of deposit, a sky
 * map, colour populations and neighbour smoothing lengths; and a bad
 * particle is reported as one thread would report it. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/owned.h"
#include "encode/fits_read.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tmpdir.h"

static const int thread_counts[3] = {1, 2, 4};

typedef struct rendering {
    orr_status st;
    orr_render_report rep;
    orr_plane planes[3];
    int nplanes;
    char msg[ORR_ERROR_MSG_MAX];
} rendering;

/* Renders yaml with the given number of threads into tmpdir/NAME_tT.fits
 * and reads the planes back. */
static void render_with(const char *yaml, const char *name, int threads, rendering *out)
{
    memset(out, 0, sizeof *out);
    orr_scene *s = calloc(1, sizeof *s);
    orr_error err = {0};
    CHECK(s != NULL);
    out->st = orr_scene_load_string(s, yaml, name, ".", NULL, 0, &err);
    CHECK(out->st == ORR_OK);
    if (out->st) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
        orr_scene_free(s);
        free(s);
        return;
    }
    orr_owned_set(&s->output.dir, tmpdir, NULL);
    snprintf(s->output.name, sizeof s->output.name, "%s_t%d", name, threads);
    s->output.write_png = 0;
    omp_set_num_threads(threads);
    out->st = orr_render_scene(s, &out->rep, NULL, NULL, &err);
    snprintf(out->msg, sizeof out->msg, "%s", err.msg);
    if (out->st == ORR_OK) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s_t%d.fits", tmpdir, name, threads);
        CHECK(orr_read_fits_planes(path, out->planes, 3, &out->nplanes, &err) == ORR_OK);
    }
    orr_scene_free(s);
    free(s);
}

static void free_rendering(rendering *r)
{
    for (int k = 0; k < r->nplanes; k++)
        orr_plane_free(&r->planes[k]);
}

static int same_stats(const orr_deposit_stats *a, const orr_deposit_stats *b)
{
    return a->deposited == b->deposited && a->outside == b->outside && a->culled == b->culled &&
           a->n_particles == b->n_particles && a->n_culled == b->n_culled;
}

/* Pixels that differ between a and b, NaN (outside a sky map) equal to NaN. */
static size_t differing_pixels(const orr_plane *a, const orr_plane *b)
{
    size_t n = (size_t)a->width * (size_t)a->height, d = 0;
    for (size_t i = 0; i < n; i++)
        if (!(a->data[i] == b->data[i] || (isnan(a->data[i]) && isnan(b->data[i]))))
            d++;
    return d;
}

/* Renders on 1, 2 and 4 threads; every plane and sum must match the
 * single thread's exactly. The single thread's image must hold weight, and
 * the weight must be accounted for (deposited + outside + culled = the
 * selected particles' total, independently of the threads). */
static void check_independent(const char *name, const char *yaml, int nplanes, double total_weight)
{
    rendering r[3];
    for (int t = 0; t < 3; t++)
        render_with(yaml, name, thread_counts[t], &r[t]);
    CHECK(r[0].st == ORR_OK);
    CHECK(r[0].nplanes == nplanes);
    if (r[0].st || r[0].nplanes != nplanes)
        goto done;
    const orr_deposit_stats *d = &r[0].rep.deposit;
    CHECK(d->deposited > 0);
    if (total_weight > 0)
        CHECK_NEAR(d->deposited + d->outside + d->culled, total_weight, 1e-5 * total_weight);
    for (int t = 1; t < 3; t++) {
        CHECK(r[t].st == ORR_OK && r[t].nplanes == nplanes);
        if (r[t].st || r[t].nplanes != nplanes)
            continue;
        for (int k = 0; k < nplanes; k++) {
            size_t diff = differing_pixels(&r[0].planes[k], &r[t].planes[k]);
            if (diff)
                fprintf(stderr, "%s: plane %d differs at %zu pixels on %d threads\n", name, k, diff,
                        thread_counts[t]);
            CHECK(diff == 0);
        }
        CHECK(same_stats(&r[0].rep.deposit, &r[t].rep.deposit));
        CHECK(same_stats(&r[0].rep.deposit_y, &r[t].rep.deposit_y));
        CHECK(r[0].rep.n_read == r[t].rep.n_read);
        CHECK(r[0].rep.n_selected == r[t].rep.n_selected);
        CHECK(r[0].rep.n_nonfinite == r[t].rep.n_nonfinite);
    }
done:
    for (int t = 0; t < 3; t++)
        free_rendering(&r[t]);
}

/* Point deposits get a lane for every four shares a pixel (lanes_for: NGP
 * one a particle, CIC four), so their images here are at most 1875 pixels
 * for NGP and 7500 for CIC: four lanes for 30000 particles. */
/* 30000 particles in chunks of 20000 (five blocks: lane 0 takes two) and a
 * last chunk of 10000 (three blocks, one lane idle). Every type is drawn,
 * weighted by mass. */
#define MODEL "input: {model: {name: mw-m31, particles: 30000, seed: 4}, chunk: 20000}\n"

static double model_total_mass(void)
{
    /* An orthographic view wide enough to hold every particle: nothing is
     * culled, so deposited + outside is the total mass. */
    rendering r;
    render_with(MODEL "camera: {projection: orthographic, width: 100000}\n"
                      "image: {width: 16, height: 16}\ndeposit: ngp\n",
                "total", 1, &r);
    double total = r.rep.deposit.deposited + r.rep.deposit.outside;
    CHECK(r.st == ORR_OK && r.rep.deposit.culled == 0);
    free_rendering(&r);
    return total;
}

static double total; /* the model's mass: model_total_mass() */

static void test_deposits(void)
{
    check_independent("ngp", MODEL "camera: {projection: orthographic, width: 60}\n"
                                   "image: {width: 50, height: 37}\ndeposit: ngp\n",
                      1, total);
    check_independent("cic", MODEL "camera: {projection: orthographic, width: 60}\n"
                                   "image: {width: 100, height: 75}\ndeposit: cic\n",
                      1, total);
    check_independent("sph", MODEL "camera: {projection: orthographic, width: 60}\n"
                                   "image: {width: 160, height: 120}\ndeposit: sph\n"
                                   "smoothing: {lengths: neighbours, neighbours: 16}\n",
                      1, total);
}

static void test_sky_maps(void)
{
    check_independent("dome", MODEL "camera: {projection: dome, position: [8, 0, 0]}\n"
                                    "image: {width: 86, height: 86}\ndeposit: cic\n",
                      1, total);
    check_independent("dome_sph", MODEL "camera: {projection: dome, position: [8, 0, 0]}\n"
                                        "image: {width: 128, height: 128}\ndeposit: sph\n"
                                        "smoothing: {lengths: neighbours, neighbours: 16}\n",
                      1, total);
    check_independent("aitoff_psf", MODEL "camera: {projection: hammer-aitoff, position: [8, 0, 0]}\n"
                                          "image: {width: 200, height: 100}\ndeposit: ngp\n"
                                          "psf: {kind: gaussian, fwhm_arcmin: 120}\n",
                      1, 0);
    /* The automatic core, on a map large enough that its stars are drawn
     * from the stamp table (splat/sky_cores.h), whose cells the threads
     * make as their stars arrive. */
    check_independent("dome_core", MODEL "camera: {projection: dome, position: [8, 0, 0]}\n"
                                         "image: {width: 1200, height: 1200}\ndeposit: cic\n"
                                         "psf: {kind: gaussian}\n",
                      1, 0);
}

static void test_colour(void)
{
    check_independent("colour", MODEL "camera: {projection: orthographic, width: 60}\n"
                                      "image: {width: 100, height: 75}\ndeposit: cic\n"
                                      "colour:\n"
                                      "  populations:\n"
                                      "    - {name: bulge, select: {types: [3]}, colour: {temperature: 4000},"
                                      " luminance: {mass: 1}}\n"
                                      "    - name: old\n"
                                      "      select: {types: [2], random: {field: r, law: logistic, v0: 6, dv: 2}}\n"
                                      "      colour: {temperature: 4600}\n"
                                      "      luminance: {mass: 1}\n"
                                      "    - {name: young, select: {types: [2]}, colour: {temperature: 12000},"
                                      " luminance: {mass: 1}}\n",
                      3, 0);
}

/* Point deposits into images of more than 2^22 pixels are splatted in
 * bands (splat/bands.h), not lanes: the same bits on every thread count,
 * on a flat image and on a dome master (whose shares fold at the rim). */
static void test_bands(void)
{
    check_independent("ngp_bands", MODEL "camera: {projection: orthographic, width: 60}\n"
                                         "image: {width: 2100, height: 2048}\ndeposit: ngp\n",
                      1, total);
    check_independent("dome_bands", MODEL "camera: {projection: dome, position: [8, 0, 0]}\n"
                                          "image: {width: 2100, height: 2100}\ndeposit: cic\n",
                      1, total);
}

/* Pixels off a sky map are NaN in the FITS planes, and only those: the
 * dome master's circle and the Hammer-Aitoff ellipse (pixel centres within
 * the outline, centred on the image, semi-axes half its sides), for even
 * and odd sizes. */
static void check_outline(const char *name, const char *projection, int W, int H)
{
    char yaml[512];
    snprintf(yaml, sizeof yaml, MODEL "camera: {projection: %s, position: [8, 0, 0]}\n"
                                      "image: {width: %d, height: %d}\ndeposit: ngp\n",
             projection, W, H);
    rendering r;
    render_with(yaml, name, 1, &r);
    CHECK(r.st == ORR_OK && r.nplanes == 1);
    if (r.st == ORR_OK && r.nplanes == 1) {
        size_t wrong = 0;
        for (int j = 0; j < H; j++)
            for (int i = 0; i < W; i++) {
                double u = (i + 0.5 - 0.5 * W) / (0.5 * W), v = (j + 0.5 - 0.5 * H) / (0.5 * H);
                int inside = u * u + v * v <= 1.0;
                wrong += inside == (int)isnan(r.planes[0].data[(size_t)j * W + i]);
            }
        CHECK(wrong == 0);
    }
    free_rendering(&r);
}

static void test_map_outline(void)
{
    check_outline("outline_dome", "dome", 86, 86);
    check_outline("outline_dome_odd", "dome", 87, 87);
    check_outline("outline_aitoff", "hammer-aitoff", 200, 100);
    check_outline("outline_aitoff_odd", "hammer-aitoff", 201, 101);
}

/* Two bad particles, in different blocks (so different lanes): every
 * thread count names the first, as a single thread meets it. */
static void test_first_error(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/bad.txt", tmpdir);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (!f)
        return;
    fprintf(f, "x y z mass\n");
    for (int i = 0; i < 20000; i++) {
        if (i == 9000)
            fprintf(f, "nan 0 0 1\n");
        else if (i == 4500)
            fprintf(f, "0 inf 0 1\n");
        else
            fprintf(f, "%g %g 0 1\n", (i % 100) / 100.0, (i / 100) / 200.0);
    }
    fclose(f);
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "input: {file: %s}\ncamera: {projection: orthographic, width: 2, position: [0.5, 0.5, 0]}\n"
             "image: {width: 32, height: 32}\n",
             path);
    rendering r[3];
    for (int t = 0; t < 3; t++) {
        render_with(yaml, "bad", thread_counts[t], &r[t]);
        CHECK(r[t].st == ORR_ERR_DATA);
        CHECK_CONTAINS(r[t].msg, "particle 4500 ");
        CHECK(strcmp(r[t].msg, r[0].msg) == 0);
        free_rendering(&r[t]);
    }
    /* ... and in bands (blocks shared out among the threads) */
    snprintf(yaml, sizeof yaml,
             "input: {file: %s}\ncamera: {projection: orthographic, width: 2, position: [0.5, 0.5, 0]}\n"
             "image: {width: 2100, height: 2100}\n",
             path);
    for (int t = 0; t < 3; t++) {
        render_with(yaml, "bad_bands", thread_counts[t], &r[t]);
        CHECK(r[t].st == ORR_ERR_DATA);
        CHECK_CONTAINS(r[t].msg, "particle 4500 ");
        free_rendering(&r[t]);
    }
}

int main(void)
{
    make_tmpdir();
    total = model_total_mass();
    CHECK(total > 0);
    RUN(test_deposits);
    RUN(test_sky_maps);
    RUN(test_colour);
    RUN(test_bands);
    RUN(test_map_outline);
    RUN(test_first_error);
    remove_tmpdir();
    return check_summary();
}
