#include "encode/fits.h"

#include <ctype.h>
#include <errno.h>
#include <fitsio.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "core/atomic.h"

const orr_named orr_fits_compression_names[] = {{"none", ORR_FITS_UNCOMPRESSED}, {"gzip", ORR_FITS_GZIP}, {NULL, 0}};

/* ---- writing ------------------------------------------------------------ */

/* cfitsio takes non-const pointers for values it only reads, hence the
 * copies. update (not write) so a caller's card replaces ours of that name. */
static int write_card(fitsfile *f, const orr_card *c, int *status)
{
    char key[sizeof c->key], comment[sizeof c->comment];
    memcpy(key, c->key, sizeof key);
    memcpy(comment, c->comment, sizeof comment);
    switch (c->type) {
    case ORR_CARD_STRING: {
        char str[sizeof c->str];
        memcpy(str, c->str, sizeof str);
        return fits_update_key(f, TSTRING, key, str, comment, status);
    }
    case ORR_CARD_DOUBLE: {
        double d = c->dbl;
        return fits_update_key(f, TDOUBLE, key, &d, comment, status);
    }
    case ORR_CARD_LONG: {
        LONGLONG v = c->lng;
        return fits_update_key(f, TLONGLONG, key, &v, comment, status);
    }
    case ORR_CARD_BOOL: {
        int b = c->lng != 0;
        return fits_update_key(f, TLOGICAL, key, &b, comment, status);
    }
    case ORR_CARD_UNSET:
        break;
    }
    return *status;
}

static int write_string_key(fitsfile *f, const char *key, const char *value, const char *comment, int *status)
{
    char k[16], v[ORR_PLANE_NAME_MAX], c[72];
    snprintf(k, sizeof k, "%s", key);
    snprintf(v, sizeof v, "%s", value);
    snprintf(c, sizeof c, "%s", comment);
    return fits_update_key(f, TSTRING, k, v, c, status);
}

/* The FITS standard's data checksum (DATASUM) of a float plane as an
 * uncompressed image HDU holds it: the 32-bit ones' complement sum of the
 * data's big-endian words, which are the floats' bit patterns (the zero
 * fill after the data adds nothing). Summed from memory on every thread,
 * in integers, so any order gives the same value. */
static unsigned long plane_datasum(const orr_plane *p)
{
    size_t n = (size_t)p->width * (size_t)p->height;
    uint64_t sum = 0; /* at most 2^32 words of 32 bits: no overflow before the fold */
#pragma omp parallel for reduction(+ : sum) schedule(static)
    for (size_t i = 0; i < n; i++) {
        uint32_t word;
        memcpy(&word, &p->data[i], sizeof word);
        sum += word;
    }
    while (sum >> 32) /* end-around carry */
        sum = (sum & 0xFFFFFFFFu) + (sum >> 32);
    return (unsigned long)sum;
}

/* DATASUM with its value and CHECKSUM zeroed, written into the header
 * before the data so that they take no room the data would have to move
 * for; fits_update_chksum sets CHECKSUM afterwards from the header alone. */
static int write_datasum(fitsfile *f, unsigned long datasum, int *status)
{
    char date[32], value[24], data_comment[72], hdu_comment[72];
    fits_get_system_time(date, NULL, status);
    snprintf(value, sizeof value, "%lu", datasum);
    snprintf(data_comment, sizeof data_comment, "data unit checksum updated %s", date);
    snprintf(hdu_comment, sizeof hdu_comment, "HDU checksum updated %s", date);
    fits_update_key(f, TSTRING, "CHECKSUM", "0000000000000000", hdu_comment, status);
    return fits_update_key(f, TSTRING, "DATASUM", value, data_comment, status);
}

/* One image HDU: header, then the rows bottom-up, because FITS pixel (1,1)
 * is the lower left corner while plane row 0 is the top of the picture. */
static int write_plane_hdu(fitsfile *f, const orr_plane *p, const orr_cards *header, int *status)
{
    long naxes[2] = {p->width, p->height};
    fits_create_img(f, FLOAT_IMG, 2, naxes, status);
    if (p->name[0])
        write_string_key(f, "EXTNAME", p->name, "plane", status);
    if (p->unit[0])
        write_string_key(f, "BUNIT", p->unit, "unit of the pixel values", status);
    for (int i = 0; header && i < header->n; i++)
        write_card(f, &header->cards[i], status);
    fits_write_date(f, status);
    /* A tile-compressed image's data are its compressed tiles, summed only
     * once written; a plain image's data are the plane's floats, summed
     * here rather than read back through cfitsio's buffers after writing
     * (805 MB at 8192², 1.6 s of one core). */
    int compressed = fits_is_compressed_image(f, status);
    if (!compressed)
        write_datasum(f, plane_datasum(p), status);
    for (int y = 0; y < p->height && *status == 0; y++) {
        LONGLONG first[2] = {1, p->height - y};
        float *row = p->data + (size_t)y * (size_t)p->width;
        errno = 0; /* so a failed write's errno is its own (see system_errno) */
        fits_write_pixll(f, TFLOAT, first, p->width, row, status);
    }
    /* Last, over the final header and data, so astropy and fitsverify can
     * prove the HDU arrived intact (a truncated copy, a flipped bit). */
    return compressed ? fits_write_chksum(f, status) : fits_update_chksum(f, status);
}

