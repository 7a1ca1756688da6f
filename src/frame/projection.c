#include "frame/projection.h"

#include <math.h>

const char *orr_projection_name(orr_projection_kind kind)
{
    switch (kind) {
    case ORR_PROJ_ORTHOGRAPHIC: return "orthographic";
    case ORR_PROJ_PERSPECTIVE: return "perspective";
    }
    return "unknown";
}

orr_status orr_projection_setup(orr_projection *p, orr_error *err)
{
    if (p->width <= 0 || p->height <= 0 || p->width > ORR_IMAGE_SIDE_MAX || p->height > ORR_IMAGE_SIDE_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "image size %d x %d is out of range (1 to %d pixels a side)",
                        p->width, p->height, ORR_IMAGE_SIDE_MAX);
    p->cx = 0.5 * p->width;
    p->cy = 0.5 * p->height;
    int wider = p->width > p->height ? p->width : p->height;
    switch (p->kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        if (!(p->ortho_width > 0) || !isfinite(p->ortho_width))
            return orr_fail(err, ORR_ERR_USAGE, "orthographic width %g must be a positive number",
                            p->ortho_width);
        p->focal = p->width / p->ortho_width;
        return ORR_OK;
    case ORR_PROJ_PERSPECTIVE:
        if (!(p->fov_deg > 0 && p->fov_deg < 180))
            return orr_fail(err, ORR_ERR_USAGE,
                            "perspective field of view %g degrees must lie between 0 and 180", p->fov_deg);
        if (!(p->near >= 0) || !isfinite(p->near))
            return orr_fail(err, ORR_ERR_USAGE, "perspective near distance %g must be zero or positive",
                            p->near);
        p->focal = 0.5 * wider / tan(0.5 * p->fov_deg * ORR_PI / 180.0);
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_INTERNAL, "unknown projection kind %d", (int)p->kind);
}

int orr_project_point(const orr_projection *p, orr_vec3 c, double *px, double *py, double *scale)
{
    switch (p->kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        *px = p->cx + p->focal * c.x;
        *py = p->cy + p->focal * c.y;
        *scale = p->focal;
        return 1;
    case ORR_PROJ_PERSPECTIVE:
        if (!(c.z > p->near) || c.z <= 0)
            return 0;
        *scale = p->focal / c.z;
        *px = p->cx + *scale * c.x;
        *py = p->cy + *scale * c.y;
        return 1;
    }
    return 0;
}

/* Each kind has its own loop so the compiler can vectorise it. */
static void project_orthographic(const orr_projection *p, size_t n, const float *x, const float *y,
                                 float *px, float *py, float *scale, uint8_t *visible)
{
    const float f = (float)p->focal, cx = (float)p->cx, cy = (float)p->cy;
    for (size_t i = 0; i < n; i++) {
        px[i] = cx + f * x[i];
        py[i] = cy + f * y[i];
        scale[i] = f;
        visible[i] = 1;
    }
}

static void project_perspective(const orr_projection *p, size_t n, const float *x, const float *y,
                                const float *z, float *px, float *py, float *scale, uint8_t *visible)
{
    const float f = (float)p->focal, cx = (float)p->cx, cy = (float)p->cy;
    const float near = (float)p->near;
    for (size_t i = 0; i < n; i++) {
        int vis = z[i] > near && z[i] > 0.0f;
        /* Dividing by a safe denominator keeps the loop branch-free; the
         * results of invisible points are never read. */
        float s = f / (vis ? z[i] : 1.0f);
        px[i] = cx + s * x[i];
        py[i] = cy + s * y[i];
        scale[i] = s;
        visible[i] = (uint8_t)vis;
    }
}

void orr_project_batch(const orr_projection *p, size_t n, const float *x, const float *y,
                       const float *z, float *px, float *py, float *scale, uint8_t *visible)
{
    switch (p->kind) {
    case ORR_PROJ_ORTHOGRAPHIC:
        project_orthographic(p, n, x, y, px, py, scale, visible);
        return;
    case ORR_PROJ_PERSPECTIVE:
        project_perspective(p, n, x, y, z, px, py, scale, visible);
        return;
    }
}
