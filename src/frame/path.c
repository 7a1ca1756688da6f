#include "frame/path.h"

#include <math.h>
#include <string.h>

const orr_named orr_path_kind_names[] = {{"keyframes", ORR_PATH_KEYFRAMES}, {"orbit", ORR_PATH_ORBIT},
                                         {"line", ORR_PATH_LINE},           {"inspiral", ORR_PATH_INSPIRAL},
                                         {"rotate", ORR_PATH_ROTATE},       {NULL, 0}};
const orr_named orr_path_interp_names[] = {
    {"catmull-rom", ORR_PATH_CATMULL_ROM}, {"hermite", ORR_PATH_HERMITE}, {NULL, 0}};
const orr_named orr_path_orient_names[] = {{"slerp", ORR_ORIENT_SLERP}, {"squad", ORR_ORIENT_SQUAD}, {NULL, 0}};
const orr_named orr_ease_names[] = {
    {"none", ORR_EASE_NONE}, {"in", ORR_EASE_IN}, {"out", ORR_EASE_OUT}, {"in-out", ORR_EASE_IN_OUT}, {NULL, 0}};
const orr_named orr_radial_law_names[] = {
    {"exponential", ORR_RADIAL_EXPONENTIAL}, {"linear", ORR_RADIAL_LINEAR}, {NULL, 0}};

const char *orr_path_kind_name(orr_path_kind kind) { return orr_named_name(orr_path_kind_names, (int)kind); }

ORR_NAMED_PARSER(orr_path_kind_from_name, orr_path_kind, orr_path_kind_names)

ORR_NAMED_PARSER(orr_ease_from_name, orr_ease, orr_ease_names)

void orr_path_defaults(orr_camera_path *p, orr_path_kind kind)
{
    memset(p, 0, sizeof *p);
    p->kind = kind;
    p->ease = ORR_EASE_NONE;
    p->interpolation = ORR_PATH_CATMULL_ROM;
    p->orientation = ORR_ORIENT_SLERP;
    p->axis = orr_v3(0, 0, 1);
    p->ref = orr_v3(1, 0, 0);
    p->radial = ORR_RADIAL_EXPONENTIAL;
    p->turns = 1;
    p->up = orr_v3(0, 1, 0);
    p->start.orientation = orr_quat_identity();
}

/* ---- easing ---- */

/* The ease-in curve is the first half of smoothstep stretched to [0, 1]:
 * e(s) = 2 smoothstep(s / 2) = 1.5 s^2 - 0.5 s^3, at rest at s = 0 and
 * arriving at 1.5 times the mean speed, so it joins a constant-speed run
 * without a jolt in position (only in speed). */
static double ease_in(double s) { return 1.5 * s * s - 0.5 * s * s * s; }

double orr_ease_apply(orr_ease ease, double s)
{
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    switch (ease) {
    case ORR_EASE_NONE: return s;
    case ORR_EASE_IN: return ease_in(s);
    case ORR_EASE_OUT: return 1.0 - ease_in(1.0 - s);
    case ORR_EASE_IN_OUT: return s * s * (3.0 - 2.0 * s);
    }
    return s;
}

/* ---- keyframe orientations ---- */

orr_status orr_keyframe_from_spec(const orr_keyframe_spec *spec, orr_keyframe *key, orr_error *err)
{
    orr_camera cam;
    orr_status st = ORR_OK;
    const orr_vec3 up = spec->has_up ? spec->up : orr_v3(0, 1, 0);
    switch (spec->aim) {
    case ORR_AIM_QUATERNION: {
        orr_quat q = spec->quaternion;
        if (q.w == 0 && q.x == 0 && q.y == 0 && q.z == 0)
            return orr_fail(err, ORR_ERR_USAGE, "quaternion [0, 0, 0, 0] is not a rotation (zero length)");
        cam.position = spec->position;
        cam.orientation = orr_quat_normalize(q); /* people round their quaternions */
        break;
    }
    case ORR_AIM_LOOK_AT:
        st = orr_camera_look_at(&cam, spec->position, spec->look, up, spec->roll, err);
        break;
    case ORR_AIM_DIRECTION:
        /* As camera.direction: without an up vector, the design notes' rotation. */
        st = spec->has_up ? orr_camera_look_along(&cam, spec->position, spec->look, up, spec->roll, err)
                          : orr_camera_look_along_roll(&cam, spec->position, spec->look, spec->roll, err);
        break;
    }
    if (st)
        return st;
    key->frame = spec->frame;
    key->position = spec->position;
    key->orientation = cam.orientation;
    return ORR_OK;
}

/* ---- checks ---- */

