#include "frame/camera_settings.h"

#include <math.h>
#include <string.h>

#include "core/owned.h"

static int is_zero(orr_vec3 v) { return v.x == 0 && v.y == 0 && v.z == 0; }

/* True when a and b point along the same line (or either is zero). */
static int parallel(orr_vec3 a, orr_vec3 b)
{
    return orr_v3_norm(orr_v3_cross(a, b)) <= 1e-12 * orr_v3_norm(a) * orr_v3_norm(b);
}

/* At most one of the keys that orient the camera. */
static orr_status check_orientation_count(const orr_keys *keys, orr_error *err)
{
    static const char *const orientation[] = {"camera.look_at", "camera.direction", "camera.quaternion"};
    const char *first = NULL;
    for (int i = 0; i < 3; i++) {
        if (!orr_key_given(keys, orientation[i]))
            continue;
        if (first)
            return orr_fail_key(keys, orientation[i], err,
                                "%s and %s are both set; use at most one of camera.look_at, camera.direction, "
                                "camera.quaternion",
                                first, orientation[i]);
        first = orientation[i];
    }
    return ORR_OK;
}

static orr_status check_orientation(orr_camera_settings *c, const orr_keys *keys, orr_error *err)
{
    orr_status st = check_orientation_count(keys, err);
    if (st != ORR_OK)
        return st;
    if (c->has_quaternion) {
        orr_quat q = c->quaternion;
        if (q.w == 0 && q.x == 0 && q.y == 0 && q.z == 0)
            return orr_fail_key(keys, "camera.quaternion", err,
                                "camera.quaternion: [0, 0, 0, 0] is not a rotation (zero length)");
        /* Users round their quaternions; the renderer wants a unit one. */
        c->quaternion = orr_quat_normalize(q);
    }
    if (c->has_direction && is_zero(c->direction))
        return orr_fail_key(keys, "camera.direction", err, "camera.direction: must not be [0, 0, 0]");
    if (c->has_up && is_zero(c->up))
        return orr_fail_key(keys, "camera.up", err, "camera.up: must not be [0, 0, 0]");
    orr_vec3 view = c->has_look_at ? orr_v3_sub(c->look_at, c->position) : c->direction;
    if (c->has_look_at && is_zero(view))
        return orr_fail_key(keys, "camera.look_at", err,
                            "camera.look_at: equals camera.position, so there is no direction to look in");
    if (c->has_up && (c->has_look_at || c->has_direction) && parallel(view, c->up))
        return orr_fail_key(keys, "camera.up", err, "camera.up: is parallel to the view direction (%s)",
                            c->has_look_at ? "camera.look_at - camera.position" : "camera.direction");
    return ORR_OK;
}

static orr_vec3 lb_direction(const double lb[2])
{
    const double l = lb[0] * ORR_PI / 180.0, b = lb[1] * ORR_PI / 180.0;
    return orr_v3(cos(b) * cos(l), cos(b) * sin(l), sin(b));
}

/* The front is projected perpendicular to the zenith; along the zenith (or
 * opposite it) nothing is left to project. */
static orr_status check_zenith_front(const orr_camera_settings *c, const orr_keys *keys, orr_error *err)
{
    const orr_vec3 zenith = lb_direction(c->zenith_lb), front = lb_direction(c->front_lb);
    const double angle = atan2(orr_v3_norm(orr_v3_cross(zenith, front)), orr_v3_dot(zenith, front)) * 180.0 / ORR_PI;
    if (angle >= 1e-6 && angle <= 180 - 1e-6)
        return ORR_OK;
    return orr_fail_key(keys, orr_key_given(keys, "camera.front") ? "camera.front" : "camera.zenith", err,
                        "camera.front [%g, %g] and camera.zenith [%g, %g] are %s: the front is projected "
                        "perpendicular to the zenith, so it must point some other way",
                        c->front_lb[0], c->front_lb[1], c->zenith_lb[0], c->zenith_lb[1],
                        angle < 90 ? "the same direction" : "opposite directions");
}

