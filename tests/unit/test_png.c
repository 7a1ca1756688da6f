#include <dirent.h>
#include <png.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tmpdir.h"
#include "check.h"
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

int main(void)
{
    RUN(test_round_trip_8);
    RUN(test_round_trip_16);
    RUN(test_bad_bits_and_arguments);
    RUN(test_unwritable_folder);
    RUN(test_libpng_error_keeps_old_file);
    return check_summary();
}
