/* Periodic boxes drawn as copies: where the copies go, which the view test
 * culls, and renders of a uniform box from inside its copies: seamless,
 * conserving weight over the copies, and the same image with culling off. */
#include <omp.h>
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "planned.h"
#include "encode/fits_read.h"
#include "frame/projection.h"
#include "frame/replicas.h"
#include "pass/periodic_view.h"
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

/* The sphere of centre: camera: its default radius is as far as the
 * copies reach, its fade a quarter of it; a radius beyond the copies'
 * reach or a fade wider than the radius is an error naming the key. */
static void test_sphere_resolve(void)
{
    orr_replica_sphere sp;
    orr_error err;
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 0, -1, &err) == ORR_OK);
    CHECK_NEAR(sp.radius, 10, 0);
    CHECK_NEAR(sp.fade, 2.5, 0);
    CHECK(orr_replica_sphere_resolve(&sp, 10, 5, 0, 0, &err) == ORR_OK);
    CHECK_NEAR(sp.radius, 20, 0);
    CHECK_NEAR(sp.fade, 0, 0);
    CHECK(orr_replica_sphere_resolve(&sp, 10, 5, 15, 15, &err) == ORR_OK);
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 10.5, -1, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.radius 10.5 is larger than the replicated volume allows");
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 8, 9, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.fade 9 is wider than the radius 8");
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 0, 11, &err) == ORR_ERR_USAGE); /* wider than the default */
    CHECK_CONTAINS(err.msg, "input.periodic.fade");
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, NAN, -1, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.radius");
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 5, NAN, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.fade");

    /* Boxes against a sphere of radius 10, fade 2, around (25, 5, 5). */
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 10, 2, &err) == ORR_OK);
    sp.camera = orr_v3(25, 5, 5);
    const orr_vec3 zero = orr_v3(0, 0, 0);
    CHECK(orr_replica_sphere_box(&sp, orr_v3(24, 4, 4), orr_v3(26, 6, 6), zero) == ORR_SPHERE_INSIDE);
    CHECK(orr_replica_sphere_box(&sp, orr_v3(30, 4, 4), orr_v3(33, 6, 6), zero) == ORR_SPHERE_ACROSS); /* far 8.2 */
    CHECK(orr_replica_sphere_box(&sp, orr_v3(35.5, 4, 4), orr_v3(37, 6, 6), zero) == ORR_SPHERE_BEYOND);
    CHECK(orr_replica_sphere_box(&sp, orr_v3(5.5, 4, 4), orr_v3(7, 6, 6), orr_v3(30, 0, 0)) == ORR_SPHERE_BEYOND);
    /* A corner 9.9 away is across; 10.1 away beyond. */
    double d = 9.9 / sqrt(3.0), e = 10.1 / sqrt(3.0);
    CHECK(orr_replica_sphere_box(&sp, orr_v3(25 + d, 5 + d, 5 + d), orr_v3(40, 20, 20), zero) == ORR_SPHERE_ACROSS);
    CHECK(orr_replica_sphere_box(&sp, orr_v3(25 + e, 5 + e, 5 + e), orr_v3(40, 20, 20), zero) == ORR_SPHERE_BEYOND);

    /* The copies kept: those whose cell reaches into the sphere. Camera at
     * the centre of copy (2, 0, 0) of a box of 10: with radius 10 the 6
     * face neighbours and 12 edge neighbours (nearest 5 and 7.07 away) stay,
     * the 8 corner ones (8.66) too: 27. With radius 6 the edge ones (7.07)
     * and corner ones go: 7. */
    orr_replicas r;
    CHECK(orr_replicas_place(&r, 10, 3, 1, sp.camera, &err) == ORR_OK);
    orr_replicas_keep_sphere(&r, 10, &sp);
    CHECK(r.n == 27);
    CHECK(orr_replica_sphere_resolve(&sp, 10, 3, 6, 0, &err) == ORR_OK);
    sp.camera = orr_v3(25, 5, 5);
    CHECK(orr_replicas_place(&r, 10, 3, 1, sp.camera, &err) == ORR_OK);
    orr_replicas_keep_sphere(&r, 10, &sp);
    CHECK(r.n == 7);
    CHECK(r.offset[0].x == 20 && r.offset[0].y == 0 && r.offset[0].z == 0);
}

