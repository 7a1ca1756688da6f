#include "splat/deposit.h"
#include "core/simd.h"

#include <math.h>
#include <string.h>

const orr_named orr_deposit_names[] = {
    {"ngp", ORR_DEPOSIT_NGP}, {"cic", ORR_DEPOSIT_CIC}, {"sph", ORR_DEPOSIT_SPH}, {NULL, 0}};

const char *orr_deposit_name(orr_deposit_kind kind) { return orr_named_name(orr_deposit_names, (int)kind); }

void orr_deposit_settings_defaults(orr_deposit_settings *d)
{
    memset(d, 0, sizeof *d);
    d->kind = ORR_DEPOSIT_CIC;
    d->kernel = ORR_KERNEL_CUBIC;
    d->lengths = ORR_LENGTHS_AUTO;
    d->neighbours = 32;
    d->h_scale = 1.0;
}

void orr_deposit_cards(const orr_deposit_settings *d, int kernels, orr_cards *h)
{
    orr_cards_add_string(h, "DEPOSIT", orr_deposit_name(d->kind), "deposit method");
    if (!kernels)
        return;
    orr_cards_add_string(h, "KERNEL", orr_kernel_name(d->kernel), "SPH kernel (support 2h)");
    orr_cards_reserve(h, "HSOURCE", "where smoothing lengths came from");
    orr_cards_reserve(h, "NNEIGH", "h = half the distance to this neighbour");
    orr_cards_add_double(h, "HSCALE", d->h_scale, "smoothing lengths multiplied by this");
}

void orr_deposit_frame_cards(const orr_deposit_settings *d, int from_neighbours, orr_cards *h)
{
    orr_cards_set_string(h, "HSOURCE", from_neighbours ? "neighbours" : "file");
    if (from_neighbours)
        orr_cards_set_long(h, "NNEIGH", d->neighbours);
}

/* Points a stack batch of orr_deposit handles at once (its shares stay in
 * L1 cache). */
#define POINT_BATCH 512

/* The sum in double of the weights w[i] of the points whose index[i] is
 * at least lo (every point when index is NULL). Eight independent
 * accumulators, which the compiler turns into vector additions (a single
 * running sum could not be reordered); the order of the terms is fixed, so
 * the sums do not depend on the machine. */
ORR_VECTOR_CLONES
static double sum_from(const float *restrict w, const int32_t *restrict index, int32_t lo, size_t n)
{
    double acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    size_t i = 0;
    if (!index) {
        for (; i + 8 <= n; i += 8)
            for (int j = 0; j < 8; j++)
                acc[j] += w[i + j];
    } else {
        for (; i + 8 <= n; i += 8)
            for (int j = 0; j < 8; j++)
                acc[j] += index[i + j] >= lo ? w[i + j] : 0.0f;
    }
    for (; i < n; i++)
        acc[0] += !index || index[i] >= lo ? w[i] : 0.0f;
    return ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
}

static double sum_floats(const float *w, size_t n)
{
    return sum_from(w, NULL, 0, n);
}

