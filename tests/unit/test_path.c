/* Camera paths: keyframe interpolation (through every keyframe, C1 at the
 * interior ones, unit quaternions), the generators against their geometry,
 * easing, the CSV reader and its errors, and the scene keys. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "frame/path.h"
#include "render/path_overview.h"
#include "scene/scene.h"
#include "tmpdir.h"

static orr_camera_path g_path;
static orr_scene g_scene;

static orr_vec3 forward_of(const orr_camera *cam) { return orr_quat_rotate(cam->orientation, orr_v3(0, 0, 1)); }

static double quat_norm(orr_quat q) { return sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z); }

/* |<a, b>| = 1 when a and b are the same rotation. */
static double same_rotation(orr_quat a, orr_quat b) { return fabs(a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z); }

static orr_camera eval(const orr_camera_path *p, double frame, double u)
{
    orr_camera cam;
    orr_error err;
    CHECK(orr_path_eval(p, frame, u, &cam, &err) == ORR_OK);
    return cam;
}

/* Five keyframes at uneven frames, aimed in each of the three ways. */
static void make_keyframes(orr_camera_path *p)
{
    static const orr_keyframe_spec specs[] = {
        {.frame = 0, .position = {10, 0, 0}, .aim = ORR_AIM_LOOK_AT, .look = {0, 0, 0}},
        {.frame = 7, .position = {7, 7, 2}, .aim = ORR_AIM_LOOK_AT, .look = {0, 0, 0}, .has_up = 1, .up = {0, 0, 1}},
        {.frame = 20, .position = {0, 10, 5}, .aim = ORR_AIM_DIRECTION, .look = {0, -1, -0.5}, .roll = 20},
        {.frame = 24.5, .position = {-6, 8, 3}, .aim = ORR_AIM_QUATERNION, .quaternion = {0.5, 0.5, -0.5, 0.5}},
        {.frame = 40, .position = {-10, 0, 0}, .aim = ORR_AIM_LOOK_AT, .look = {0, 0, 1}},
    };
    orr_path_defaults(p, ORR_PATH_KEYFRAMES);
    p->nkeys = (int)(sizeof specs / sizeof specs[0]);
    for (int i = 0; i < p->nkeys; i++) {
        orr_error err;
        CHECK(orr_keyframe_from_spec(&specs[i], &p->keys[i], &err) == ORR_OK);
    }
    orr_error err;
    CHECK(orr_path_check(p, &err) == ORR_OK);
}

static void test_through_keyframes(void)
{
    for (int interp = 0; interp < 2; interp++)
        for (int orient = 0; orient < 2; orient++) {
            make_keyframes(&g_path);
            g_path.interpolation = (orr_path_interp)interp;
            g_path.orientation = (orr_path_orient)orient;
            for (int i = 0; i < g_path.nkeys; i++) {
                const orr_keyframe *k = &g_path.keys[i];
                orr_camera cam = eval(&g_path, k->frame, 0);
                CHECK_NEAR(cam.position.x, k->position.x, 1e-12);
                CHECK_NEAR(cam.position.y, k->position.y, 1e-12);
                CHECK_NEAR(cam.position.z, k->position.z, 1e-12);
                CHECK_NEAR(same_rotation(cam.orientation, k->orientation), 1.0, 1e-12);
            }
            /* Before the first and after the last keyframe the camera holds. */
            orr_camera before = eval(&g_path, -5, 0), after = eval(&g_path, 99, 0);
            CHECK_NEAR(before.position.x, 10, 0);
            CHECK_NEAR(after.position.x, -10, 0);
            CHECK_NEAR(same_rotation(after.orientation, g_path.keys[4].orientation), 1.0, 1e-12);
        }
    /* A look_at keyframe's forward axis points at its target. */
    orr_vec3 f = forward_of(&(orr_camera){g_path.keys[0].position, g_path.keys[0].orientation});
    CHECK_NEAR(f.x, -1, 1e-12);
}

