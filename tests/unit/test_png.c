#include <dirent.h>
#include <omp.h>
#include <png.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tmpdir.h"
#include "check.h"
#include "core/srgb_code.h"
#include "encode/png.h"

enum { W = 4, H = 2 };

/* Chosen inputs and the codes the documented rounding gives for them. */
static const float inputs[W * H * 3] = {
    0.0f, 1.0f, 0.5f,   0.25f, -0.2f, 1.7f,  NAN, 0.1f, 0.75f,  1.0f / 255, 0.999f, 0.002f,
    0.9f, 0.3f, 0.6f,   0.0f, 0.0f, 0.0f,    1.0f, 1.0f, 1.0f,  0.05f, 0.15f, 0.35f,
};

static unsigned expected(float v, unsigned max)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return max;
    return (unsigned)((double)v * max + 0.5);
}

typedef struct decoded {
    png_uint_32 width, height;
    int bit_depth, color_type, srgb;
    unsigned values[W * H * 3];
    int has_software, has_description;
} decoded;

/* Reads a PNG with libpng's low-level API; returns 0 on any error. */
static int read_png(const char *path, decoded *out)
{
    memset(out, 0, sizeof *out);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return 0;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return 0;
    }
    png_init_io(png, fp);
    png_read_info(png, info);
    int interlace = 0, compression = 0, filter = 0;
    png_get_IHDR(png, info, &out->width, &out->height, &out->bit_depth, &out->color_type, &interlace,
                 &compression, &filter);
    int intent = -1;
    out->srgb = png_get_sRGB(png, info, &intent) != 0;
    if (out->width == W && out->height == H && out->color_type == PNG_COLOR_TYPE_RGB) {
        png_byte row[W * 3 * 2];
        for (int y = 0; y < H; y++) {
            png_read_row(png, row, NULL);
            for (int i = 0; i < W * 3; i++)
                out->values[y * W * 3 + i] =
                    out->bit_depth == 16 ? (unsigned)(row[2 * i] << 8 | row[2 * i + 1]) : row[i];
        }
    }
    png_textp text = NULL;
    int ntext = png_get_text(png, info, &text, NULL);
    for (int i = 0; i < ntext; i++) {
        if (!strcmp(text[i].key, "Software") && !strcmp(text[i].text, "orrery test"))
            out->has_software = 1;
        if (!strcmp(text[i].key, "Description") && !strcmp(text[i].text, "two rows of chosen values"))
            out->has_description = 1;
    }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return 1;
}

static const orr_png_text texts[] = {
    {"Software", "orrery test"},
    {"Description", "two rows of chosen values"},
};

static void round_trip(int bits)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/image.png", tmpdir);
    orr_error err;
    orr_error_clear(&err);
    orr_status st = orr_write_png_rgb(path, W, H, inputs, bits, texts, 2, &err);
    CHECK(st == ORR_OK);
    if (st != ORR_OK)
        fprintf(stderr, "  %s\n", err.msg);
    CHECK(count_entries() == 1);
    decoded d;
    CHECK(read_png(path, &d));
    CHECK(d.width == W && d.height == H);
    CHECK(d.bit_depth == bits);
    CHECK(d.color_type == PNG_COLOR_TYPE_RGB);
    CHECK(d.srgb);
    CHECK(d.has_software);
    CHECK(d.has_description);
    unsigned max = bits == 8 ? 255 : 65535;
    int mismatches = 0;
    for (int i = 0; i < W * H * 3; i++)
        mismatches += d.values[i] != expected(inputs[i], max);
    CHECK(mismatches == 0);
    /* a few codes spelled out, row 0 first (the top of the image) */
    if (bits == 8) {
        CHECK(d.values[0] == 0 && d.values[1] == 255 && d.values[2] == 128);
        CHECK(d.values[3] == 64 && d.values[4] == 0 && d.values[5] == 255);
        CHECK(d.values[6] == 0 && d.values[7] == 26 && d.values[9] == 1);
        CHECK(d.values[13] == 77); /* 0.3f * 255 = 76.5000031 -> 77 */
    } else {
        CHECK(d.values[0] == 0 && d.values[1] == 65535 && d.values[2] == 32768);
        CHECK(d.values[3] == 16384 && d.values[4] == 0 && d.values[5] == 65535);
        CHECK(d.values[7] == 6554 && d.values[8] == 49151 && d.values[9] == 257);
    }
    remove_tmpdir();
}

static void test_round_trip_8(void) { round_trip(8); }
static void test_round_trip_16(void) { round_trip(16); }

static void test_bad_bits_and_arguments(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/image.png", tmpdir);
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_png_rgb(path, W, H, inputs, 12, NULL, 0, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "12");
    CHECK(orr_write_png_rgb(path, 0, H, inputs, 8, NULL, 0, &err) == ORR_ERR_USAGE);
    const orr_png_text bad_key[] = {{"", "empty key"}};
    CHECK(orr_write_png_rgb(path, W, H, inputs, 8, bad_key, 1, &err) == ORR_ERR_USAGE);
    CHECK(count_entries() == 0);
    remove_tmpdir();
}

static void test_unwritable_folder(void)
{
    make_tmpdir();
    char file[512], path[600];
    snprintf(file, sizeof file, "%s/regular", tmpdir);
    FILE *f = fopen(file, "w");
    fclose(f);
    snprintf(path, sizeof path, "%s/image.png", file);
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_png_rgb(path, W, H, inputs, 8, NULL, 0, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, file);
    CHECK(count_entries() == 1);
    remove_tmpdir();
}

/* libpng rejects a width above its default limit of a million pixels from
 * inside png_set_IHDR: the error must come back through longjmp as a
 * message, with the old file intact and no temporary file left. */