/* A perspective camera at the origin looking along -z (no orientation:
 * +y up), 90 degrees across 100 x 100 pixels: the view is |x|, |y| <= -z. */
static orr_view_cull perspective_view(void)
{
    orr_projection p = PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = 100, .height = 100, .fov_deg = 90, .near = 0.01);
    orr_error err;
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
    orr_projection p = PLANNED(.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 100, .height = 50, .ortho_width = 10);
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
    orr_projection sky = PLANNED(.kind = ORR_PROJ_EQUIRECTANGULAR, .width = 100, .height = 50);
    orr_view_cull_setup(&vc, &sky, &cam, 1.0);
    CHECK(!vc.active);
    CHECK(!orr_view_cull_box(&vc, orr_v3(60, 60, 60), orr_v3(61, 61, 61), orr_v3(0, 0, 0), 0));
}

static void test_box_side_from_header(void)
{
    orr_scene s;
    orr_scene_defaults(&s, NULL);
    s.periodic.replicas = 3;
    orr_source_info info;
    memset(&info, 0, sizeof info);
    snprintf(info.path, sizeof info.path, "snap.hdf5");
    orr_error err;
    double box = 0;
    CHECK(orr_periodic_box_side(&s.periodic, s.path, &info, &box, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "input.periodic.box");
    orr_source_add_header(&info, "BoxSize", "50000 50000 50000");
    CHECK(orr_periodic_box_side(&s.periodic, s.path, &info, &box, &err) == ORR_OK);
    CHECK_NEAR(box, 50000, 0);
    snprintf(info.header[0].value, sizeof info.header[0].value, "100 100 50");
    CHECK(orr_periodic_box_side(&s.periodic, s.path, &info, &box, &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "100 100 50");
    s.periodic.box = 7; /* the key wins over the header */
    CHECK(orr_periodic_box_side(&s.periodic, s.path, &info, &box, &err) == ORR_OK);
    CHECK_NEAR(box, 7, 0);
    orr_scene_free(&s);
}

static void test_scene_keys(void)
{
    static orr_scene s; /* zeroed: freed before each load */
    orr_error err;
    const char *ok = "input: {file: x.txt, periodic: {box: 2, replicas: 5, centre: origin}}\n";
    orr_scene_free(&s);
    CHECK(orr_scene_load_string(&s, ok, "ok.yaml", "/tmp", NULL, 0, &err) == ORR_OK);
    CHECK_NEAR(s.periodic.box, 2, 0);
    CHECK(s.periodic.replicas == 5 && s.periodic.around_camera == 0);
    orr_scene_free(&s);
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt}\n", "d.yaml", "/tmp", NULL, 0, &err) == ORR_OK);
    CHECK(s.periodic.box == 0 && s.periodic.replicas == 1 && s.periodic.around_camera == 1);
    orr_scene_free(&s);
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt, periodic: {replicas: 4}}\n", "e.yaml", "/tmp", NULL, 0,
                                &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "input.periodic.replicas");
    orr_scene_free(&s);
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt, periodic: {centre: middle}}\n", "f.yaml", "/tmp", NULL, 0,
                                &err) != ORR_OK);
    CHECK_CONTAINS(err.msg, "middle");
    orr_scene_free(&s);
    CHECK(orr_scene_load_string(&s, "input: {file: x.txt, periodic: {replicas: 5, radius: 1.5, fade: 0}}\n",
                                "g.yaml", "/tmp", NULL, 0, &err) == ORR_OK);
    CHECK(s.periodic.radius == 1.5 && s.periodic.fade == 0 && s.periodic.has_fade);
    /* Bad radius and fade values name their key. */
    static const struct {
        const char *periodic, *message;
    } bad[] = {
        {"{box: 2, replicas: 3, radius: 2.5}", "input.periodic.radius 2.5 is larger than the replicated volume"},
        {"{box: 2, replicas: 3, radius: 1, fade: 1.5}", "input.periodic.fade 1.5 is wider than the radius 1"},
        {"{replicas: 3, radius: 1, fade: 1.5}", "input.periodic.fade 1.5 is wider than the radius 1"},
        {"{box: 2, replicas: 3, fade: 2.5}", "input.periodic.fade 2.5 is wider than the radius 2"},
        {"{replicas: 3, radius: .nan}", "input.periodic.radius"},
        {"{replicas: 3, fade: .nan}", "input.periodic.fade"},
        {"{replicas: 3, radius: -1}", "input.periodic.radius"},
        {"{replicas: 3, fade: -1}", "input.periodic.fade"},
        {"{replicas: 3, centre: origin, radius: 1}", "input.periodic.radius applies to input.periodic.centre: camera"},
        {"{radius: 1}", "input.periodic.radius needs copies of the box around the camera"},
        {"{fade: 1}", "input.periodic.fade needs copies"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char yaml[256];
        snprintf(yaml, sizeof yaml, "input: {file: x.txt, periodic: %s}\n", bad[k].periodic);
        orr_scene_free(&s);
        CHECK(orr_scene_load_string(&s, yaml, "bad.yaml", "/tmp", NULL, 0, &err) == ORR_ERR_USAGE);
        CHECK_CONTAINS(err.msg, bad[k].message);
    }
    orr_scene_free(&s);
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

/* Renders yaml (the output's dir and name added) and reads its plane. */
static orr_status render_yaml(const char *body, const char *name, orr_render_report *rep, orr_plane *plane,
                              int *nplanes)
{
    char yaml[2048], fits[600];
    snprintf(yaml, sizeof yaml, "%soutput: {dir: %s, name: %s, png: false}\n", body, tmpdir, name);
    orr_scene s;
    orr_error err;
    orr_status st = orr_scene_load_string(&s, yaml, name, tmpdir, NULL, 0, &err);
    if (!st)
        st = orr_render_scene(&s, rep, NULL, NULL, &err);
    orr_scene_free(&s);
    if (st) {
        fprintf(stderr, "%s\n", err.msg);
        return st;
    }
    snprintf(fits, sizeof fits, "%s/%s.fits", tmpdir, name);
    return orr_read_fits_planes(fits, plane, 1, nplanes, &err);
}

/* The 27 copies around the box itself (centre: origin): the camera sits on
 * the boundary x = 0 between two copies, in the middle of the others
 * (y, z = 0.5), looking along -z with 60 degrees across 120 x 80 pixels:
 * its copies (x from -1 to 2, z from -1 to 2) fill the view to the depth
 * 1.5 of the plane z = -1 (the view's half-width there is 1.5 tan 30 =
 * 0.87 < 1). */
static orr_status render_box(const char *name, const char *deposit, orr_render_report *rep, orr_plane *plane,
                             int *nplanes)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "input: {file: box.txt, periodic: {box: 1, replicas: 3, centre: origin}}\n"
             "camera: {position: [0, 0.5, 0.5], projection: perspective, fov: 60, near: 0.001}\n"
             "image: {width: 120, height: 80}\n"
             "deposit: %s\n",
             deposit);
    return render_yaml(yaml, name, rep, plane, nplanes);
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
    /* Copies culled whole: the 9 behind the camera (z from 1 to 2); x from 1
     * to 2 (the view reaches x = 0.87 at most): 3 more in front; and
     * with z from 0 to 1 (depth 0 to 0.5, where the view's half-height is
     * 0.5 tan 21.05 deg = 0.19) those with y below 0 or above 1: 4 more; 19.
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
     * NPART D^3 / 3 (strip_ratio: and off the axis). The boundary x = 0
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

/* ---- the sphere around the camera (centre: camera) ---- */

