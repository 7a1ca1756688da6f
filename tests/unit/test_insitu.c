/* The in-situ API (orrery.h): arrays read in place in any layout, frames
 * rendered from them with the same pixels as a file of the same particles,
 * and errors that come back as codes and messages. */
#include <math.h>
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "fits_image.h"
#include "orrery.h"
#include "source/arrays.h"
#include "tmpdir.h"

/* A simulation's own array of structures. */
typedef struct body {
    double pos[3];
    double vel[3];
    float mass;
    uint64_t id;
    uint8_t type;
} body;

#define NB 1000

static body bodies[NB];

static void make_bodies(void)
{
    srand(7);
    for (int i = 0; i < NB; i++) {
        for (int k = 0; k < 3; k++) {
            bodies[i].pos[k] = 8.0 * rand() / RAND_MAX - 4.0;
            bodies[i].vel[k] = k + 0.5 * i;
        }
        bodies[i].mass = 0.5f + (float)(i % 3);
        bodies[i].id = 1000 + 3 * (uint64_t)i;
        bodies[i].type = (uint8_t)(i % 2 ? 4 : 1);
    }
}

static orr_particle_arrays aos_arrays(void)
{
    orr_particle_arrays p = {0};
    p.n = NB;
    p.x = (orr_array){&bodies[0].pos[0], ORR_F64, sizeof(body)};
    p.y = (orr_array){&bodies[0].pos[1], ORR_F64, sizeof(body)};
    p.z = (orr_array){&bodies[0].pos[2], ORR_F64, sizeof(body)};
    p.vx = (orr_array){&bodies[0].vel[0], ORR_F64, sizeof(body)};
    p.mass = (orr_array){&bodies[0].mass, ORR_F32, sizeof(body)};
    p.id = &bodies[0].id;
    p.id_stride = sizeof(body);
    p.type = &bodies[0].type;
    p.type_stride = sizeof(body);
    p.time = 2.5;
    return p;
}

