/* The first image of a FITS file as floats, read with cfitsio itself (an
 * independent reader of what orrery wrote). */
#ifndef ORR_TEST_FITS_IMAGE_H
#define ORR_TEST_FITS_IMAGE_H

/* The primary image's pixels (malloc'ed; free() them) and their count in
 * *npix, or NULL when the file cannot be read. */
float *read_fits_image(const char *path, long *npix);

#endif
