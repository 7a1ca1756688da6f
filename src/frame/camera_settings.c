#include "frame/camera_settings.h"

#include <string.h>

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
