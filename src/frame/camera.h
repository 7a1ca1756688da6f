/* A camera: a position and an orientation. The camera frame is right-handed
 * with x to the right of the image, y down the image and z along the view
 * direction, so image rows grow with y like the rows of a PNG. The
 * orientation quaternion takes camera-frame vectors to world vectors. */
#ifndef ORR_FRAME_CAMERA_H
#define ORR_FRAME_CAMERA_H

#include "core/error.h"
#include "core/vecmath.h"

typedef struct orr_camera {
    orr_vec3 position;
    orr_quat orientation; /* world = R(orientation) * camera */
} orr_camera;

/* Looks along direction dir with the image's up as close to `up` as possible,
 * then rolls by roll_deg (positive turns the image clockwise as seen).
 * Fails when dir is zero or parallel to up. */
orr_status orr_camera_look_along(orr_camera *cam, orr_vec3 position, orr_vec3 dir, orr_vec3 up,
                                 double roll_deg, orr_error *err);

/* Looks from position toward target (see orr_camera_look_along). */
orr_status orr_camera_look_at(orr_camera *cam, orr_vec3 position, orr_vec3 target, orr_vec3 up,
                              double roll_deg, orr_error *err);

/* Looks along dir without an up vector: the rotation by acos(n_z) about
 * (n_y, -n_x, 0) that takes the world's +z to n (the design notes' camera
 * matrix), then a roll about the view direction. */
orr_status orr_camera_look_along_roll(orr_camera *cam, orr_vec3 position, orr_vec3 dir,
                                      double roll_deg, orr_error *err);

/* The matrix taking world vectors (relative to the camera position) into the
 * camera frame: its rows are the camera's right, down and forward axes. */
orr_mat3 orr_camera_world_to_camera(const orr_camera *cam);

#endif
