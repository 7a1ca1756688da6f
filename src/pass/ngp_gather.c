#include "pass/ngp_gather.h"

#include "core/fastmath.h"
#include "core/simd.h"
#include "frame/project_point.h"

/* The loop, for a constant kind and dim (so that each caller below is a
 * straight loop the compiler vectorises). */
static ORR_ALWAYS_INLINE int gather_loop(orr_projection_kind kind, int dim, const orr_projection *p,
                                          const orr_map_outline *outline, const orr_camera_transform *transform,
                                          size_t n, const float *restrict x, const float *restrict y,
                                          const float *restrict z, const float *restrict w,
                                          int32_t *restrict index, float *restrict px, float *restrict py,
                                          float *restrict dimming)
{
    const orr_proj_consts k = orr_proj_consts_of(p);
    const orr_map_outline m = *outline;
    const orr_camera_transform t = *transform;
    const int sky = orr_projection_traits_of(kind).folds;
    uint32_t bad = 0;
    for (size_t i = 0; i < n; i++) {
        bad |= (uint32_t)(orr_not_finite_f(x[i]) | orr_not_finite_f(y[i]) | orr_not_finite_f(z[i]) |
                          orr_not_finite_f(w[i]));
        orr_camera_point c = orr_to_camera(&t, x[i], y[i], z[i]);
        if (dim)
            dimming[i] = orr_camera_dimming(&t, c.r2);
        orr_projected q = orr_project_point_f(kind, &k, c.x, c.y, c.z);
        if (sky) {
            index[i] = orr_ngp_sky_index(&m, q.px, q.py, q.visible);
            px[i] = q.px;
            py[i] = q.py;
        } else {
            index[i] = orr_ngp_flat_index(m.width, m.height, q.px, q.py, q.visible);
        }
    }
    return bad == 0;
}

#define GATHER_KIND(name, kind, clones)                                                                         \
    clones                                                                                                       \
    static int name(const orr_projection *p, const orr_map_outline *m, const orr_camera_transform *t, size_t n, \
                    const float *x, const float *y, const float *z, const float *w,                              \
                    const orr_ngp_gather_out *o)                                                                 \
    {                                                                                                            \
        if (t->dim)                                                                                              \
            return gather_loop(kind, 1, p, m, t, n, x, y, z, w, o->index, o->px, o->py, o->dimming);             \
        return gather_loop(kind, 0, p, m, t, n, x, y, z, w, o->index, o->px, o->py, o->dimming);                 \
    }
GATHER_KIND(gather_orthographic, ORR_PROJ_ORTHOGRAPHIC, ORR_VECTOR_CLONES)
GATHER_KIND(gather_perspective, ORR_PROJ_PERSPECTIVE, ORR_VECTOR_CLONES)
GATHER_KIND(gather_hammer_aitoff, ORR_PROJ_HAMMER_AITOFF, ORR_WIDE_VECTOR_CLONES)
GATHER_KIND(gather_equirectangular, ORR_PROJ_EQUIRECTANGULAR, ORR_WIDE_VECTOR_CLONES)
GATHER_KIND(gather_dome, ORR_PROJ_DOME, ORR_WIDE_VECTOR_CLONES)
GATHER_KIND(gather_healpix, ORR_PROJ_HEALPIX, ) /* chealpix's pixel search: no vector clones */

int orr_ngp_gather(const orr_projection *p, const orr_map_outline *m, const orr_camera_transform *t, size_t n,
                   const float *x, const float *y, const float *z, const float *w, const orr_ngp_gather_out *out)
{
    switch (p->settings.kind) {
    case ORR_PROJ_ORTHOGRAPHIC: return gather_orthographic(p, m, t, n, x, y, z, w, out);
    case ORR_PROJ_PERSPECTIVE: return gather_perspective(p, m, t, n, x, y, z, w, out);
    case ORR_PROJ_HAMMER_AITOFF: return gather_hammer_aitoff(p, m, t, n, x, y, z, w, out);
    case ORR_PROJ_EQUIRECTANGULAR: return gather_equirectangular(p, m, t, n, x, y, z, w, out);
    case ORR_PROJ_HEALPIX: return gather_healpix(p, m, t, n, x, y, z, w, out);
    case ORR_PROJ_DOME: break;
    }
    return gather_dome(p, m, t, n, x, y, z, w, out);
}
