/* A spike star's stamp on a sky map (post/sky_psf.h; docs/psf.md, "Sky
 * maps and dome masters"): the PSF's light in every map pixel within its
 * reach, tile by tile of the deposit's index (ORR_SPH_TILE pixels a side),
 * unnormalised. Private to post/sky_psf.c and its tests. */
#ifndef ORR_POST_SKY_PSF_STAMP_H
#define ORR_POST_SKY_PSF_STAMP_H

#include "post/sky_psf.h"

#define ORR_PSF_STAMP_TILE_PIXELS (ORR_SPH_TILE * ORR_SPH_TILE)

typedef struct orr_psf_stamp {
    size_t ntiles, cap;
    int *tile;    /* the tiles visited, ty * tiles_x + tx, increasing */
    float *value; /* ORR_PSF_STAMP_TILE_PIXELS per tile, row by row; 0 off the map (and off the image) */
    double total; /* the sum of the values, tile after tile */
    int *meets;   /* scratch: which groups of a row the PSF reaches */
    struct orr_psf_corner *corners; /* scratch: two rows of tile corners, mapped */
} orr_psf_stamp;

/* The PSF of sp centred on direction dir (a unit vector), reused from star
 * to star; a stamp belongs to one thread at a time. */
orr_status orr_psf_stamp_make(const orr_sky_psf *sp, const orr_sph *sph, orr_vec3 dir, orr_psf_stamp *st,
                              orr_error *err);
void orr_psf_stamp_free(orr_psf_stamp *st);

#endif
