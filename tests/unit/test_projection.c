/* Projections: known points land on known pixels; points behind the camera
 * are rejected; the batch loop agrees with the single-point function. */
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "frame/projection.h"
#include "render/map_alpha.h"

static orr_projection ortho(int w, int h, double width)
{
    return PLANNED(.kind = ORR_PROJ_ORTHOGRAPHIC, .width = w, .height = h, .ortho_width = width);
}

static orr_projection persp(int w, int h, double fov, double near)
{
    return PLANNED(.kind = ORR_PROJ_PERSPECTIVE, .width = w, .height = h, .fov_deg = fov, .near = near);
}

static void test_orthographic_known_points(void)
{
    orr_projection p = ortho(200, 100, 50.0); /* 4 pixels per unit */
    double px, py, s;
    CHECK(orr_project_point(&p, orr_v3(0, 0, -7), &px, &py, &s) == 1);
    CHECK_NEAR(px, 100, 1e-12);
    CHECK_NEAR(py, 50, 1e-12);
    CHECK_NEAR(s, 4, 1e-12);
    /* The right edge is at x = +25; y grows down the image. */
    orr_project_point(&p, orr_v3(25, 0, 3), &px, &py, &s);
    CHECK_NEAR(px, 200, 1e-12);
    orr_project_point(&p, orr_v3(-12.5, 12.5, 0), &px, &py, &s);
    CHECK_NEAR(px, 50, 1e-12);
    CHECK_NEAR(py, 100, 1e-12);
    /* The centre of pixel (0, 0) is half a pixel (1/8 unit) in from the corner. */
    orr_project_point(&p, orr_v3(-25 + 0.125, -12.5 + 0.125, 0), &px, &py, &s);
    CHECK_NEAR(px, 0.5, 1e-12);
    CHECK_NEAR(py, 0.5, 1e-12);
}

static void test_perspective_known_points(void)
{
    /* 90 degrees across the wider axis (width 400): focal length 200 pixels. */
    orr_projection p = persp(400, 300, 90.0, 0.1);
    double px, py, s;
    CHECK(orr_project_point(&p, orr_v3(0, 0, 5), &px, &py, &s) == 1);
    CHECK_NEAR(px, 200, 1e-9);
    CHECK_NEAR(py, 150, 1e-9);
    CHECK_NEAR(s, 200.0 / 5, 1e-9);
    /* 45 degrees to the right is the right edge; the same angle down lands
     * 200 pixels below the centre (off the 300-pixel-high image). */
    orr_project_point(&p, orr_v3(5, 0, 5), &px, &py, &s);
    CHECK_NEAR(px, 400, 1e-9);
    orr_project_point(&p, orr_v3(0, 5, 5), &px, &py, &s);
    CHECK_NEAR(py, 350, 1e-9);
    /* A portrait image measures the field of view along its height. */
    orr_projection q = persp(300, 400, 90.0, 0.1);
    orr_project_point(&q, orr_v3(0, -2, 2), &px, &py, &s);
    CHECK_NEAR(py, 0, 1e-9);
}

static void test_perspective_rejects_behind_camera(void)
{
    orr_projection p = persp(100, 100, 60.0, 0.5);
    double px, py, s;
    CHECK(orr_project_point(&p, orr_v3(0, 0, -1), &px, &py, &s) == 0);
    CHECK(orr_project_point(&p, orr_v3(1, 1, 0), &px, &py, &s) == 0);
    CHECK(orr_project_point(&p, orr_v3(0, 0, 0.5), &px, &py, &s) == 0); /* at the near plane */
    CHECK(orr_project_point(&p, orr_v3(0, 0, 0.51), &px, &py, &s) == 1);
}

static void test_batch_matches_single(void)
{
    enum { N = 1000 };
    float x[N], y[N], z[N], px[N], py[N], sc[N];
    uint8_t vis[N];
    srand(7);
    for (int i = 0; i < N; i++) {
        x[i] = (float)(rand() / (double)RAND_MAX * 20 - 10);
        y[i] = (float)(rand() / (double)RAND_MAX * 20 - 10);
        z[i] = (float)(rand() / (double)RAND_MAX * 20 - 10);
    }
    orr_projection projs[2] = {ortho(640, 480, 30.0), persp(640, 480, 70.0, 0.01)};
    for (int k = 0; k < 2; k++) {
        orr_project_batch(&projs[k], N, x, y, z, px, py, sc, vis);
        for (int i = 0; i < N; i++) {
            double qx, qy, qs;
            int v = orr_project_point(&projs[k], orr_v3(x[i], y[i], z[i]), &qx, &qy, &qs);
            CHECK(v == vis[i]);
            if (v) {
                CHECK_NEAR(px[i], qx, 1e-3 * (1 + fabs(qx)));
                CHECK_NEAR(py[i], qy, 1e-3 * (1 + fabs(qy)));
                CHECK_NEAR(sc[i], qs, 1e-4 * qs);
            }
        }
    }
}

