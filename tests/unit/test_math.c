/* Vectors, matrices, quaternions and cameras against explicit matrices. */
#include "check.h"
#include "core/vecmath.h"
#include "frame/camera.h"

static const double EPS = 1e-12;

static void check_mat_near(orr_mat3 a, orr_mat3 b, double tol)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(a.m[i][j], b.m[i][j], tol);
}

static void check_vec_near(orr_vec3 a, orr_vec3 b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

/* The textbook rotation matrices about the coordinate axes. */
static orr_mat3 rot_x(double t) { return (orr_mat3){{{1, 0, 0}, {0, cos(t), -sin(t)}, {0, sin(t), cos(t)}}}; }
static orr_mat3 rot_y(double t) { return (orr_mat3){{{cos(t), 0, sin(t)}, {0, 1, 0}, {-sin(t), 0, cos(t)}}}; }
static orr_mat3 rot_z(double t) { return (orr_mat3){{{cos(t), -sin(t), 0}, {sin(t), cos(t), 0}, {0, 0, 1}}}; }

static void test_quaternion_matches_axis_matrices(void)
{
    for (double t = -3.0; t <= 3.0; t += 0.37) {
        check_mat_near(orr_quat_to_mat3(orr_quat_axis_angle(orr_v3(1, 0, 0), t)), rot_x(t), EPS);
        check_mat_near(orr_quat_to_mat3(orr_quat_axis_angle(orr_v3(0, 1, 0), t)), rot_y(t), EPS);
        check_mat_near(orr_quat_to_mat3(orr_quat_axis_angle(orr_v3(0, 0, 2), t)), rot_z(t), EPS);
    }
}

static void test_quaternion_rotation_of_vectors(void)
{
    /* A quarter turn about z takes x to y; a third of a turn about (1,1,1)
     * cycles the axes x -> y -> z. */
    orr_quat q = orr_quat_axis_angle(orr_v3(0, 0, 1), ORR_PI / 2);
    check_vec_near(orr_quat_rotate(q, orr_v3(1, 0, 0)), orr_v3(0, 1, 0), EPS);
    orr_quat c = orr_quat_axis_angle(orr_v3(1, 1, 1), 2 * ORR_PI / 3);
    check_vec_near(orr_quat_rotate(c, orr_v3(1, 0, 0)), orr_v3(0, 1, 0), EPS);
    check_vec_near(orr_quat_rotate(c, orr_v3(0, 1, 0)), orr_v3(0, 0, 1), EPS);
    /* Composition: q1 q2 rotates by q2 first, like the matrix product. */
    orr_quat q1 = orr_quat_axis_angle(orr_v3(0.3, -1, 0.2), 0.7);
    orr_quat q2 = orr_quat_axis_angle(orr_v3(1, 0.5, -0.4), -1.9);
    check_mat_near(orr_quat_to_mat3(orr_quat_mul(q1, q2)),
                   orr_mat3_mul(orr_quat_to_mat3(q1), orr_quat_to_mat3(q2)), EPS);
    orr_vec3 v = orr_v3(0.4, -2, 3);
    check_vec_near(orr_quat_rotate(q1, v), orr_mat3_apply(orr_quat_to_mat3(q1), v), EPS);
    /* Rodrigues' formula is an independent construction of the same matrix. */
    check_mat_near(orr_mat3_axis_angle(orr_v3(0.3, -1, 0.2), 0.7), orr_quat_to_mat3(q1), EPS);
}

static void test_quaternion_from_matrix_round_trip(void)
{
    orr_vec3 axes[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 2, 3}, {-1, 0.5, 0.1}};
    double angles[] = {0.0, 0.5, 1.5, 3.0, 3.14159, -2.5};
    for (int a = 0; a < 5; a++)
        for (int k = 0; k < 6; k++) {
            orr_mat3 m = orr_mat3_axis_angle(axes[a], angles[k]);
            check_mat_near(orr_quat_to_mat3(orr_quat_from_mat3(m)), m, 1e-10);
        }
}

static void test_slerp(void)
{
    orr_quat a = orr_quat_axis_angle(orr_v3(0, 0, 1), 0.2);
    orr_quat b = orr_quat_axis_angle(orr_v3(0, 0, 1), 1.4);
    orr_quat s0 = orr_quat_slerp(a, b, 0), s1 = orr_quat_slerp(a, b, 1);
    check_mat_near(orr_quat_to_mat3(s0), orr_quat_to_mat3(a), EPS);
    check_mat_near(orr_quat_to_mat3(s1), orr_quat_to_mat3(b), EPS);
    /* Half way about one axis is the mean angle. */
    check_mat_near(orr_quat_to_mat3(orr_quat_slerp(a, b, 0.5)), rot_z(0.8), EPS);
    /* -b is the same rotation: slerp must take the short way, not a full turn. */
    orr_quat nb = {-b.w, -b.x, -b.y, -b.z};
    check_mat_near(orr_quat_to_mat3(orr_quat_slerp(a, nb, 0.25)), rot_z(0.5), EPS);
}

