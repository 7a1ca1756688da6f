#include "frame/replicas.h"

#include <math.h>
#include <string.h>

/* The sphere of centre: camera (input.periodic.radius, .fade): only there,
 * only with copies, and when the box side is given, within the copies'
 * reach (else the render checks it against the file's BoxSize). */
static orr_status check_sphere(const orr_periodic_settings *p, const orr_keys *keys, orr_error *err)
{
    static const char *const sphere_keys[] = {"input.periodic.radius", "input.periodic.fade"};
    for (int k = 0; k < 2; k++) {
        if (!orr_key_given(keys, sphere_keys[k]))
            continue;
        if (!p->around_camera)
            return orr_fail_key(keys, sphere_keys[k], err,
                                "%s applies to input.periodic.centre: camera (the images within a sphere "
                                "around the camera), but the centre is origin",
                                sphere_keys[k]);
        if (p->replicas < 3)
            return orr_fail_key(keys, sphere_keys[k], err,
                                "%s needs copies of the box around the camera: set input.periodic.replicas to "
                                "3 or more (it is %d)",
                                sphere_keys[k], p->replicas);
    }
    if (!p->around_camera || p->replicas < 3)
        return ORR_OK;
    /* The box's side stands in for an unknown one: a radius or fade that
     * fails now fails whatever the side. */
    orr_replica_sphere sp;
    orr_error why;
    double box = p->box > 0 ? p->box : HUGE_VAL;
    if (orr_replica_sphere_resolve(&sp, box, p->replicas, p->radius, p->has_fade ? p->fade : -1, &why) == ORR_OK)
        return ORR_OK;
    const char *key = strstr(why.msg, "input.periodic.fade") == why.msg ? sphere_keys[1] : sphere_keys[0];
    return orr_fail_key(keys, key, err, "%s", why.msg);
}

orr_status orr_periodic_prepare(const orr_periodic_settings *p, const orr_keys *keys, orr_error *err)
{
    if (p->replicas % 2 == 0)
        return orr_fail_key(keys, "input.periodic.replicas", err,
                            "input.periodic.replicas is %d; it must be odd (1, 3, 5, ...): copies of the box "
                            "sit symmetrically around the middle one",
                            p->replicas);
    return check_sphere(p, keys, err);
}

const orr_named orr_periodic_centre_names[] = {{"camera", 1}, {"origin", 0}, {NULL, 0}};

void orr_periodic_settings_defaults(orr_periodic_settings *d)
{
    memset(d, 0, sizeof *d);
    d->box = 0;
    d->replicas = 1;
    d->around_camera = 1;
}

orr_status orr_replicas_place(orr_replicas *r, double box, int per_axis, int around_camera, orr_vec3 camera,
                              orr_error *err)
{
    r->n = 0;
    if (!(box > 0) || !isfinite(box))
        return orr_fail(err, ORR_ERR_USAGE, "input.periodic.box is %g; the box side must be a positive number", box);
    if (per_axis < 1 || per_axis > ORR_REPLICAS_PER_AXIS_MAX || per_axis % 2 == 0)
        return orr_fail(err, ORR_ERR_USAGE, "input.periodic.replicas is %d; it must be odd, 1 to %d", per_axis,
                        ORR_REPLICAS_PER_AXIS_MAX);
    double cell[3] = {0, 0, 0};
    if (around_camera) {
        const double c[3] = {camera.x, camera.y, camera.z};
        for (int a = 0; a < 3; a++) {
            if (!isfinite(c[a]) || fabs(c[a] / box) > 1e15)
                return orr_fail(err, ORR_ERR_USAGE,
                                "input.periodic.centre camera: the camera position (%g, %g, %g) is not a finite "
                                "number of boxes of side %g from the origin",
                                camera.x, camera.y, camera.z, box);
            cell[a] = floor(c[a] / box);
        }
    }
    const int half = per_axis / 2;
    /* The middle copy first, then the others in order. */
    r->offset[r->n++] = orr_v3(cell[0] * box, cell[1] * box, cell[2] * box);
    for (int i = -half; i <= half; i++)
        for (int j = -half; j <= half; j++)
            for (int k = -half; k <= half; k++)
                if (i || j || k)
                    r->offset[r->n++] = orr_v3((cell[0] + i) * box, (cell[1] + j) * box, (cell[2] + k) * box);
    return ORR_OK;
}

orr_status orr_replica_sphere_resolve(orr_replica_sphere *sp, double box, int per_axis, double radius, double fade,
                                      orr_error *err)
{
    /* The copies reach half per-axis-less-one box sides beyond the middle
     * copy's faces: that far from a camera anywhere inside it. */
    const double reach = 0.5 * (per_axis - 1) * box;
    sp->radius = sp->fade = 0;
    sp->camera = orr_v3(0, 0, 0);
    if (radius != 0 && !(radius > 0 && isfinite(radius)))
        return orr_fail(err, ORR_ERR_USAGE, "input.periodic.radius is %g; it must be a positive number", radius);
    if (radius > reach)
        return orr_fail(err, ORR_ERR_USAGE,
                        "input.periodic.radius %g is larger than the replicated volume allows: %d copies a side of "
                        "a box of %g reach %g from the camera in every direction; lower the radius or raise "
                        "input.periodic.replicas",
                        radius, per_axis, box, reach);
    if (radius == 0)
        radius = reach;
    if (isnan(fade) || isinf(fade))
        return orr_fail(err, ORR_ERR_USAGE, "input.periodic.fade is %g; it must be a number from 0 to the radius",
                        fade);
    if (fade < 0)
        fade = 0.25 * radius;
    if (fade > radius)
        return orr_fail(err, ORR_ERR_USAGE,
                        "input.periodic.fade %g is wider than the radius %g (input.periodic.radius): the taper runs "
                        "from radius - fade to the radius",
                        fade, radius);
    sp->radius = radius;
    sp->fade = fade;
    return ORR_OK;
}

