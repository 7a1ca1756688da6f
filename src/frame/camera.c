#include "frame/camera.h"

static orr_quat roll_about_view(orr_quat orientation, double roll_deg)
{
    /* A roll is a rotation about the camera's own z axis, applied in the
     * camera frame, so it composes on the right. Positive roll_deg turns the
     * scene clockwise on the image, i.e. the camera turns about -z. */
    orr_quat roll = orr_quat_axis_angle(orr_v3(0, 0, 1), -roll_deg * ORR_PI / 180.0);
    return orr_quat_normalize(orr_quat_mul(orientation, roll));
}

orr_status orr_camera_look_along(orr_camera *cam, orr_vec3 position, orr_vec3 dir, orr_vec3 up,
                                 double roll_deg, orr_error *err)
{
    orr_vec3 forward = orr_v3_normalize(dir);
    if (orr_v3_norm(forward) == 0)
        return orr_fail(err, ORR_ERR_USAGE, "camera view direction is zero (position equals the look-at point?)");
    orr_vec3 right = orr_v3_normalize(orr_v3_cross(forward, up));
    if (orr_v3_norm(right) < 1e-12 || orr_v3_norm(orr_v3_cross(forward, orr_v3_normalize(up))) < 1e-9)
        return orr_fail(err, ORR_ERR_USAGE,
                        "camera up vector (%g, %g, %g) is zero or parallel to the view direction (%g, %g, %g)",
                        up.x, up.y, up.z, forward.x, forward.y, forward.z);
    orr_vec3 down = orr_v3_cross(forward, right);
    /* Columns of the camera-to-world matrix are the camera axes in world. */
    orr_mat3 cam_to_world = orr_mat3_transpose(orr_mat3_from_rows(right, down, forward));
    cam->position = position;
    cam->orientation = roll_about_view(orr_quat_from_mat3(cam_to_world), roll_deg);
    return ORR_OK;
}

orr_status orr_camera_look_at(orr_camera *cam, orr_vec3 position, orr_vec3 target, orr_vec3 up,
                              double roll_deg, orr_error *err)
{
    return orr_camera_look_along(cam, position, orr_v3_sub(target, position), up, roll_deg, err);
}

orr_status orr_camera_look_along_roll(orr_camera *cam, orr_vec3 position, orr_vec3 dir,
                                      double roll_deg, orr_error *err)
{
    orr_vec3 n = orr_v3_normalize(dir);
    if (orr_v3_norm(n) == 0)
        return orr_fail(err, ORR_ERR_USAGE, "camera view direction is zero");
    /* The rotation by acos(n_z) about (n_y, -n_x, 0) takes n to +z; its
     * inverse, the camera-to-world rotation, takes +z to n. When n is +-z the
     * axis vanishes and any axis in the xy plane does for the half turn. */
    orr_vec3 axis = orr_v3(n.y, -n.x, 0);
    if (orr_v3_norm(axis) < 1e-15)
        axis = orr_v3(1, 0, 0);
    double angle = acos(fmax(-1.0, fmin(1.0, n.z)));
    orr_quat world_to_cam = orr_quat_axis_angle(axis, angle);
    cam->position = position;
    cam->orientation = roll_about_view(orr_quat_conj(world_to_cam), roll_deg);
    return ORR_OK;
}

orr_mat3 orr_camera_world_to_camera(const orr_camera *cam)
{
    return orr_mat3_transpose(orr_quat_to_mat3(cam->orientation));
}
