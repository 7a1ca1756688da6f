/* Periodic boxes drawn as copies: where the copies go, which the view test
 * culls, and renders of a uniform box from inside its copies: seamless,
 * conserving weight over the copies, and the same image with culling off. */
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "encode/fits_read.h"
#include "frame/replicas.h"
#include "render/periodic_view.h"
#include "render/render.h"
#include "scene/scene.h"

static char tmpdir[] = "/tmp/orrery-periodic-XXXXXX";

static void test_replicas_around_camera(void)
{
    orr_replicas r;
    orr_error err;
    /* Camera in the copy (2, 0, -1) of a box of side 10. */
    CHECK(orr_replicas_place(&r, 10, 3, 1, orr_v3(25, 5, -5), &err) == ORR_OK);
    CHECK(r.n == 27);
    CHECK_NEAR(r.offset[0].x, 20, 0);
    CHECK_NEAR(r.offset[0].y, 0, 0);
    CHECK_NEAR(r.offset[0].z, -10, 0);
    /* Every copy distinct, each within one box of the middle one. */
    int distinct = 1, near = 1;
    for (int a = 0; a < r.n; a++) {
        orr_vec3 d = orr_v3_sub(r.offset[a], r.offset[0]);
        near = near && fabs(d.x) <= 10 && fabs(d.y) <= 10 && fabs(d.z) <= 10;
        for (int b = 0; b < a; b++)
            distinct = distinct && orr_v3_norm(orr_v3_sub(r.offset[a], r.offset[b])) > 1;
    }
    CHECK(distinct && near);
    /* Around the origin: the box itself in the middle, wherever the camera. */
    CHECK(orr_replicas_place(&r, 10, 5, 0, orr_v3(25, 5, -5), &err) == ORR_OK);
    CHECK(r.n == 125);
    CHECK(orr_v3_norm(r.offset[0]) == 0);
    CHECK(orr_replicas_place(&r, 10, 4, 0, orr_v3(0, 0, 0), &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "odd");
    CHECK(orr_replicas_place(&r, -1, 3, 0, orr_v3(0, 0, 0), &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.box");
}

/* A perspective camera at the origin looking along -z (no orientation:
 * +y up), 90 degrees across 100 x 100 pixels: the view is |x|, |y| <= -z. */
static orr_view_cull perspective_view(void)
{
    orr_projection p = {.kind = ORR_PROJ_PERSPECTIVE, .width = 100, .height = 100, .fov_deg = 90, .near = 0.01};
    orr_error err;
    CHECK(orr_projection_setup(&p, &err) == ORR_OK);
    orr_camera cam;
    CHECK(orr_camera_look_along(&cam, orr_v3(0, 0, 0), orr_v3(0, 0, -1), orr_v3(0, 1, 0), 0, &err) == ORR_OK);
    orr_view_cull vc;
    orr_view_cull_setup(&vc, &p, &cam, 2.0);
    return vc;
}

static void test_perspective_culling(void)
{
    orr_view_cull vc = perspective_view();
    const orr_vec3 zero = orr_v3(0, 0, 0);
    CHECK(vc.active);
    /* In front, in the middle of the view: kept. */
    CHECK(!orr_view_cull_box(&vc, orr_v3(-1, -1, -6), orr_v3(1, 1, -4), zero, 0));
    /* Behind the camera: culled (by the near plane). */
    CHECK(orr_view_cull_box(&vc, orr_v3(-1, -1, 4), orr_v3(1, 1, 6), zero, 0));
    /* The camera's own box: kept. */
    CHECK(orr_view_cull_box(&vc, orr_v3(-1, -1, -1), orr_v3(1, 1, 1), zero, 0) == 0);
    /* Wholly left of the frustum (x < -z - margin at every depth): culled;
     * moved right by a shift so that it straddles the left edge: kept. */
    CHECK(orr_view_cull_box(&vc, orr_v3(-9, -1, -5), orr_v3(-7, 1, -4), zero, 0));
    CHECK(!orr_view_cull_box(&vc, orr_v3(-9, -1, -5), orr_v3(-7, 1, -4), orr_v3(4, 0, 0), 0));
    /* Above the top edge by 1 at depth 5: culled, unless kernels reach 1.5. */
    CHECK(orr_view_cull_box(&vc, orr_v3(-1, 6, -5), orr_v3(1, 7, -5), zero, 0));
    CHECK(!orr_view_cull_box(&vc, orr_v3(-1, 6, -5), orr_v3(1, 7, -5), zero, 1.5));
    /* A thin box just behind the camera, within the side planes' wedge
     * behind it: culled by the near plane alone. */
    CHECK(orr_view_cull_box(&vc, orr_v3(-1, -1, 1e-3), orr_v3(1, 1, 2e-3), zero, 0));
}

static void test_orthographic_and_sky(void)
{
    orr_error err;
    orr_projection p = {.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 100, .height = 50, .ortho_width = 10};
    CHECK(orr_projection_setup(&p, &err) == ORR_OK);
    orr_camera cam;
    CHECK(orr_camera_look_along(&cam, orr_v3(0, 0, 0), orr_v3(0, 0, -1), orr_v3(0, 1, 0), 0, &err) == ORR_OK);
    orr_view_cull vc;
    orr_view_cull_setup(&vc, &p, &cam, 1.0);
    /* The slab |x| <= 5.1, |y| <= 2.6 at every depth, behind the camera too. */
    CHECK(!orr_view_cull_box(&vc, orr_v3(-1, -1, 100), orr_v3(1, 1, 101), orr_v3(0, 0, 0), 0));
    CHECK(orr_view_cull_box(&vc, orr_v3(6, -1, -3), orr_v3(7, 1, -2), orr_v3(0, 0, 0), 0));
    CHECK(!orr_view_cull_box(&vc, orr_v3(5, -1, -3), orr_v3(7, 1, -2), orr_v3(0, 0, 0), 0));
    CHECK(orr_view_cull_box(&vc, orr_v3(-1, 2.8, -3), orr_v3(1, 3, -2), orr_v3(0, 0, 0), 0));
    /* A sky map sees everything. */
    orr_projection sky = {.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 100, .height = 50};
    CHECK(orr_projection_setup(&sky, &err) == ORR_OK);
    orr_view_cull_setup(&vc, &sky, &cam, 1.0);
    CHECK(!vc.active);
    CHECK(!orr_view_cull_box(&vc, orr_v3(60, 60, 60), orr_v3(61, 61, 61), orr_v3(0, 0, 0), 0));
}

static void test_box_side_from_header(void)
{
    orr_scene s;
    orr_scene_defaults(&s);
    s.periodic_replicas = 3;
    orr_source_info info;
    memset(&info, 0, sizeof info);
    snprintf(info.path, sizeof info.path, "snap.hdf5");
    orr_error err;
    double box = 0;
    CHECK(orr_periodic_box_side(&s, &info, &box, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.box");
    orr_source_add_header(&info, "BoxSize", "50000 50000 50000");
    CHECK(orr_periodic_box_side(&s, &info, &box, &err) == ORR_OK);
    CHECK_NEAR(box, 50000, 0);
    snprintf(info.header[0].value, sizeof info.header[0].value, "100 100 50");
    CHECK(orr_periodic_box_side(&s, &info, &box, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "100 100 50");
    s.periodic_box = 7; /* the key wins over the header */
    CHECK(orr_periodic_box_side(&s, &info, &box, &err) == ORR_OK);
    CHECK_NEAR(box, 7, 0);
}

static void test_scene_keys(void)
{
    orr_scene s;
    orr_error err;
    const char *ok = "input: {file: x.txt, periodic: {box: 2, replicas: 5, centre: origin}}\n";
    CHECK(orr_scene_load_string(&s, ok, "ok.yaml", "/tmp", NULL, 0, &err) == ORR_OK);
    CHECK_NEAR(s.periodic_box, 2, 0);
    CHECK(s.periodic_replicas == 5 && s.periodic_around_camera == 0);
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt}\n", "d.yaml", "/tmp", NULL, 0, &err) == ORR_OK);
    CHECK(s.periodic_box == 0 && s.periodic_replicas == 1 && s.periodic_around_camera == 1);
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt, periodic: {replicas: 4}}\n", "e.yaml", "/tmp", NULL, 0,
                                &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "input.periodic.replicas");
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt, periodic: {centre: middle}}\n", "f.yaml", "/tmp", NULL, 0,
                                &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "middle");
}

/* ---- renders of a uniform box ---- */

#define NPART 20000

static int cmp_x(const void *a, const void *b)
{
    double d = ((const double *)a)[0] - ((const double *)b)[0];
    return (d > 0) - (d < 0);
}

/* NPART particles of mass 1 uniformly in the unit box, written in order of
 * x (as a spatially ordered snapshot), so blocks of 4096 are slabs. */
static void write_uniform_box(const char *path)
{
    double *p = malloc(3 * NPART * sizeof *p);
    srand(11);
    for (int i = 0; i < 3 * NPART; i++)
        p[i] = rand() / (RAND_MAX + 1.0);
    qsort(p, NPART, 3 * sizeof *p, cmp_x);
    FILE *fp = fopen(path, "w");
    fprintf(fp, "x y z mass\n");
    for (int i = 0; i < NPART; i++)
        fprintf(fp, "%.7f %.7f %.7f 1\n", p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    fclose(fp);
    free(p);
}

/* The camera sits on the boundary x = 1 between two copies, in the middle
 * of the others (y, z = 1.5), looking along -z with 60 degrees across
 * 120 x 80 pixels: its copies (x from 0 to 3, z from 0 to 3) fill the view
 * to the depth 1.5 of the plane z = 0 (the view's half-width there is
 * 1.5 tan 30 = 0.87 < 1). */
static orr_status render_box(const char *name, const char *deposit, orr_render_report *rep, orr_plane *plane,
                             int *nplanes)
{
    char yaml[1024], fits[600];
    snprintf(yaml, sizeof yaml,
             "input: {file: box.txt, periodic: {box: 1, replicas: 3}}\n"
             "camera: {position: [1, 1.5, 1.5], projection: perspective, fov: 60, near: 0.001}\n"
             "image: {width: 120, height: 80}\n"
             "deposit: %s\n"
             "output: {dir: %s, name: %s, png: false}\n",
             deposit, tmpdir, name);
    orr_scene s;
    orr_error err;
    orr_status st = orr_scene_load_string(&s, yaml, name, tmpdir, NULL, 0, &err);
    if (!st)
        st = orr_render_scene(&s, rep, NULL, NULL, &err);
    if (st) {
        fprintf(stderr, "%s\n", err.msg);
        return st;
    }
    snprintf(fits, sizeof fits, "%s/%s.fits", tmpdir, name);
    return orr_read_fits_planes(fits, plane, 1, nplanes, &err);
}

/* The mean over columns [i0, i1) of each pixel's value over what a uniform
 * slab predicts there: expect / cos^3 theta, theta the pixel centre's angle
 * off the axis (a pixel holds mass per steradian, and the sightline to the
 * slab's far face grows as 1 / cos theta, the volume per steradian as its
 * cube). f is the focal length in pixels. */
static double strip_ratio(const orr_plane *p, int i0, int i1, double f, double expect)
{
    double sum = 0;
    for (int j = 0; j < p->height; j++)
        for (int i = i0; i < i1; i++) {
            double x = i + 0.5 - 0.5 * p->width, y = j + 0.5 - 0.5 * p->height;
            double cos_theta = f / sqrt(x * x + y * y + f * f);
            sum += p->data[(size_t)j * p->width + i] * cos_theta * cos_theta * cos_theta / expect;
        }
    return sum / ((double)(i1 - i0) * p->height);
}

static void test_render_uniform_box(void)
{
    char table[600];
    snprintf(table, sizeof table, "%s/box.txt", tmpdir);
    write_uniform_box(table);
    orr_render_report culled, full;
    orr_plane a, b;
    int na = 0, nb = 0;
    unsetenv("ORRERY_NO_CULL");
    CHECK(render_box("culled", "cic", &culled, &a, &na) == ORR_OK && na == 1);
    setenv("ORRERY_NO_CULL", "1", 1);
    CHECK(render_box("full", "cic", &full, &b, &nb) == ORR_OK && nb == 1);
    unsetenv("ORRERY_NO_CULL");
    if (na != 1 || nb != 1)
        return;

    /* Culling changes nothing in the image, bit for bit. */
    CHECK(memcmp(a.data, b.data, (size_t)a.width * a.height * sizeof(float)) == 0);
    /* Conservation over the copies: every copy of every particle is
     * deposited, fell off the image, or was not drawn (culled). */
    const orr_render_report *reps[2] = {&culled, &full};
    for (int k = 0; k < 2; k++) {
        const orr_deposit_stats *d = &reps[k]->deposit;
        CHECK(reps[k]->n_replicas == 27);
        CHECK(reps[k]->n_selected == 27ull * NPART);
        CHECK_NEAR(d->deposited + d->outside + d->culled, 27.0 * NPART, 1e-6 * NPART);
        CHECK_NEAR(d->deposited, full.deposit.deposited, 1e-9 * NPART);
    }
    /* Copies culled whole: the 9 behind the camera (z from 2 to 3); x from 2
     * to 3 (the view reaches x = 1 + 0.87 at most): 3 more in front; and
     * with z from 1 to 2 (depth 0 to 0.5, where the view's half-height is
     * 0.5 tan 21.05 deg = 0.19) those with y below 1 or above 2: 4 more; 19.
     * Of the blocks (slabs of x) of the others, those beside the view too. */
    CHECK(culled.n_replicas_culled == 19);
    CHECK(culled.n_blocks == 27 * 5);
    CHECK(culled.n_blocks_culled > 19 * 5);
    CHECK(full.n_replicas_culled == 0 && full.n_blocks_culled == 0);
    fprintf(stderr, "  culled %llu of 27 copies, %llu of %llu blocks\n", (unsigned long long)culled.n_replicas_culled,
            (unsigned long long)culled.n_blocks_culled, (unsigned long long)culled.n_blocks);

    /* Seamless: in perspective the cone of one steradian along the axis to
     * the depth D = 1.5 holds the volume D^3 / 3: with NPART per unit
     * volume, and pixels holding mass per steradian, the centre expects
     * NPART D^3 / 3 (strip_ratio: and off the axis). The boundary x = 1
     * passes through the camera, so it is the middle column: the strips
     * either side (different copies, different particles) agree, and with
     * the image as a whole. */
    double expect = NPART * 1.5 * 1.5 * 1.5 / 3.0;
    double f = 60.0 / tan(30.0 * 3.14159265358979 / 180.0);
    double left = strip_ratio(&a, 40, 60, f, expect), right = strip_ratio(&a, 60, 80, f, expect);
    double all = strip_ratio(&a, 2, 118, f, expect);
    /* A strip of 20 x 80 pixels holds about 20000 / 6 particles: 1.7 % noise. */
    CHECK_NEAR(left / right, 1.0, 0.08);
    CHECK_NEAR(left, 1.0, 0.08);
    CHECK_NEAR(right, 1.0, 0.08);
    CHECK_NEAR(all, 1.0, 0.04);
    fprintf(stderr, "  measured over expected: left %.4f right %.4f all %.4f\n", left, right, all);
    orr_plane_free(&a);
    orr_plane_free(&b);
}

/* SPH kernels reach past their centres (support 2h, h from the 32nd
 * neighbour here): culling allows for the largest kernel of a block, and
 * the copies take the same lengths from the neighbour pass. */
static void test_render_sph_same_image(void)
{
    orr_render_report culled, full;
    orr_plane a, b;
    int na = 0, nb = 0;
    CHECK(render_box("sph_culled", "sph", &culled, &a, &na) == ORR_OK && na == 1);
    setenv("ORRERY_NO_CULL", "1", 1);
    CHECK(render_box("sph_full", "sph", &full, &b, &nb) == ORR_OK && nb == 1);
    unsetenv("ORRERY_NO_CULL");
    if (na != 1 || nb != 1)
        return;
    CHECK(memcmp(a.data, b.data, (size_t)a.width * a.height * sizeof(float)) == 0);
    CHECK(culled.n_blocks_culled > 0);
    CHECK_NEAR(culled.deposit.deposited, full.deposit.deposited, 1e-9 * NPART);
    const orr_deposit_stats *d = &culled.deposit;
    CHECK_NEAR(d->deposited + d->outside + d->culled, 27.0 * NPART, 1e-6 * NPART);
    fprintf(stderr, "  sph: culled %llu of 135 blocks\n", (unsigned long long)culled.n_blocks_culled);
    orr_plane_free(&a);
    orr_plane_free(&b);
}

int main(void)
{
    if (!mkdtemp(tmpdir))
        return 1;
    RUN(test_replicas_around_camera);
    RUN(test_perspective_culling);
    RUN(test_orthographic_and_sky);
    RUN(test_box_side_from_header);
    RUN(test_scene_keys);
    RUN(test_render_uniform_box);
    RUN(test_render_sph_same_image); /* after: uses its box.txt */
    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0)
        return 1;
    fprintf(stderr, "%d checks, %d failed\n", check_count, check_failures);
    return check_failures ? 1 : 0;
}