/* The taper, written out independently of the renderer's: 1 to R - F, the
 * smoothstep down to 0 at R. */
static double taper(double r, double R, double F)
{
    if (r <= R - F)
        return 1;
    if (r >= R)
        return 0;
    double s = (R - r) / F;
    return s * s * (3 - 2 * s);
}

/* The integral of taper(r) r^2 dr from 0 to R (Simpson, 2000 intervals):
 * a uniform box of unit density seen from inside holds this much mass per
 * steradian in the sphere, in every direction. */
static double tapered_depth(double R, double F)
{
    const int n = 2000;
    double sum = 0, h = R / n;
    for (int i = 0; i <= n; i++) {
        double r = i * h, f = taper(r, R, F) * r * r;
        sum += (i == 0 || i == n) ? f : (i % 2 ? 4 * f : 2 * f);
    }
    return sum * h / 3;
}

/* The frames' image: 120 x 80 pixels, 60 degrees across, perspective. */
#define SPH_W 120
#define SPH_H 80

/* The light of a frame: each pixel's value (mass per steradian) times its
 * solid angle, summed. */
static double frame_light(const orr_plane *p)
{
    orr_projection proj = PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = SPH_W, .height = SPH_H, .fov_deg = 60);
    double sum = 0;
    for (int j = 0; j < p->height; j++)
        for (int i = 0; i < p->width; i++)
            sum += p->data[(size_t)j * p->width + i] * orr_pixel_measure(&proj, i, j);
    return sum;
}

