/* The PNG encoder's settings on a real picture: reads a PNG (a render's,
 * e.g. out/futuresky-dome.png) and writes it again with each zlib level and
 * row filter choice, printing the CPU time and the size of each.
 *
 *   bench_png PICTURE.png            every level (and zlib's RLE strategy) and
 *                                    filter choice, one thread
 *   bench_png PICTURE.png --orrery   orrery's writer (encode/png_idat.h: bands
 *                                    deflated on every thread) against
 *                                    libpng at its settings, CPU and wall
 *
 * What src/encode/png.c uses was chosen from this (docs/performance.md). */
#define _GNU_SOURCE /* mkstemps */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "encode/png.h"

#include "clocks.h"

typedef struct picture {
    png_uint_32 width, height;
    int bits;
    png_bytep *rows;
} picture;

static int read_png(const char *path, picture *pic)
{
    FILE *fp = fopen(path, "rb");
    png_structp png = fp ? png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL) : NULL;
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info || setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "bench_png: cannot read %s\n", path);
        return 0;
    }
    png_init_io(png, fp);
    png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
    pic->width = png_get_image_width(png, info);
    pic->height = png_get_image_height(png, info);
    pic->bits = png_get_bit_depth(png, info);
    png_bytep *rows = png_get_rows(png, info);
    size_t bytes = png_get_rowbytes(png, info);
    pic->rows = malloc(pic->height * sizeof *pic->rows);
    for (png_uint_32 y = 0; y < pic->height; y++) {
        pic->rows[y] = malloc(bytes);
        for (size_t k = 0; k < bytes; k++)
            pic->rows[y][k] = rows[y][k];
    }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return 1;
}

enum { RLE = 100 }; /* a level that means zlib's run-length strategy, orrery's */

/* Writes pic to a scratch file with the given zlib level (or RLE) and
 * filters; returns its size, and the CPU seconds in *seconds. */
static long write_with(const picture *pic, int level, int filters, double *seconds)
{
    FILE *fp = tmpfile();
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png)))
        return -1;
    double t0 = cpu_seconds();
    png_init_io(png, fp);
    png_set_IHDR(png, info, pic->width, pic->height, pic->bits, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (level == RLE)
        png_set_compression_strategy(png, Z_RLE);
    else if (level >= 0)
        png_set_compression_level(png, level);
    if (filters >= 0)
        png_set_filter(png, PNG_FILTER_TYPE_BASE, filters);
    png_write_info(png, info);
    png_write_image(png, pic->rows);
    png_write_end(png, info);
    fflush(fp);
    *seconds = cpu_seconds() - t0;
    long size = ftell(fp);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
    return size;
}

/* The picture's codes as the floats that quantise back to them. */
static float *picture_floats(const picture *pic)
{
    size_t per_row = (size_t)pic->width * 3, max = pic->bits == 16 ? 65535 : 255;
    float *v = malloc(per_row * pic->height * sizeof *v);
    for (png_uint_32 y = 0; y < pic->height; y++)
        for (size_t i = 0; i < per_row; i++) {
            const png_byte *r = pic->rows[y];
            unsigned code = pic->bits == 16 ? (unsigned)(r[2 * i] << 8 | r[2 * i + 1]) : r[i];
            v[y * per_row + i] = (float)((double)code / (double)max);
        }
    return v;
}

/* orrery's writer against libpng at the same strategy and filter, best of 3. */
static int compare_writers(const picture *pic)
{
    float *v = picture_floats(pic);
    char path[] = "/tmp/bench_png_XXXXXX.png";
    int fd = mkstemps(path, 4);
    if (fd < 0)
        return 1;
    double cpu = 1e30, wall = 1e30, libpng = 1e30, t;
    for (int rep = 0; rep < 3; rep++) {
        orr_error err;
        double c0 = cpu_seconds(), w0 = wall_seconds();
        if (orr_write_png_rgb(path, (int)pic->width, (int)pic->height, v, pic->bits, NULL, 0, &err)) {
            fprintf(stderr, "bench_png: %s\n", err.msg);
            return 1;
        }
        double c = cpu_seconds() - c0, w = wall_seconds() - w0;
        cpu = c < cpu ? c : cpu;
        wall = w < wall ? w : wall;
        write_with(pic, RLE, PNG_FILTER_UP, &t);
        libpng = t < libpng ? t : libpng;
    }
    FILE *fp = fopen(path, "rb");
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    fclose(fp);
    unlink(path);
    printf("  libpng, RLE, up:      %7.3f s CPU (one thread)\n", libpng);
    printf("  orrery's bands:       %7.3f s CPU, %7.3f s wall, %9.1f MB\n", cpu, wall, size / 1e6);
    free(v);
    return 0;
}

int main(int argc, char **argv)
{
    picture pic;
    if ((argc != 2 && (argc != 3 || strcmp(argv[2], "--orrery"))) || !read_png(argv[1], &pic)) {
        fprintf(stderr, "usage: bench_png PICTURE.png [--orrery]\n");
        return 2;
    }
    if (argc == 3)
        return compare_writers(&pic);
    printf("%s: %u x %u, %d bits; CPU seconds, best of 3\n", argv[1], pic.width, pic.height, pic.bits);
    const struct {
        const char *name;
        int filters;
    } filters[] = {{"libpng's default filters", -1}, {"up only", PNG_FILTER_UP}, {"sub only", PNG_FILTER_SUB},
                   {"none", PNG_FILTER_NONE}};
    const int levels[] = {-1, 1, 2, 3, 6, RLE};
    for (size_t f = 0; f < sizeof filters / sizeof filters[0]; f++)
        for (size_t l = 0; l < sizeof levels / sizeof levels[0]; l++) {
            double best = 1e30, t;
            long size = 0;
            for (int rep = 0; rep < 3; rep++) {
                size = write_with(&pic, levels[l], filters[f].filters, &t);
                best = t < best ? t : best;
            }
            char level[16];
            snprintf(level, sizeof level, "%d", levels[l]);
            printf("  %-26s level %-8s %7.3f s  %9.1f MB\n", filters[f].name, levels[l] < 0 ? "default" : levels[l] == RLE ? "RLE" : level,
                   best, size / 1e6);
        }
    return 0;
}
