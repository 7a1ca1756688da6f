#include "splat/deposit.h"

#include <math.h>

const char *orr_deposit_name(orr_deposit_kind kind)
{
    switch (kind) {
    case ORR_DEPOSIT_NGP: return "ngp";
    case ORR_DEPOSIT_CIC: return "cic";
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

void orr_deposit(orr_deposit_kind kind, orr_plane *plane, size_t n, const float *px, const float *py,
                 const float *w, const uint8_t *visible, orr_deposit_stats *stats)
{
    switch (kind) {
    case ORR_DEPOSIT_NGP:
        deposit_ngp(plane, n, px, py, w, visible, stats);
        return;
    case ORR_DEPOSIT_CIC:
        deposit_cic(plane, n, px, py, w, visible, stats);
        return;
    }
}
