/* The renderer's plan (render/plan.h): one plan executed for every frame of
 * a run gives each frame exactly the planes a plan made for that frame
 * alone gives, while what moves is redone each frame (a camera on a path,
 * a stereo eye's convergence that follows it, a sky map's PSF core stamps
 * kept from frame to frame); and the plan makes its FFT plans once. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/owned.h"
#include "post/convolve.h"
#include "render/plan.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tmpdir.h"

#define MODEL "input: {model: {name: mw-m31, particles: 30000, seed: 7}, types: [2, 3], chunk: 10000}\n"
#define FRAMES 3
#define MAX_PLANES 8

/* The planes a frame's views were kept with (orr_frame_input.keep). */
typedef struct kept {
    int n;
    size_t npix[MAX_PLANES];
    float *data[MAX_PLANES];
} kept;

static orr_status keep_planes(void *user, int view, const orr_plane *planes, int nplanes, const float *rgb,
                              const struct orr_cards *cards, orr_error *err)
{
    (void)view, (void)rgb, (void)cards, (void)err;
    kept *k = user;
    for (int j = 0; j < nplanes && k->n < MAX_PLANES; j++, k->n++) {
        k->npix[k->n] = (size_t)planes[j].width * (size_t)planes[j].height;
        k->data[k->n] = malloc(k->npix[k->n] * sizeof(float));
        CHECK(k->data[k->n] != NULL);
        memcpy(k->data[k->n], planes[j].data, k->npix[k->n] * sizeof(float));
    }
    return ORR_OK;
}

static void kept_free(kept *k)
{
    for (int j = 0; j < k->n; j++)
        free(k->data[j]);
    memset(k, 0, sizeof *k);
}

static int kept_equal(const kept *a, const kept *b)
{
    if (a->n != b->n || a->n == 0)
        return 0;
    for (int j = 0; j < a->n; j++)
        if (a->npix[j] != b->npix[j] || memcmp(a->data[j], b->data[j], a->npix[j] * sizeof(float)) != 0)
            return 0;
    return 1;
}

static orr_scene *load(const char *yaml, const char *name)
{
    orr_scene *s = calloc(1, sizeof *s);
    orr_error err = {0};
    CHECK(s != NULL);
    orr_status st = orr_scene_load_string(s, yaml, name, ".", NULL, 0, &err);
    if (st)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(st == ORR_OK);
    orr_owned_set(&s->output.dir, tmpdir, NULL);
    snprintf(s->output.name, sizeof s->output.name, "%s", name);
    return s;
}

/* Frees a scene after scribbling over it: a plan that still pointed into it
 * would read garbage (under AddressSanitizer, freed memory). */
static void scribble_free(orr_scene *s)
{
    orr_scene_free(s);
    memset(s, 0xA5, sizeof *s);
    free(s);
}

static orr_frame_input frame_input(const orr_scene *s, long f, kept *k)
{
    orr_frame_input in = {orr_frame_at(f, FRAMES, s->animation.fps, 0, 0), NULL, NULL, keep_planes, k};
    return in;
}

/* Frame by frame through one plan, and each frame through a plan of its
 * own (orr_render_frame): the same bits; and the frames differ (the camera
 * moved, so the check could fail). */
static void check_run(const char *yaml, const char *name)
{
    orr_scene *s = load(yaml, name);
    const orr_scene *list[1] = {s};
    orr_render_report rep;
    orr_error err = {0};
    kept planned[FRAMES] = {{0}}, alone[FRAMES] = {{0}};
    orr_plan *plan = NULL;
    CHECK(orr_plan_create(&plan, list, 1, ORR_PLAN_RENDER, &err) == ORR_OK);
    for (long f = 0; f < FRAMES && plan; f++) {
        orr_frame_input in = frame_input(s, f, &planned[f]);
        orr_status st = orr_plan_execute(plan, &in, &rep, NULL, NULL, &err);
        if (st)
            fprintf(stderr, "%s\n", err.msg);
        CHECK(st == ORR_OK);
    }
    orr_plan_destroy(plan);
    for (long f = 0; f < FRAMES; f++) {
        orr_frame_input in = frame_input(s, f, &alone[f]);
        CHECK(orr_render_frame(list, 1, &in, &rep, NULL, NULL, &err) == ORR_OK);
        CHECK(kept_equal(&planned[f], &alone[f]));
    }
    CHECK(!kept_equal(&planned[0], &planned[FRAMES - 1]));
    for (int f = 0; f < FRAMES; f++) {
        kept_free(&planned[f]);
        kept_free(&alone[f]);
    }
    orr_scene_free(s);
    free(s);
}

