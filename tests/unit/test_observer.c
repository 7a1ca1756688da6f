/* The observer frame: the reference particle stays on l = 0 wherever the
 * observer is, its latitude is the angle between the line of sight and the
 * disc plane, and the sky cameras put it where the maps say. */
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "frame/observer.h"
#include "frame/projection.h"

static double urand(void)
{
    return rand() / (double)RAND_MAX;
}

static orr_vec3 random_vec(double scale)
{
    return orr_v3(scale * (2 * urand() - 1), scale * (2 * urand() - 1), scale * (2 * urand() - 1));
}

static void test_reference_on_central_meridian(void)
{
    srand(23);
    for (int trial = 0; trial < 200; trial++) {
        orr_vec3 obs = random_vec(50), ref = random_vec(50), n0 = random_vec(1);
        orr_sky_frame f;
        orr_error err = {0};
        CHECK(orr_sky_frame_build(&f, obs, ref, n0, &err) == ORR_OK);
        /* Right-handed orthonormal axes with z = n0. */
        CHECK_NEAR(orr_v3_dot(f.x, f.y), 0, 1e-12);
        CHECK_NEAR(orr_v3_dot(f.x, f.z), 0, 1e-12);
        CHECK_NEAR(orr_v3_norm(orr_v3_sub(orr_v3_cross(f.x, f.y), f.z)), 0, 1e-12);
        CHECK_NEAR(orr_v3_norm(orr_v3_sub(f.z, orr_v3_normalize(n0))), 0, 1e-12);
        orr_vec3 d = orr_v3_sub(ref, obs);
        double l, b;
        orr_sky_lb(&f, d, &l, &b);
        CHECK_NEAR(l, 0, 1e-9);
        /* b is the angle between the line of sight and the disc plane. */
        double expected_b = asin(orr_v3_dot(orr_v3_normalize(d), orr_v3_normalize(n0))) * 180 / ORR_PI;
        CHECK_NEAR(b, expected_b, 1e-9);
        /* (l, b) -> direction -> (l, b) round trip. */
        double l2, b2, lt = 360 * urand() - 180, bt = 180 * urand() - 90;
        orr_sky_lb(&f, orr_sky_direction(&f, lt, bt), &l2, &b2);
        CHECK_NEAR(b2, bt, 1e-9);
        CHECK_NEAR(remainder(l2 - lt, 360.0), 0, 1e-7);
    }
}

static void test_centre_camera_on_hammer_aitoff(void)
{
    /* The Sun 8 kpc from the centre, 0.5 kpc above the plane: the centre
     * appears on the central meridian, below the equator by atan(0.5/8). */
    orr_sky_frame f;
    orr_error err = {0};
    orr_vec3 sun = orr_v3(-8, 0, 0.5), centre = orr_v3(0, 0, 0);
    CHECK(orr_sky_frame_build(&f, sun, centre, orr_v3(0, 0, 1), &err) == ORR_OK);
    orr_camera cam;
    CHECK(orr_sky_camera_centre(&cam, &f, 0, &err) == ORR_OK);
    orr_projection p = PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 800, .height = 400);
    orr_vec3 c = orr_mat3_apply(orr_camera_world_to_camera(&cam), orr_v3_sub(centre, sun));
    double px, py, s;
    CHECK(orr_project_point(&p, c, &px, &py, &s) == 1);
    CHECK_NEAR(px, 400, 1e-9);
    double b = -atan2(0.5, 8);
    double Y = sqrt(2) * sin(b) / sqrt(1 + cos(b));
    CHECK_NEAR(py, 200 - Y / sqrt(2) * 200, 1e-9);
    /* l = 90 (along +y here: y = z x x) is to the left of the centre. */
    c = orr_mat3_apply(orr_camera_world_to_camera(&cam), orr_v3(0, 1, 0));
    CHECK(orr_project_point(&p, c, &px, &py, &s) == 1);
    CHECK(px < 400);
    CHECK_NEAR(py, 200, 1e-9);
}

static void test_dome_camera(void)
{
    orr_sky_frame f = orr_sky_frame_world(orr_v3(1, 2, 3));
    orr_camera cam;
    orr_error err = {0};
    double zenith[2] = {0, 90}, front[2] = {30, 0};
    CHECK(orr_sky_camera_dome(&cam, &f, zenith, front, 0, &err) == ORR_OK);
    orr_projection p = PLANNED(.kind = ORR_PROJ_DOME, .width = 1000, .height = 1000, .dome_fov_deg = 180);
    orr_mat3 R = orr_camera_world_to_camera(&cam);
    double px, py, s;
    /* The zenith at the centre, the front on the bottom of the rim. */
    CHECK(orr_project_point(&p, orr_mat3_apply(R, orr_sky_direction(&f, 0, 90)), &px, &py, &s) == 1);
    CHECK_NEAR(px, 500, 1e-9);
    CHECK_NEAR(py, 500, 1e-9);
    CHECK(orr_project_point(&p, orr_mat3_apply(R, orr_sky_direction(&f, 30, 0)), &px, &py, &s) == 1);
    CHECK_NEAR(px, 500, 1e-9);
    CHECK_NEAR(py, 1000, 1e-9);
    /* Tilted 30 degrees toward the front: the front now sits 60 degrees from
     * the zenith, and what was the zenith is 30 degrees behind the centre. */
    CHECK(orr_sky_camera_dome(&cam, &f, zenith, front, 30, &err) == ORR_OK);
    R = orr_camera_world_to_camera(&cam);
    CHECK(orr_project_point(&p, orr_mat3_apply(R, orr_sky_direction(&f, 30, 0)), &px, &py, &s) == 1);
    CHECK_NEAR(py, 500 + 500 * 60.0 / 90, 1e-9);
    CHECK(orr_project_point(&p, orr_mat3_apply(R, orr_sky_direction(&f, 0, 90)), &px, &py, &s) == 1);
    CHECK_NEAR(py, 500 - 500 * 30.0 / 90, 1e-9);
    double bad_front[2] = {123, 90};
    CHECK(orr_sky_camera_dome(&cam, &f, zenith, bad_front, 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "parallel");
}

static void test_bad_frames(void)
{
    orr_sky_frame f;
    orr_error err = {0};
    CHECK(orr_sky_frame_build(&f, orr_v3(1, 1, 1), orr_v3(1, 1, 1), orr_v3(0, 0, 1), &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "same position");
    CHECK(orr_sky_frame_build(&f, orr_v3(0, 0, 0), orr_v3(0, 0, 5), orr_v3(0, 0, 1), &err) == ORR_ERR_DATA);
    CHECK_CONTAINS(err.msg, "along the disc normal");
    CHECK(orr_sky_frame_build(&f, orr_v3(0, 0, 0), orr_v3(1, 0, 0), orr_v3(0, 0, 0), &err) == ORR_ERR_USAGE);
}

int main(void)
{
    RUN(test_reference_on_central_meridian);
    RUN(test_centre_camera_on_hammer_aitoff);
    RUN(test_dome_camera);
    RUN(test_bad_frames);
    return check_summary();
}
