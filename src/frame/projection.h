/* Projections map a point in the camera frame (x right, y down, z forward)
 * to continuous image coordinates plus the local scale in pixels per unit
 * length, or report it as not visible. Pixel (i, j) covers [i, i+1) x [j, j+1),
 * so its centre is at (i + 0.5, j + 0.5); row j = 0 is the top of the image.
 * The splatter knows only this interface. */
#ifndef ORR_FRAME_PROJECTION_H
#define ORR_FRAME_PROJECTION_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "core/vecmath.h"

typedef enum {
    ORR_PROJ_ORTHOGRAPHIC,
    ORR_PROJ_PERSPECTIVE,
} orr_projection_kind;

#define ORR_IMAGE_SIDE_MAX 65536

typedef struct orr_projection {
    orr_projection_kind kind;
    int width, height;  /* image size in pixels */
    double ortho_width; /* orthographic: simulation units across the image width */
    double fov_deg;     /* perspective: field of view along the wider image axis */
    double near;        /* perspective: points with z <= near are not drawn */

    /* Derived by orr_projection_setup. */
    double cx, cy;      /* image centre in pixel coordinates */
    double focal;       /* orthographic: pixels per unit; perspective: focal length in pixels */
} orr_projection;

/* Checks the parameters and computes the derived fields. */
orr_status orr_projection_setup(orr_projection *p, orr_error *err);

const char *orr_projection_name(orr_projection_kind kind);

/* Projects one camera-frame point. Returns 1 and sets (px, py, scale) when the
 * point is visible; returns 0 when it is not (behind the near plane). Points
 * that project outside the image are still "visible": the deposit decides. */
int orr_project_point(const orr_projection *p, orr_vec3 cam, double *px, double *py, double *scale);

/* The same for n camera-frame points in SoA arrays, the form the hot loop
 * uses; visible[i] is 1 or 0, and px, py, scale are set only when visible. */
void orr_project_batch(const orr_projection *p, size_t n, const float *x, const float *y,
                       const float *z, float *px, float *py, float *scale, uint8_t *visible);

#endif