orr_sphere_place orr_replica_sphere_box(const orr_replica_sphere *sp, orr_vec3 lo, orr_vec3 hi, orr_vec3 offset)
{
    const double c[3] = {sp->camera.x, sp->camera.y, sp->camera.z};
    const double a[3] = {lo.x + offset.x, lo.y + offset.y, lo.z + offset.z};
    const double b[3] = {hi.x + offset.x, hi.y + offset.y, hi.z + offset.z};
    double near2 = 0, far2 = 0, size2 = 0;
    for (int k = 0; k < 3; k++) {
        double below = a[k] - c[k], above = c[k] - b[k];
        double gap = below > 0 ? below : above > 0 ? above : 0;
        double far = fmax(fabs(c[k] - a[k]), fabs(c[k] - b[k]));
        near2 += gap * gap;
        far2 += far * far;
        size2 += (b[k] - a[k]) * (b[k] - a[k]);
    }
    const double slack = 1e-5 * (sqrt(far2) + sqrt(size2));
    if (sqrt(near2) > sp->radius + slack)
        return ORR_SPHERE_BEYOND;
    if (sqrt(far2) < sp->radius - sp->fade - slack)
        return ORR_SPHERE_INSIDE;
    return ORR_SPHERE_ACROSS;
}

void orr_replicas_keep_sphere(orr_replicas *r, double box, const orr_replica_sphere *sp)
{
    int kept = 0;
    for (int k = 0; k < r->n; k++)
        if (orr_replica_sphere_box(sp, orr_v3(0, 0, 0), orr_v3(box, box, box), r->offset[k]) != ORR_SPHERE_BEYOND)
            r->offset[kept++] = r->offset[k];
    r->n = kept;
}

/* A camera-frame half-space n . q + d >= 0 (q = R (p - c)) as a world one:
 * (R^T n) . p + d - (R^T n) . c >= 0. */
static void add_plane(orr_view_cull *vc, const orr_mat3 *world_to_camera, orr_vec3 camera, orr_vec3 n, double d,
                      int is_side)
{
    orr_vec3 nw = orr_mat3_apply(orr_mat3_transpose(*world_to_camera), n);
    int k = vc->nplanes++;
    vc->n[k] = nw;
    vc->d[k] = d - orr_v3_dot(nw, camera);
    vc->reach[k] = is_side ? orr_v3_norm(n) : 0.0;
}

void orr_view_cull_setup(orr_view_cull *vc, const orr_projection *p, const orr_camera *cam, double margin)
{
    vc->active = 0;
    vc->nplanes = 0;
    vc->camera = cam->position;
    if (p->settings.kind != ORR_PROJ_PERSPECTIVE && p->settings.kind != ORR_PROJ_ORTHOGRAPHIC)
        return;
    const orr_mat3 R = orr_camera_world_to_camera(cam);
    const orr_vec3 c = cam->position;
    const double f = p->focal, m = margin;
    const double left = p->cx + m, right = p->width + m - p->cx, top = p->cy + m, bottom = p->height + m - p->cy;
    if (p->settings.kind == ORR_PROJ_PERSPECTIVE) {
        /* px = cx + f x / z >= -m  <=>  f x + (cx + m) z >= 0 for z > 0; likewise the others. */
        add_plane(vc, &R, c, orr_v3(f, 0, left), 0, 1);
        add_plane(vc, &R, c, orr_v3(-f, 0, right), 0, 1);
        add_plane(vc, &R, c, orr_v3(0, f, top), 0, 1);
        add_plane(vc, &R, c, orr_v3(0, -f, bottom), 0, 1);
        /* Points with z <= near (and z <= 0) are not drawn at all, kernel or not. */
        add_plane(vc, &R, c, orr_v3(0, 0, 1), -(p->settings.near > 0 ? p->settings.near : 0.0), 0);
    } else {
        /* px = cx + f x >= -m  <=>  f x + (cx + m) >= 0; every depth is drawn. */
        add_plane(vc, &R, c, orr_v3(f, 0, 0), left, 1);
        add_plane(vc, &R, c, orr_v3(-f, 0, 0), right, 1);
        add_plane(vc, &R, c, orr_v3(0, f, 0), top, 1);
        add_plane(vc, &R, c, orr_v3(0, -f, 0), bottom, 1);
    }
    vc->active = 1;
}

int orr_view_cull_box(const orr_view_cull *vc, orr_vec3 lo, orr_vec3 hi, orr_vec3 offset, double radius)
{
    if (!vc->active)
        return 0;
    const orr_vec3 centre = orr_v3_add(orr_v3_scale(orr_v3_add(lo, hi), 0.5), offset);
    const orr_vec3 half = orr_v3_scale(orr_v3_sub(hi, lo), 0.5);
    /* The renderer moves particles into the camera frame in float: a point
     * on the near plane may land on either side of it, so the near plane
     * culls only boxes clearly behind it. (The sides have the pixel margin.) */
    const double slack = 1e-5 * (orr_v3_norm(orr_v3_sub(centre, vc->camera)) + orr_v3_norm(half));
    for (int k = 0; k < vc->nplanes; k++) {
        const orr_vec3 n = vc->n[k];
        /* The largest n . p + d over the box is at the corner n points to. */
        double most = orr_v3_dot(n, centre) + fabs(n.x) * half.x + fabs(n.y) * half.y + fabs(n.z) * half.z + vc->d[k];
        if (vc->reach[k] > 0 ? most + radius * vc->reach[k] < 0 : most < -slack * orr_v3_norm(n))
            return 1;
    }
    return 0;
}