/* dP/dframe from each side of frame f. */
static void one_sided(const orr_camera_path *p, double f, double h, orr_vec3 *left, orr_vec3 *right)
{
    orr_vec3 at = eval(p, f, 0).position;
    *left = orr_v3_scale(orr_v3_sub(at, eval(p, f - h, 0).position), 1 / h);
    *right = orr_v3_scale(orr_v3_sub(eval(p, f + h, 0).position, at), 1 / h);
}

static void test_velocity_continuous(void)
{
    for (int interp = 0; interp < 2; interp++) {
        make_keyframes(&g_path);
        g_path.interpolation = (orr_path_interp)interp;
        for (int i = 1; i + 1 < g_path.nkeys; i++) {
            const orr_keyframe *k = g_path.keys;
            orr_vec3 left, right;
            one_sided(&g_path, k[i].frame, 1e-6, &left, &right);
            double jump = orr_v3_norm(orr_v3_sub(left, right)), speed = orr_v3_norm(left);
            CHECK(speed > 0.1);
            CHECK(jump < 1e-4 * speed);
            /* The check has teeth: straight segments would jump here. */
            orr_vec3 chord_in =
                orr_v3_scale(orr_v3_sub(k[i].position, k[i - 1].position), 1 / (k[i].frame - k[i - 1].frame));
            orr_vec3 chord_out =
                orr_v3_scale(orr_v3_sub(k[i + 1].position, k[i].position), 1 / (k[i + 1].frame - k[i].frame));
            CHECK(orr_v3_norm(orr_v3_sub(chord_in, chord_out)) > 0.05);
        }
    }
    /* Catmull-Rom's interior tangent is the chord across its neighbours. */
    make_keyframes(&g_path);
    orr_vec3 left, right;
    one_sided(&g_path, g_path.keys[2].frame, 1e-6, &left, &right);
    orr_vec3 chord = orr_v3_scale(orr_v3_sub(g_path.keys[3].position, g_path.keys[1].position), 1 / (24.5 - 7));
    CHECK_NEAR(right.x, chord.x, 1e-4);
    CHECK_NEAR(right.y, chord.y, 1e-4);
}

static void test_unit_quaternions(void)
{
    for (int orient = 0; orient < 2; orient++) {
        make_keyframes(&g_path);
        g_path.orientation = (orr_path_orient)orient;
        double worst = 0, worst_step = 0;
        orr_quat prev = eval(&g_path, 0, 0).orientation;
        for (double f = 0; f <= 40; f += 0.05) {
            orr_quat q = eval(&g_path, f, 0).orientation;
            worst = fmax(worst, fabs(quat_norm(q) - 1));
            worst_step = fmax(worst_step, 1 - same_rotation(q, prev)); /* no sudden turns */
            prev = q;
        }
        CHECK(worst < 1e-12);
        CHECK(worst_step < 1e-3);
    }
}

/* The body-frame angular velocity 2 log(a^-1 b) / h between two orientations h frames apart. */
static orr_vec3 angular_velocity(orr_quat a, orr_quat b, double h)
{
    orr_quat d = orr_quat_mul(orr_quat_conj(a), b);
    if (d.w < 0)
        d = (orr_quat){-d.w, -d.x, -d.y, -d.z};
    orr_vec3 v = orr_v3(d.x, d.y, d.z);
    double s = orr_v3_norm(v);
    return s > 0 ? orr_v3_scale(v, 2 * atan2(s, d.w) / s / h) : v;
}

/* Squad turns smoothly through the keyframes; slerp does not (the check's teeth). */
static void test_squad_smooth(void)
{
    for (int orient = 0; orient < 2; orient++) {
        make_keyframes(&g_path);
        g_path.orientation = (orr_path_orient)orient;
        double worst = 0;
        for (int i = 1; i + 1 < g_path.nkeys; i++) {
            const double f = g_path.keys[i].frame, h = 1e-5;
            orr_quat q = eval(&g_path, f, 0).orientation;
            orr_vec3 left = angular_velocity(eval(&g_path, f - h, 0).orientation, q, h);
            orr_vec3 right = angular_velocity(q, eval(&g_path, f + h, 0).orientation, h);
            worst = fmax(worst, orr_v3_norm(orr_v3_sub(left, right)) / orr_v3_norm(left));
        }
        if (orient == ORR_ORIENT_SQUAD)
            CHECK(worst < 1e-3);
        else
            CHECK(worst > 0.05);
    }
}