orr_status orr_path_plane_ref(orr_vec3 axis, orr_vec3 *ref, orr_error *err)
{
    orr_vec3 a = orr_v3_normalize(axis);
    if (!(orr_v3_norm(a) > 0))
        return orr_fail(err, ORR_ERR_USAGE, "camera.path.axis: must not be [0, 0, 0]");
    orr_vec3 x = fabs(a.x) > 0.9 ? orr_v3(0, 1, 0) : orr_v3(1, 0, 0);
    *ref = orr_v3_normalize(orr_v3_sub(x, orr_v3_scale(a, orr_v3_dot(x, a))));
    return ORR_OK;
}

static orr_status check_keyframes(const orr_camera_path *p, orr_error *err)
{
    if (p->nkeys < 2)
        return orr_fail(err, ORR_ERR_USAGE, "camera.path: a keyframe path needs at least 2 keyframes, got %d",
                        p->nkeys);
    for (int i = 1; i < p->nkeys; i++)
        if (!(p->keys[i].frame > p->keys[i - 1].frame))
            return orr_fail(err, ORR_ERR_USAGE,
                            "camera.path: keyframe %d (frame %g) is not after keyframe %d (frame %g); keyframes "
                            "must be in increasing frame order",
                            i, p->keys[i].frame, i - 1, p->keys[i - 1].frame);
    return ORR_OK;
}

orr_status orr_path_check(orr_camera_path *p, orr_error *err)
{
    if (p->kind == ORR_PATH_KEYFRAMES)
        return check_keyframes(p, err);
    if (!(orr_v3_norm(p->axis) > 0))
        return orr_fail(err, ORR_ERR_USAGE, "camera.path.axis: must not be [0, 0, 0]");
    p->axis = orr_v3_normalize(p->axis);
    switch (p->kind) {
    case ORR_PATH_ORBIT:
        if (!(p->radius > 0))
            return orr_fail(err, ORR_ERR_USAGE, "camera.path.radius: an orbit needs a radius > 0 (or a start point)");
        break;
    case ORR_PATH_INSPIRAL:
        if (!(p->r0 > 0) || !(p->r1 > 0))
            return orr_fail(err, ORR_ERR_USAGE, "camera.path: an inspiral needs camera.path.r0 and camera.path.r1, "
                                                "both > 0 (got %g and %g)", p->r0, p->r1);
        break;
    case ORR_PATH_LINE: {
        orr_vec3 d = orr_v3_sub(p->to, p->from);
        if (!(orr_v3_norm(d) > 0))
            return orr_fail(err, ORR_ERR_USAGE, "camera.path.to: equals camera.path.from, so the line has no length");
        if (!(orr_v3_norm(p->up) > 0))
            return orr_fail(err, ORR_ERR_USAGE, "camera.path.up: must not be [0, 0, 0]");
        if (!p->has_look_at && orr_v3_norm(orr_v3_cross(orr_v3_normalize(d), orr_v3_normalize(p->up))) < 1e-9)
            return orr_fail(err, ORR_ERR_USAGE,
                            "camera.path.up: is parallel to the line (camera.path.to - camera.path.from), "
                            "along which the camera looks; give another up");
        break;
    }
    default: break;
    }
    return ORR_OK;
}

/* ---- keyframe interpolation ---- */

/* The tangent dP/dframe at keyframe i. The ends take the one-sided slope. */
static orr_vec3 key_tangent(const orr_camera_path *p, int i)
{
    const orr_keyframe *k = p->keys;
    const int n = p->nkeys;
    if (i == 0)
        return orr_v3_scale(orr_v3_sub(k[1].position, k[0].position), 1.0 / (k[1].frame - k[0].frame));
    if (i == n - 1)
        return orr_v3_scale(orr_v3_sub(k[n - 1].position, k[n - 2].position), 1.0 / (k[n - 1].frame - k[n - 2].frame));
    if (p->interpolation == ORR_PATH_CATMULL_ROM)
        return orr_v3_scale(orr_v3_sub(k[i + 1].position, k[i - 1].position), 1.0 / (k[i + 1].frame - k[i - 1].frame));
    orr_vec3 after = orr_v3_scale(orr_v3_sub(k[i + 1].position, k[i].position), 1.0 / (k[i + 1].frame - k[i].frame));
    orr_vec3 before = orr_v3_scale(orr_v3_sub(k[i].position, k[i - 1].position), 1.0 / (k[i].frame - k[i - 1].frame));
    return orr_v3_scale(orr_v3_add(after, before), 0.5);
}

/* The cubic Hermite segment from keyframe i to i + 1 at s in [0, 1]. The
 * tangents are per frame, so they are scaled by the segment's length in
 * frames: that keeps dP/dframe the same on both sides of a keyframe. */