/* The unit box around a camera at `at` looking along `dir` (centre: camera
 * unless periodic says otherwise). */
static orr_status render_from(const char *name, const char *periodic, orr_vec3 at, orr_vec3 dir,
                              orr_render_report *rep, orr_plane *plane)
{
    char yaml[1024];
    int np = 0;
    snprintf(yaml, sizeof yaml,
             "input: {file: box.txt, periodic: {box: 1, replicas: 3%s}}\n"
             "camera: {position: [%.17g, %.17g, %.17g], direction: [%g, %g, %g], projection: perspective, "
             "fov: 60, near: 0.001}\n"
             "image: {width: %d, height: %d}\n"
             "deposit: cic\n",
             periodic, at.x, at.y, at.z, dir.x, dir.y, dir.z, SPH_W, SPH_H);
    orr_status st = render_yaml(yaml, name, rep, plane, &np);
    return st ? st : np == 1 ? ORR_OK : ORR_ERR_DATA;
}

/* From the middle of a uniform box the sphere (radius 1, the default with 3
 * copies; fade 0.25) holds the same mass per steradian in every direction:
 * the image is flat, at NPART times the tapered depth. Culling (of copies
 * and blocks beyond the sphere, and out of view) changes no pixel, and
 * every copy's weight is drawn, off the image or not drawn (beyond the
 * radius, or faded). */
static void test_sphere_uniform(void)
{
    orr_render_report culled, full;
    orr_plane a, b;
    const orr_vec3 at = orr_v3(0.5, 0.45, 0.55), dir = orr_v3(0.3, 0.2, -1);
    CHECK(render_from("sphere", "", at, dir, &culled, &a) == ORR_OK);
    setenv("ORRERY_NO_CULL", "1", 1);
    CHECK(render_from("sphere_full", "", at, dir, &full, &b) == ORR_OK);
    unsetenv("ORRERY_NO_CULL");
    CHECK(memcmp(a.data, b.data, sizeof(float) * SPH_W * SPH_H) == 0);
    CHECK(culled.n_blocks_culled > 0 && full.n_blocks_culled == 0);
    /* Every copy's cell reaches into the sphere (the corner ones' nearest
     * corners are 0.87 away). */
    CHECK(culled.n_replicas == 27 && full.n_replicas == 27);
    const orr_render_report *reps[2] = {&culled, &full};
    for (int k = 0; k < 2; k++) {
        const orr_deposit_stats *d = &reps[k]->deposit;
        CHECK_NEAR(d->deposited + d->outside + d->culled, 27.0 * NPART, 1e-5 * NPART);
        CHECK_NEAR(d->deposited, full.deposit.deposited, 1e-9 * NPART);
    }

    const double expect = NPART * tapered_depth(1.0, 0.25);
    double sum[2] = {0, 0};
    long count[2] = {0, 0};
    for (int j = 2; j < SPH_H - 2; j++)
        for (int i = 2; i < SPH_W - 2; i++) {
            sum[i >= SPH_W / 2] += a.data[(size_t)j * SPH_W + i];
            count[i >= SPH_W / 2]++;
        }
    double left = sum[0] / count[0] / expect, right = sum[1] / count[1] / expect;
    double all = (sum[0] + sum[1]) / (count[0] + count[1]) / expect;
    /* About 3600 particle images in the view: 1.7 % noise in all, 2.4 % in a half. */
    CHECK_NEAR(left, 1.0, 0.08);
    CHECK_NEAR(right, 1.0, 0.08);
    CHECK_NEAR(all, 1.0, 0.05);
    fprintf(stderr, "  sphere, measured over expected: left %.4f right %.4f all %.4f; culled %llu of %llu blocks\n",
            left, right, all, (unsigned long long)culled.n_blocks_culled, (unsigned long long)culled.n_blocks);
    orr_plane_free(&a);
    orr_plane_free(&b);

    /* The same pixels on 1 and 2 threads. */
    orr_render_report one;
    orr_plane c;
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    CHECK(render_from("sphere_t1", "", at, dir, &one, &c) == ORR_OK);
    omp_set_num_threads(2);
    CHECK(render_from("sphere_t2", "", at, dir, &one, &a) == ORR_OK);
    omp_set_num_threads(threads);
    CHECK(memcmp(a.data, c.data, sizeof(float) * SPH_W * SPH_H) == 0);
    orr_plane_free(&a);
    orr_plane_free(&c);
}

