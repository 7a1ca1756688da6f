#include "splat/bands.h"

#include <stdlib.h>
#include <string.h>

#include "core/simd.h"

/* 2^16 pixels: 256 KiB of floats a plane, within a core's L2 cache. */
#define BAND_SHIFT_MIN 16

orr_status orr_bands_init(orr_bands *b, size_t npix, int nplanes, size_t nregions, size_t region_cap,
                          orr_error *err)
{
    memset(b, 0, sizeof *b);
    int shift = BAND_SHIFT_MIN;
    while (((npix + ((size_t)1 << shift) - 1) >> shift) > ORR_MAX_BANDS)
        shift++;
    b->shift = shift;
    b->nbands = (int)((npix + ((size_t)1 << shift) - 1) >> shift);
    b->nbands = b->nbands ? b->nbands : 1;
    b->nplanes = nplanes;
    b->nregions = nregions;
    b->region_cap = region_cap;
    size_t n = nregions * region_cap;
    b->pixel = orr_malloc(n * sizeof *b->pixel, "splat bands", err);
    b->start = b->pixel ? orr_malloc(nregions * (size_t)(b->nbands + 1) * sizeof *b->start, "splat bands", err)
                        : NULL;
    for (int p = 0; p < nplanes && b->start; p++)
        if (!(b->w[p] = orr_malloc(n * sizeof *b->w[p], "splat bands", err))) {
            orr_bands_free(b);
            return ORR_ERR_NOMEM;
        }
    if (!b->start) {
        orr_bands_free(b);
        return ORR_ERR_NOMEM;
    }
    return ORR_OK;
}

void orr_bands_free(orr_bands *b)
{
    free(b->pixel);
    free(b->start);
    for (int p = 0; p < ORR_PLANES_MAX; p++)
        free(b->w[p]);
    memset(b, 0, sizeof *b);
}

void orr_bands_put(orr_bands *b, size_t r, const orr_shares *s, uint32_t *cursor)
{
    const int shift = b->shift, nbands = b->nbands;
    uint32_t *start = b->start + r * (size_t)(nbands + 1);
    memset(cursor, 0, (size_t)nbands * sizeof *cursor);
    for (size_t k = 0; k < s->n; k++)
        cursor[(uint32_t)s->pixel[k] >> shift]++;
    uint32_t at = 0;
    for (int band = 0; band < nbands; band++) {
        start[band] = at;
        at += cursor[band];
        cursor[band] = start[band];
    }
    start[nbands] = at;
    int32_t *restrict pixel = b->pixel + r * b->region_cap;
    const int32_t *restrict from = s->pixel;
    const size_t n = s->n;
    if (b->nplanes == 1) { /* the common case, without the loop over planes */
        float *restrict w = b->w[0] + r * b->region_cap;
        const float *restrict wf = s->w[0];
        for (size_t k = 0; k < n; k++) {
            uint32_t to = cursor[(uint32_t)from[k] >> shift]++;
            pixel[to] = from[k];
            w[to] = wf[k];
        }
        return;
    }
    for (size_t k = 0; k < n; k++) {
        uint32_t to = cursor[(uint32_t)from[k] >> shift]++;
        pixel[to] = from[k];
        for (int p = 0; p < b->nplanes; p++)
            b->w[p][r * b->region_cap + to] = s->w[p][k];
    }
}

/* A band's pixels come from main memory (a window's shares touch most of
 * their cache lines once), and the additions wait on them. So while a
 * band is added, the pixels of the next band's shares are prefetched:
 * independent loads, many more in flight than the additions allow
 * (measured on a 10^7-particle dome master: 7-9 % faster). */
static void prefetch_band(const orr_bands *b, int band, const uint32_t *start, size_t base, const float *data)
{
    if (band >= b->nbands)
        return;
    const int32_t *pixel = b->pixel + base;
    for (uint32_t k = start[band]; k < start[band + 1]; k++)
        ORR_PREFETCH_FOR_WRITE(data + pixel[k]);
}

void orr_bands_apply(const orr_bands *b, int band, size_t nregions, orr_plane *planes)
{
    for (size_t r = 0; r < nregions; r++) {
        const uint32_t *start = b->start + r * (size_t)(b->nbands + 1);
        size_t base = r * b->region_cap;
        prefetch_band(b, band + 1, start, base, planes[0].data);
        orr_shares s = {b->pixel + base, {NULL}, 0};
        for (int p = 0; p < b->nplanes; p++)
            s.w[p] = b->w[p] + base;
        orr_shares_apply(&s, start[band], start[band + 1], planes, b->nplanes);
    }
}