ORR_VECTOR_CLONES
static size_t count_below(const int32_t *restrict index, int32_t bound, size_t n)
{
    size_t count = 0;
    for (size_t i = 0; i < n; i++)
        count += index[i] < bound;
    return count;
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

orr_map_outline orr_map_outline_of(const orr_projection *p, int width, int height)
{
    orr_map_outline m = {width, height, 0.5f * (float)width, 0.5f * (float)height, 0.0f, 0.0f};
    if (p && orr_projection_traits_of(p->settings.kind).elliptic_map) {
        m.cx = (float)p->cx;
        m.cy = (float)p->cy;
        m.ax = (float)(1.0 / (p->half_w * p->half_w));
        m.ay = (float)(1.0 / (p->half_h * p->half_h));
    }
    return m;
}

/* 1 when pixel (i, j) is surely inside the map; 0 when it may not be (near
 * the rim the float test is not trusted, and the projection's own test
 * decides, so deposits and the mask written to FITS always agree). */
static inline int surely_in_outline(const orr_map_outline *m, int i, int j)
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
static inline int32_t map_pixel(const orr_projection *proj, const orr_map_outline *m, float fx, float fy)
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

static void sky_cic_shares(const orr_point_batch *b, const orr_projection *proj, orr_shares *out,
                           orr_deposit_stats *st)
{
    const orr_map_outline m = orr_map_outline_of(proj, proj->width, proj->height);
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

/* ---- nearest pixel ---- */

/* The NGP index of each projected point: a loop for each kind of image,
 * which the compiler vectorises. */
ORR_VECTOR_CLONES
static void flat_indices(int W, int H, size_t n, const float *restrict px, const float *restrict py,
                         const uint8_t *restrict visible, int32_t *restrict index)
{
    for (size_t i = 0; i < n; i++)
        index[i] = orr_ngp_flat_index(W, H, px[i], py[i], visible[i]);
}

ORR_VECTOR_CLONES
static void sky_indices(const orr_map_outline *outline, size_t n, const float *restrict px,
                        const float *restrict py, const uint8_t *restrict visible, int32_t *restrict index)
{
    const orr_map_outline m = *outline;
    for (size_t i = 0; i < n; i++)
        index[i] = orr_ngp_sky_index(&m, px[i], py[i], visible[i]);
}

static void ngp_indices(const orr_projection *proj, const orr_map_outline *m, const orr_point_batch *b,
                        int32_t *index)
{
    if (proj && orr_projection_is_sky(proj))
        sky_indices(m, b->n, b->px, b->py, b->visible, index);
    else
        flat_indices(m->width, m->height, b->n, b->px, b->py, b->visible, index);
}

/* The report's sums come from plain sums over the block: deposited is the
 * weight of the points with a pixel, outside the visible points' less
 * that, culled the rest. */
void orr_ngp_place(const orr_projection *proj, const orr_map_outline *m, orr_ngp_batch *b,
                   orr_deposit_stats *st)
{
    const size_t n = b->n, n_culled = count_below(b->index, ORR_NGP_OFF, n);
    size_t n_missing = count_below(b->index, 0, n);
    if (n_missing > n_culled && proj && orr_projection_is_sky(proj)) {
        for (size_t i = 0; i < n; i++)
            if (b->index[i] == ORR_NGP_OFF)
                b->index[i] = map_pixel(proj, m, floorf(b->px[i]), floorf(b->py[i]));
        n_missing = n_culled;
    }
    b->n_missing = n_missing;
    for (int p = 0; p < b->nw; p++) {
        double all = sum_floats(b->w[p], n);
        double visible = n_culled ? sum_from(b->w[p], b->index, ORR_NGP_OFF, n) : all;
        double deposited = n_missing == n_culled ? visible : sum_from(b->w[p], b->index, 0, n);
        st[p].deposited += deposited;
        st[p].outside += visible - deposited;
        st[p].culled += all - visible;
        st[p].n_culled += n_culled;
        st[p].n_particles += n;
    }
}

void orr_ngp_add(const orr_ngp_batch *b, orr_plane *planes)
{
    for (int p = 0; p < b->nw; p++) {
        float *restrict data = planes[p].data;
        const int32_t *restrict index = b->index;
        const float *restrict w = b->w[p];
        if (b->n_missing == 0) {
            for (size_t i = 0; i < b->n; i++)
                data[index[i]] += w[i];
            continue;
        }
        /* Points without a pixel add 0 to pixel 0, which leaves its value
         * as it is (x + 0 = x; only -0 turns +0, the same number): no branch
         * a point, which mispredicted where points fall off the image at
         * random (the Plummer sphere's tenth: 7-19 % slower), and no second
         * pass to pack the others first. */
        for (size_t i = 0; i < b->n; i++) {
            const int in = index[i] >= 0;
            data[in ? index[i] : 0] += in ? w[i] : 0.0f;
        }
    }
}

void orr_ngp_shares(const orr_ngp_batch *b, orr_shares *out)
{
    const size_t first = out->n, n = b->n;
    int32_t *pixel = out->pixel;
    if (b->n_missing == 0) {
        if (b->index != pixel + first)
            memcpy(pixel + first, b->index, n * sizeof *pixel);
        for (int p = 0; p < b->nw; p++)
            memcpy(out->w[p] + first, b->w[p], n * sizeof(float));
        out->n = first + n;
        return;
    }
    /* Branch-free: each share is written, and the next one written over it
     * when it has no pixel. Reading index[i] before writing pixel[k], k <= i,
     * allows index to be pixel + first. */
    size_t k = first;
    for (size_t i = 0; i < n; i++) {
        const int32_t at = b->index[i];
        pixel[k] = at;
        for (int p = 0; p < b->nw; p++)
            out->w[p][k] = b->w[p][i];
        k += at >= 0;
    }
    out->n = k;
}

/* NGP shares: the indices go straight into out, beside a copy of the weights. */
static void ngp_shares(const orr_point_batch *b, const orr_projection *proj, int W, int H, orr_shares *out,
                       orr_deposit_stats *st)
{
    const orr_map_outline m = orr_map_outline_of(proj, W, H);
    orr_ngp_batch nb = {b->n, out->pixel + out->n, b->px, b->py, {NULL}, b->nw, 0};
    memcpy(nb.w, b->w, sizeof nb.w);
    ngp_indices(proj, &m, b, nb.index);
    orr_ngp_place(proj, &m, &nb, st);
    orr_ngp_shares(&nb, out);
}

void orr_deposit_shares(orr_deposit_kind kind, const orr_point_batch *b, const orr_projection *proj, int width,
                        int height, orr_shares *out, orr_deposit_stats *stats)
{
    if (kind == ORR_DEPOSIT_NGP)
        ngp_shares(b, proj, width, height, out, stats);
    else if (proj && orr_projection_is_sky(proj))
        sky_cic_shares(b, proj, out, stats);
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
                        const uint8_t *visible, const orr_projection *proj, orr_deposit_stats *st)
{
    int32_t index[POINT_BATCH];
    const orr_map_outline m = orr_map_outline_of(proj, plane->width, plane->height);
    for (size_t start = 0; start < n; start += POINT_BATCH) {
        size_t count = n - start < POINT_BATCH ? n - start : POINT_BATCH;
        orr_point_batch pb = {count, px + start, py + start, visible + start, {w + start}, 1};
        orr_ngp_batch nb = {count, index, px + start, py + start, {w + start}, 1, 0};
        ngp_indices(proj, &m, &pb, index);
        orr_ngp_place(proj, &m, &nb, st);
        orr_ngp_add(&nb, plane);
    }
}

void orr_deposit(orr_deposit_kind kind, orr_plane *plane, size_t n, const float *px, const float *py,
                 const float *w, const uint8_t *visible, const orr_projection *proj, orr_deposit_stats *stats)
{
    if (kind == ORR_DEPOSIT_NGP) {
        deposit_ngp(plane, n, px, py, w, visible, proj, stats);
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
