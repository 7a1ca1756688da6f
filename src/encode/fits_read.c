#include "encode/fits_read.h"

#include <fitsio.h>
#include <stdio.h>
#include <string.h>

#include "core/fits_scan.h"

static orr_status read_failure(const char *path, int hdu, int status, orr_error *err)
{
    char text[FLEN_STATUS] = "";
    fits_get_errstatus(status, text);
    fits_clear_errmsg();
    return orr_fail(err, ORR_ERR_IO, "%s: HDU %d: cannot read FITS image: %s", path, hdu, text);
}

/* One image HDU (the current one) into p; rows are stored bottom-up. */
static orr_status read_hdu(fitsfile *f, const char *path, int hdu, int width, int height, orr_plane *p,
                           orr_error *err)
{
    char name[FLEN_VALUE] = "", unit[FLEN_VALUE] = "";
    int status = 0;
    fits_read_key(f, TSTRING, "EXTNAME", name, NULL, &status);
    status = 0;
    fits_read_key(f, TSTRING, "BUNIT", unit, NULL, &status);
    orr_status st = orr_plane_alloc(p, width, height, name, unit, err);
    status = 0;
    for (int y = 0; !st && y < height && status == 0; y++) {
        LONGLONG first[2] = {1, height - y};
        fits_read_pixll(f, TFLOAT, first, width, NULL, p->data + (size_t)y * (size_t)width, NULL, &status);
    }
    if (!st && status) {
        orr_plane_free(p); /* not handed out: the caller frees only the planes it counts */
        st = read_failure(path, hdu, status, err);
    }
    return st;
}

/* The HDU's data must be in the file before a plane of the size its header
 * claims is allocated (and zeroed): a truncated file, or a header that lies,
 * must not cost a plane of up to 8 GiB for nothing. (cfitsio reads whole
 * 2880-byte blocks, so the last one must be there, padding and all.) */
static orr_status check_data_present(fitsfile *f, const char *path, int hdu, orr_error *err)
{
    LONGLONG head = 0, start = 0, end = 0;
    int status = 0;
    /* orrery writes its planes uncompressed, and cfitsio (4.2) crashes on a
     * damaged tile (fits_rdecomp reads out of bounds), so a tile-compressed
     * HDU is refused before it is decompressed. */
    if (fits_is_compressed_image(f, &status))
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: HDU %d is a tile-compressed image; orrery reads its planes uncompressed (funpack "
                        "the file first)",
                        path, hdu);
    status = 0;
    if (fits_get_hduaddrll(f, &head, &start, &end, &status))
        return read_failure(path, hdu, status, err);
    const LONGLONG size = f->Fptr->logfilesize;
    if (end > size)
        return orr_fail(err, ORR_ERR_FORMAT,
                        "%s: HDU %d: the header calls for %lld bytes of data but the file ends after %lld "
                        "(truncated?)",
                        path, hdu, (long long)(end - start), (long long)(size > start ? size - start : 0));
    return ORR_OK;
}

static orr_status image_size(fitsfile *f, const char *path, int hdu, int *w, int *h, orr_error *err)
{
    int status = 0, naxis = 0;
    long naxes[2] = {0, 0};
    fits_get_img_dim(f, &naxis, &status);
    if (!status && naxis == 2)
        fits_get_img_size(f, 2, naxes, &status);
    if (status)
        return read_failure(path, hdu, status, err);
    if (naxis != 2 || naxes[0] < 1 || naxes[1] < 1 || naxes[0] > 1 << 20 || naxes[1] > 1 << 20)
        return orr_fail(err, ORR_ERR_FORMAT, "%s: HDU %d is not a 2-D image (NAXIS = %d)", path, hdu, naxis);
    *w = (int)naxes[0];
    *h = (int)naxes[1];
    return ORR_OK;
}

/* The scene text orrery stores after the planes (encode/fits.h): no plane. */
static int is_scene_hdu(fitsfile *f)
{
    char name[FLEN_VALUE] = "";
    int status = 0;
    fits_read_key(f, TSTRING, "EXTNAME", name, NULL, &status);
    fits_clear_errmsg();
    return status == 0 && strcmp(name, "SCENE") == 0;
}

orr_status orr_read_fits_planes(const char *path, orr_plane *planes, int max, int *n, orr_error *err)
{
    *n = 0;
    fitsfile *f = NULL;
    int status = 0, nhdu = 0;
    orr_status refused = orr_fits_refuse_compressed(path, "its planes", err);
    if (refused)
        return refused;
    /* fits_open_diskfile takes the name literally: fits_open_file would parse
     * cfitsio's extended syntax, so "run[1]/a.raw.fits" would not open. */
    if (fits_open_diskfile(&f, path, READONLY, &status) || fits_get_num_hdus(f, &nhdu, &status)) {
        char text[FLEN_STATUS] = "";
        fits_get_errstatus(status, text);
        fits_clear_errmsg();
        if (f)
            fits_close_file(f, &status);
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open FITS file: %s", path, text);
    }
    orr_status st = ORR_OK;
    int w0 = 0, h0 = 0;
    for (int hdu = 1; hdu <= nhdu && *n < max && !st; hdu++) {
        int w = 0, h = 0;
        if (fits_movabs_hdu(f, hdu, NULL, &status))
            st = read_failure(path, hdu, status, err);
        if (!st && is_scene_hdu(f))
            continue;
        if (!st)
            st = image_size(f, path, hdu, &w, &h, err);
        if (!st && hdu == 1) {
            w0 = w;
            h0 = h;
        }
        if (!st && (w != w0 || h != h0))
            st = orr_fail(err, ORR_ERR_FORMAT, "%s: HDU %d is %d x %d, HDU 1 is %d x %d", path, hdu, w, h, w0, h0);
        if (!st)
            st = check_data_present(f, path, hdu, err);
        if (!st && !(st = read_hdu(f, path, hdu, w, h, &planes[*n], err)))
            (*n)++;
    }
    status = 0;
    fits_close_file(f, &status);
    if (st) {
        for (int i = 0; i < *n; i++)
            orr_plane_free(&planes[i]);
        *n = 0;
    }
    return st;
}
