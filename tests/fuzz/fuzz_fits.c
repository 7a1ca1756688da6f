/* Fuzz target for the FITS files orrery reads: the raw planes `orrery
 * compose` reads back (orr_read_fits_planes, src/encode/fits_read.c) and PSF
 * images (orr_psf_load_fits, src/post/psf_fits.c: read, clean, centre,
 * rebin, taper, normalise).
 *
 * Both readers take a path and open it with cfitsio, so the input is
 * written to a temporary file in /tmp (removed after each run) rather than
 * handed over with fits_open_memfile: that would need a second entry point
 * into each reader, and these are fuzzed as users call them.
 *
 * The input is the FITS file itself, read by both readers (unless it
 * mentions ZIMAGE: see mentions_zimage). The PSF options
 * come from its last byte (in a FITS file, the padding of the last block:
 * 0 for data, a blank for a header, which both give the defaults the
 * renderer uses):
 *   bits 0-1: psf.file_subsample - 1 (1..4);
 *   bits 2-3: psf.size: 0 (automatic), 3, 33 or 129;
 *   bits 4-5: 0: no resampling (the file's detector pixels);
 *             1: resampled to 0.04"/pixel from 0.025"/pixel files;
 *             2: centroid centring and background subtraction;
 *             3: resampled to 0.05"/pixel from 0.1"/pixel (upsampled);
 *   bit 6:    no taper (else 0.3, as the renderer);
 *   bit 7:    unused.
 * The file's pixel scale is always given, never taken from the PIXSCALE
 * keyword, when resampling: a tiny PIXSCALE makes the automatic size
 * overflow int (psf_fits.c build_kernel, being fixed on another branch).
 * Define FUZZ_FITS_HEADER_SCALE to fuzz that path too.
 *
 * Errors are fine; a crash, sanitizer report, hang or leak is a bug, and so
 * are a successful read with planes out of range and a PSF kernel that is
 * not odd-sized or holds non-finite values. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "encode/fits_read.h"
#include "fuzz_common.h"
#include "post/convolve.h"
#include "post/psf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *__asan_default_options(void);

/* cfitsio answers a failed allocation with MEMORY_ALLOCATION, and asks for
 * impossible ones on some damaged headers (calloc(4.8e18, 160) once, from a
 * BINTABLE header with a garbled NAXIS2, not reproducible alone: an
 * uninitialised count in cfitsio 4.2). Let such calls fail as they do
 * outside ASan; libFuzzer's -malloc_limit_mb and -rss_limit_mb still catch
 * allocations that succeed and are too large. */
const char *__asan_default_options(void)
{
    return "allocator_may_return_null=1";
}

static void read_planes(const char *path)
{
    orr_plane planes[3];
    int n = -1;
    orr_error err = {0};
    if (orr_read_fits_planes(path, planes, 3, &n, &err) == ORR_OK) {
        if (n < 0 || n > 3)
            abort();
        for (int i = 0; i < n; i++) {
            if (!planes[i].data || planes[i].width != planes[0].width || planes[i].height != planes[0].height)
                abort();
            /* Touch the first and the last pixel. */
            volatile float v = planes[i].data[0] +
                               planes[i].data[(size_t)planes[i].width * (size_t)planes[i].height - 1];
            (void)v;
            orr_plane_free(&planes[i]);
        }
    } else if (n != 0 || err.msg[0] == '\0') {
        abort();
    }
}

static void read_psf(const char *path, uint8_t options)
{
    static const int sizes[4] = {0, 3, 33, 129};
    orr_psf_fits_options opt = {0};
    opt.subsample = 1 + (options & 3);
    opt.size = sizes[(options >> 2) & 3];
    opt.centre = ORR_PSF_CENTRE_PEAK;
    opt.taper = options & 0x40 ? 0 : 0.3;
    switch ((options >> 4) & 3) {
    case 1:
        opt.arcsec_per_pixel = 0.04;
        opt.file_arcsec_per_pixel = 0.025;
        break;
    case 2:
        opt.centre = ORR_PSF_CENTRE_CENTROID;
        opt.subtract_background = 1;
        break;
    case 3:
        opt.arcsec_per_pixel = 0.05;
        opt.file_arcsec_per_pixel = 0.1;
        break;
    }
#ifdef FUZZ_FITS_HEADER_SCALE
    if (options & 0x80)
        opt.file_arcsec_per_pixel = 0;
#endif
    orr_image_kernel k = {0};
    orr_psf_fits_info info;
    orr_error err = {0};
    if (orr_psf_load_fits(path, &opt, &k, &info, &err) == ORR_OK) {
        if (!k.data || k.width < 1 || k.width % 2 == 0 || k.height != k.width)
            abort();
        for (size_t i = 0; i < (size_t)k.width * (size_t)k.height; i++)
            if (!isfinite(k.data[i]))
                abort();
        orr_image_kernel_free(&k);
    } else if (err.msg[0] == '\0') {
        abort();
    }
}

/* Whether the input holds the keyword ZIMAGE (any case), by which cfitsio
 * knows a tile-compressed image. cfitsio 4.2 crashes while merely moving to
 * a damaged compressed HDU (SIGFPE in imcomp_get_compressed_image_par from
 * ffmahd, before orrery can look at the HDU; SEGV in fits_rdecomp on a
 * damaged tile), as libhdf5 does on damaged HDF5 (fuzz_hdf5.c). Those are
 * cfitsio's bugs; both readers refuse compressed images (the tile crash is
 * covered by test_fits and test_psf), so such inputs are skipped here rather
 * than drown the readers' own bugs. */
static int mentions_zimage(const uint8_t *data, size_t size)
{
    static const char key[] = "ZIMAGE";
    for (size_t i = 0; i + 6 <= size; i++) {
        size_t k = 0;
        while (k < 6 && (data[i + k] & ~0x20) == (uint8_t)key[k])
            k++;
        if (k == 6)
            return 1;
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (mentions_zimage(data, size))
        return 0;
    char path[64];
    fuzz_write_input(data, size, "fits", path, sizeof path);
    read_planes(path);
    read_psf(path, size ? data[size - 1] : 0);
    unlink(path);
    return 0;
}