static void test_camera_look_at(void)
{
    orr_camera cam;
    orr_error err = {0};
    orr_vec3 pos = orr_v3(10, 0, 0), target = orr_v3(0, 0, 0);
    CHECK(orr_camera_look_at(&cam, pos, target, orr_v3(0, 0, 1), 0, &err) == ORR_OK);
    orr_mat3 R = orr_camera_world_to_camera(&cam);
    /* The target is straight ahead at distance 10; world up is image up (-y). */
    check_vec_near(orr_mat3_apply(R, orr_v3_sub(target, pos)), orr_v3(0, 0, 10), EPS);
    check_vec_near(orr_mat3_apply(R, orr_v3(0, 0, 1)), orr_v3(0, -1, 0), EPS);
    /* Looking along -x with z up, world +y is on the right of the image
     * (right = forward x up). */
    check_vec_near(orr_mat3_apply(R, orr_v3(0, 1, 0)), orr_v3(1, 0, 0), EPS);
    /* A 90 degree roll turns the scene clockwise: up moves to the right. */
    CHECK(orr_camera_look_at(&cam, pos, target, orr_v3(0, 0, 1), 90, &err) == ORR_OK);
    R = orr_camera_world_to_camera(&cam);
    check_vec_near(orr_mat3_apply(R, orr_v3(0, 0, 1)), orr_v3(1, 0, 0), EPS);
    /* Up parallel to the view, or a zero view direction, are errors. */
    CHECK(orr_camera_look_at(&cam, pos, target, orr_v3(1, 0, 0), 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "parallel");
    CHECK(orr_camera_look_at(&cam, pos, pos, orr_v3(0, 0, 1), 0, &err) == ORR_ERR_USAGE);
}

static void test_camera_face_on_default(void)
{
    /* Looking down -z with +y up shows the xy plane as on a plot: +x right,
     * +y up (image y points down). */
    orr_camera cam;
    orr_error err = {0};
    CHECK(orr_camera_look_along(&cam, orr_v3(0, 0, 0), orr_v3(0, 0, -1), orr_v3(0, 1, 0), 0, &err) == ORR_OK);
    orr_mat3 R = orr_camera_world_to_camera(&cam);
    check_vec_near(orr_mat3_apply(R, orr_v3(1, 0, 0)), orr_v3(1, 0, 0), EPS);
    check_vec_near(orr_mat3_apply(R, orr_v3(0, 1, 0)), orr_v3(0, -1, 0), EPS);
    check_vec_near(orr_mat3_apply(R, orr_v3(0, 0, -1)), orr_v3(0, 0, 1), EPS);
}

static void test_camera_design_note_rotation(void)
{
    /* The rotation by acos(n_z) about (n_y, -n_x, 0) takes n to the view axis. */
    orr_vec3 dirs[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 2, -3}, {-0.2, 0.1, 0.9}};
    for (int i = 0; i < 6; i++) {
        orr_camera cam;
        orr_error err = {0};
        CHECK(orr_camera_look_along_roll(&cam, orr_v3(1, 2, 3), dirs[i], 0, &err) == ORR_OK);
        orr_mat3 R = orr_camera_world_to_camera(&cam);
        check_vec_near(orr_mat3_apply(R, orr_v3_normalize(dirs[i])), orr_v3(0, 0, 1), 1e-12);
        /* Rolling keeps the view axis and turns the image. */
        orr_camera rolled;
        CHECK(orr_camera_look_along_roll(&rolled, orr_v3(1, 2, 3), dirs[i], 30, &err) == ORR_OK);
        orr_mat3 Rr = orr_camera_world_to_camera(&rolled);
        check_vec_near(orr_mat3_apply(Rr, orr_v3_normalize(dirs[i])), orr_v3(0, 0, 1), 1e-12);
        orr_vec3 a = orr_mat3_apply(R, orr_v3(0.3, -0.7, 0.2)), b = orr_mat3_apply(Rr, orr_v3(0.3, -0.7, 0.2));
        double angle_a = atan2(a.y, a.x), angle_b = atan2(b.y, b.x);
        CHECK_NEAR(remainder(angle_b - angle_a, 2 * ORR_PI), 30 * ORR_PI / 180, 1e-9);
    }
}

int main(void)
{
    RUN(test_quaternion_matches_axis_matrices);
    RUN(test_quaternion_rotation_of_vectors);
    RUN(test_quaternion_from_matrix_round_trip);
    RUN(test_slerp);
    RUN(test_camera_look_at);
    RUN(test_camera_face_on_default);
    RUN(test_camera_design_note_rotation);
    return check_summary();
}
