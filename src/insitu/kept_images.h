/* The images of a frame kept in memory for the caller (orrery_keep_images):
 * a copy of each view's final planes, its graded picture and its FITS
 * cards as text, so a Python caller gets arrays rather than files. */
#ifndef ORR_INSITU_KEPT_IMAGES_H
#define ORR_INSITU_KEPT_IMAGES_H

#include "core/error.h"
#include "encode/fits.h"
#include "core/plane.h"

typedef struct orr_kept_image {
    int width, height, nplanes;
    orr_plane planes[3]; /* copies: the weight plane, or CIE X, Y, Z */
    float *rgb;          /* the graded picture, sRGB, width * height * 3 */
    char *header;        /* the FITS cards, one "KEY = VALUE" line each */
} orr_kept_image;

typedef struct orr_kept_images {
    int n, capacity;
    orr_kept_image *image;
} orr_kept_images;

/* Frees the images kept (the list stays usable, empty). */
void orr_kept_clear(orr_kept_images *k);

/* An orr_keep_fn (render/render.h): appends a copy of one view's images to
 * the orr_kept_images that user points at. */
orr_status orr_kept_add(void *user, int view, const orr_plane *planes, int nplanes, const float *rgb,
                        const orr_cards *cards, orr_error *err);

/* The FITS cards as text: one line per card, "KEY = VALUE", VALUE being a
 * quoted string ('' for a quote inside), T or F, an integer, or a number
 * in the shortest form that reads back exactly. A malloc'd string. */
char *orr_kept_header_text(const orr_cards *cards, orr_error *err);

#endif