/* The scene as the file's last HDU (orr_cards.scene): its bytes as
 * a one-dimensional image of unsigned bytes, so that any text (UTF-8, long
 * lines) is kept exactly and astropy gives it back with
 * fits.getdata(path, "SCENE").tobytes().decode(). Never compressed: it is
 * small, and a plain image is what every FITS reader knows. */
static int write_scene_hdu(fitsfile *f, const char *text, int *status)
{
    LONGLONG n = (LONGLONG)strlen(text), first = 1;
    fits_set_compression_type(f, 0, status); /* 0: no compression */
    fits_create_imgll(f, BYTE_IMG, 1, &n, status);
    write_string_key(f, "EXTNAME", "SCENE", "the scene these planes were rendered from", status);
    write_string_key(f, "CONTENT", "YAML", "an orrery scene: the data are its UTF-8 text", status);
    fits_write_comment(f, "Read it back: fits.getdata(path, 'SCENE').tobytes().decode() (astropy).", status);
    fits_write_date(f, status);
    errno = 0;
    fits_write_img(f, TBYTE, first, n, (void *)text, status); /* only read, though not const */
    return fits_write_chksum(f, status);
}

static int has_scene(const orr_cards *h)
{
    return h && h->scene && h->scene[0];
}

/* The system's reason for a failed cfitsio call (ENOSPC, EFBIG, EIO...),
 * read from errno right after it, or 0. cfitsio reports a full disk only
 * as "error writing to FITS file" (or "reading", when it reads a buffer
 * back), so the reason comes from errno; only for its file I/O statuses,
 * since after its other failures errno is unrelated. */
static int system_errno(int status)
{
    int io = status >= FILE_NOT_OPENED && status <= FILE_NOT_CLOSED;
    return io ? errno : 0;
}

static orr_status check_planes(const char *path, const orr_plane *planes, int nplanes, orr_error *err)
{
    if (!path || !path[0])
        return orr_fail(err, ORR_ERR_USAGE, "FITS output: no file name given");
    if (!planes || nplanes < 1)
        return orr_fail(err, ORR_ERR_USAGE, "%s: no image plane to write", path);
    for (int i = 0; i < nplanes; i++) {
        const orr_plane *p = &planes[i];
        if (!p->data || p->width <= 0 || p->height <= 0)
            return orr_fail(err, ORR_ERR_USAGE, "%s: plane %d (%s) is empty", path, i + 1, p->name);
        if (p->width != planes[0].width || p->height != planes[0].height)
            return orr_fail(err, ORR_ERR_USAGE, "%s: plane %d (%s) is %d x %d but plane 1 is %d x %d", path,
                            i + 1, p->name, p->width, p->height, planes[0].width, planes[0].height);
    }
    return ORR_OK;
}

/* The system's reason when there is one (sys_errno), else cfitsio's short
 * text for the status plus the first detail on its stack. */
static orr_status fits_failure(const char *path, int status, int sys_errno, orr_error *err)
{
    char text[FLEN_STATUS] = "", detail[FLEN_ERRMSG] = "";
    fits_get_errstatus(status, text);
    fits_read_errmsg(detail);
    fits_clear_errmsg();
    if (sys_errno)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write FITS file: %s (cfitsio: %s)", path, strerror(sys_errno),
                        text);
    if (detail[0])
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write FITS file: %s (%s)", path, text, detail);
    return orr_fail(err, ORR_ERR_IO, "%s: cannot write FITS file: %s", path, text);
}

typedef struct star_body {
    const orr_star_table *table;
    const orr_cards *header;
} star_body;

/* What goes into a FITS file between creating and closing it. */
typedef int (*fits_body_fn)(fitsfile *f, const void *ctx, int *status, int *sys_errno);

/* Creates path atomically, has body write its HDUs, and closes it; any
 * failure removes the temporary file and names cfitsio's (or the
 * system's) reason. */
