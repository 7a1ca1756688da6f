#include "pass/motion_blur.h"

#include <math.h>

void orr_motion_blur_plan(orr_motion_blur *b, double half_time, const orr_camera *open, const orr_camera *close,
                          const orr_projection *proj)
{
    b->active = 1;
    b->half_time = half_time;
    b->open = *open;
    b->close = *close;
    b->open_rot = orr_camera_world_to_camera(open);
    b->close_rot = orr_camera_world_to_camera(close);
    b->kind = proj->settings.kind;
    b->k = orr_proj_consts_of(proj);
    b->px_per_radian = (float)proj->focal;
}

void orr_motion_blur_transforms(const orr_motion_blur *b, orr_vec3 shift, orr_camera_transform *open,
                                orr_camera_transform *close)
{
    *open = orr_camera_transform_at(b->open.position, &b->open_rot, shift);
    *close = orr_camera_transform_at(b->close.position, &b->close_rot, shift);
}

void orr_motion_blur_streak(const orr_motion_blur *b, const orr_camera_transform *open,
                            const orr_camera_transform *close, const float p[3], const float v[3], float q0[3],
                            float s[3])
{
    const float ht = (float)b->half_time;
    float d[3] = {0, 0, 0};
    if (ht != 0.0f)
        for (int a = 0; a < 3; a++)
            d[a] = v[a] * ht;
    orr_camera_point a = orr_to_camera(open, p[0] - d[0], p[1] - d[1], p[2] - d[2]);
    orr_camera_point c = orr_to_camera(close, p[0] + d[0], p[1] + d[1], p[2] + d[2]);
    q0[0] = a.x, q0[1] = a.y, q0[2] = a.z;
    s[0] = c.x - a.x, s[1] = c.y - a.y, s[2] = c.z - a.z;
}

/* The angle between the directions to q0 and q1, radians. */
static float angle_between(const float q0[3], const float q1[3])
{
    float cx = q0[1] * q1[2] - q0[2] * q1[1], cy = q0[2] * q1[0] - q0[0] * q1[2],
          cz = q0[0] * q1[1] - q0[1] * q1[0];
    float dot = q0[0] * q1[0] + q0[1] * q1[1] + q0[2] * q1[2];
    return atan2f(sqrtf(cx * cx + cy * cy + cz * cz), dot);
}

/* The streak's length on the image, pixels. Orthographic: exact. The
 * others: the distance between its projected ends, but where an end is not
 * drawn (behind a perspective camera, past a dome's rim) the angle it
 * sweeps at the centre's scale; and a sky map's distance is capped at four
 * times that, since a streak across the seam (or a pole) has its ends on
 * opposite sides of the map while its samples stay close on the sky. */
static float streak_pixels(const orr_motion_blur *b, const float q0[3], const float s[3])
{
    if (orr_projection_traits_of(b->kind).parallel)
        return b->k.f * sqrtf(s[0] * s[0] + s[1] * s[1]);
    const float q1[3] = {q0[0] + s[0], q0[1] + s[1], q0[2] + s[2]};
    const float swept = angle_between(q0, q1) * b->px_per_radian;
    orr_projected a = orr_project_point_f(b->kind, &b->k, q0[0], q0[1], q0[2]);
    orr_projected c = orr_project_point_f(b->kind, &b->k, q1[0], q1[1], q1[2]);
    if (!a.visible || !c.visible)
        return swept;
    const float on_image = hypotf(c.px - a.px, c.py - a.py);
    if (orr_projection_traits_of(b->kind).rectilinear)
        return on_image;
    return on_image < 4.0f * swept + 2.0f ? on_image : 4.0f * swept + 2.0f;
}

int orr_motion_blur_samples(const orr_motion_blur *b, const float q0[3], const float s[3])
{
    const float len = streak_pixels(b, q0, s) / ORR_BLUR_STEP_PX;
    if (!(len > 1.0f))
        return 1;
    if (len >= (float)ORR_BLUR_MAX_SAMPLES)
        return ORR_BLUR_MAX_SAMPLES;
    return (int)ceilf(len);
}
