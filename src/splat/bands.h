/* Point deposits by bands of the image, for threads.
 *
 * The shares of a run of blocks (orr_deposit_shares) are sorted, block by
 * block, by the band of pixels they fall in: a band is 2^shift consecutive
 * pixels, sized to stay in a core's L2 cache. Then each band is added by
 * one thread, block after block and share after share, so every pixel
 * receives its additions in the particles' order whatever the number of
 * threads (the planes are the same bits as one thread's), threads never
 * write the same pixel, and the pixels a band touches stay in cache even
 * when the image is far larger than it (a 3600^2 dome master is 52 MB). */
#ifndef ORR_SPLAT_BANDS_H
#define ORR_SPLAT_BANDS_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "splat/deposit.h"
#include "core/plane.h"

/* More bands than this only add bookkeeping: very large images get wider
 * bands instead. */
#define ORR_MAX_BANDS 4096

typedef struct orr_bands {
    int shift, nbands, nplanes;
    size_t nregions;   /* regions: one a block */
    size_t region_cap; /* shares a region holds */
    int32_t *pixel;    /* nregions * region_cap */
    float *w[ORR_PLANES_MAX];       /* nplanes of them, as pixel */
    uint32_t *start;   /* per region, nbands + 1: where each band's shares start */
} orr_bands;

/* Sets up bands for an image of npix pixels (below 2^31) and nplanes
 * planes, with nregions regions of region_cap shares. */
orr_status orr_bands_init(orr_bands *b, size_t npix, int nplanes, size_t nregions, size_t region_cap,
                          orr_error *err);
void orr_bands_free(orr_bands *b);

/* Sorts shares s (at most region_cap) into region r by band, keeping their
 * order within each band. cursor: scratch room for nbands values. */
void orr_bands_put(orr_bands *b, size_t r, const orr_shares *s, uint32_t *cursor);

/* Adds band `band` of regions [0, nregions) to the planes, in region order,
 * prefetching band + 1's pixels: give each thread runs of consecutive
 * bands. */
void orr_bands_apply(const orr_bands *b, int band, size_t nregions, orr_plane *planes);

#endif
