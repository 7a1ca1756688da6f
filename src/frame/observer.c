#include "frame/observer.h"

#include <string.h>

const orr_named orr_normal_sign_names[] = {{"+1", 1}, {"-1", -1}, {"1", 1}, {NULL, 0}};

void orr_observer_settings_defaults(orr_observer_settings *d)
{
    memset(d, 0, sizeof *d);
    d->normal = orr_v3(0, 0, 1);
    d->normal_types = 0;
    d->normal_radius = 30;
    d->normal_sign = -1;
    d->dim = 1;
    d->dim_near = 0.01;
}

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* The observer.* keys that mean something only with observer.id. */
static const char *const OBSERVER_KEYS[] = {
    "observer.reference_id", "observer.normal", "observer.normal_from.types", "observer.normal_from.radius",
    "observer.normal_from.sign", "observer.dim", "observer.dim_near",
};

static orr_status check_without_observer(const orr_keys *keys, orr_error *err)
{
    if (orr_key_given(keys, "observer.reference_id"))
        return orr_fail_key(keys, "observer.reference_id", err,
                            "observer.reference_id is set but observer.id is not: set both (the observer particle, "
                            "and the particle that fixes the frame's x axis)");
    for (size_t i = 0; i < COUNT(OBSERVER_KEYS); i++)
        if (orr_key_given(keys, OBSERVER_KEYS[i]))
            return orr_fail_key(keys, OBSERVER_KEYS[i], err,
                                "%s applies to an observer-centred sky, but observer.id is not set", OBSERVER_KEYS[i]);
    return ORR_OK;
}

static orr_status check_observer_normal(const orr_observer_settings *o, const orr_keys *keys, orr_error *err)
{
    static const char *const from_keys[] = {"observer.normal_from.types", "observer.normal_from.radius",
                                            "observer.normal_from.sign"};
    for (size_t i = 0; i < COUNT(from_keys); i++) {
        if (!orr_key_given(keys, from_keys[i]))
            continue;
        if (o->has_normal)
            return orr_fail_key(keys, from_keys[i], err,
                                "observer.normal and %s are both set; give the normal, or say how to compute it",
                                from_keys[i]);
        if (!orr_key_given(keys, "observer.normal_from.types"))
            return orr_fail_key(keys, from_keys[i], err,
                                "%s needs observer.normal_from.types: the particle types whose spin gives the "
                                "normal",
                                from_keys[i]);
    }
    if (o->has_normal && o->normal.x == 0 && o->normal.y == 0 && o->normal.z == 0)
        return orr_fail_key(keys, "observer.normal", err, "observer.normal: must not be [0, 0, 0]");
    return ORR_OK;
}

orr_status orr_observer_prepare(const orr_observer_settings *o, const orr_keys *keys, orr_error *err)
{
    if (!o->has_id)
        return check_without_observer(keys, err);
    if (!orr_key_given(keys, "observer.reference_id"))
        return orr_fail_key(keys, "observer.id", err,
                            "observer.id needs observer.reference_id: the particle that fixes the frame's x axis");
    if (o->id == o->reference_id)
        return orr_fail_key(keys, "observer.reference_id", err,
                            "observer.reference_id equals observer.id (%llu); the reference must be another "
                            "particle",
                            (unsigned long long)o->id);
    return check_observer_normal(o, keys, err);
}

void orr_observer_cards(const orr_observer_settings *o, orr_cards *h)
{
    if (!o->has_id)
        return;
    orr_cards_add_long(h, "OBSID", (long long)o->id, "observer particle id");
    orr_cards_add_long(h, "REFID", (long long)o->reference_id, "reference particle id (l = 0)");
    orr_cards_reserve(h, "NORMX", "disc normal n0 (b = 90) x");
    orr_cards_reserve(h, "NORMY", "disc normal n0 (b = 90) y");
    orr_cards_reserve(h, "NORMZ", "disc normal n0 (b = 90) z");
    orr_cards_add_bool(h, "DIMMED", o->dim, "weights divided by r^2 from the observer");
}

