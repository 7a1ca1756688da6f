/* A picture of a camera path for checking it before a long render
 * (`orrery path -o`): the scene's particles seen from above (an
 * orthographic view down the path's main axis), with the path drawn over
 * them as a bright polyline and ticks showing where the camera looks. */
#ifndef ORR_RENDER_PATH_OVERVIEW_H
#define ORR_RENDER_PATH_OVERVIEW_H

#include "frame/camera.h"
#include "scene/scene.h"

typedef struct orr_path_overview {
    int width, height;      /* the picture, pixels */
    int fit_path;           /* 1: frame the path alone; 0: the path and every particle */
    /* Filled in: the view chosen. */
    orr_vec3 normal;        /* the axis looked down (from its + side) */
    orr_camera view;        /* the orthographic camera */
    double view_width;      /* simulation units across the picture */
    unsigned long long n_particles; /* particles drawn */
} orr_path_overview;

/* The axis an overview looks down: the axis of an orbit, inspiral or
 * rotate path; for a line or keyframes, the normal of the plane the
 * positions wind around (Newell's method), or when they lie on a line, the
 * world axis most across it (z first). */
orr_vec3 orr_path_main_axis(const orr_camera_path *path, const orr_camera *cams, long n);

/* Draws the overview of the cameras cams[0..n) (one per frame) over the
 * scene's particles and writes it as a PNG to png_path (atomically). */
orr_status orr_path_overview_write(const orr_scene *s, const orr_camera *cams, long n, orr_path_overview *ov,
                                   const char *png_path, orr_error *err);

#endif