static void test_libpng_error_keeps_old_file(void)
{
    make_tmpdir();
    char path[512];
    snprintf(path, sizeof path, "%s/keep.png", tmpdir);
    FILE *f = fopen(path, "w");
    fputs("old", f);
    fclose(f);
    int wide = 1000001;
    float *rgb = calloc((size_t)wide * 3, sizeof *rgb);
    orr_error err;
    orr_error_clear(&err);
    CHECK(orr_write_png_rgb(path, wide, 1, rgb, 8, texts, 2, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, "IHDR");
    free(rgb);
    CHECK(count_entries() == 1);
    char buf[8] = "";
    f = fopen(path, "r");
    CHECK(f && fgets(buf, sizeof buf, f) && strcmp(buf, "old") == 0);
    if (f)
        fclose(f);
    remove_tmpdir();
}

/* ---- the bands: a picture of several, on any number of threads ---- */

enum { BW = 1000, BH = 1300 }; /* 8-bit RGB: 4 bands; 16-bit RGBA: 11 */

/* Gradients, noise, NaN and out-of-range values: rows that compress unevenly. */
static float band_value(int y, size_t i)
{
    uint32_t h = (uint32_t)(y * 2654435761u) ^ (uint32_t)(i * 40503u);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    if (h % 97 == 0)
        return NAN;
    if (h % 89 == 0)
        return 1.5f;
    if ((y / 100) % 2)
        return (float)(h % 1000) / 999.0f;
    return (float)(i % 300) / 299.0f * (float)y / BH - 0.01f;
}

static float *band_picture(int channels)
{
    float *v = malloc((size_t)BW * BH * (size_t)channels * sizeof *v);
    for (int y = 0; y < BH; y++)
        for (size_t i = 0; i < (size_t)BW * (size_t)channels; i++)
            v[(size_t)y * BW * (size_t)channels + i] = band_value(y, i);
    return v;
}

typedef struct row_ctx {
    int channels, bits;
} row_ctx;

static void make_row(void *ctx, int y, float *scratch, uint16_t *codes)
{
    const row_ctx *c = ctx;
    size_t n = (size_t)BW * (size_t)c->channels;
    for (size_t i = 0; i < n; i++)
        scratch[i] = band_value(y, i);
    orr_codes_of(scratch, n, c->bits, codes);
}

static unsigned char *file_bytes(const char *path, long *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    *size = ftell(f);
    rewind(f);
    unsigned char *b = malloc((size_t)*size);
    if (fread(b, 1, (size_t)*size, f) != (size_t)*size)
        *size = -1;
    fclose(f);
    return b;
}

/* libpng's decoding of path equals the documented rounding of v. */
static int decodes_to(const char *path, const float *v, int channels, int bits)
{
    FILE *fp = fopen(path, "rb");
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        if (fp)
            fclose(fp);
        return 0;
    }
    png_init_io(png, fp);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
    int ok = png_get_image_width(png, info) == BW && png_get_image_height(png, info) == BH &&
             png_get_bit_depth(png, info) == bits && png_get_channels(png, info) == channels;
    png_bytep *rows = png_get_rows(png, info);
    unsigned max = bits == 8 ? 255 : 65535;
    for (int y = 0; ok && y < BH; y++)
        for (size_t i = 0; ok && i < (size_t)BW * (size_t)channels; i++) {
            unsigned code = bits == 8 ? rows[y][i] : (unsigned)(rows[y][2 * i] << 8 | rows[y][2 * i + 1]);
            ok = code == expected(v[(size_t)y * BW * (size_t)channels + i], max);
        }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return ok;
}

/* The same bytes on 1 and 3 threads, from the picture or from its rows,
 * and libpng reads back every value. */
static void bands_alike(int channels, int bits)
{
    make_tmpdir();
    float *v = band_picture(channels);
    char path[3][512];
    orr_error err;
    orr_error_clear(&err);
    int saved = omp_get_max_threads();
    row_ctx ctx = {channels, bits};
    for (int k = 0; k < 3; k++) {
        snprintf(path[k], sizeof path[k], "%s/bands-%d.png", tmpdir, k);
        omp_set_num_threads(k == 0 ? 1 : 3);
        orr_png_rows rows = {BW, BH, channels, bits, k == 2 ? NULL : v, make_row, &ctx};
        CHECK(orr_write_png_rows(path[k], &rows, texts, 2, &err) == ORR_OK);
    }
    omp_set_num_threads(saved);
    long size[3];
    unsigned char *b[3];
    for (int k = 0; k < 3; k++)
        b[k] = file_bytes(path[k], &size[k]);
    CHECK(b[0] && b[1] && b[2] && size[0] > 0);
    CHECK(size[0] == size[1] && size[0] == size[2]);
    CHECK(size[0] == size[1] && !memcmp(b[0], b[1], (size_t)size[0]));
    CHECK(size[0] == size[2] && !memcmp(b[0], b[2], (size_t)size[0]));
    CHECK(decodes_to(path[1], v, channels, bits));
    decoded d;
    CHECK(read_png(path[1], &d) && d.has_software && d.has_description && d.srgb);
    for (int k = 0; k < 3; k++)
        free(b[k]);
    free(v);
    remove_tmpdir();
}

static void test_bands_rgb_8(void) { bands_alike(3, 8); }
static void test_bands_rgba_16(void) { bands_alike(4, 16); }

int main(void)
{
    RUN(test_round_trip_8);
    RUN(test_round_trip_16);
    RUN(test_bad_bits_and_arguments);
    RUN(test_unwritable_folder);
    RUN(test_libpng_error_keeps_old_file);
    RUN(test_bands_rgb_8);
    RUN(test_bands_rgba_16);
    return check_summary();
}
