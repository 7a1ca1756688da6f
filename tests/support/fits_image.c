/* See fits_image.h. */
#include "fits_image.h"

#include <fitsio.h>
#include <stdlib.h>

float *read_fits_image(const char *path, long *npix)
{
    fitsfile *f;
    int status = 0, anynul = 0;
    long size[2] = {0, 0};
    fits_open_file(&f, path, READONLY, &status);
    fits_get_img_size(f, 2, size, &status);
    if (status)
        return NULL;
    *npix = size[0] * size[1];
    float *d = malloc((size_t)*npix * sizeof *d);
    fits_read_img(f, TFLOAT, 1, *npix, NULL, d, &anynul, &status);
    fits_close_file(f, &status);
    return status ? (free(d), NULL) : d;
}
