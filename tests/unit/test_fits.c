#include <dirent.h>
#include <fitsio.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tmpdir.h"
#include "check.h"
#include "post/psf.h"
#include "encode/fits.h"
#include "encode/fits_read.h"

enum { W = 5, H = 3 };

/* Plane value at (x, y), y = 0 the top row; distinct and exactly representable. */
static float value_at(int plane, int x, int y)
{
    return (plane ? -1.0f : 1.0f) * ((float)(y * 100 + x) + 0.25f);
}

static void make_planes(orr_plane planes[2])
{
    orr_error err;
    CHECK(orr_plane_alloc(&planes[0], W, H, "mass", "Msun / pixel", &err) == ORR_OK);
    CHECK(orr_plane_alloc(&planes[1], W, H, "count", "particles", &err) == ORR_OK);
    for (int p = 0; p < 2; p++)
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                planes[p].data[y * W + x] = value_at(p, x, y);
    planes[0].data[W + 2] = 1.0e30f; /* an extreme value survives too */
}

static void make_header(orr_cards *h)
{
    memset(h, 0, sizeof *h);
    orr_cards_add_string(h, "creator", "orrery test", "lower-case key is upper-cased");
    orr_cards_add_double(h, "BOXSIZE", 62.5, "Mpc/h");
    orr_cards_add_long(h, "NPART", 123456789012LL, "particles");
    orr_cards_add_bool(h, "PERIODIC", 1, "");
    orr_cards_add_string(h, "TOOLONGKEY", "x", "ignored: more than 8 characters");
}

static void check_key_string(fitsfile *f, const char *key, const char *expect)
{
    char value[FLEN_VALUE] = "";
    int status = 0;
    fits_read_key(f, TSTRING, key, value, NULL, &status);
    CHECK(status == 0);
    CHECK(strcmp(value, expect) == 0);
}

/* Reads one HDU back and compares header and pixels with plane p. */
static void check_hdu(fitsfile *f, int hdu, const orr_plane *plane, int p)
{
    int status = 0, type = 0, bitpix = 0, naxis = 0;
    long naxes[2] = {0, 0};
    fits_movabs_hdu(f, hdu, &type, &status);
    CHECK(status == 0 && type == IMAGE_HDU);
    fits_get_img_param(f, 2, &bitpix, &naxis, naxes, &status);
    CHECK(status == 0);
    CHECK(bitpix == FLOAT_IMG);
    CHECK(naxis == 2);
    CHECK(naxes[0] == W);
    CHECK(naxes[1] == H);
    check_key_string(f, "EXTNAME", plane->name);
    check_key_string(f, "BUNIT", plane->unit);
    check_key_string(f, "CREATOR", "orrery test");
    double box = 0;
    LONGLONG npart = 0;
    int periodic = 0;
    char date[FLEN_VALUE] = "";
    fits_read_key(f, TDOUBLE, "BOXSIZE", &box, NULL, &status);
    fits_read_key(f, TLONGLONG, "NPART", &npart, NULL, &status);
    fits_read_key(f, TLOGICAL, "PERIODIC", &periodic, NULL, &status);
    fits_read_key(f, TSTRING, "DATE", date, NULL, &status);
    CHECK(status == 0);
    CHECK_NEAR(box, 62.5, 0);
    CHECK(npart == 123456789012LL);
    CHECK(periodic == 1);
    CHECK(strlen(date) >= 10);
    char card[FLEN_CARD];
    fits_read_card(f, "TOOLONGK", card, &status);
    CHECK(status == KEY_NO_EXIST);
    status = 0;
    fits_clear_errmsg();

    float pixels[W * H];
    long first[2] = {1, 1};
    fits_read_pix(f, TFLOAT, first, W * H, NULL, pixels, NULL, &status);
    CHECK(status == 0);
    /* FITS row 1 is the bottom: plane row H-1. */
    int mismatches = 0;
    for (int r = 0; r < H; r++)
        for (int x = 0; x < W; x++)
            mismatches += pixels[r * W + x] != plane->data[(H - 1 - r) * W + x];
    CHECK(mismatches == 0);
    CHECK(pixels[(H - 1) * W + 3] == value_at(p, 3, 0)); /* top-left region: last FITS row */
}