orr_status orr_sky_frame_build(orr_sky_frame *f, orr_vec3 observer, orr_vec3 reference, orr_vec3 n0,
                               orr_error *err)
{
    orr_vec3 z = orr_v3_normalize(n0);
    if (orr_v3_norm(z) == 0)
        return orr_fail(err, ORR_ERR_USAGE, "the disc normal n0 is the zero vector");
    orr_vec3 d = orr_v3_sub(reference, observer);
    double dist = orr_v3_norm(d);
    if (!(dist > 0))
        return orr_fail(err, ORR_ERR_DATA, "the observer and reference particles are at the same position (%g, %g, %g)",
                        observer.x, observer.y, observer.z);
    orr_vec3 in_plane = orr_v3_sub(d, orr_v3_scale(z, orr_v3_dot(d, z)));
    if (orr_v3_norm(in_plane) < 1e-9 * dist)
        return orr_fail(err, ORR_ERR_DATA,
                        "the reference particle lies straight along the disc normal from the observer, "
                        "so longitude 0 is undefined");
    f->origin = observer;
    f->z = z;
    f->x = orr_v3_normalize(in_plane);
    f->y = orr_v3_cross(f->z, f->x);
    return ORR_OK;
}

orr_sky_frame orr_sky_frame_world(orr_vec3 origin)
{
    return (orr_sky_frame){origin, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
}

orr_vec3 orr_sky_direction(const orr_sky_frame *f, double l_deg, double b_deg)
{
    double l = l_deg * ORR_PI / 180, b = b_deg * ORR_PI / 180;
    orr_vec3 d = orr_v3_scale(f->x, cos(b) * cos(l));
    d = orr_v3_add(d, orr_v3_scale(f->y, cos(b) * sin(l)));
    return orr_v3_add(d, orr_v3_scale(f->z, sin(b)));
}

void orr_sky_lb(const orr_sky_frame *f, orr_vec3 dir, double *l_deg, double *b_deg)
{
    double x = orr_v3_dot(dir, f->x), y = orr_v3_dot(dir, f->y), z = orr_v3_dot(dir, f->z);
    *l_deg = atan2(y, x) * 180 / ORR_PI;
    *b_deg = atan2(z, sqrt(x * x + y * y)) * 180 / ORR_PI;
}

orr_status orr_sky_camera_centre(orr_camera *cam, const orr_sky_frame *f, double roll_deg, orr_error *err)
{
    return orr_camera_look_along(cam, f->origin, f->x, f->z, roll_deg, err);
}

orr_status orr_sky_camera_dome(orr_camera *cam, const orr_sky_frame *f, const double zenith_lb[2],
                               const double front_lb[2], double tilt_deg, orr_error *err)
{
    orr_vec3 zen = orr_sky_direction(f, zenith_lb[0], zenith_lb[1]);
    orr_vec3 front = orr_sky_direction(f, front_lb[0], front_lb[1]);
    front = orr_v3_sub(front, orr_v3_scale(zen, orr_v3_dot(front, zen)));
    if (orr_v3_norm(front) < 1e-9)
        return orr_fail(err, ORR_ERR_USAGE, "camera.front (%g, %g) is parallel to camera.zenith (%g, %g)",
                        front_lb[0], front_lb[1], zenith_lb[0], zenith_lb[1]);
    front = orr_v3_normalize(front);
    /* A tilted dome leans toward its front: its zenith moves toward the
     * front by the tilt, and the front moves down by as much. */
    double t = tilt_deg * ORR_PI / 180;
    orr_vec3 zt = orr_v3_add(orr_v3_scale(zen, cos(t)), orr_v3_scale(front, sin(t)));
    orr_vec3 ft = orr_v3_sub(orr_v3_scale(front, cos(t)), orr_v3_scale(zen, sin(t)));
    /* The dome projection draws the camera's down (+y) at the bottom: the front. */
    return orr_camera_look_along(cam, f->origin, zt, orr_v3_scale(ft, -1), 0, err);
}
