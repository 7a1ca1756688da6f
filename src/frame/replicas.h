/* Periodic boxes drawn as copies (replicas) of the box around the camera,
 * and the test that lets the renderer skip a copy, or a block of particles
 * of a copy, that the view cannot see, before touching its particles
 * (docs/periodic.md). */
#ifndef ORR_FRAME_REPLICAS_H
#define ORR_FRAME_REPLICAS_H

#include "core/error.h"
#include "core/keys.h"
#include "core/names.h"
#include "core/vecmath.h"
#include "frame/camera.h"
#include "frame/projection.h"

/* 9 copies per axis at most (input.periodic.replicas). */
#define ORR_REPLICAS_PER_AXIS_MAX 9
#define ORR_REPLICAS_MAX (ORR_REPLICAS_PER_AXIS_MAX * ORR_REPLICAS_PER_AXIS_MAX * ORR_REPLICAS_PER_AXIS_MAX)

/* input.periodic.*: a periodic box drawn replicated (docs/periodic.md). The
 * keys sit under input: because they describe the data, but the copies are
 * the frame stage's. */
typedef struct orr_periodic_settings {
    double box;        /* input.periodic.box: the box side (0 = auto: the file's BoxSize) */
    int replicas;      /* input.periodic.replicas: copies per axis, odd (default 1 = off) */
    int around_camera; /* input.periodic.centre: camera (1, default) | origin (0) */
    double radius;     /* input.periodic.radius: centre camera draws the images within it
                        * (0 = auto: (replicas - 1) / 2 box sides) */
    double fade;       /* input.periodic.fade: the width of the taper inside the radius */
    int has_fade;      /* ... given (else a quarter of the radius) */
} orr_periodic_settings;

/* The words of input.periodic.centre. */
extern const orr_named orr_periodic_centre_names[];

/* Fills d with the defaults above. */
void orr_periodic_settings_defaults(orr_periodic_settings *d);

/* The input.periodic.* keys checked against each other: an odd count of
 * copies per axis (they sit symmetrically around the middle one), and the
 * sphere around the camera (.radius, .fade) only with copies around it,
 * within their reach when the box's side is given (else the render checks
 * it against the file's); keys says which were given, and where. */
orr_status orr_periodic_prepare(const orr_periodic_settings *p, const orr_keys *keys, orr_error *err);

/* The shifts of the copies: particle p is drawn at p + offset[k] for each k. */
typedef struct orr_replicas {
    int n;
    orr_vec3 offset[ORR_REPLICAS_MAX];
} orr_replicas;

/* Places per_axis^3 copies (per_axis odd) of a periodic box of side box,
 * taken as [0, box)^3: around the box itself (around_camera 0), or around
 * the copy holding the camera (around_camera 1), so that a camera moving
 * through the box is always at least (per_axis - 1) / 2 box sides from the
 * edge of what is drawn. The middle copy comes first. */
orr_status orr_replicas_place(orr_replicas *r, double box, int per_axis, int around_camera, orr_vec3 camera,
                              orr_error *err);

/* centre: camera draws each particle at its images within a sphere around
 * the camera, the sphere moving with it (docs/periodic.md): no copy appears
 * or vanishes at once as the camera crosses a face. Weights taper smoothly
 * from 1 at radius - fade to 0 at radius, so structure entering the sphere
 * fades in. radius 0: inactive (centre: origin). */
typedef struct orr_replica_sphere {
    double radius, fade;
    orr_vec3 camera;
} orr_replica_sphere;

/* The sphere's radius and fade width for a box of side box drawn with
 * per_axis copies a side: radius 0 takes the default, (per_axis - 1) / 2
 * box sides (as far as the copies reach from anywhere in the middle one);
 * fade < 0 takes the default, a quarter of the radius. An error naming
 * input.periodic.radius or .fade when the radius is beyond that reach, or
 * the fade wider than the radius. */
orr_status orr_replica_sphere_resolve(orr_replica_sphere *sp, double box, int per_axis, double radius, double fade,
                                      orr_error *err);

/* Where a box [lo, hi] shifted by offset lies against the sphere: wholly
 * inside radius - fade (weights untouched), wholly beyond the radius
 * (nothing drawn), or across (each particle weighed). Conservative by a
 * relative 1e-5, for the renderer measures distances in float. */
typedef enum { ORR_SPHERE_INSIDE, ORR_SPHERE_ACROSS, ORR_SPHERE_BEYOND } orr_sphere_place;
orr_sphere_place orr_replica_sphere_box(const orr_replica_sphere *sp, orr_vec3 lo, orr_vec3 hi, orr_vec3 offset);

/* Keeps of r's copies those whose cell [0, box)^3 + offset reaches into
 * the sphere (the middle copy stays first when kept). */
void orr_replicas_keep_sphere(orr_replicas *r, double box, const orr_replica_sphere *sp);

/* A view's visible region as half-spaces in world coordinates: a point p is
 * inside when n . p + d >= 0 for every plane. Perspective: the four sides
 * of the frustum and the near plane; orthographic: the four sides of the
 * slab (every depth is drawn). Sky maps see every direction: inactive. */
typedef struct orr_view_cull {
    int active;
    int nplanes;
    orr_vec3 n[5];
    double d[5];
    double reach[5]; /* |n| for the sides (a kernel of radius r reaches r |n|); 0 for the near plane */
    orr_vec3 camera;
} orr_view_cull;

/* The view of a camera through a projection (set up), widened by margin
 * pixels on every side of the image: deposits spread a particle over a
 * pixel or two beyond its centre (cloud-in-cell, a kernel's smallest disc). */
void orr_view_cull_setup(orr_view_cull *vc, const orr_projection *p, const orr_camera *cam, double margin);

/* Whether nothing in the box [lo, hi] shifted by offset, with kernels of
 * radius up to radius around its points, can land in the image: 1 when the
 * box lies wholly outside one of the planes (conservative: a box outside
 * the view but across no single plane is kept). Never 1 when inactive. */
int orr_view_cull_box(const orr_view_cull *vc, orr_vec3 lo, orr_vec3 hi, orr_vec3 offset, double radius);

#endif
