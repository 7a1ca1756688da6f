#include "splat/deposit.h"
#include "core/simd.h"

#include <math.h>
#include <string.h>

const char *orr_deposit_name(orr_deposit_kind kind)
{
    switch (kind) {
    case ORR_DEPOSIT_NGP: return "ngp";
    case ORR_DEPOSIT_CIC: return "cic";
    case ORR_DEPOSIT_SPH: return "sph";
    }
    return "unknown";
}

/* Points a stack batch of orr_deposit handles at once (its shares stay in
 * L1 cache). */
#define POINT_BATCH 512

/* The pixel index of each point of [0, n) (NGP: the pixel containing it),
 * or -1 for a culled point or one off the image. Branch-free, so the loop
 * vectorises: a point outside is clamped to pixel 0 before the conversion
 * (converting a float that does not fit an int is undefined) and its index
 * then replaced. For non-negative values truncation is floor, and the
 * bounds test is done in float first, so the conversions are exact. */
ORR_VECTOR_CLONES
static void ngp_indices(int W, int H, size_t n, const float *restrict px, const float *restrict py,
                        const uint8_t *restrict visible, int32_t *restrict index)
{
    const float fw = (float)W, fh = (float)H;
    for (size_t i = 0; i < n; i++) {
        float x = px[i], y = py[i];
        int in = (visible[i] != 0) & (x >= 0.0f) & (x < fw) & (y >= 0.0f) & (y < fh);
        int32_t ix = (int32_t)(in ? x : 0.0f), iy = (int32_t)(in ? y : 0.0f);
        index[i] = in ? iy * W + ix : -1;
    }
}

/* The sum of n floats in double; four accumulators break the chain of
 * dependent additions. */
static double sum_floats(const float *restrict a, size_t n)
{
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    size_t i = 0;
    for (; i + 3 < n; i += 4) {
        s0 += a[i];
        s1 += a[i + 1];
        s2 += a[i + 2];
        s3 += a[i + 3];
    }
    for (; i < n; i++)
        s0 += a[i];
    return (s0 + s1) + (s2 + s3);
}

/* The sum of the weights of visible points. */
static double sum_visible(const float *restrict w, const uint8_t *restrict visible, size_t n)
{
    double s0 = 0, s1 = 0;
    size_t i = 0;
    for (; i + 1 < n; i += 2) {
        s0 += visible[i] ? w[i] : 0.0;
        s1 += visible[i + 1] ? w[i + 1] : 0.0;
    }
    for (; i < n; i++)
        s0 += visible[i] ? w[i] : 0.0;
    return s0 + s1;
}

/* The sum of the weights of points with a pixel (index >= 0). */
static double sum_inside(const float *restrict w, const int32_t *restrict index, size_t n)
{
    double s0 = 0, s1 = 0;
    size_t i = 0;
    for (; i + 1 < n; i += 2) {
        s0 += index[i] >= 0 ? w[i] : 0.0;
        s1 += index[i + 1] >= 0 ? w[i + 1] : 0.0;
    }
    for (; i < n; i++)
        s0 += index[i] >= 0 ? w[i] : 0.0;
    return s0 + s1;
}

ORR_VECTOR_CLONES
static size_t count_visible(const uint8_t *restrict visible, size_t n)
{
    size_t count = 0;
    for (size_t i = 0; i < n; i++)
        count += visible[i] != 0;
    return count;
}

ORR_VECTOR_CLONES
static size_t count_negative(const int32_t *restrict index, size_t n)
{
    size_t count = 0;
    for (size_t i = 0; i < n; i++)
        count += index[i] < 0;
    return count;
}

/* Drops the shares [from, from + m) of out whose pixel is negative, keeping
 * the others in order: branch-free, each share written and the next one
 * written over it when it is dropped. */
static void drop_negative(orr_shares *out, size_t from, size_t m, int nw)
{
    int32_t *restrict pixel = out->pixel;
    size_t k = from;
    for (size_t i = from; i < from + m; i++) {
        int32_t px = pixel[i];
        pixel[k] = px;
        for (int p = 0; p < nw; p++)
            out->w[p][k] = out->w[p][i];
        k += px >= 0;
    }
    out->n = k;
}