static orr_vec3 hermite_position(const orr_camera_path *p, int i, double s)
{
    const double h = p->keys[i + 1].frame - p->keys[i].frame;
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    orr_vec3 r = orr_v3_scale(p->keys[i].position, h00);
    r = orr_v3_add(r, orr_v3_scale(key_tangent(p, i), h10 * h));
    r = orr_v3_add(r, orr_v3_scale(p->keys[i + 1].position, h01));
    return orr_v3_add(r, orr_v3_scale(key_tangent(p, i + 1), h11 * h));
}

static double quat_dot(orr_quat a, orr_quat b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }

/* b or -b (the same rotation), whichever is nearer a: squad's control
 * points must come from quaternions on one side of the sphere. */
static orr_quat quat_near(orr_quat a, orr_quat b)
{
    return quat_dot(a, b) < 0 ? (orr_quat){-b.w, -b.x, -b.y, -b.z} : b;
}

/* log of a unit quaternion (cos t, sin t n) is (0, t n); returned as a vector. */
static orr_vec3 quat_log(orr_quat q)
{
    orr_vec3 v = orr_v3(q.x, q.y, q.z);
    double s = orr_v3_norm(v);
    if (s < 1e-15)
        return orr_v3(0, 0, 0);
    double t = atan2(s, q.w);
    return orr_v3_scale(v, t / s);
}

static orr_quat quat_exp(orr_vec3 v)
{
    double t = orr_v3_norm(v);
    if (t < 1e-15)
        return orr_quat_identity();
    double k = sin(t) / t;
    return (orr_quat){cos(t), k * v.x, k * v.y, k * v.z};
}

/* Shoemake's inner control points, generalised to unevenly spaced
 * keyframes. A squad segment leaves q_i with the (half-angle, body-frame)
 * log-velocity L_next + 2 log(q_i^-1 a_i) per unit of s, where L_next =
 * log(q_i^-1 q_{i+1}) and L_prev = log(q_i^-1 q_{i-1}). We ask for the
 * same velocity per frame on both sides of q_i, the Catmull-Rom-like
 * T = (L_next - L_prev) / (h_prev + h_next), so the control point leaving
 * q_i is a_out = q_i exp((h_next T - L_next) / 2) and the one arriving is
 * a_in = q_i exp((-h_prev T - L_prev) / 2). With even spacing both are
 * Shoemake's a_i = q_i exp(-(L_next + L_prev) / 4). The ends use a = q. */
static orr_quat squad_control(const orr_camera_path *p, int i, int outgoing)
{
    if (i == 0 || i == p->nkeys - 1)
        return p->keys[i].orientation;
    orr_quat q = p->keys[i].orientation;
    orr_quat prev = quat_near(q, p->keys[i - 1].orientation), next = quat_near(q, p->keys[i + 1].orientation);
    orr_quat inv = orr_quat_conj(q);
    orr_vec3 l_next = quat_log(orr_quat_mul(inv, next)), l_prev = quat_log(orr_quat_mul(inv, prev));
    const double h_prev = p->keys[i].frame - p->keys[i - 1].frame, h_next = p->keys[i + 1].frame - p->keys[i].frame;
    orr_vec3 t = orr_v3_scale(orr_v3_sub(l_next, l_prev), 1.0 / (h_prev + h_next));
    orr_vec3 v = outgoing ? orr_v3_sub(orr_v3_scale(t, h_next), l_next) : orr_v3_sub(orr_v3_scale(t, -h_prev), l_prev);
    return orr_quat_normalize(orr_quat_mul(q, quat_exp(orr_v3_scale(v, 0.5))));
}

/* Slerp along the arc from a to b as given, without orr_quat_slerp's
 * shorter-arc flip: squad blends two slerps whose ends may be more than 90
 * degrees apart, and a flip half way through would turn the camera
 * suddenly. The caller puts its quaternions on one side beforehand. */
static orr_quat slerp_direct(orr_quat a, orr_quat b, double t)
{
    double d = quat_dot(a, b);
    d = d > 1 ? 1 : d < -1 ? -1 : d;
    double wa = 1.0 - t, wb = t;
    if (fabs(d) < 0.9995) {
        double theta = acos(d), s = sin(theta);
        wa = sin((1.0 - t) * theta) / s;
        wb = sin(t * theta) / s;
    }
    return orr_quat_normalize((orr_quat){wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y,
                                         wa * a.z + wb * b.z});
}