static void test_round_trip(void)
{
    make_tmpdir();
    orr_plane planes[2];
    make_planes(planes);
    orr_cards header;
    make_header(&header);
    CHECK(header.n == 4);
    char path[512];
    snprintf(path, sizeof path, "%s/render[1].fits", tmpdir); /* brackets: no cfitsio filename syntax */
    orr_error err;
    orr_error_clear(&err);
    orr_status st = orr_write_fits(path, planes, 2, &header, &err);
    CHECK(st == ORR_OK);
    if (st != ORR_OK)
        fprintf(stderr, "  %s\n", err.msg);
    CHECK(count_entries() == 1);

    fitsfile *f = NULL;
    int status = 0, nhdu = 0;
    fits_open_diskfile(&f, path, READONLY, &status);
    CHECK(status == 0);
    if (status == 0) {
        fits_get_num_hdus(f, &nhdu, &status);
        CHECK(nhdu == 2);
        check_hdu(f, 1, &planes[0], 0);
        check_hdu(f, 2, &planes[1], 1);
        char xtension[FLEN_VALUE] = "";
        fits_read_key(f, TSTRING, "XTENSION", xtension, NULL, &status);
        CHECK(status == 0 && strcmp(xtension, "IMAGE") == 0);
        status = 0;
        fits_close_file(f, &status);
    }
    /* orrery's own reader (compose reads raw planes with it) opens the name
     * as it is, brackets and all, rather than as cfitsio's syntax. */
    orr_plane back[3];
    int n = 0;
    st = orr_read_fits_planes(path, back, 3, &n, &err);
    CHECK(st == ORR_OK && n == 2);
    if (st != ORR_OK)
        fprintf(stderr, "  %s\n", err.msg);
    for (int p = 0; p < n; p++) {
        CHECK(back[p].width == W && back[p].height == H);
        CHECK(memcmp(back[p].data, planes[p].data, sizeof(float) * W * H) == 0);
        orr_plane_free(&back[p]);
    }
    orr_plane_free(&planes[0]);
    orr_plane_free(&planes[1]);
    remove_tmpdir();
}

static void test_overwrites_existing_file(void)
{
    make_tmpdir();
    orr_plane planes[2];
    make_planes(planes);
    char path[512];
    snprintf(path, sizeof path, "%s/out.fits", tmpdir);
    FILE *old = fopen(path, "w");
    fputs("old", old);
    fclose(old);
    orr_error err;
    CHECK(orr_write_fits(path, planes, 1, NULL, &err) == ORR_OK);
    fitsfile *f = NULL;
    int status = 0, nhdu = 0;
    fits_open_diskfile(&f, path, READONLY, &status);
    fits_get_num_hdus(f, &nhdu, &status);
    CHECK(status == 0 && nhdu == 1);
    fits_close_file(f, &status);
    CHECK(count_entries() == 1);
    orr_plane_free(&planes[0]);
    orr_plane_free(&planes[1]);
    remove_tmpdir();
}

/* A key cfitsio rejects makes the write fail half-way: the old file must
 * stay as it was and no temporary file may be left. */
static void test_cfitsio_failure_keeps_old_file(void)
{
    make_tmpdir();
    orr_plane planes[2];
    make_planes(planes);
    orr_cards header;
    memset(&header, 0, sizeof header);
    orr_cards_add_string(&header, "BAD=KEY", "x", "");
    CHECK(header.n == 1);
    char path[512];
    snprintf(path, sizeof path, "%s/keep.fits", tmpdir);
    FILE *old = fopen(path, "w");
    fputs("old", old);
    fclose(old);
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_fits(path, planes, 2, &header, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, "keyword"); /* cfitsio's own explanation */
    CHECK(count_entries() == 1);
    char buf[8] = "";
    FILE *f = fopen(path, "r");
    CHECK(f && fgets(buf, sizeof buf, f) && strcmp(buf, "old") == 0);
    if (f)
        fclose(f);
    orr_plane_free(&planes[0]);
    orr_plane_free(&planes[1]);
    remove_tmpdir();
}

