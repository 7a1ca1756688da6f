/* Moving particles into the camera frame: position less the camera's (in
 * double, which keeps precision for cameras far from the coordinate origin,
 * inside a big box or at the Sun), turned by the view's rotation. Inline,
 * for the renderer's gather loops (splat_gather.c, ngp_gather.c), which the
 * compiler vectorises; copy the transform into a local before such a loop,
 * so the compiler knows the loop's stores cannot change it. */
#ifndef ORR_PASS_CAMERA_TRANSFORM_H
#define ORR_PASS_CAMERA_TRANSFORM_H

#include <math.h>

#include "core/vecmath.h"

typedef struct orr_camera_transform {
    double ox, oy, oz; /* the camera's position, less a periodic copy's shift */
    float r[3][3];     /* world to camera */
    int dim;           /* weights fall off as 1/r^2 from the camera (observer.dim, camera.dim) */
    float near2;       /* ... but no faster than at this distance, squared */
    /* A periodic box's sphere around the camera (input.periodic.radius,
     * .fade): weights taper from 1 at distance inner to 0 at outer. */
    int fade;
    float inner, outer, inner2, outer2;
} orr_camera_transform;

/* The transform of a camera at position with world-to-camera rotation rot,
 * for particles moved by shift (a periodic copy's; 0 for the box itself);
 * no dimming, no fade. */
static inline orr_camera_transform orr_camera_transform_at(orr_vec3 position, const orr_mat3 *rot, orr_vec3 shift)
{
    const orr_vec3 origin = orr_v3_sub(position, shift); /* p + shift - camera */
    orr_camera_transform t = {.ox = origin.x, .oy = origin.y, .oz = origin.z};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            t.r[a][b] = (float)rot->m[a][b];
    return t;
}

/* A point in the camera frame, and its distance from the camera squared. */
typedef struct orr_camera_point {
    float x, y, z, r2;
} orr_camera_point;

static inline orr_camera_point orr_to_camera(const orr_camera_transform *t, float x, float y, float z)
{
    float dx = (float)((double)x - t->ox), dy = (float)((double)y - t->oy), dz = (float)((double)z - t->oz);
    orr_camera_point c = {t->r[0][0] * dx + t->r[0][1] * dy + t->r[0][2] * dz,
                          t->r[1][0] * dx + t->r[1][1] * dy + t->r[1][2] * dz,
                          t->r[2][0] * dx + t->r[2][1] * dy + t->r[2][2] * dz, dx * dx + dy * dy + dz * dz};
    return c;
}

/* The 1/r^2 dimming factor of a point at distance^2 r2. */
static inline float orr_camera_dimming(const orr_camera_transform *t, float r2)
{
    return 1.0f / (r2 > t->near2 ? r2 : t->near2);
}

/* The taper of a point at distance^2 r2: 1 up to inner, 0 from outer on,
 * between them the smoothstep s^2 (3 - 2 s) of s = (outer - r) / (outer -
 * inner), whose slope is 0 at both ends: a knot entering the sphere
 * brightens gradually, with no kink in the light curve. */
static inline float orr_camera_fade(const orr_camera_transform *t, float r2)
{
    if (r2 <= t->inner2)
        return 1.0f;
    if (r2 >= t->outer2)
        return 0.0f;
    float s = (t->outer - sqrtf(r2)) / (t->outer - t->inner);
    return s * s * (3.0f - 2.0f * s);
}

#endif
