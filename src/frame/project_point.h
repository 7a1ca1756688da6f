/* The projections of one camera-frame point in float, as inline functions:
 * orr_project_batch's loops are built from them, and so is the renderer's
 * fused gather for nearest-pixel deposits (pass/ngp_gather.c), which
 * projects each particle in the same loop that reads it. One definition of
 * each formula serves both, so the two give the same bits. Called with a
 * constant kind, orr_project_point_f reduces to that kind's formula and
 * the loop around it vectorises (no branches, no libm calls: the dome's and
 * equirectangular's arctangent is core/fastmath.h's). */
#ifndef ORR_FRAME_PROJECT_POINT_H
#define ORR_FRAME_PROJECT_POINT_H

#include <math.h>

#include "core/fastmath.h"
#include "frame/projection.h"

/* A projection's constants in float, set up once per batch. */
typedef struct orr_proj_consts {
    float f, cx, cy;   /* pixels per unit (or per radian, or focal length); the image centre */
    float near;        /* perspective */
    float hw, hh, sgn; /* Hammer-Aitoff: semi-axes, longitude sign */
    float ax, ay;      /* equirectangular: pixels per radian of longitude (signed) and latitude */
    float tmax;        /* dome: the largest angle from the zenith */
    const orr_projection *proj; /* HEALPix: its pixel search takes the projection */
} orr_proj_consts;

static inline orr_proj_consts orr_proj_consts_of(const orr_projection *p)
{
    orr_proj_consts k;
    k.f = (float)p->focal;
    k.cx = (float)p->cx;
    k.cy = (float)p->cy;
    k.near = (float)p->settings.near;
    k.hw = (float)p->half_w;
    k.hh = (float)p->half_h;
    k.sgn = (float)p->lon_sign;
    k.ax = (float)(p->lon_sign * p->width / (2.0 * ORR_PI));
    k.ay = (float)(p->height / ORR_PI);
    k.tmax = (float)p->theta_max;
    k.proj = p;
    return k;
}

/* A projected point: image position, pixels per unit length there, and
 * whether it is drawn at all (px, py, scale are meaningless when not). */
typedef struct orr_projected {
    float px, py, scale;
    int visible;
} orr_projected;

static inline orr_projected orr_project_orthographic_f(const orr_proj_consts *k, float x, float y)
{
    orr_projected q = {k->cx + k->f * x, k->cy + k->f * y, k->f, 1};
    return q;
}

static inline orr_projected orr_project_perspective_f(const orr_proj_consts *k, float x, float y, float z)
{
    int vis = z > k->near && z > 0.0f;
    /* Dividing by a safe denominator keeps the loop branch-free; the
     * results of invisible points are never read. */
    float s = k->f / (vis ? z : 1.0f);
    orr_projected q = {k->cx + s * x, k->cy + s * y, s, vis};
    return q;
}

/* Hammer-Aitoff without trigonometry (projection.c's hammer_aitoff says
 * how): the camera's -x is toward l = +90, -y toward b = +90. */
static inline orr_projected orr_project_hammer_aitoff_f(const orr_proj_consts *k, float x, float y, float z)
{
    float fwd = z, left = -x, up = -y;
    float r = sqrtf(fwd * fwd + left * left + up * up);
    float rho = sqrtf(fwd * fwd + left * left);
    float big = rho + fabsf(fwd), small = left * left / (big > 0.0f ? big : 1.0f);
    float cbc = sqrtf(0.5f * rho * (fwd >= 0.0f ? big : small));
    float cbs = sqrtf(0.5f * rho * (fwd >= 0.0f ? small : big));
    cbs = left < 0.0f ? -cbs : cbs;
    int vis = r > 0.0f;
    float s = 1.0f / sqrtf(vis ? r * (r + cbc) : 1.0f);
    orr_projected q = {k->cx + k->sgn * k->hw * cbs * s, k->cy - k->hh * up * s, k->f / (vis ? r : 1.0f), vis};
    return q;
}

static inline orr_projected orr_project_equirectangular_f(const orr_proj_consts *k, float x, float y, float z)
{
    float h = sqrtf(x * x + z * z);
    float r = sqrtf(h * h + y * y);
    float l = orr_atan2f(-x, z), b = orr_atan2f(-y, h);
    int vis = r > 0.0f;
    float cosb = vis ? h / r : 1.0f;
    cosb = cosb > 1e-6f ? cosb : 1e-6f; /* not fmaxf: its NaN rule keeps the loop scalar */
    orr_projected q = {k->cx + k->ax * l, k->cy - k->ay * b, k->f / (sqrtf(cosb) * (vis ? r : 1.0f)), vis};
    return q;
}

/* Azimuthal equidistant: the radius on the master is proportional to the
 * angle from the zenith; the camera's x and y keep their directions, so
 * the front (+y) is at the bottom. */
static inline orr_projected orr_project_dome_f(const orr_proj_consts *k, float x, float y, float z)
{
    float rho = sqrtf(x * x + y * y);
    float theta = orr_atan2f(rho, z);
    float r2 = rho * rho + z * z, r = sqrtf(r2);
    /* r > 0, tested on r2: a caller that needs no scale (the NGP gather)
     * then takes no square root. */
    int vis = r2 > 0.0f && theta <= k->tmax;
    float s = rho > 0.0f ? k->f * theta / rho : k->f;
    /* The isotropic scale: geometric mean of radial f and tangential
     * f theta / sin theta; sin theta = rho / r. */
    float stretch = rho > 0.0f ? theta * r / rho : 1.0f;
    orr_projected q = {k->cx + s * x, k->cy + s * y, k->f * sqrtf(stretch) / (vis ? r : 1.0f), vis};
    return q;
}

/* HEALPix: the centre of the pixel the direction falls in (not
 * vectorised: the pixel search is chealpix's). */
static inline orr_projected orr_project_healpix_f(const orr_proj_consts *k, float x, float y, float z)
{
    float r2 = x * x + y * y + z * z;
    int vis = r2 > 0.0f;
    long pix = vis ? orr_healpix_pixel(k->proj, x, y, z) : 0;
    int width = k->proj->width;
    orr_projected q = {(float)(pix % width) + 0.5f, (float)(pix / width) + 0.5f,
                       vis ? k->f / sqrtf(r2) : 0.0f, vis};
    return q;
}

static inline orr_projected orr_project_point_f(orr_projection_kind kind, const orr_proj_consts *k, float x,
                                                float y, float z)
{
    switch (kind) {
    case ORR_PROJ_ORTHOGRAPHIC: return orr_project_orthographic_f(k, x, y);
    case ORR_PROJ_PERSPECTIVE: return orr_project_perspective_f(k, x, y, z);
    case ORR_PROJ_HAMMER_AITOFF: return orr_project_hammer_aitoff_f(k, x, y, z);
    case ORR_PROJ_EQUIRECTANGULAR: return orr_project_equirectangular_f(k, x, y, z);
    case ORR_PROJ_HEALPIX: return orr_project_healpix_f(k, x, y, z);
    case ORR_PROJ_DOME: break;
    }
    return orr_project_dome_f(k, x, y, z);
}

#endif