static orr_status write_fits_file(const char *path, fits_body_fn body, const void *ctx, orr_error *err)
{
    orr_atomic_file af;
    orr_status st = orr_atomic_begin(&af, path, err);
    if (st != ORR_OK)
        return st;

    /* cfitsio's disk-file variant does not parse the name for its extended
     * syntax (brackets in a file name are harmless) but neither does it
     * accept "!" to overwrite, so the empty file mkstemp made is removed and
     * cfitsio creates the name afresh; it refuses should anyone else have
     * taken the name meanwhile, and then that file is not ours to remove. */
    unlink(af.temp_path);
    fitsfile *f = NULL;
    int status = 0, sys_errno = 0;
    errno = 0;
    if (fits_create_diskfile(&f, af.temp_path, &status) != 0) {
        af.temp_path[0] = '\0';
        return fits_failure(path, status, system_errno(status), err);
    }
    body(f, ctx, &status, &sys_errno);
    int close_status = 0;
    errno = 0;
    if (f && fits_close_file(f, &close_status) && !status)
        sys_errno = system_errno(close_status);
    if (status == 0)
        status = close_status;
    if (status != 0) {
        orr_atomic_abort(&af);
        return fits_failure(path, status, sys_errno, err);
    }
    return orr_atomic_commit(&af, err);
}

typedef struct image_body {
    const orr_plane *planes;
    int nplanes;
    const orr_cards *header;
    orr_fits_compression compression;
} image_body;

/* Asks cfitsio to tile-compress the images created from now on, without
 * quantising floats (quantize level 0: lossless). The primary HDU cannot
 * be compressed: cfitsio puts an empty one first. */
static int request_compression(fitsfile *f, orr_fits_compression c, int *status)
{
    if (c == ORR_FITS_UNCOMPRESSED)
        return *status;
    fits_set_compression_type(f, GZIP_2, status);
    fits_set_quantize_level(f, 0.0f, status);
    return *status;
}

static int write_image_hdus(fitsfile *f, const void *ctx, int *status, int *sys_errno)
{
    const image_body *b = ctx;
    request_compression(f, b->compression, status);
    for (int i = 0; i < b->nplanes && *status == 0; i++) {
        errno = 0;
        if (write_plane_hdu(f, &b->planes[i], b->header, status))
            *sys_errno = system_errno(*status);
    }
    if (*status == 0 && has_scene(b->header) && write_scene_hdu(f, b->header->scene, status))
        *sys_errno = system_errno(*status);
    /* The empty primary HDU cfitsio puts before compressed images gets its
     * checksums too: every HDU of the file can be verified. */
    if (b->compression != ORR_FITS_UNCOMPRESSED && *status == 0)
        fits_movabs_hdu(f, 1, NULL, status);
    if (b->compression != ORR_FITS_UNCOMPRESSED && *status == 0)
        fits_write_chksum(f, status);
    return *status;
}

int orr_fits_thread_safe(void)
{
    return fits_is_reentrant();
}

orr_status orr_write_fits(const char *path, const orr_plane *planes, int nplanes,
                          const orr_cards *header, orr_error *err)
{
    orr_status st = check_planes(path, planes, nplanes, err);
    if (st != ORR_OK)
        return st;
    image_body b = {planes, nplanes, header, ORR_FITS_UNCOMPRESSED};
    return write_fits_file(path, write_image_hdus, &b, err);
}

orr_status orr_write_fits_compressed(const char *path, const orr_plane *planes, int nplanes,
                                     const orr_cards *header, orr_fits_compression compression,
                                     orr_error *err)
{
    orr_status st = check_planes(path, planes, nplanes, err);
    if (st != ORR_OK)
        return st;
    image_body b = {planes, nplanes, header, compression};
    return write_fits_file(path, write_image_hdus, &b, err);
}

/* ---- HEALPix maps ---- */

typedef struct healpix_body {
    const orr_plane *planes;
    int nplanes;
    const orr_healpix_info *info;
    const orr_cards *header;
} healpix_body;

/* The HEALPix keywords (the HEALPix FITS convention, as healpy and the
 * HEALPix libraries write and read them). */
void orr_fits_add_healpix(orr_cards *h, const orr_healpix_info *info)
{
    orr_cards_add_string(h, "PIXTYPE", "HEALPIX", "HEALPix pixelisation");
    orr_cards_add_string(h, "ORDERING", info->nested ? "NESTED" : "RING", "pixel ordering scheme");
    orr_cards_add_long(h, "NSIDE", info->nside, "resolution parameter");
    orr_cards_add_long(h, "FIRSTPIX", 0, "first pixel number (0-based)");
    orr_cards_add_long(h, "LASTPIX", 12LL * info->nside * info->nside - 1, "last pixel number (0-based)");
    orr_cards_add_string(h, "INDXSCHM", "IMPLICIT", "indexing: implicit (every pixel, in order)");
    orr_cards_add_string(h, "OBJECT", "FULLSKY", "sky coverage");
    if (info->coordsys && info->coordsys[0])
        orr_cards_add_string(h, "COORDSYS", info->coordsys, "coordinate system");
}

