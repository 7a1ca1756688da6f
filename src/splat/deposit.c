#include "splat/deposit.h"

#include <math.h>

const char *orr_deposit_name(orr_deposit_kind kind)
{
    switch (kind) {
    case ORR_DEPOSIT_NGP: return "ngp";
    case ORR_DEPOSIT_CIC: return "cic";
    case ORR_DEPOSIT_SPH: return "sph";
    }
    return "unknown";
}

static void deposit_ngp(orr_plane *plane, size_t n, const float *px, const float *py, const float *w,
                        const uint8_t *visible, orr_deposit_stats *st)
{
    const int W = plane->width, H = plane->height;
    float *data = plane->data;
    double in = 0, out = 0, culled = 0;
    uint64_t ncull = 0;
    for (size_t i = 0; i < n; i++) {
        if (!visible[i]) {
            culled += w[i];
            ncull++;
            continue;
        }
        /* Compare in float before converting: a far-off point must not
         * overflow the int conversion. */
        float fx = floorf(px[i]), fy = floorf(py[i]);
        if (fx >= 0.0f && fx < (float)W && fy >= 0.0f && fy < (float)H) {
            data[(size_t)fy * (size_t)W + (size_t)fx] += w[i];
            in += w[i];
        } else {
            out += w[i];
        }
    }
    st->deposited += in;
    st->outside += out;
    st->culled += culled;
    st->n_culled += ncull;
    st->n_particles += n;
}

static void deposit_cic(orr_plane *plane, size_t n, const float *px, const float *py, const float *w,
                        const uint8_t *visible, orr_deposit_stats *st)
{
    const int W = plane->width, H = plane->height;
    float *data = plane->data;
    double in = 0, out = 0, culled = 0;
    uint64_t ncull = 0;
    for (size_t i = 0; i < n; i++) {
        if (!visible[i]) {
            culled += w[i];
            ncull++;
            continue;
        }
        /* The unit square centred on the point overlaps pixels i0 and i0+1
         * (likewise in y); tx is the share of the right-hand column. */
        float gx = px[i] - 0.5f, gy = py[i] - 0.5f;
        float fx = floorf(gx), fy = floorf(gy);
        if (!(fx >= -1.0f && fx < (float)W && fy >= -1.0f && fy < (float)H)) {
            out += w[i];
            continue;
        }
        int i0 = (int)fx, j0 = (int)fy;
        float tx = gx - fx, ty = gy - fy;
        float wx[2] = {1.0f - tx, tx}, wy[2] = {1.0f - ty, ty};
        for (int b = 0; b < 2; b++) {
            int j = j0 + b;
            for (int a = 0; a < 2; a++) {
                int ii = i0 + a;
                float share = w[i] * wx[a] * wy[b];
                if (ii >= 0 && ii < W && j >= 0 && j < H) {
                    data[(size_t)j * (size_t)W + (size_t)ii] += share;
                    in += share;
                } else {
                    out += share;
                }
            }
        }
    }
    st->deposited += in;
    st->outside += out;
    st->culled += culled;
    st->n_culled += ncull;
    st->n_particles += n;
}

/* The map's outline, set up once per call so the per-share test is a few
 * multiplications: inside the ellipse or circle (or the whole image). */
typedef struct map_outline {
    int width, height;
    float cx, cy;
    float ax, ay; /* squared reciprocal semi-axes; 0 for a rectangular map */
} map_outline;

static map_outline outline_of(const orr_projection *p)
{
    map_outline m = {p->width, p->height, (float)p->cx, (float)p->cy, 0.0f, 0.0f};
    if (p->kind == ORR_PROJ_HAMMER_AITOFF || p->kind == ORR_PROJ_DOME) {
        m.ax = (float)(1.0 / (p->half_w * p->half_w));
        m.ay = (float)(1.0 / (p->half_h * p->half_h));
    }
    return m;
}

/* 1 when pixel (i, j) is surely inside the map; 0 when it may not be (near
 * the rim the float test is not trusted, and the projection's own test
 * decides, so deposits and the mask written to FITS always agree). */
static inline int surely_in_outline(const map_outline *m, int i, int j)
{
    if (i < 0 || j < 0 || i >= m->width || j >= m->height)
        return 0;
    float u = (float)i + 0.5f - m->cx, v = (float)j + 0.5f - m->cy;
    return m->ax == 0.0f || u * u * m->ax + v * v * m->ay <= 0.9999f;
}

/* Adds a share to pixel (i, j) of a sky map, folding it onto the map first
 * when it lies outside (rare: the rim, the seam, the poles). Coordinates far
 * outside (a float that does not fit an int) cannot come from a sky
 * projection, whose points lie on the map. */
static inline void add_to_map(orr_plane *plane, const orr_projection *proj, const map_outline *m, float fx,
                              float fy, float share)
{
    /* Ternaries, not fminf/fmaxf: those are calls that handle NaN, which a
     * visible point never is. */
    fx = fx < 1e9f ? (fx > -1e9f ? fx : -1e9f) : 1e9f;
    fy = fy < 1e9f ? (fy > -1e9f ? fy : -1e9f) : 1e9f;
    int i = (int)fx, j = (int)fy;
    if (!surely_in_outline(m, i, j) && !orr_projection_pixel_in_map(proj, i, j))
        orr_projection_fold(proj, &i, &j);
    plane->data[(size_t)j * (size_t)plane->width + (size_t)i] += share;
}

static void deposit_sky(orr_deposit_kind kind, orr_plane *plane, size_t n, const float *px, const float *py,
                        const float *w, const uint8_t *visible, const orr_projection *proj,
                        orr_deposit_stats *st)
{
    const map_outline m = outline_of(proj);
    double in = 0, culled = 0;
    uint64_t ncull = 0;
    for (size_t i = 0; i < n; i++) {
        if (!visible[i]) {
            culled += w[i];
            ncull++;
            continue;
        }
        in += w[i];
        if (kind == ORR_DEPOSIT_NGP) {
            add_to_map(plane, proj, &m, floorf(px[i]), floorf(py[i]), w[i]);
            continue;
        }
        float gx = px[i] - 0.5f, gy = py[i] - 0.5f;
        float fx = floorf(gx), fy = floorf(gy);
        float tx = gx - fx, ty = gy - fy;
        add_to_map(plane, proj, &m, fx, fy, w[i] * (1.0f - tx) * (1.0f - ty));
        add_to_map(plane, proj, &m, fx + 1.0f, fy, w[i] * tx * (1.0f - ty));
        add_to_map(plane, proj, &m, fx, fy + 1.0f, w[i] * (1.0f - tx) * ty);
        add_to_map(plane, proj, &m, fx + 1.0f, fy + 1.0f, w[i] * tx * ty);
    }
    st->deposited += in;
    st->culled += culled;
    st->n_culled += ncull;
    st->n_particles += n;
}

void orr_deposit(orr_deposit_kind kind, orr_plane *plane, size_t n, const float *px, const float *py,
                 const float *w, const uint8_t *visible, const orr_projection *proj, orr_deposit_stats *stats)
{
    if (proj && orr_projection_is_sky(proj)) {
        deposit_sky(kind, plane, n, px, py, w, visible, proj, stats);
        return;
    }
    switch (kind) {
    case ORR_DEPOSIT_NGP:
        deposit_ngp(plane, n, px, py, w, visible, stats);
        return;
    case ORR_DEPOSIT_CIC:
    case ORR_DEPOSIT_SPH: /* without smoothing lengths a kernel deposit is CIC */
        deposit_cic(plane, n, px, py, w, visible, stats);
        return;
    }
}
