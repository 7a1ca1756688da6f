/* The frame stage's camera.* settings: where the camera is and where it
 * looks, a path it follows over an animation, a dome master's orientation,
 * dimming with distance. The keys camera.projection, .width, .fov, .near,
 * .lon_flip, .healpix_*, .dome_fov and image.* are held by the projection
 * itself (frame/projection.h). */
#ifndef ORR_FRAME_CAMERA_SETTINGS_H
#define ORR_FRAME_CAMERA_SETTINGS_H

#include "core/keys.h"
#include "core/limits.h"
#include "core/vecmath.h"
#include "frame/camera.h"
#include "frame/path.h"
#include "frame/projection.h"

typedef struct orr_camera_settings {
    /* Exactly one of look_at, direction, quaternion orients the camera;
     * none means looking along -z with +y up (the xy plane face-on). */
    orr_vec3 position;   /* camera.position (default 0,0,0) */
    int has_look_at, has_direction, has_quaternion, has_up;
    orr_vec3 look_at;    /* camera.look_at */
    orr_vec3 direction;  /* camera.direction */
    orr_vec3 up;         /* camera.up (default 0,1,0) */
    double roll;         /* camera.roll, degrees (default 0) */
    orr_quat quaternion; /* camera.quaternion: [w, x, y, z] */

    /* camera.path.*: a camera that moves over an animation (docs/paths.md).
     * The path places and orients the camera in every frame, so
     * camera.position and the orientation keys are not allowed with it
     * (except with kind rotate, whose start they are), nor is observer.id.
     * The renderer asks orr_path_camera(&s->camera.path, frame_time, ...)
     * for each frame. */
    int has_path;                 /* camera.path.kind was given */
    orr_camera_path path;         /* camera.path.kind: keyframes | orbit | line | inspiral | rotate,
                                   * and the keys of each kind */
    char *path_file;              /* camera.path.file: keyframes from CSV, resolved; owned, NULL when
                                   * unset (core/owned.h) */
    int has_path_start;
    orr_vec3 path_start;          /* camera.path.start: an orbit's first point */

    /* A dome master's orientation (camera.projection: dome); its field of
     * view is the projection's dome_fov_deg. */
    char dome[ORR_NAME_MAX]; /* camera.dome: a profile name from domes/ (default none) */
    double dome_tilt;        /* camera.dome_tilt, degrees 0..90 (default from the profile, else 0):
                              * the dome's zenith is pitched toward its front by this angle */
    int has_zenith, has_front;
    double zenith_lb[2];     /* camera.zenith: [l, b] degrees in the observer frame: the
                              * direction at the dome's zenith before tilting (default [0, 90]) */
    double front_lb[2];      /* camera.front: [l, b] degrees: the direction drawn toward the
                              * bottom of the dome master (default [0, 0]) */

    int dim;                 /* camera.dim: weights fall off as 1/r^2 from the camera (default false) */
    double dim_near;         /* camera.dim_near: r below this counts as this (default 0.01) */
} orr_camera_settings;

/* Fills d, which holds no strings (zeroed or freed), with the defaults above. */
void orr_camera_settings_defaults(orr_camera_settings *d);
/* d's owned strings (core/owned.h), at most ORR_CAMERA_STRINGS, into fields; returns how many. */
#define ORR_CAMERA_STRINGS 1
int orr_camera_settings_strings(orr_camera_settings *d, char **fields[]);
/* Frees d's strings. */
void orr_camera_settings_free(orr_camera_settings *d);
/* dst (its strings freed first) becomes a copy of src with strings of its own. */
orr_status orr_camera_settings_copy(orr_camera_settings *dst, const orr_camera_settings *src, orr_error *err);

/* The camera.* keys checked against each other: at most one of look_at,
 * direction and quaternion, none of them zero or looking nowhere, up not
 * along the view; a dome's front not along its zenith; dim_near only with
 * dim. Normalises the quaternion, which users round. keys says which were
 * given, and where. The keys that span stages (a path's, an observer's) are
 * the scene's checks. */
orr_status orr_camera_settings_prepare(orr_camera_settings *c, const orr_keys *keys, orr_error *err);

/* A dome master's orientation cards (DOMETILT, DOMEPROF), for a projection
 * of that kind; none for the others. */
void orr_camera_dome_cards(const orr_camera_settings *c, orr_projection_kind kind, orr_cards *h);
/* DIMMED when camera.dim dims the weights with the distance from the camera. */
void orr_camera_dim_cards(const orr_camera_settings *c, orr_cards *h);

/* The point the camera keeps looking at, where there is one: camera.look_at,
 * an orbit's centre, an inspiral's target, a line's look_at. A stereo pair
 * converges there by default. Returns 0 when there is none. */
int orr_camera_settings_look_target(const orr_camera_settings *c, orr_vec3 *target);

/* The camera of camera.position and its orientation keys (quaternion,
 * look_at, direction with up or roll; none: looking along -z with +y up),
 * ignoring any path: a still's camera, and where a rotate path starts. */
orr_status orr_camera_settings_static(const orr_camera_settings *c, orr_camera *cam, orr_error *err);

#endif