/* A camera flies along x through the face x = 1 of the unit box, looking
 * ahead. With the copies of the camera's cell (as before the sphere; here
 * centre: origin with the camera taken back into [0, 1)^3, which draws the
 * same copies around it) the depth ahead jumps from 1.06 to 1.98 box
 * sides as it crosses, and the light with it; with the sphere the light of
 * consecutive frames changes by 5 % at most. */
#define FLY_FRAMES 10
static void test_flythrough_light(void)
{
    const orr_vec3 dir = orr_v3(1, 0.12, 0.07);
    double cells[FLY_FRAMES], sphere[FLY_FRAMES], worst_cells = 0, worst_sphere = 0;
    for (int f = 0; f < FLY_FRAMES; f++) {
        const orr_vec3 at = orr_v3(0.62 + 0.08 * f, 0.43, 0.57);
        const orr_vec3 in_box = orr_v3(at.x - floor(at.x), at.y, at.z);
        orr_render_report rep;
        orr_plane p;
        CHECK(render_from("fly_cells", ", centre: origin", in_box, dir, &rep, &p) == ORR_OK);
        cells[f] = frame_light(&p);
        orr_plane_free(&p);
        CHECK(render_from("fly_sphere", "", at, dir, &rep, &p) == ORR_OK);
        sphere[f] = frame_light(&p);
        /* The light is the weight that landed in the image. */
        CHECK_NEAR(sphere[f], rep.deposit.deposited, 1e-4 * rep.deposit.deposited);
        orr_plane_free(&p);
        if (f == 0)
            continue;
        double dc = fabs(cells[f] / cells[f - 1] - 1), ds = fabs(sphere[f] / sphere[f - 1] - 1);
        worst_cells = dc > worst_cells ? dc : worst_cells;
        worst_sphere = ds > worst_sphere ? ds : worst_sphere;
    }
    fprintf(stderr, "  fly-through, light per frame (copies of the camera's cell | sphere):\n");
    for (int f = 0; f < FLY_FRAMES; f++)
        fprintf(stderr, "    x %.2f: %10.1f | %10.1f\n", 0.62 + 0.08 * f, cells[f], sphere[f]);
    fprintf(stderr, "  largest change between frames: cells %.1f %%, sphere %.2f %%\n", 100 * worst_cells,
            100 * worst_sphere);
    CHECK(worst_cells > 1.0);
    CHECK(worst_sphere <= 0.05);
}

int main(void)
{
    if (!mkdtemp(tmpdir))
        return 1;
    RUN(test_replicas_around_camera);
    RUN(test_sphere_resolve);
    RUN(test_perspective_culling);
    RUN(test_orthographic_and_sky);
    RUN(test_box_side_from_header);
    RUN(test_scene_keys);
    RUN(test_render_uniform_box);
    RUN(test_render_sph_same_image); /* after: uses its box.txt */
    RUN(test_sphere_uniform);
    RUN(test_flythrough_light);
    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0)
        return 1;
    fprintf(stderr, "%d checks, %d failed\n", check_count, check_failures);
    return check_failures ? 1 : 0;
}