/* A stereo pair on an orbit: each eye's camera and principal point (the
 * convergence is the distance to the orbit's centre) follow the path; the
 * Gaussian PSF's convolvers are the plan's. */
static void test_stereo_orbit(void)
{
    check_run(MODEL "camera:\n  projection: perspective\n  fov: 50\n  near: 0.1\n"
                    "  path: {kind: orbit, centre: [0, 0, 0], axis: [0, 0, 1], start: [70, -50, 45], turns: 0.5}\n"
                    "animation: {frames: 3}\nimage: {width: 96, height: 64}\ndeposit: cic\n"
                    "psf: {kind: gaussian, fwhm: 2}\n"
                    "stereo: {mode: separate, eye_separation: 2}\n"
                    "output: {fits: false, png: false}\n",
              "orbit");
}

/* A dome master on a line, every star drawn as the PSF's core from the
 * plan's stamps (kept across frames: they depend on the map alone). */
static void test_dome_cores(void)
{
    check_run(MODEL "camera:\n  projection: dome\n"
                    "  path: {kind: line, from: [8, 0, -2], to: [8, 0, 2], up: [1, 0, 0]}\n"
                    "animation: {frames: 3}\nimage: {width: 128, height: 128}\ndeposit: cic\n"
                    "psf: {kind: gaussian}\n"
                    "output: {fits: false, png: false}\n",
              "dome");
}

/* The FFT plans are the run's: made when the plan is, for each eye's
 * convolver, and never again however many frames are executed. */
static void test_fft_planned_once(void)
{
    orr_scene *s = load(MODEL "camera: {projection: orthographic, width: 100}\nimage: {width: 80, height: 60}\n"
                              "psf: {kind: gaussian, fwhm: 3}\n"
                              "output: {fits: false, png: false}\n",
                        "flat");
    const orr_scene *list[1] = {s};
    orr_render_report rep;
    orr_error err = {0};
    long before = orr_convolve_plans_created();
    orr_plan *plan = NULL;
    CHECK(orr_plan_create(&plan, list, 1, ORR_PLAN_RENDER, &err) == ORR_OK);
    CHECK(orr_convolve_plans_created() == before + 1);
    CHECK(orr_plan_seconds(plan) > 0);
    for (long f = 0; f < FRAMES && plan; f++) {
        kept k = {0};
        orr_frame_input in = frame_input(s, f, &k);
        CHECK(orr_plan_execute(plan, &in, &rep, NULL, NULL, &err) == ORR_OK);
        CHECK(k.n == 1);
        kept_free(&k);
    }
    CHECK(orr_convolve_plans_created() == before + 1);
    orr_plan_destroy(plan);
    orr_scene_free(s);
    free(s);
}

static int ends_with(const char *s, const char *end)
{
    size_t n = strlen(s), m = strlen(end);
    return n >= m && strcmp(s + n - m, end) == 0;
}

/* The frame input names each frame's files: the view's output.name with
 * the frame's number (output.frame_*), a separate eye's -left or -right
 * after it (the right eye's files reported with the left's); a still keeps
 * the name as it is. */
static void test_frame_names(void)
{
    orr_scene *s = load(MODEL "camera:\n  projection: perspective\n  fov: 50\n  near: 0.1\n"
                              "  position: [0, 0, 120]\n  look_at: [0, 0, 0]\n"
                              "image: {width: 32, height: 24}\n"
                              "stereo: {mode: separate, eye_separation: 2}\n"
                              "output: {fits: true, png: false, frame_start: 1, frame_digits: 3}\n",
                        "named");
    const orr_scene *list[1] = {s};
    orr_render_report rep;
    orr_error err = {0};
    orr_plan *plan = NULL;
    CHECK(orr_plan_create(&plan, list, 1, ORR_PLAN_RENDER, &err) == ORR_OK);
    scribble_free(s); /* the plan holds its own copies */
    orr_frame_input in = {orr_frame_at(2, 12, 25, 0, 0), NULL, NULL, NULL, NULL};
    orr_status st = plan ? orr_plan_execute(plan, &in, &rep, NULL, NULL, &err) : ORR_ERR_INTERNAL;
    if (st)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(st == ORR_OK);
    CHECK(rep.noutputs == 2);
    CHECK(ends_with(rep.outputs[0], "/named_003-left.fits"));
    CHECK(ends_with(rep.outputs[1], "/named_003-right.fits"));
    CHECK(plan && orr_plan_execute(plan, NULL, &rep, NULL, NULL, &err) == ORR_OK);
    CHECK(rep.noutputs == 2 && ends_with(rep.outputs[0], "/named-left.fits"));
    orr_plan_destroy(plan);
}