static void test_check_rejects_bad_parameters(void)
{
    orr_error err = {0};
    orr_projection_settings s = {.kind = ORR_PROJ_ORTHOGRAPHIC, .width = 0, .height = 10, .ortho_width = 1};
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "0 x 10");
    s.width = -5;
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    s.width = 100000;
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    s.width = 10;
    s.ortho_width = 0;
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "camera.width: 0 is out of range (must be > 0)") == 0);
    s = (orr_projection_settings){.kind = ORR_PROJ_PERSPECTIVE, .width = 10, .height = 10, .fov_deg = 180};
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "camera.fov: 180 is out of range (must be > 0 and < 180)") == 0);
    s.fov_deg = NAN;
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    s = (orr_projection_settings){.kind = ORR_PROJ_HEALPIX, .width = 1, .height = 1, .healpix_nside = 12};
    CHECK(orr_projection_check(&s, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "camera.healpix_nside: must be a power of 2 (1, 2, 4, ..., 4096), got 12");
}

/* A scene's projection is checked whole, the parameters of other kinds
 * too, each message naming its key; a program's only its kind's. */
static void test_prepare_checks_every_parameter(void)
{
    orr_error err = {0};
    orr_projection_settings s;
    orr_projection_defaults(&s);
    CHECK(orr_projection_prepare(&s, NULL, &err) == ORR_OK);
    s.dome_fov_deg = 80;
    CHECK(orr_projection_prepare(&s, NULL, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "camera.dome_fov: 80 is out of range (90 to 360)") == 0);
    CHECK(orr_projection_check(&s, &err) == ORR_OK); /* an orthographic one has no dome */
    orr_projection_defaults(&s);
    s.near = -1;
    CHECK(orr_projection_prepare(&s, NULL, &err) == ORR_ERR_USAGE);
    CHECK(strcmp(err.msg, "camera.near: -1 is out of range (must be >= 0)") == 0);
}

/* A row's coverages (sampled only along the outline) are every pixel's
 * own, for domes and Hammer-Aitoff maps of odd and even sizes and fields,
 * and 1 everywhere on a map without an outline. */
static void test_row_coverage_matches_pixels(void)
{
    const struct { orr_projection_kind kind; int w, h; double fov; } maps[] = {
        {ORR_PROJ_DOME, 64, 64, 180},         {ORR_PROJ_DOME, 101, 101, 180}, {ORR_PROJ_DOME, 97, 60, 220},
        {ORR_PROJ_DOME, 7, 7, 90},            {ORR_PROJ_HAMMER_AITOFF, 128, 64, 0},
        {ORR_PROJ_HAMMER_AITOFF, 257, 129, 0}, {ORR_PROJ_HAMMER_AITOFF, 9, 5, 0},
        {ORR_PROJ_EQUIRECTANGULAR, 40, 20, 0},
    };
    for (size_t m = 0; m < sizeof maps / sizeof *maps; m++) {
        const orr_projection p = PLANNED(.kind = maps[m].kind, .width = maps[m].w, .height = maps[m].h,
                                         .dome_fov_deg = maps[m].fov > 0 ? maps[m].fov : 180);
        float *row = malloc((size_t)p.width * sizeof *row);
        int differ = 0, partial = 0;
        for (int j = 0; j < p.height; j++) {
            orr_map_row_coverage(&p, j, row);
            for (int i = 0; i < p.width; i++) {
                const float want = orr_map_pixel_coverage(&p, i, j);
                differ += row[i] != want;
                partial += want > 0 && want < 1;
            }
        }
        CHECK(differ == 0);
        CHECK(p.settings.kind == ORR_PROJ_EQUIRECTANGULAR ? partial == 0 : partial > 0);
        free(row);
    }
}

int main(void)
{
    RUN(test_orthographic_known_points);
    RUN(test_prepare_checks_every_parameter);
    RUN(test_perspective_known_points);
    RUN(test_perspective_rejects_behind_camera);
    RUN(test_batch_matches_single);
    RUN(test_check_rejects_bad_parameters);
    RUN(test_row_coverage_matches_pixels);
    return check_summary();
}