/* NGP: one share a point that lands on the image. The indices go straight
 * into out and the weights are copied beside them; the points off the
 * image (or culled) are then dropped, when there are any. The report's
 * sums come from plain sums: deposited is the shares', outside the visible
 * points' less that, culled the rest. */
static void ngp_shares(const orr_point_batch *b, int W, int H, orr_shares *out, orr_deposit_stats *st)
{
    const size_t n = b->n, first = out->n;
    ngp_indices(W, H, n, b->px, b->py, b->visible, out->pixel + first);
    for (int p = 0; p < b->nw; p++)
        memcpy(out->w[p] + first, b->w[p], n * sizeof(float));
    out->n = first + n;
    const size_t nvis = count_visible(b->visible, n);
    if (count_negative(out->pixel + first, n) > 0)
        drop_negative(out, first, n, b->nw);
    for (int p = 0; p < b->nw; p++) {
        double deposited = sum_floats(out->w[p] + first, out->n - first);
        double all = sum_floats(b->w[p], n);
        double visible = nvis == n ? all : sum_visible(b->w[p], b->visible, n);
        st[p].deposited += deposited;
        st[p].outside += visible - deposited;
        st[p].culled += all - visible;
        st[p].n_culled += n - nvis;
        st[p].n_particles += n;
    }
}

