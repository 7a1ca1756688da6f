/* A rendered view's image metadata (encode/view_meta.h). */
#include "encode/view_meta.h"

#include <stdio.h>

/* The projection's parameters a file should carry: what orrery alone
 * defines (sky maps, orthographic), and for a perspective view OpenEXR's
 * screen window. */
static void projection_meta(const orr_projection *p, orr_image_meta *m, orr_view_meta_text *t)
{
    const char *key = NULL;
    double value = 0;
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC: key = "orthoWidth", value = p->settings.ortho_width; break;
    case ORR_PROJ_PERSPECTIVE:
        key = "fieldOfViewDeg", value = p->settings.fov_deg;
        m->has_screen_window = 1;
        m->screen_window_width = p->width / p->focal;
        m->screen_window_center[0] = -p->settings.shift_x / p->focal;
        m->screen_window_center[1] = 0;
        break;
    case ORR_PROJ_DOME: key = "domeFieldOfViewDeg", value = p->settings.dome_fov_deg; break;
    case ORR_PROJ_HEALPIX: key = "healpixNside", value = p->settings.healpix_nside; break;
    default: break;
    }
    if (key) {
        snprintf(t->number, sizeof t->number, "%.17g", value);
        m->extra_key[m->nextra] = key;
        m->extra_value[m->nextra++] = t->number;
    }
    if (orr_projection_is_sky(p)) {
        m->extra_key[m->nextra] = "longitudeGrows";
        m->extra_value[m->nextra++] = p->lon_sign > 0 ? "right" : "left"; /* dome, HEALPix: always left */
    }
}

orr_image_meta orr_view_image_meta(const char *name, const orr_projection *p, double time, const orr_camera *cam,
                                   const char *desc, orr_view_meta_text *t)
{
    orr_image_meta m = {0};
    m.scene = name;
    m.projection = orr_projection_name(p->settings.kind);
    m.has_time = 1;
    m.time = time;
    m.has_camera = 1;
    m.cam_pos[0] = cam->position.x;
    m.cam_pos[1] = cam->position.y;
    m.cam_pos[2] = cam->position.z;
    m.cam_quat[0] = cam->orientation.w;
    m.cam_quat[1] = cam->orientation.x;
    m.cam_quat[2] = cam->orientation.y;
    m.cam_quat[3] = cam->orientation.z;
    m.extra_key[0] = "description";
    m.extra_value[0] = desc;
    m.nextra = 1;
    projection_meta(p, &m, t);
    return m;
}