static orr_quat key_orientation(const orr_camera_path *p, int i, double s)
{
    orr_quat q0 = p->keys[i].orientation, q1 = quat_near(q0, p->keys[i + 1].orientation);
    if (p->orientation == ORR_ORIENT_SLERP)
        return orr_quat_slerp(q0, q1, s);
    /* squad(s) = slerp(slerp(q0, q1, s), slerp(a0, a1, s), 2 s (1 - s)). */
    orr_quat a0 = squad_control(p, i, 1), a1 = squad_control(p, i + 1, 0);
    if (quat_dot(q0, p->keys[i + 1].orientation) < 0) /* q1 was flipped: its control point goes with it */
        a1 = (orr_quat){-a1.w, -a1.x, -a1.y, -a1.z};
    return slerp_direct(slerp_direct(q0, q1, s), slerp_direct(a0, a1, s), 2 * s * (1 - s));
}

static void eval_keyframes(const orr_camera_path *p, double frame, orr_camera *cam)
{
    const int n = p->nkeys;
    const double f0 = p->keys[0].frame, f1 = p->keys[n - 1].frame;
    /* Easing reshapes the keyframes' span of frames; outside it, hold. */
    double f = f0 + (f1 - f0) * orr_ease_apply(p->ease, (frame - f0) / (f1 - f0));
    if (f <= f0) {
        cam->position = p->keys[0].position;
        cam->orientation = p->keys[0].orientation;
        return;
    }
    if (f >= f1) {
        cam->position = p->keys[n - 1].position;
        cam->orientation = p->keys[n - 1].orientation;
        return;
    }
    int i = 0;
    while (i + 2 < n && f >= p->keys[i + 1].frame)
        i++;
    const double s = (f - p->keys[i].frame) / (p->keys[i + 1].frame - p->keys[i].frame);
    cam->position = hermite_position(p, i, s);
    cam->orientation = key_orientation(p, i, s);
}

/* ---- generators ---- */

/* The point at angle phi (radians) and distance r around centre in the
 * plane normal to axis, raised by height along it. */
static orr_vec3 circle_point(const orr_camera_path *p, double phi, double r, double height)
{
    orr_vec3 e2 = orr_v3_cross(p->axis, p->ref);
    orr_vec3 in_plane = orr_v3_add(orr_v3_scale(p->ref, cos(phi)), orr_v3_scale(e2, sin(phi)));
    return orr_v3_add(orr_v3_add(p->centre, orr_v3_scale(p->axis, height)), orr_v3_scale(in_plane, r));
}

static double path_angle(const orr_camera_path *p, double u)
{
    return (p->start_angle + 360.0 * p->turns * u) * ORR_PI / 180.0;
}

static double inspiral_radius(const orr_camera_path *p, double u)
{
    if (p->radial == ORR_RADIAL_LINEAR)
        return p->r0 + (p->r1 - p->r0) * u;
    return p->r0 * pow(p->r1 / p->r0, u);
}

orr_status orr_path_eval(const orr_camera_path *p, double frame, double u, orr_camera *cam, orr_error *err)
{
    orr_status st = ORR_OK;
    if (p->kind == ORR_PATH_KEYFRAMES) {
        if (p->nkeys < 2)
            return orr_fail(err, ORR_ERR_USAGE, "camera.path: a keyframe path needs at least 2 keyframes");
        eval_keyframes(p, frame, cam);
        return ORR_OK;
    }
    const double e = orr_ease_apply(p->ease, u);
    switch (p->kind) {
    case ORR_PATH_ORBIT: {
        orr_vec3 pos = circle_point(p, path_angle(p, e), p->radius, p->height);
        st = orr_camera_look_at(cam, pos, p->centre, p->axis, 0, err);
        break;
    }
    case ORR_PATH_INSPIRAL: {
        orr_vec3 pos = circle_point(p, path_angle(p, e), inspiral_radius(p, e), 0);
        st = orr_camera_look_at(cam, pos, p->centre, p->axis, 0, err);
        break;
    }
    case ORR_PATH_LINE: {
        orr_vec3 d = orr_v3_sub(p->to, p->from);
        orr_vec3 pos = orr_v3_add(p->from, orr_v3_scale(d, e));
        st = p->has_look_at ? orr_camera_look_at(cam, pos, p->look_at, p->up, 0, err)
                            : orr_camera_look_along(cam, pos, d, p->up, 0, err);
        break;
    }
    case ORR_PATH_ROTATE: {
        /* A turn about a world axis composes on the left of camera-to-world. */
        orr_quat turn = orr_quat_axis_angle(p->axis, p->angle * e * ORR_PI / 180.0);
        cam->position = p->start.position;
        cam->orientation = orr_quat_normalize(orr_quat_mul(turn, p->start.orientation));
        break;
    }
    default: break;
    }
    if (st)
        return orr_fail_prefix(err, "camera.path (%s) at frame %g: ", orr_path_kind_name(p->kind), frame);
    return ORR_OK;
}

orr_status orr_path_camera(const orr_camera_path *p, const orr_frame_time *t, orr_camera *cam, orr_error *err)
{
    return orr_path_eval(p, (double)t->frame, t->u, cam, err);
}
