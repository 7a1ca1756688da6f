/* Reading back the image planes orrery wrote to FITS (for `orrery compose`,
 * which re-grades a render from its raw planes without rendering again). */
#ifndef ORR_ENCODE_FITS_READ_H
#define ORR_ENCODE_FITS_READ_H

#include "core/error.h"
#include "core/plane.h"

/* Reads up to max image HDUs of path into planes[0..*n) (allocated here;
 * free each with orr_plane_free), row 0 at the top, with EXTNAME and BUNIT
 * as name and unit. Every HDU must be a 2-D image of the first one's size,
 * except the SCENE text orrery writes after the planes, which is skipped.
 * Errors name the file and the HDU. */
orr_status orr_read_fits_planes(const char *path, orr_plane *planes, int max, int *n, orr_error *err);

#endif
