/* A picture of a camera path for checking it before a long render
 * (`orrery path -o`): the scene's particles seen from above (an
 * orthographic view down the path's main axis), with the path drawn over
 * them as a bright polyline and ticks showing where the camera looks. */
#ifndef ORR_RENDER_PATH_OVERVIEW_H
#define ORR_RENDER_PATH_OVERVIEW_H

#include "frame/camera.h"
#include "frame/path.h"
#include "post/stretch.h"
#include "render/source_request.h"

/* What `orrery path` and its overview read of a scene, compiled by the
 * plan (orr_plan_path_scene, render/plan.h); it points into the scene. */
typedef struct orr_path_scene {
    const char *scene_path;             /* for messages and the picture's description */
    long long frames;                   /* animation.frames */
    int has_camera_path;                /* camera.path.kind was given */
    const orr_camera_path *camera_path; /* camera.path.* */
    orr_source_request source;          /* the particles drawn under it: input.types, weighed by input.weight */
    const orr_stretch *stretch;         /* output.stretch: how they are graded */
} orr_path_scene;

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
orr_status orr_path_overview_write(const orr_path_scene *ps, const orr_camera *cams, long n, orr_path_overview *ov,
                                   const char *png_path, orr_error *err);

#endif