static void test_orbit(void)
{
    orr_path_defaults(&g_path, ORR_PATH_ORBIT);
    g_path.centre = orr_v3(1, 2, 3);
    g_path.axis = orr_v3(0, 1, 1);
    g_path.radius = 5;
    g_path.turns = 0.75;
    orr_error err;
    CHECK(orr_path_plane_ref(g_path.axis, &g_path.ref, &err) == ORR_OK);
    CHECK(orr_path_check(&g_path, &err) == ORR_OK);
    for (double u = 0; u <= 1.0; u += 0.05) {
        orr_camera cam = eval(&g_path, 0, u);
        orr_vec3 to_centre = orr_v3_sub(g_path.centre, cam.position);
        CHECK_NEAR(orr_v3_norm(to_centre), 5, 1e-12);
        CHECK_NEAR(orr_v3_dot(forward_of(&cam), orr_v3_normalize(to_centre)), 1, 1e-12);
        CHECK_NEAR(orr_v3_dot(to_centre, g_path.axis), 0, 1e-12); /* stays in the plane */
    }
    /* A quarter of the 0.75 turns, i.e. 67.5 degrees, from the start. */
    orr_vec3 a = orr_v3_sub(eval(&g_path, 0, 0).position, g_path.centre);
    orr_vec3 b = orr_v3_sub(eval(&g_path, 0, 0.25).position, g_path.centre);
    CHECK_NEAR(acos(orr_v3_dot(a, b) / 25) * 180 / ORR_PI, 67.5, 1e-9);
    /* Counter-clockwise seen from +axis. */
    CHECK(orr_v3_dot(orr_v3_cross(a, b), g_path.axis) > 0);
}