orr_status orr_camera_settings_prepare(orr_camera_settings *c, const orr_keys *keys, orr_error *err)
{
    orr_status st = check_orientation(c, keys, err);
    if (!st)
        st = check_zenith_front(c, keys, err);
    if (!st && !c->dim && orr_key_given(keys, "camera.dim_near"))
        return orr_fail_key(keys, "camera.dim_near", err,
                            "camera.dim_near applies to camera.dim: true, but camera.dim is off");
    return st;
}

void orr_camera_settings_defaults(orr_camera_settings *d)
{
    memset(d, 0, sizeof *d);
    d->position = orr_v3(0, 0, 0);
    d->up = orr_v3(0, 1, 0);
    d->roll = 0;
    d->quaternion = (orr_quat){1, 0, 0, 0};
    orr_path_defaults(&d->path, ORR_PATH_KEYFRAMES);
    d->dome_tilt = 0;
    d->zenith_lb[0] = 0;
    d->zenith_lb[1] = 90;
    d->front_lb[0] = 0;
    d->front_lb[1] = 0;
    d->dim_near = 0.01;
}

void orr_camera_dome_cards(const orr_camera_settings *c, orr_projection_kind kind, orr_cards *h)
{
    if (kind != ORR_PROJ_DOME)
        return;
    orr_cards_add_double(h, "DOMETILT", c->dome_tilt, "[deg] dome tilt toward the front");
    if (c->dome[0])
        orr_cards_add_string(h, "DOMEPROF", c->dome, "dome profile");
}

void orr_camera_dim_cards(const orr_camera_settings *c, orr_cards *h)
{
    if (c->dim)
        orr_cards_add_bool(h, "DIMMED", 1, "weights divided by r^2 from the camera");
}

int orr_camera_settings_look_target(const orr_camera_settings *c, orr_vec3 *target)
{
    const orr_camera_path *p = &c->path;
    if (c->has_path && (p->kind == ORR_PATH_ORBIT || p->kind == ORR_PATH_INSPIRAL)) {
        *target = p->centre;
        return 1;
    }
    if (c->has_path && p->kind == ORR_PATH_LINE && p->has_look_at) {
        *target = p->look_at;
        return 1;
    }
    if (!c->has_path && c->has_look_at) {
        *target = c->look_at;
        return 1;
    }
    return 0;
}

orr_status orr_camera_settings_static(const orr_camera_settings *c, orr_camera *cam, orr_error *err)
{
    if (c->has_quaternion) {
        cam->position = c->position;
        cam->orientation = orr_quat_normalize(c->quaternion);
        return ORR_OK;
    }
    if (c->has_look_at)
        return orr_camera_look_at(cam, c->position, c->look_at, c->up, c->roll, err);
    if (c->has_direction && !c->has_up)
        return orr_camera_look_along_roll(cam, c->position, c->direction, c->roll, err);
    orr_vec3 dir = c->has_direction ? c->direction : orr_v3(0, 0, -1);
    return orr_camera_look_along(cam, c->position, dir, c->up, c->roll, err);
}

int orr_camera_settings_strings(orr_camera_settings *d, char **fields[])
{
    fields[0] = &d->path_file;
    return ORR_CAMERA_STRINGS;
}

void orr_camera_settings_free(orr_camera_settings *d)
{
    char **fields[ORR_CAMERA_STRINGS];
    orr_owned_free_all(fields, orr_camera_settings_strings(d, fields));
}

orr_status orr_camera_settings_copy(orr_camera_settings *dst, const orr_camera_settings *src, orr_error *err)
{
    char **fields[ORR_CAMERA_STRINGS];
    return orr_owned_copy(dst, src, sizeof *dst, fields, orr_camera_settings_strings(dst, fields), err);
}