static void test_arrays_source(void)
{
    orr_particle_arrays p = aos_arrays();
    orr_source *src;
    orr_error err = {0};
    /* Only type 4 (the odd bodies), in chunks of 7. */
    CHECK(orr_arrays_source_open(&p, "test bodies", 7, 1u << 4, &src, &err) == ORR_OK);
    CHECK_NEAR(src->info.time, 2.5, 0);
    CHECK(src->info.nextra == 1 && strcmp(src->info.extra_names[0], "vx") == 0);
    size_t seen = 0;
    int ok = 1;
    for (;;) {
        const orr_chunk *c;
        CHECK(orr_source_next(src, &c, &err) == ORR_OK);
        if (c->n == 0)
            break;
        CHECK(c->n <= 7);
        for (size_t i = 0; i < c->n; i++, seen++) {
            const body *b = &bodies[2 * seen + 1];
            ok &= c->x[i] == (float)b->pos[0] && c->y[i] == (float)b->pos[1] && c->z[i] == (float)b->pos[2];
            ok &= c->mass[i] == b->mass && c->id[i] == b->id && c->type[i] == 4;
            ok &= orr_chunk_field(c, "vx")[i] == (float)b->vel[0];
        }
    }
    CHECK(ok);
    CHECK(seen == NB / 2);
    /* Rewound, it yields the same first particle again. */
    const orr_chunk *c;
    CHECK(orr_source_rewind(src, &err) == ORR_OK);
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 7 && c->id[0] == bodies[1].id);
    orr_source_close(src);

    /* Packed float arrays, constant mass, ids numbered from an offset. */
    float xs[3] = {1, 2, 3}, ys[3] = {4, 5, 6}, zs[3] = {7, 8, 9};
    orr_particle_arrays q = {.n = 3, .x = {xs, ORR_F32, 0}, .y = {ys, ORR_F32, 0}, .z = {zs, ORR_F32, 0},
                             .mass_value = 0.25, .id_offset = 40};
    CHECK(orr_arrays_source_open(&q, "packed", 100, 0, &src, &err) == ORR_OK);
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 3);
    CHECK(c->y[2] == 6 && c->mass[1] == 0.25f && c->id[2] == 42);
    orr_source_close(src);

    /* Bad arrays are refused with the array named. */
    q.y.data = NULL;
    CHECK(orr_arrays_source_open(&q, "packed", 100, 0, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "positions");
    q.y = (orr_array){ys, (orr_dtype)9, 0};
    CHECK(orr_arrays_source_open(&q, "packed", 100, 0, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "array y");
}

/* Strides that no array has are refused with the array named: elements
 * that would overlap, and a negative stride (a reversed NumPy view handed
 * over as size_t), which wraps past the end of the address space. */
static void test_bad_strides(void)
{
    double xs[4] = {1, 2, 3, 4}, ys[4] = {5, 6, 7, 8}, zs[4] = {0};
    uint64_t ids[4] = {1, 2, 3, 4};
    orr_particle_arrays q = {.n = 4, .x = {xs, ORR_F64, 0}, .y = {ys, ORR_F64, 0}, .z = {zs, ORR_F64, 0},
                             .mass_value = 1};
    orr_source *src = NULL;
    orr_error err = {0};
    q.y.stride = sizeof(float); /* doubles 4 bytes apart */
    CHECK(orr_arrays_source_open(&q, "strides", 100, 0, &src, &err) == ORR_ERR_USAGE && !src);
    CHECK_CONTAINS(err.msg, "strides: array y has a stride of 4 bytes, less than its 8-byte elements");
    q.y.stride = 0;
    q.id = ids;
    q.id_stride = 2;
    CHECK(orr_arrays_source_open(&q, "strides", 100, 0, &src, &err) == ORR_ERR_USAGE && !src);
    CHECK_CONTAINS(err.msg, "array id has a stride of 2 bytes");
    /* x[::-1]: the last element first, stride -8. */
    q.id_stride = 0;
    q.x = (orr_array){&xs[3], ORR_F64, (size_t)-(ptrdiff_t)sizeof(double)};
    CHECK(orr_arrays_source_open(&q, "strides", 100, 0, &src, &err) == ORR_ERR_USAGE && !src);
    CHECK_CONTAINS(err.msg, "array x: 4 elements");
    CHECK_CONTAINS(err.msg, "run past the end of memory");
    q.x = (orr_array){xs, ORR_F64, 0};
    uint8_t types[4] = {0, 1, 0, 1};
    q.type = &types[3];
    q.type_stride = SIZE_MAX;
    CHECK(orr_arrays_source_open(&q, "strides", 100, 0, &src, &err) == ORR_ERR_USAGE && !src);
    CHECK_CONTAINS(err.msg, "array type: 4 elements");
    /* One particle: any stride reads only its first element. */
    q.type_stride = 0;
    q.n = 1;
    q.y.stride = 1u << 30;
    CHECK(orr_arrays_source_open(&q, "strides", 100, 0, &src, &err) == ORR_OK);
    orr_source_close(src);
}

/* Packed arrays at an address that is no multiple of their element's
 * alignment are converted, not read in place through a misaligned
 * pointer (which the undefined-behaviour sanitizer reports). */
static void test_misaligned_arrays(void)
{
    enum { N = 5 };
    _Alignas(8) unsigned char raw[N * 8 + 8 + 1];
    float xs[N];
    uint64_t ids[N];
    for (int i = 0; i < N; i++) {
        xs[i] = 0.5f * (float)i;
        ids[i] = 100 + (uint64_t)i;
    }
    unsigned char *xp = raw + 1; /* floats at an odd address */
    memcpy(xp, xs, sizeof xs);
    _Alignas(8) unsigned char idraw[N * 8 + 8];
    unsigned char *ip = idraw + 4; /* ids 4 bytes off their alignment */
    memcpy(ip, ids, sizeof ids);
    orr_particle_arrays q = {.n = N, .x = {xp, ORR_F32, 0}, .y = {xs, ORR_F32, 0}, .z = {xs, ORR_F32, 0},
                             .mass_value = 1, .id = (const uint64_t *)(const void *)ip};
    orr_source *src = NULL;
    orr_error err = {0};
    const orr_chunk *c;
    CHECK(orr_arrays_source_open(&q, "misaligned", 100, 0, &src, &err) == ORR_OK);
    CHECK(src && orr_source_next(src, &c, &err) == ORR_OK && c->n == N);
    int same = 1;
    for (int i = 0; src && i < N; i++)
        same &= c->x[i] == xs[i] && c->id[i] == ids[i];
    CHECK(same);
    CHECK(src && (const void *)c->x != (const void *)xp && (const void *)c->id != (const void *)ip);
    orr_source_close(src);
}

static const char scene_yaml[] = "camera: {projection: orthographic, width: 10}\n"
                                 "image: {width: 40, height: 30}\n"
                                 "deposit: ngp\n"
                                 "output: {name: step, png: false}\n";

/* A fresh temporary folder and a renderer of scene_yaml writing into it
 * (NULL, with the message printed, when it cannot be opened: a failed
 * CHECK). */
static orrery_renderer *open_in_tmpdir(void)
{
    make_tmpdir();
    char outdir[320], msg[1024];
    snprintf(outdir, sizeof outdir, "output.dir=%s", tmpdir);
    const char *sets[1] = {outdir};
    orrery_renderer *r = NULL;
    CHECK(orrery_open_yaml(&r, scene_yaml, ".", sets, 1, msg, sizeof msg) == ORRERY_OK);
    if (!r)
        fprintf(stderr, "%s\n", msg);
    return r;
}

static void test_render_steps(void)
{
    orrery_renderer *r = open_in_tmpdir();
    if (!r)
        return;
    orr_particle_arrays p = aos_arrays();
    CHECK(orrery_render(r, &p, 0) == ORRERY_OK);
    CHECK(orrery_output_count(r) == 1);
    char path[512];
    snprintf(path, sizeof path, "%s/step_0000.fits", tmpdir);
    CHECK(orrery_output(r, 0) && strcmp(orrery_output(r, 0), path) == 0);
    CHECK(orrery_render_seconds(r) > 0);

    /* Mass conservation: every body lies within the 10 x 7.5 view. */
    long npix = 0;
    float *a = read_fits_image(path, &npix);
    double sum = 0, mass = 0;
    for (long i = 0; a && i < npix; i++)
        sum += a[i];
    for (int i = 0; i < NB; i++)
        mass += fabs(bodies[i].pos[1]) < 3.75 ? bodies[i].mass : 0;
    CHECK_NEAR(sum * (10.0 / 40) * (10.0 / 40), mass, 1e-4 * mass); /* mass per unit area, times a pixel's */

    /* The next step moves every body; its frame has its own name and image. */
    for (int i = 0; i < NB; i++)
        bodies[i].pos[0] += 0.5;
    CHECK(orrery_render(r, &p, 1) == ORRERY_OK);
    snprintf(path, sizeof path, "%s/step_0001.fits", tmpdir);
    float *b = read_fits_image(path, &npix);
    int differ = 0;
    for (long i = 0; a && b && i < npix; i++)
        differ |= a[i] != b[i];
    CHECK(b && differ);
    free(a);
    free(b);

    /* A non-finite position is an error naming it, not a crash. */
    bodies[5].pos[2] = NAN;
    CHECK(orrery_render(r, &p, 2) == ORRERY_ERR_DATA);
    CHECK_CONTAINS(orrery_error(r), "in-situ particles");
    bodies[5].pos[2] = 0;
    CHECK(orrery_render(r, NULL, 3) == ORRERY_ERR_USAGE);
    orrery_close(r);

    /* A bad scene fails at open with the key named. */
    r = NULL;
    const char *bad[1] = {"camera.fov=500"};
    char msg[1024];
    CHECK(orrery_open_yaml(&r, scene_yaml, ".", bad, 1, msg, sizeof msg) == ORRERY_ERR_USAGE);
    CHECK(r == NULL);
    CHECK_CONTAINS(msg, "camera.fov");
    remove_tmpdir();
}

/* orrery_keep_images: the planes in memory are the FITS file's, row for row
 * (the file's rows bottom-up), with the picture and the cards. */
static void test_kept_images(void)
{
    char path[512];
    orrery_renderer *r = open_in_tmpdir();
    if (!r)
        return;
    orr_particle_arrays p = aos_arrays();
    CHECK(orrery_particle_arrays_size() == sizeof(orr_particle_arrays));
    CHECK(orrery_image_count(r) == 0);
    CHECK(orrery_render(r, &p, 0) == ORRERY_OK && orrery_image_count(r) == 0); /* off by default */
    CHECK(orrery_keep_images(r, 1) == ORRERY_OK);
    CHECK(orrery_render(r, &p, 1) == ORRERY_OK);
    CHECK(orrery_image_count(r) == 1);
    int w = 0, h = 0, np = 0;
    CHECK(orrery_image_size(r, 0, &w, &h, &np) == ORRERY_OK && w == 40 && h == 30 && np == 1);
    CHECK(orrery_image_size(r, 1, &w, &h, &np) == ORRERY_ERR_USAGE);
    const char *name = NULL, *unit = NULL;
    const float *plane = orrery_image_plane(r, 0, 0, &name, &unit);
    CHECK(plane && name && strcmp(name, "mass") == 0 && unit); /* the unit: output.bunit's, per area */
    CHECK(orrery_image_plane(r, 0, 1, NULL, NULL) == NULL);
    snprintf(path, sizeof path, "%s/step_0001.fits", tmpdir);
    long npix = 0;
    float *file = read_fits_image(path, &npix);
    int same = file && npix == 40 * 30;
    for (int y = 0; same && y < 30; y++)
        same = memcmp(plane + (size_t)y * 40, file + (size_t)(29 - y) * 40, 40 * sizeof(float)) == 0;
    CHECK(same);
    free(file);
    const float *rgb = orrery_image_rgb(r, 0);
    int in_range = rgb != NULL;
    for (int i = 0; in_range && i < 40 * 30 * 3; i++)
        in_range = rgb[i] >= 0 && rgb[i] <= 1;
    CHECK(in_range);
    const char *cards = orrery_image_header(r, 0);
    CHECK(cards && strstr(cards, "PROJTYPE = 'orthographic'\n") && strstr(cards, "NPART = 1000\n"));
    CHECK(cards && strstr(cards, "SIMTIME = 2.5\n"));
    /* A failed frame keeps nothing. */
    bodies[3].pos[0] = NAN;
    CHECK(orrery_render(r, &p, 2) == ORRERY_ERR_DATA && orrery_image_count(r) == 0);
    bodies[3].pos[0] = 0;
    orrery_close(r);
    remove_tmpdir();
}

/* struct_size: 0 and sizeof are this header's layout; anything else, a
 * caller built against another orrery.h, is refused naming both sizes. */
static void test_struct_size(void)
{
    char want[160];
    orrery_renderer *r = open_in_tmpdir();
    if (!r)
        return;
    orr_particle_arrays p = aos_arrays();
    p.struct_size = 0;
    CHECK(orrery_render(r, &p, 0) == ORRERY_OK);
    p.struct_size = sizeof p;
    CHECK(orrery_render(r, &p, 1) == ORRERY_OK);
    size_t wrong[] = {sizeof p - 8, sizeof p + 8, 8};
    for (int k = 0; k < 3; k++) {
        p.struct_size = wrong[k];
        CHECK(orrery_render(r, &p, 2) == ORRERY_ERR_USAGE);
        snprintf(want, sizeof want, "orr_particle_arrays.struct_size is %zu, but this liborrery's "
                 "orr_particle_arrays is %zu bytes", wrong[k], sizeof p);
        CHECK_CONTAINS(orrery_error(r), want);
    }
    orrery_close(r);
    remove_tmpdir();
}

static void cancel_at_first_call(void *user, uint64_t done, int64_t total)
{
    (void)done;
    (void)total;
    CHECK(orrery_cancel(user) == ORRERY_OK);
}

/* orrery_cancel from the progress callback (here after the only chunk):
 * the frame stops with its own code, writes nothing, keeps nothing; the
 * next frame renders. */
static void test_cancel(void)
{
    char path[512];
    orrery_renderer *r = open_in_tmpdir();
    if (!r)
        return;
    orr_particle_arrays p = aos_arrays();
    CHECK(orrery_keep_images(r, 1) == ORRERY_OK);
    CHECK(orrery_set_progress(r, cancel_at_first_call, r) == ORRERY_OK);
    CHECK(orrery_render(r, &p, 0) == ORRERY_ERR_CANCELLED);
    CHECK_CONTAINS(orrery_error(r), "cancelled");
    snprintf(path, sizeof path, "%s/step_0000.fits", tmpdir);
    CHECK(access(path, F_OK) != 0 && orrery_output_count(r) == 0 && orrery_image_count(r) == 0);
    CHECK(orrery_set_progress(r, NULL, NULL) == ORRERY_OK);
    CHECK(orrery_cancel(r) == ORRERY_OK); /* while nothing renders: forgotten by the next render */
    CHECK(orrery_render(r, &p, 0) == ORRERY_OK && access(path, F_OK) == 0 && orrery_image_count(r) == 1);
    CHECK(orrery_cancel(NULL) == ORRERY_ERR_USAGE);
    orrery_close(r);
    remove_tmpdir();
}

int main(void)
{
    make_bodies();
    test_arrays_source();
    test_render_steps();
    test_kept_images();
    test_struct_size();
    test_cancel();
    test_bad_strides();
    test_misaligned_arrays();
    return check_summary();
}