static void test_bad_arguments(void)
{
    make_tmpdir();
    orr_plane planes[2];
    make_planes(planes);
    char path[512];
    snprintf(path, sizeof path, "%s/x.fits", tmpdir);
    orr_error err;
    CHECK(orr_write_fits(path, planes, 0, NULL, &err) == ORR_ERR_USAGE);
    CHECK(orr_write_fits(path, NULL, 1, NULL, &err) == ORR_ERR_USAGE);
    orr_plane other;
    CHECK(orr_plane_alloc(&other, W + 1, H, "other", "", &err) == ORR_OK);
    orr_plane mixed[2] = {planes[0], other};
    orr_error_clear(&err);
    CHECK(orr_write_fits(path, mixed, 2, NULL, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "other");
    CHECK(count_entries() == 0);
    /* an output folder below a regular file cannot be written */
    char below[600];
    snprintf(below, sizeof below, "%s/x.fits/y.fits", tmpdir);
    FILE *blocker = fopen(path, "w");
    fclose(blocker);
    CHECK(orr_write_fits(below, planes, 1, NULL, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, path);
    CHECK(count_entries() == 1);
    orr_plane_free(&other);
    orr_plane_free(&planes[0]);
    orr_plane_free(&planes[1]);
    remove_tmpdir();
}

static void test_header_limits(void)
{
    orr_cards h;
    memset(&h, 0, sizeof h);
    for (int i = 0; i < ORR_CARDS_MAX + 5; i++)
        orr_cards_add_long(&h, "K", i, "");
    CHECK(h.n == ORR_CARDS_MAX);
    memset(&h, 0, sizeof h);
    orr_cards_add_long(&h, "", 1, "");
    orr_cards_add_long(&h, NULL, 1, "");
    orr_cards_add_long(&h, "NINECHARS", 1, "");
    orr_cards_add_long(&h, "EIGHTCHR", 1, "");
    CHECK(h.n == 1);
    CHECK(strcmp(h.cards[0].key, "EIGHTCHR") == 0);
}

/* A primary header of 2880 bytes (cards padded to 80 characters, END last). */
static void write_header_only(const char *path, const char *const *cards, int n, size_t extra)
{
    char block[2880];
    memset(block, ' ', sizeof block);
    for (int i = 0; i < n; i++)
        memcpy(block + 80 * i, cards[i], strlen(cards[i]));
    memcpy(block + 80 * n, "END", 3);
    FILE *fp = fopen(path, "wb");
    CHECK(fp != NULL);
    if (!fp)
        return;
    fwrite(block, 1, sizeof block, fp);
    for (size_t i = 0; i < extra; i++)
        fputc(0, fp);
    fclose(fp);
}

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* orr_read_fits_planes (orrery compose) on truncated files and headers that
 * claim more data than the file holds: an error naming the HDU, before a
 * plane of the claimed size is allocated (found by fuzz_fits: a 5760-byte
 * file claiming 65536 x 32767 pixels had it allocate and zero 8 GiB), and no
 * plane leaked when HDU 2 is cut short (fuzz_fits under LeakSanitizer). */
static void test_read_truncated(void)
{
    make_tmpdir();
    orr_plane planes[2], back[3];
    make_planes(planes);
    orr_cards header;
    make_header(&header);
    char path[512], cut[600];
    snprintf(path, sizeof path, "%s/planes.fits", tmpdir);
    orr_error err;
    CHECK(orr_write_fits(path, planes, 2, &header, &err) == ORR_OK);
    int n = -1;
    CHECK(orr_read_fits_planes(path, back, 3, &n, &err) == ORR_OK);
    CHECK(n == 2);
    for (int k = 0; k < n; k++) {
        CHECK(back[k].width == W && back[k].height == H);
        CHECK(back[k].data[W + 2] == planes[k].data[W + 2]);
        orr_plane_free(&back[k]);
    }

    /* Cut inside HDU 2's data, and after it but before the end of its
     * 2880-byte block (cfitsio cannot read that either). */
    long size = file_size(path);
    CHECK(size > 0 && size % 2880 == 0);
    snprintf(cut, sizeof cut, "%s/cut.fits", tmpdir);
    for (int pass = 0; pass < 2; pass++) {
        long keep = pass == 0 ? size - 2880 + 8 : size - 2880 + W * H * 4; /* 2 pixels / all of HDU 2's data */
        FILE *in = fopen(path, "rb"), *out = fopen(cut, "wb");
        CHECK(in && out);
        for (long i = 0; in && out && i < keep; i++)
            fputc(fgetc(in), out);
        if (in)
            fclose(in);
        if (out)
            fclose(out);
        n = -1;
        CHECK(orr_read_fits_planes(cut, back, 3, &n, &err) == ORR_ERR_FORMAT);
        CHECK(n == 0);
        CHECK_CONTAINS(err.msg, "HDU 2");
        CHECK_CONTAINS(err.msg, "truncated");
    }

    /* A header alone, claiming the largest plane orrery draws. */
    const char *cards[] = {"SIMPLE  =                    T", "BITPIX  =                  -32",
                           "NAXIS   =                    2", "NAXIS1  =                65536",
                           "NAXIS2  =                32767"};
    snprintf(cut, sizeof cut, "%s/claims.fits", tmpdir);
    write_header_only(cut, cards, 5, 2880);
    n = -1;
    CHECK(orr_read_fits_planes(cut, back, 3, &n, &err) == ORR_ERR_FORMAT);
    CHECK(n == 0);
    CHECK_CONTAINS(err.msg, "HDU 1");
    CHECK_CONTAINS(err.msg, "8589674880 bytes of data"); /* 65536 x 32767 x 4, in blocks */

    orr_plane_free(&planes[0]);
    orr_plane_free(&planes[1]);
    remove_tmpdir();
}

/* A tile-compressed HDU is refused before cfitsio decompresses it: orrery
 * writes its planes uncompressed, and cfitsio 4.2 crashes on a damaged tile
 * (fuzz_fits: SEGV in fits_rdecomp; tests/data/fits/regress_rice_tile_damaged.fits). */
static void test_read_compressed(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/packed.fits", tmpdir);
    fitsfile *f = NULL;
    int status = 0, ipx[W * H] = {0};
    long naxes[2] = {W, H};
    float px[W * H] = {0};
    fits_create_file(&f, path, &status);
    fits_create_img(f, FLOAT_IMG, 2, naxes, &status);
    fits_write_img(f, TFLOAT, 1, W * H, px, &status);
    fits_set_compression_type(f, RICE_1, &status);
    fits_create_img(f, LONG_IMG, 2, naxes, &status);
    fits_write_img(f, TINT, 1, W * H, ipx, &status);
    fits_close_file(f, &status);
    CHECK(status == 0);
    orr_plane back[3];
    int n = -1;
    orr_error err;
    CHECK(orr_read_fits_planes(path, back, 3, &n, &err) == ORR_ERR_FORMAT);
    CHECK(n == 0);
    CHECK_CONTAINS(err.msg, "HDU 2 is a tile-compressed image");
    remove_tmpdir();
    /* The file fuzz_fits found: HDU 2's Rice tiles damaged. */
    const char *damaged = ORRERY_TEST_DATA "/fits/regress_rice_tile_damaged.fits";
    CHECK(orr_read_fits_planes(damaged, back, 3, &n, &err) == ORR_ERR_FORMAT);
    CHECK(n == 0);
    CHECK_CONTAINS(err.msg, "HDU 2 is a tile-compressed image");
    /* One whose compressed header is damaged: cfitsio 4.2 dies of SIGFPE
     * merely moving to HDU 2, so orrery's own scan of the headers must
     * refuse it before cfitsio opens the file. */
    const char *fpe = ORRERY_TEST_DATA "/fits/regress_cfitsio_fpe_damaged_compressed_header.fits";
    CHECK(orr_read_fits_planes(fpe, back, 3, &n, &err) == ORR_ERR_FORMAT);
    CHECK(n == 0);
    CHECK_CONTAINS(err.msg, "HDU 2 is a tile-compressed image");
    orr_image_kernel k = {0};
    CHECK(orr_psf_load_fits(fpe, NULL, &k, NULL, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "a PSF uncompressed");
}

/* Every HDU's DATASUM and CHECKSUM as cfitsio recomputes them from the
 * file: the data sum orrery takes from memory must be the standard's,
 * whatever the bits (NaN, infinities, negative zero, words whose sum
 * carries many times) and with a data unit that ends in fill. */
static void test_checksums_verify(void)
{
    make_tmpdir();
    enum { CW = 37, CH = 29 };
    orr_plane planes[2];
    orr_error err;
    CHECK(orr_plane_alloc(&planes[0], CW, CH, "odd", "", &err) == ORR_OK);
    CHECK(orr_plane_alloc(&planes[1], CW, CH, "carries", "", &err) == ORR_OK);
    const uint32_t specials[] = {0x7FC00000u, 0xFFFFFFFFu, 0x7F800000u, 0xFF800000u, 0x80000000u, 0x00000001u};
    for (int i = 0; i < CW * CH; i++) {
        uint32_t word = i < 6 ? specials[i] : 0x9E3779B9u * (uint32_t)i;
        memcpy(&planes[0].data[i], &word, sizeof word);
        uint32_t high = 0xFFFFFFFEu;
        memcpy(&planes[1].data[i], &high, sizeof high);
    }
    const orr_fits_compression kinds[] = {ORR_FITS_UNCOMPRESSED, ORR_FITS_GZIP};
    for (int k = 0; k < 2; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/sums%d.fits", tmpdir, k);
        CHECK(orr_write_fits_compressed(path, planes, 2, NULL, kinds[k], &err) == ORR_OK);
        fitsfile *f = NULL;
        int status = 0, nhdu = 0;
        fits_open_diskfile(&f, path, READONLY, &status);
        fits_get_num_hdus(f, &nhdu, &status);
        CHECK(status == 0 && nhdu == 2 + k);
        for (int h = 1; h <= nhdu && status == 0; h++) {
            int data_ok = 0, hdu_ok = 0;
            fits_movabs_hdu(f, h, NULL, &status);
            fits_verify_chksum(f, &data_ok, &hdu_ok, &status);
            CHECK(status == 0 && data_ok == 1 && hdu_ok == 1);
        }
        fits_close_file(f, &status);
    }
    orr_plane_free(&planes[0]);
    orr_plane_free(&planes[1]);
    remove_tmpdir();
}

int main(void)
{
    RUN(test_round_trip);
    RUN(test_checksums_verify);
    RUN(test_overwrites_existing_file);
    RUN(test_cfitsio_failure_keeps_old_file);
    RUN(test_bad_arguments);
    RUN(test_header_limits);
    RUN(test_read_truncated);
    RUN(test_read_compressed);
    return check_summary();
}