static void write_healpix_keys(fitsfile *f, const orr_healpix_info *info, int *status)
{
    orr_cards keys = {0};
    orr_fits_add_healpix(&keys, info);
    for (int i = 0; i < keys.n; i++)
        write_card(f, &keys.cards[i], status);
}

/* An empty primary HDU, then one binary table: a float column per plane,
 * one row per pixel. */
static int write_healpix_hdus(fitsfile *f, const void *ctx, int *status, int *sys_errno)
{
    const healpix_body *b = ctx;
    long npix = (long)b->planes[0].width * b->planes[0].height;
    fits_create_img(f, FLOAT_IMG, 0, NULL, status);
    fits_write_chksum(f, status);
    char *ttype[3], *tform[3], *tunit[3], forms[3][4];
    for (int i = 0; i < b->nplanes; i++) {
        ttype[i] = (char *)b->planes[i].name;
        tunit[i] = (char *)b->planes[i].unit;
        snprintf(forms[i], sizeof forms[i], "1E");
        tform[i] = forms[i];
    }
    fits_create_tbl(f, BINARY_TBL, npix, b->nplanes, ttype, tform, tunit, "xtension", status);
    write_healpix_keys(f, b->info, status);
    for (int i = 0; b->header && i < b->header->n; i++)
        write_card(f, &b->header->cards[i], status);
    fits_write_date(f, status);
    for (int i = 0; i < b->nplanes && *status == 0; i++) {
        errno = 0;
        if (fits_write_col(f, TFLOAT, i + 1, 1, 1, npix, b->planes[i].data, status))
            *sys_errno = system_errno(*status);
    }
    fits_write_chksum(f, status);
    if (*status == 0 && has_scene(b->header) && write_scene_hdu(f, b->header->scene, status))
        *sys_errno = system_errno(*status);
    return *status;
}

orr_status orr_write_healpix_fits(const char *path, const orr_plane *planes, int nplanes,
                                  const orr_healpix_info *info, const orr_cards *header, orr_error *err)
{
    orr_status st = check_planes(path, planes, nplanes, err);
    if (st != ORR_OK)
        return st;
    long npix = 12L * info->nside * info->nside;
    if (nplanes > 3 || (long)planes[0].width * planes[0].height != npix)
        return orr_fail(err, ORR_ERR_USAGE, "%s: %d planes of %d x %d pixels are no HEALPix map of nside %d", path,
                        nplanes, planes[0].width, planes[0].height, info->nside);
    healpix_body b = {planes, nplanes, info, header};
    return write_fits_file(path, write_healpix_hdus, &b, err);
}

/* ---- the star list ---- */

static int write_star_hdus(fitsfile *f, const void *ctx, int *status, int *sys_errno)
{
    const orr_star_table *t = ((const star_body *)ctx)->table;
    const orr_cards *header = ((const star_body *)ctx)->header;
    fits_create_img(f, FLOAT_IMG, 0, NULL, status);
    for (int i = 0; header && i < header->n; i++)
        write_card(f, &header->cards[i], status);
    fits_write_date(f, status);
    fits_write_chksum(f, status);
    char *ttype[] = {"L", "B", "V", "BV", "MV", "DIST", "PARTICLE", "STAR"};
    char *tform[] = {"1D", "1D", "1E", "1E", "1E", "1E", "1K", "1J"};
    char *tunit[] = {"deg", "deg", "mag", "mag", "mag", "pc", "", ""};
    fits_create_tbl(f, BINARY_TBL, (LONGLONG)t->n, 8, ttype, tform, tunit, "STARS", status);
    write_string_key(f, "MAGSYS", "Johnson V", "apparent V with the dust in front; BV unreddened", status);
    if (t->n) {
        LONGLONG n = (LONGLONG)t->n;
        errno = 0;
        fits_write_col(f, TDOUBLE, 1, 1, 1, n, (void *)t->l, status);
        fits_write_col(f, TDOUBLE, 2, 1, 1, n, (void *)t->b, status);
        fits_write_col(f, TFLOAT, 3, 1, 1, n, (void *)t->v, status);
        fits_write_col(f, TFLOAT, 4, 1, 1, n, (void *)t->bv, status);
        fits_write_col(f, TFLOAT, 5, 1, 1, n, (void *)t->abs_v, status);
        fits_write_col(f, TFLOAT, 6, 1, 1, n, (void *)t->dist_pc, status);
        fits_write_col(f, TLONGLONG, 7, 1, 1, n, (void *)t->parent, status);
        fits_write_col(f, TINT, 8, 1, 1, n, (void *)t->index, status);
    }
    fits_write_chksum(f, status);
    if (*status)
        *sys_errno = system_errno(*status);
    return *status;
}

orr_status orr_write_star_table(const char *path, const orr_star_table *t, const orr_cards *header,
                                orr_error *err)
{
    star_body b = {t, header};
    return write_fits_file(path, write_star_hdus, &b, err);
}