static void cic_shares(const orr_point_batch *b, int W, int H, orr_shares *out, orr_deposit_stats *st)
{
    size_t k = out->n;
    for (size_t i = 0; i < b->n; i++) {
        if (!b->visible[i]) {
            for (int p = 0; p < b->nw; p++) {
                st[p].culled += b->w[p][i];
                st[p].n_culled++;
            }
            continue;
        }
        /* The unit square centred on the point overlaps pixels i0 and i0+1
         * (likewise in y); tx is the share of the right-hand column. */
        float gx = b->px[i] - 0.5f, gy = b->py[i] - 0.5f;
        float fx = floorf(gx), fy = floorf(gy);
        if (!(fx >= -1.0f && fx < (float)W && fy >= -1.0f && fy < (float)H)) {
            for (int p = 0; p < b->nw; p++)
                st[p].outside += b->w[p][i];
            continue;
        }
        int i0 = (int)fx, j0 = (int)fy;
        float tx = gx - fx, ty = gy - fy;
        float wx[2] = {1.0f - tx, tx}, wy[2] = {1.0f - ty, ty};
        for (int c = 0; c < 2; c++) {
            int j = j0 + c;
            for (int a = 0; a < 2; a++) {
                int ii = i0 + a, inside = ii >= 0 && ii < W && j >= 0 && j < H;
                for (int p = 0; p < b->nw; p++) {
                    float share = b->w[p][i] * wx[a] * wy[c];
                    out->w[p][k] = share;
                    if (inside)
                        st[p].deposited += share;
                    else
                        st[p].outside += share;
                }
                out->pixel[k] = inside ? j * W + ii : -1;
                k += inside;
            }
        }
    }
    out->n = k;
    for (int p = 0; p < b->nw; p++)
        st[p].n_particles += b->n;
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

/* The pixel of a sky map a share at (fx, fy) goes to, folding it onto the
 * map first when it lies outside (rare: the rim, the seam, the poles).
 * Coordinates far outside (a float that does not fit an int) cannot come
 * from a sky projection, whose points lie on the map. */
static inline int32_t map_pixel(const orr_projection *proj, const map_outline *m, float fx, float fy)
{
    /* Ternaries, not fminf/fmaxf: those are calls that handle NaN, which a
     * visible point never is. */
    fx = fx < 1e9f ? (fx > -1e9f ? fx : -1e9f) : 1e9f;
    fy = fy < 1e9f ? (fy > -1e9f ? fy : -1e9f) : 1e9f;
    int i = (int)fx, j = (int)fy;
    if (!surely_in_outline(m, i, j) && !orr_projection_pixel_in_map(proj, i, j))
        orr_projection_fold(proj, &i, &j);
    return (int32_t)j * m->width + i;
}

/* Appends a share of every weight (the point's weights times frac). */
static inline void add_share(const orr_point_batch *b, size_t i, int32_t pixel, float frac, orr_shares *out)
{
    size_t k = out->n++;
    out->pixel[k] = pixel;
    for (int p = 0; p < b->nw; p++)
        out->w[p][k] = b->w[p][i] * frac;
}

/* The pixel index of each visible point of a sky map that is surely on
 * the map (surely_in_outline, in a loop that vectorises), or -1: culled,
 * or near the rim, the seam or off the image, where map_pixel decides. */
ORR_VECTOR_CLONES
static void sky_ngp_indices(const map_outline *m, size_t n, const float *restrict px, const float *restrict py,
                            const uint8_t *restrict visible, int32_t *restrict index)
{
    const float fw = (float)m->width, fh = (float)m->height, cx = m->cx, cy = m->cy, ax = m->ax, ay = m->ay;
    const int W = m->width;
    for (size_t i = 0; i < n; i++) {
        float x = px[i], y = py[i];
        int on_image = (visible[i] != 0) & (x >= 0.0f) & (x < fw) & (y >= 0.0f) & (y < fh);
        int32_t ix = (int32_t)(on_image ? x : 0.0f), iy = (int32_t)(on_image ? y : 0.0f);
        float u = (float)ix + 0.5f - cx, v = (float)iy + 0.5f - cy;
        /* A rectangular map has ax = ay = 0: every pixel is surely on it. */
        int sure = on_image & (u * u * ax + v * v * ay <= 0.9999f);
        index[i] = sure ? iy * W + ix : -1;
    }
}

/* NGP on a sky map: every visible point's weight lands (folded onto the
 * map where it falls outside). */
static void sky_ngp_shares(const orr_point_batch *b, const orr_projection *proj, const map_outline *m,
                           orr_shares *out, orr_deposit_stats *st)
{
    int32_t index[POINT_BATCH];
    for (size_t start = 0; start < b->n; start += POINT_BATCH) {
        size_t n = b->n - start < POINT_BATCH ? b->n - start : POINT_BATCH;
        const uint8_t *visible = b->visible + start;
        sky_ngp_indices(m, n, b->px + start, b->py + start, visible, index);
        for (size_t i = 0; i < n; i++)
            if (index[i] < 0 && visible[i])
                index[i] = map_pixel(proj, m, floorf(b->px[start + i]), floorf(b->py[start + i]));
        size_t k = out->n;
        for (size_t i = 0; i < n; i++) {
            out->pixel[k] = index[i];
            k += index[i] >= 0;
        }
        for (int p = 0; p < b->nw; p++) {
            const float *restrict w = b->w[p] + start;
            float *restrict ow = out->w[p];
            size_t kp = out->n;
            for (size_t i = 0; i < n; i++) {
                ow[kp] = w[i];
                kp += index[i] >= 0;
            }
        }
        out->n = k;
        const size_t nvis = count_visible(visible, n);
        for (int p = 0; p < b->nw; p++) {
            double all = sum_floats(b->w[p] + start, n);
            double vis = nvis == n ? all : sum_visible(b->w[p] + start, visible, n);
            st[p].deposited += vis;
            st[p].culled += all - vis;
            st[p].n_culled += n - nvis;
            st[p].n_particles += n;
        }
    }
}

static void sky_shares(orr_deposit_kind kind, const orr_point_batch *b, const orr_projection *proj,
                       orr_shares *out, orr_deposit_stats *st)
{
    const map_outline m = outline_of(proj);
    if (kind == ORR_DEPOSIT_NGP) {
        sky_ngp_shares(b, proj, &m, out, st);
        return;
    }
    for (size_t i = 0; i < b->n; i++) {
        if (!b->visible[i]) {
            for (int p = 0; p < b->nw; p++) {
                st[p].culled += b->w[p][i];
                st[p].n_culled++;
            }
            continue;
        }
        for (int p = 0; p < b->nw; p++)
            st[p].deposited += b->w[p][i];
        float gx = b->px[i] - 0.5f, gy = b->py[i] - 0.5f;
        float fx = floorf(gx), fy = floorf(gy);
        float tx = gx - fx, ty = gy - fy;
        add_share(b, i, map_pixel(proj, &m, fx, fy), (1.0f - tx) * (1.0f - ty), out);
        add_share(b, i, map_pixel(proj, &m, fx + 1.0f, fy), tx * (1.0f - ty), out);
        add_share(b, i, map_pixel(proj, &m, fx, fy + 1.0f), (1.0f - tx) * ty, out);
        add_share(b, i, map_pixel(proj, &m, fx + 1.0f, fy + 1.0f), tx * ty, out);
    }
    for (int p = 0; p < b->nw; p++)
        st[p].n_particles += b->n;
}

void orr_deposit_shares(orr_deposit_kind kind, const orr_point_batch *b, const orr_projection *proj, int width,
                        int height, orr_shares *out, orr_deposit_stats *stats)
{
    if (proj && orr_projection_is_sky(proj))
        sky_shares(kind, b, proj, out, stats);
    else if (kind == ORR_DEPOSIT_NGP)
        ngp_shares(b, width, height, out, stats);
    else /* CIC, and SPH without smoothing lengths */
        cic_shares(b, width, height, out, stats);
}

void orr_shares_apply(const orr_shares *s, size_t first, size_t end, orr_plane *planes, int nplanes)
{
    const int32_t *restrict pixel = s->pixel;
    for (int p = 0; p < nplanes; p++) {
        float *restrict data = planes[p].data;
        const float *restrict w = s->w[p];
        for (size_t k = first; k < end; k++)
            data[pixel[k]] += w[k];
    }
}

/* NGP into a plane: the indices of a stack batch, then the weights added
 * straight from w (no shares are copied). */
static void deposit_ngp(orr_plane *plane, size_t n, const float *px, const float *py, const float *w,
                        const uint8_t *visible, orr_deposit_stats *st)
{
    int32_t index[POINT_BATCH];
    float *restrict data = plane->data;
    for (size_t start = 0; start < n; start += POINT_BATCH) {
        size_t m = n - start < POINT_BATCH ? n - start : POINT_BATCH;
        const float *restrict wb = w + start;
        ngp_indices(plane->width, plane->height, m, px + start, py + start, visible + start, index);
        const size_t nvis = count_visible(visible + start, m), nneg = count_negative(index, m);
        double deposited = 0;
        if (nneg == 0) {
            for (size_t i = 0; i < m; i++)
                data[index[i]] += wb[i];
            deposited = sum_floats(wb, m);
        } else {
            for (size_t i = 0; i < m; i++)
                if (index[i] >= 0)
                    data[index[i]] += wb[i];
            deposited = sum_inside(wb, index, m);
        }
        double all = nneg == 0 ? deposited : sum_floats(wb, m);
        double vis = nvis == m ? all : sum_visible(wb, visible + start, m);
        st->deposited += deposited;
        st->outside += vis - deposited;
        st->culled += all - vis;
        st->n_culled += m - nvis;
        st->n_particles += m;
    }
}

void orr_deposit(orr_deposit_kind kind, orr_plane *plane, size_t n, const float *px, const float *py,
                 const float *w, const uint8_t *visible, const orr_projection *proj, orr_deposit_stats *stats)
{
    if (kind == ORR_DEPOSIT_NGP && !(proj && orr_projection_is_sky(proj))) {
        deposit_ngp(plane, n, px, py, w, visible, stats);
        return;
    }
    int32_t pixel[ORR_MAX_SHARES_PER_POINT * POINT_BATCH];
    float wshare[ORR_MAX_SHARES_PER_POINT * POINT_BATCH];
    for (size_t start = 0; start < n; start += POINT_BATCH) {
        size_t m = n - start < POINT_BATCH ? n - start : POINT_BATCH;
        orr_point_batch b = {m, px + start, py + start, visible + start, {w + start}, 1};
        orr_shares s = {pixel, {wshare}, 0};
        orr_deposit_shares(kind, &b, proj, plane->width, plane->height, &s, stats);
        orr_shares_apply(&s, 0, s.n, plane, 1);
    }
}