static void test_line(void)
{
    orr_path_defaults(&g_path, ORR_PATH_LINE);
    g_path.from = orr_v3(0, 0, 100);
    g_path.to = orr_v3(30, 40, 100);
    orr_error err;
    CHECK(orr_path_check(&g_path, &err) == ORR_OK);
    orr_vec3 prev = eval(&g_path, 0, 0).position;
    CHECK_NEAR(prev.x, 0, 0);
    for (int i = 1; i <= 20; i++) {
        orr_camera cam = eval(&g_path, 0, i / 20.0);
        CHECK_NEAR(orr_v3_norm(orr_v3_sub(cam.position, prev)), 50.0 / 20, 1e-12);
        CHECK_NEAR(orr_v3_dot(forward_of(&cam), orr_v3(0.6, 0.8, 0)), 1, 1e-12);
        prev = cam.position;
    }
    CHECK_NEAR(prev.y, 40, 1e-12);
    g_path.has_look_at = 1;
    g_path.look_at = orr_v3(0, 0, 0);
    orr_camera cam = eval(&g_path, 0, 0.5);
    CHECK_NEAR(orr_v3_dot(forward_of(&cam), orr_v3_normalize(orr_v3_scale(cam.position, -1))), 1, 1e-12);
    /* Looking along a line parallel to up has no image up. */
    g_path.has_look_at = 0;
    g_path.up = orr_v3(0.6, 0.8, 0);
    CHECK(orr_path_check(&g_path, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "camera.path.up");
}

static void test_inspiral(void)
{
    for (int law = 0; law < 2; law++) {
        orr_path_defaults(&g_path, ORR_PATH_INSPIRAL);
        g_path.centre = orr_v3(-3, 4, 0);
        g_path.r0 = 400;
        g_path.r1 = 4;
        g_path.turns = 2.5;
        g_path.radial = (orr_radial_law)law;
        orr_error err;
        CHECK(orr_path_plane_ref(g_path.axis, &g_path.ref, &err) == ORR_OK);
        CHECK(orr_path_check(&g_path, &err) == ORR_OK);
        double prev = INFINITY;
        for (double u = 0; u <= 1.0 + 1e-9; u += 0.01) {
            orr_camera cam = eval(&g_path, 0, u);
            orr_vec3 to_target = orr_v3_sub(g_path.centre, cam.position);
            double r = orr_v3_norm(to_target);
            CHECK(r < prev);
            prev = r;
            CHECK_NEAR(orr_v3_dot(forward_of(&cam), orr_v3_scale(to_target, 1 / r)), 1, 1e-12);
        }
        CHECK_NEAR(orr_v3_norm(orr_v3_sub(eval(&g_path, 0, 0).position, g_path.centre)), 400, 1e-9);
        CHECK_NEAR(orr_v3_norm(orr_v3_sub(eval(&g_path, 0, 1).position, g_path.centre)), 4, 1e-9);
        double mid = orr_v3_norm(orr_v3_sub(eval(&g_path, 0, 0.5).position, g_path.centre));
        CHECK_NEAR(mid, law == ORR_RADIAL_EXPONENTIAL ? 40 : 202, 1e-9);
    }
}

static void test_rotate(void)
{
    orr_path_defaults(&g_path, ORR_PATH_ROTATE);
    orr_error err;
    CHECK(orr_camera_look_along(&g_path.start, orr_v3(1, 2, 3), orr_v3(1, 0, 0), orr_v3(0, 0, 1), 0, &err) == ORR_OK);
    g_path.angle = 90;
    CHECK(orr_path_check(&g_path, &err) == ORR_OK);
    orr_camera mid = eval(&g_path, 0, 0.5), end = eval(&g_path, 0, 1);
    CHECK_NEAR(mid.position.y, 2, 0);
    CHECK_NEAR(forward_of(&mid).x, sqrt(0.5), 1e-12);
    CHECK_NEAR(forward_of(&mid).y, sqrt(0.5), 1e-12);
    CHECK_NEAR(forward_of(&end).y, 1, 1e-12);
    /* The image's up (-y of the camera) stays the axis. */
    CHECK_NEAR(orr_quat_rotate(end.orientation, orr_v3(0, -1, 0)).z, 1, 1e-12);
}

static void test_ease(void)
{
    const double h = 1e-6;
    CHECK_NEAR(orr_ease_apply(ORR_EASE_IN_OUT, 0), 0, 0);
    CHECK_NEAR(orr_ease_apply(ORR_EASE_IN_OUT, 1), 1, 0);
    CHECK_NEAR(orr_ease_apply(ORR_EASE_IN_OUT, 0.5), 0.5, 1e-15);
    CHECK(orr_ease_apply(ORR_EASE_IN_OUT, h) / h < 1e-5);              /* at rest at the start */
    CHECK((1 - orr_ease_apply(ORR_EASE_IN_OUT, 1 - h)) / h < 1e-5);    /* and at the end */
    CHECK(orr_ease_apply(ORR_EASE_IN, h) / h < 1e-5);
    CHECK_NEAR((1 - orr_ease_apply(ORR_EASE_IN, 1 - h)) / h, 1.5, 1e-5);
    CHECK_NEAR(orr_ease_apply(ORR_EASE_OUT, h) / h, 1.5, 1e-5);
    CHECK((1 - orr_ease_apply(ORR_EASE_OUT, 1 - h)) / h < 1e-5);
    for (int e = 0; e < 4; e++) {
        double prev = -1;
        for (double s = 0; s <= 1; s += 0.01) {
            double v = orr_ease_apply((orr_ease)e, s);
            CHECK(v > prev);
            prev = v;
        }
    }
    /* An eased line starts and ends at rest, and still gets there. */
    orr_path_defaults(&g_path, ORR_PATH_LINE);
    g_path.to = orr_v3(100, 0, 0);
    g_path.ease = ORR_EASE_IN_OUT;
    CHECK(eval(&g_path, 0, h).position.x / h < 1e-3);
    CHECK((100 - eval(&g_path, 0, 1 - h).position.x) / h < 1e-3);
    CHECK_NEAR(eval(&g_path, 0, 1).position.x, 100, 0);
    /* Easing keyframes reshapes their span of frames: the ends are at rest. */
    make_keyframes(&g_path);
    g_path.ease = ORR_EASE_IN_OUT;
    CHECK(orr_v3_norm(orr_v3_sub(eval(&g_path, 1e-3, 0).position, g_path.keys[0].position)) < 1e-5);
}

/* ---- CSV ---- */

static void write_file(const char *path, const char *text)
{
    FILE *fp = fopen(path, "w");
    CHECK(fp != NULL);
    if (fp) {
        fputs(text, fp);
        fclose(fp);
    }
}

static void test_csv_round_trip(void)
{
    make_keyframes(&g_path);
    char path[512];
    snprintf(path, sizeof path, "%s/keys.csv", tmpdir);
    FILE *fp = fopen(path, "w");
    CHECK(fp != NULL);
    if (!fp)
        return;
    fprintf(fp, "# written by test_path\nframe, x, y, z, qw, qx, qy, qz\n");
    for (int i = 0; i < g_path.nkeys; i++) {
        const orr_keyframe *k = &g_path.keys[i];
        fprintf(fp, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", k->frame, k->position.x, k->position.y,
                k->position.z, k->orientation.w, k->orientation.x, k->orientation.y, k->orientation.z);
    }
    fclose(fp);
    static orr_keyframe back[ORR_PATH_KEYFRAMES_MAX];
    int n = 0;
    orr_error err;
    CHECK(orr_path_read_csv(path, back, ORR_PATH_KEYFRAMES_MAX, &n, &err) == ORR_OK);
    CHECK(n == g_path.nkeys);
    for (int i = 0; i < n && i < g_path.nkeys; i++) {
        CHECK_NEAR(back[i].frame, g_path.keys[i].frame, 0);
        CHECK_NEAR(back[i].position.z, g_path.keys[i].position.z, 0);
        CHECK_NEAR(same_rotation(back[i].orientation, g_path.keys[i].orientation), 1, 1e-15);
    }
    /* look_at columns, in any order, give what the look_at spec gives. */
    write_file(path, "look_x,look_y,look_z,frame,x,y,z\n0,0,0, 0, 10,0,0\n0,0,0, 7, 7,7,2\n");
    CHECK(orr_path_read_csv(path, back, ORR_PATH_KEYFRAMES_MAX, &n, &err) == ORR_OK);
    CHECK(n == 2);
    CHECK_NEAR(same_rotation(back[0].orientation, g_path.keys[0].orientation), 1, 1e-15);
    remove(path);
}

static void expect_csv_error(const char *text, const char *needle1, const char *needle2)
{
    char path[512];
    snprintf(path, sizeof path, "%s/bad.csv", tmpdir);
    write_file(path, text);
    static orr_keyframe keys[ORR_PATH_KEYFRAMES_MAX];
    int n = 0;
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_path_read_csv(path, keys, ORR_PATH_KEYFRAMES_MAX, &n, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "bad.csv:");
    CHECK_CONTAINS(err.msg, needle1);
    CHECK_CONTAINS(err.msg, needle2);
    remove(path);
}

static void test_csv_errors(void)
{
    const char *head = "frame,x,y,z,look_x,look_y,look_z\n";
    char text[512];
    snprintf(text, sizeof text, "%s0,1,0,0,0,0,0\n1,1,1,0,0,0\n", head);
    expect_csv_error(text, "bad.csv:3:", "6 values, expected 7");
    snprintf(text, sizeof text, "%s0,1,0,0,0,0,0\n1,1,abc,0,0,0,0\n", head);
    expect_csv_error(text, "bad.csv:3:", "column 'y': 'abc' is not a finite number");
    expect_csv_error("frame,x,y,z,look_x,look_y,look_z,foo\n", "bad.csv:1:", "unknown column 'foo'");
    snprintf(text, sizeof text, "%s\n# a comment\n5,1,0,0,0,0,0\n5,2,0,0,0,0,0\n", head);
    expect_csv_error(text, "bad.csv:5:", "frame 5 is not after the previous keyframe's frame 5");
    expect_csv_error("frame,x,y,z\n0,0,0,1\n1,0,0,2\n", "bad.csv:1:", "exactly one orientation");
    expect_csv_error("frame,x,y,z,qw,qx,qy\n", "bad.csv:1:", "column 'qz' is missing");
    snprintf(text, sizeof text, "%s0,1,0,0,1,0,0\n1,2,0,0,0,0,0\n", head);
    expect_csv_error(text, "bad.csv:2:", "position equals the look-at point");
    snprintf(text, sizeof text, "%s0,1,0,0,0,0,0\n", head);
    expect_csv_error(text, "1 keyframe", "at least 2");
    static orr_keyframe keys[4];
    int n;
    orr_error err;
    CHECK(orr_path_read_csv("/nonexistent/keys.csv", keys, 4, &n, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "/nonexistent/keys.csv");
}

/* ---- scene keys ---- */

#define MODEL "input:\n  model: {name: mw-m31}\n"

static orr_status load(const char *yaml, orr_error *err)
{
    orr_error_clear(err);
    orr_scene_free(&g_scene);
    return orr_scene_load_string(&g_scene, yaml, "scene.yaml", tmpdir, NULL, 0, err);
}

static void expect_scene_error(const char *yaml, const char *needle1, const char *needle2)
{
    orr_error err;
    orr_status st = load(yaml, &err);
    CHECK(st == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, needle1);
    CHECK_CONTAINS(err.msg, needle2);
}

static void test_scene_good(void)
{
    orr_error err;
    CHECK(load(MODEL "camera:\n  projection: perspective\n  path:\n    kind: orbit\n    centre: [1, 0, 0]\n"
                     "    radius: 50\n    turns: 0.5\n    ease: in-out\n",
               &err) == ORR_OK);
    CHECK(g_scene.camera.has_path && g_scene.camera.path.kind == ORR_PATH_ORBIT);
    CHECK_NEAR(g_scene.camera.path.radius, 50, 0);
    CHECK(g_scene.camera.path.ease == ORR_EASE_IN_OUT);
    orr_frame_time t = orr_frame_at(0, 11, 30, 0, 0);
    orr_camera cam;
    CHECK(orr_path_camera(&g_scene.camera.path, &t, &cam, &err) == ORR_OK);
    CHECK_NEAR(orr_v3_norm(orr_v3_sub(cam.position, orr_v3(1, 0, 0))), 50, 1e-12);

    CHECK(load(MODEL "camera:\n  path:\n    kind: orbit\n    start: [0, 30, 10]\n", &err) == ORR_OK);
    CHECK_NEAR(g_scene.camera.path.radius, 30, 1e-12);
    t = orr_frame_at(0, 5, 30, 0, 0);
    CHECK(orr_path_camera(&g_scene.camera.path, &t, &cam, &err) == ORR_OK);
    CHECK_NEAR(cam.position.y, 30, 1e-12);
    CHECK_NEAR(cam.position.z, 10, 1e-12);

    CHECK(load(MODEL "camera:\n  path:\n    kind: keyframes\n    interpolation: hermite\n    orientation: squad\n"
                     "    keyframes:\n"
                     "      - {frame: 0, position: [0, 0, 50], look_at: [0, 0, 0]}\n"
                     "      - {frame: 12.5, position: [20, 0, 40], direction: [0, 0, -1], up: [0, 1, 0], roll: 5}\n"
                     "      - {frame: 30, position: [0, 20, 30], quaternion: [1, 0, 0, 0]}\n",
               &err) == ORR_OK);
    if (err.msg[0])
        fprintf(stderr, "  %s\n", err.msg);
    CHECK(g_scene.camera.path.nkeys == 3);
    CHECK_NEAR(g_scene.camera.path.keys[1].frame, 12.5, 0);
    CHECK(g_scene.camera.path.orientation == ORR_ORIENT_SQUAD);

    char csv[512];
    snprintf(csv, sizeof csv, "%s/path.csv", tmpdir);
    write_file(csv, "frame,x,y,z,dir_x,dir_y,dir_z\n0,0,0,0,0,0,-1\n10,0,0,-5,0,0,-1\n");
    CHECK(load(MODEL "camera:\n  path:\n    kind: keyframes\n    file: path.csv\n", &err) == ORR_OK);
    CHECK(g_scene.camera.path.nkeys == 2);
    remove(csv);

    CHECK(load(MODEL "camera:\n  position: [0, 0, 10]\n  direction: [1, 0, 0]\n  up: [0, 0, 1]\n"
                     "  path: {kind: rotate, angle: 360}\n",
               &err) == ORR_OK);
    CHECK_NEAR(g_scene.camera.path.start.position.z, 10, 0);
    CHECK(load(MODEL "camera:\n  path: {kind: inspiral, target: [1, 1, 1], r0: 100, r1: 1, radial: linear}\n",
               &err) == ORR_OK);
    CHECK(load(MODEL "camera:\n  path: {kind: line, from: [0, 0, 0], to: [0, 0, -100], up: [0, 1, 0]}\n",
               &err) == ORR_OK);
}

static void test_scene_bad(void)
{
    expect_scene_error(MODEL "camera:\n  position: [0, 0, 10]\n  path: {kind: orbit, radius: 5}\n",
                       "scene.yaml:4: camera.position is not allowed", "camera.path.kind: orbit");
    expect_scene_error(MODEL "camera:\n  path: {kind: orbit, radius: 5}\n  look_at: [0, 0, 0]\n",
                       "scene.yaml:5: camera.look_at", "the path places and orients the camera");
    expect_scene_error(MODEL "observer: {id: 1, reference_id: 2}\ncamera:\n  path: {kind: orbit, radius: 5}\n",
                       "camera.path.kind and observer.id", "scene.yaml:5:");
    expect_scene_error(MODEL "camera:\n  path: {kind: line, from: [0, 0, 0], to: [1, 0, 0], radius: 3}\n",
                       "camera.path.radius does not apply to camera.path.kind: line", "from, to");
    expect_scene_error(MODEL "camera:\n  path: {radius: 3}\n", "camera.path.radius needs camera.path.kind", "");
    expect_scene_error(MODEL "camera:\n  path: {kind: line, to: [1, 0, 0]}\n", "line needs camera.path.from", "");
    expect_scene_error(MODEL "camera:\n  path: {kind: orbit}\n", "camera.path.radius or camera.path.start", "");
    expect_scene_error(MODEL "camera:\n  path: {kind: orbit, start: [1, 0, 0], radius: 2}\n",
                       "camera.path.radius and camera.path.start", "");
    expect_scene_error(MODEL "camera:\n  path: {kind: orbit, radius: 2, axis: [0, 0, 0]}\n", "camera.path.axis",
                       "[0, 0, 0]");
    expect_scene_error(MODEL "camera:\n  path: {kind: spiral}\n", "camera.path.kind", "keyframes orbit line");
    expect_scene_error(MODEL "camera:\n  path:\n    kind: keyframes\n    keyframes:\n"
                             "      - {frame: 5, position: [0, 0, 1], look_at: [0, 0, 0]}\n"
                             "      - {frame: 2, position: [0, 0, 2], look_at: [0, 0, 0]}\n",
                       "scene.yaml:8: camera.path.keyframes[1].frame", "increasing frame order");
    expect_scene_error(MODEL "camera:\n  path:\n    kind: keyframes\n    keyframes:\n"
                             "      - {frame: 5, position: [0, 0, 1], look_at: [0, 0, 0]}\n",
                       "camera.path.keyframes: expected a list of 2 to 256 keyframes", "");
    expect_scene_error(MODEL "camera:\n  path:\n    kind: keyframes\n    keyframes:\n"
                             "      - {frame: 0, position: [0, 0, 1], look_at: [0, 0, 0], direction: [0, 0, 1]}\n"
                             "      - {frame: 2, position: [0, 0, 2], look_at: [0, 0, 0]}\n",
                       "camera.path.keyframes[0]", "exactly one of look_at, direction, quaternion");
    expect_scene_error(MODEL "camera:\n  path:\n    kind: keyframes\n    keyframes:\n"
                             "      - {frame: 0, position: [0, 0, 1], look_at: [0, 0, 0], fov: 3}\n"
                             "      - {frame: 2, position: [0, 0, 2], look_at: [0, 0, 0]}\n",
                       "camera.path.keyframes[0]: unknown key 'fov'", "");
    expect_scene_error(MODEL "camera:\n  path: {kind: keyframes}\n", "camera.path.keyframes", "camera.path.file");
    orr_error err;
    CHECK(load(MODEL "camera:\n  path: {kind: keyframes, file: missing.csv}\n", &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "camera.path.file");
    CHECK_CONTAINS(err.msg, "missing.csv: cannot open");
}

/* The overview looks down an orbit's axis, across a tilted keyframe loop's
 * plane, and across a straight line. */
static void test_overview_axis(void)
{
    static orr_camera cams[64];
    orr_path_defaults(&g_path, ORR_PATH_ORBIT);
    g_path.axis = orr_v3(0, 3, 4);
    orr_vec3 n = orr_path_main_axis(&g_path, cams, 0);
    CHECK_NEAR(n.y, 0.6, 1e-15);
    /* A loop in the plane normal to (1, 1, 1) / sqrt(3), counter-clockwise about it. */
    const orr_vec3 a = orr_v3_normalize(orr_v3(1, -1, 0)), b = orr_v3_cross(orr_v3_normalize(orr_v3(1, 1, 1)), a);
    for (int i = 0; i < 64; i++) {
        double t = 2 * ORR_PI * i / 64;
        orr_vec3 offset = orr_v3_add(orr_v3_scale(a, 3 * cos(t)), orr_v3_scale(b, 2 * sin(t)));
        cams[i].position = orr_v3_add(orr_v3(5, 5, 5), offset);
    }
    orr_path_defaults(&g_path, ORR_PATH_KEYFRAMES);
    n = orr_path_main_axis(&g_path, cams, 64);
    CHECK_NEAR(n.x, 1 / sqrt(3), 1e-12);
    CHECK_NEAR(n.z, 1 / sqrt(3), 1e-12);
    for (int i = 0; i < 64; i++)
        cams[i].position = orr_v3(i, 2 * i, 0);
    n = orr_path_main_axis(&g_path, cams, 64);
    CHECK_NEAR(n.z, 1, 0);
    for (int i = 0; i < 64; i++)
        cams[i].position = orr_v3(0, 0.1 * i, i);
    n = orr_path_main_axis(&g_path, cams, 64);
    CHECK_NEAR(fabs(orr_v3_dot(n, orr_v3(0, 0.1, 1))), 0, 0.2);
}

int main(void)
{
    make_tmpdir();
    RUN(test_through_keyframes);
    RUN(test_velocity_continuous);
    RUN(test_unit_quaternions);
    RUN(test_squad_smooth);
    RUN(test_orbit);
    RUN(test_line);
    RUN(test_inspiral);
    RUN(test_rotate);
    RUN(test_ease);
    RUN(test_overview_axis);
    RUN(test_csv_round_trip);
    RUN(test_csv_errors);
    RUN(test_scene_good);
    RUN(test_scene_bad);
    remove_tmpdir();
    return check_summary();
}
