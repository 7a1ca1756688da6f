/* FITS output through cfitsio: each plane an image HDU of float32 (the first
 * in the primary HDU, so every viewer opens it by default), with EXTNAME and
 * BUNIT from the plane and the header cards the caller supplies.
 * Rows are written bottom-up (FITS pixel (1,1) is the lower left), so DS9
 * shows the same orientation as the PNG. */
#ifndef ORR_ENCODE_FITS_H
#define ORR_ENCODE_FITS_H

#include <stddef.h>
#include <stdint.h>

#include "core/cards.h"
#include "core/error.h"
#include "core/names.h"
#include "core/plane.h"

/* Writes the planes (all the same size) to path, atomically. The header cards
 * go into every HDU. */
orr_status orr_write_fits(const char *path, const orr_plane *planes, int nplanes,
                          const orr_cards *header, orr_error *err);

/* Tile compression of the image HDUs (the FITS tiled-image convention, as
 * fpack writes it), lossless: GZIP_2 (each float's bytes shuffled, then
 * zlib) without quantisation (ZQUANTIZ = 'NONE'), each row a tile. RICE_1
 * is not offered: it codes integers only, and cfitsio refuses it for float
 * images unless they are quantised, which would change the values. */
typedef enum { ORR_FITS_UNCOMPRESSED, ORR_FITS_GZIP } orr_fits_compression;

/* "none", "gzip" (output.fits_compress). */
extern const orr_named orr_fits_compression_names[];

/* Whether cfitsio was built thread-safe (fits_is_reentrant), so that two
 * FITS files may be written at once on different threads. */
int orr_fits_thread_safe(void);

/* orr_write_fits with the planes tile-compressed: an empty primary HDU, then
 * each plane a compressed image extension (astropy's CompImageHDU), with the
 * same cards and checksums. */
orr_status orr_write_fits_compressed(const char *path, const orr_plane *planes, int nplanes,
                                     const orr_cards *header, orr_fits_compression compression,
                                     orr_error *err);

/* A HEALPix map's description, for its FITS header. */
typedef struct orr_healpix_info {
    int nside;
    int nested;           /* NESTED order, else RING */
    const char *coordsys; /* "G" for galactic axes, NULL or "" when unknown */
} orr_healpix_info;

/* Appends a HEALPix map's keywords (PIXTYPE, ORDERING, NSIDE, FIRSTPIX,
 * LASTPIX, INDXSCHM, OBJECT and, when known, COORDSYS) to h. */
void orr_fits_add_healpix(orr_cards *h, const orr_healpix_info *info);

/* Writes a HEALPix map (each plane 12 nside^2 pixels in pixel order, at most
 * 3) as a standard HEALPix FITS file, atomically: an empty primary HDU and a
 * binary table with one float column per plane (TTYPE the plane's name,
 * TUNIT its unit), one row per pixel, the HEALPix keywords (PIXTYPE,
 * ORDERING, NSIDE, FIRSTPIX, LASTPIX, INDXSCHM, OBJECT, COORDSYS) and the
 * caller's cards. healpy.read_map reads it. */
orr_status orr_write_healpix_fits(const char *path, const orr_plane *planes, int nplanes,
                                  const orr_healpix_info *info, const orr_cards *header, orr_error *err);

/* A sky map's star list (docs/sky.md, "The star list"): one row per star
 * drawn, as columns. */
typedef struct orr_star_table {
    size_t n;
    const double *l, *b;     /* the observer frame's longitude and latitude, degrees */
    const float *v;          /* apparent V with the dust in front, mag */
    const float *bv;         /* B-V, mag, without reddening */
    const float *abs_v;      /* absolute V, mag */
    const float *dist_pc;    /* distance from the observer, parsecs */
    const int64_t *parent;   /* the id of the particle the star came from */
    const int32_t *index;    /* its place among that particle's stars, brightest 0 */
} orr_star_table;

/* Writes the star list atomically: an empty primary HDU with the caller's
 * cards, then a binary table STARS with columns L, B (deg), V, BV, MV
 * (mag), DIST (pc), PARTICLE and STAR. astropy.table.Table.read reads it. */
orr_status orr_write_star_table(const char *path, const orr_star_table *t, const orr_cards *header,
                                orr_error *err);

#endif