/* A compose re-grades the frame it is given: its files' names carry the
 * frame's number (a frame never rendered has no raw planes: refused,
 * naming them), and its picture is the render's, tint included (the tint
 * runs with the frame's place in the run); a render plan does not
 * compose. */
#define COMPOSED MODEL "camera: {projection: orthographic, width: 100}\nimage: {width: 40, height: 30}\n" \
                       "colour: {tint: {path: [20000, 6500, 2500], t: run}}\n" \
                       "output: {raw: true, frame_digits: 3}\n"

/* The bytes of file path (NULL when it cannot be read); *n its size. */
static unsigned char *file_bytes(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    unsigned char *b = f ? malloc(1 << 20) : NULL;
    *n = b ? fread(b, 1, 1 << 20, f) : 0;
    if (f)
        fclose(f);
    return b;
}

/* The pixels of a PNG of n bytes as the file holds them: its IDAT chunks'
 * data, joined (the text chunks name the source, which a compose's differs
 * in). Returns their length, 0 when b is not a PNG. */
static size_t png_idat(const unsigned char *b, size_t n, unsigned char *out, size_t cap)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (!b || n < 8 || memcmp(b, signature, 8) != 0)
        return 0;
    size_t len = 0;
    for (size_t at = 8; at + 12 <= n;) {
        size_t size = (size_t)b[at] << 24 | (size_t)b[at + 1] << 16 | (size_t)b[at + 2] << 8 | b[at + 3];
        if (at + 12 + size > n)
            return 0;
        if (memcmp(b + at + 4, "IDAT", 4) == 0 && len + size <= cap) {
            memcpy(out + len, b + at + 8, size);
            len += size;
        }
        at += 12 + size;
    }
    return len;
}

/* Whether two PNG files hold the same pixels, byte for byte. */
static int same_png_pixels(const unsigned char *a, size_t na, const unsigned char *b, size_t nb)
{
    static unsigned char pa[1 << 20], pb[1 << 20];
    size_t la = png_idat(a, na, pa, sizeof pa), lb = png_idat(b, nb, pb, sizeof pb);
    return la > 0 && la == lb && memcmp(pa, pb, la) == 0;
}
static void test_compose_frame(void)
{
    orr_scene *s = load(COMPOSED, "comp");
    const orr_scene *list[1] = {s};
    orr_render_report rep;
    orr_error err = {0};
    orr_plan *plan = NULL;
    orr_frame_input in = {orr_frame_at(9, 12, 25, 0, 0), NULL, NULL, NULL, NULL};
    CHECK(orr_render_frame(list, 1, &in, &rep, NULL, NULL, &err) == ORR_OK);
    char png[4096];
    snprintf(png, sizeof png, "%s/comp_009.png", tmpdir);
    size_t nrendered = 0, ncomposed = 0;
    unsigned char *rendered_png = file_bytes(png, &nrendered);
    CHECK(orr_plan_create(&plan, list, 1, ORR_PLAN_COMPOSE, &err) == ORR_OK);
    scribble_free(s);
    remove(png);
    const orr_compose_frame rendered = {orr_frame_at(9, 12, 25, 0, 0), NULL};
    orr_status st = plan ? orr_plan_compose(plan, &rendered, &rep, &err) : ORR_ERR_INTERNAL;
    if (st)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(st == ORR_OK);
    int named = 0;
    for (int i = 0; i < rep.noutputs; i++)
        named += ends_with(rep.outputs[i], "/comp_009.png");
    CHECK(named == 1);
    unsigned char *composed_png = file_bytes(png, &ncomposed);
    CHECK(same_png_pixels(rendered_png, nrendered, composed_png, ncomposed));
    free(rendered_png);
    free(composed_png);
    const orr_compose_frame never = {orr_frame_at(5, 12, 25, 0, 0), NULL};
    CHECK(plan && orr_plan_compose(plan, &never, &rep, &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "comp_005.raw.fits");
    orr_plan_destroy(plan);
    plan = NULL;
    s = load(COMPOSED, "comp");
    list[0] = s;
    CHECK(orr_plan_create(&plan, list, 1, ORR_PLAN_RENDER, &err) == ORR_OK);
    CHECK(plan && orr_plan_compose(plan, &rendered, &rep, &err) == ORR_ERR_INTERNAL);
    orr_plan_destroy(plan);
    scribble_free(s);
}

int main(void)
{
    make_tmpdir();
    RUN(test_stereo_orbit);
    RUN(test_dome_cores);
    RUN(test_fft_planned_once);
    RUN(test_compose_frame);
    RUN(test_frame_names);
    remove_tmpdir();
    return check_summary();
}
