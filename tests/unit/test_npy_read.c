/* The .npy reader's value paths: float columns copied with plain loads
 * (positions, masses, h) must give what the general decoding gives, refuse
 * a bad mass or h at the row it is on, and read the same whether the file is
 * read with fread or memory-mapped, in C and Fortran order. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "source/readers/npy_reader.h"
#include "source/source.h"
#include "tmpdir.h"

#define N 1000

/* Writes an .npy version 1 file: header dict padded to 64 bytes, then the
 * rows. */
static void write_npy(const char *path, const char *dict, const void *data, size_t bytes)
{
    char text[256];
    int n = snprintf(text, sizeof text, "%s", dict);
    int pad = (64 - (10 + n + 1) % 64) % 64;
    unsigned len = (unsigned)(n + pad + 1);
    FILE *fp = fopen(path, "wb");
    fwrite("\x93NUMPY\x01\x00", 1, 8, fp);
    fputc((int)(len & 0xff), fp);
    fputc((int)(len >> 8), fp);
    fwrite(text, 1, (size_t)n, fp);
    for (int i = 0; i < pad; i++)
        fputc(' ', fp);
    fputc('\n', fp);
    fwrite(data, 1, bytes, fp);
    fclose(fp);
}

typedef struct row {
    float x, y, z;
    double mass;
    float h;
} row;

static void fill(row *r)
{
    for (int i = 0; i < N; i++)
        r[i] = (row){(float)i * 0.5f, -(float)i, 1.0f / (float)(i + 1), 1e-3 * (i + 1) + 1e-12, (float)(i % 7) * 0.25f};
}

static const char *const STRUCT_DICT =
    "{'descr': [('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('mass', '<f8'), ('h', '<f4')], 'fortran_order': False, "
    "'shape': (1000,), }";

/* The rows as numpy packs them: 24 bytes, no padding (the C struct has
 * some), in the host's byte order, which the dict says is little-endian. */
#define RECORD 24
static void write_rows(const char *path, const row *r)
{
    static unsigned char bytes[N * RECORD];
    for (int i = 0; i < N; i++) {
        unsigned char *p = bytes + (size_t)i * RECORD;
        memcpy(p, &r[i].x, 4);
        memcpy(p + 4, &r[i].y, 4);
        memcpy(p + 8, &r[i].z, 4);
        memcpy(p + 12, &r[i].mass, 8);
        memcpy(p + 20, &r[i].h, 4);
    }
    write_npy(path, STRUCT_DICT, bytes, sizeof bytes);
}

/* Reads path in chunks of 97; returns the error message ("" when the read
 * succeeded) and fills x (and mass, h when given) with what was read. */
static void read_all(const char *path, int mapped, float *x, float *y, float *mass, float *h, char *msg)
{
    orr_npy_set_mapping(mapped);
    orr_source_options opt = {.format = "npy", .chunk_size = 97};
    orr_source *src = NULL;
    orr_error err = {0};
    msg[0] = '\0';
    if (orr_source_open_file(path, &opt, &src, &err) != ORR_OK) {
        snprintf(msg, 512, "%.500s", err.msg);
        return;
    }
    const orr_chunk *c;
    size_t at = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        for (size_t i = 0; i < c->n && at + i < N; i++) {
            x[at + i] = c->x[i];
            y[at + i] = c->y[i];
            if (mass)
                mass[at + i] = c->mass[i];
            if (h && c->h)
                h[at + i] = c->h[i];
        }
        at += c->n;
    }
    if (err.code)
        snprintf(msg, 512, "%.500s", err.msg);
    orr_source_close(src);
    orr_npy_set_mapping(NPY_MAP_DEFAULT);
}

static void test_structured_fast_path_matches_conversion(void)
{
    static row r[N];
    fill(r);
    char path[512], msg[512];
    snprintf(path, sizeof path, "%s/s.npy", tmpdir);
    write_rows(path, r);
    static float x[N], y[N], m[N], h[N], x2[N], y2[N], m2[N], h2[N];
    read_all(path, 0, x, y, m, h, msg);
    CHECK(msg[0] == '\0');
    read_all(path, 1, x2, y2, m2, h2, msg);
    CHECK(msg[0] == '\0');
    int same = 1;
    for (int i = 0; i < N; i++)
        same &= x[i] == r[i].x && y[i] == r[i].y && m[i] == (float)r[i].mass && h[i] == r[i].h && x2[i] == x[i] &&
                m2[i] == m[i] && h2[i] == h[i];
    CHECK(same);
}

static void test_bad_values_named_at_their_row(void)
{
    static row r[N];
    char path[512], msg[512];
    static float x[N], y[N], m[N], h[N];
    snprintf(path, sizeof path, "%s/bad.npy", tmpdir);
    for (int mapped = 0; mapped <= 1; mapped++) {
        fill(r);
        r[613].mass = -2.0;
        write_rows(path, r);
        read_all(path, mapped, x, y, m, h, msg);
        CHECK_CONTAINS(msg, "row 613: mass -2 is negative");
        fill(r);
        r[250].mass = 1e-300; /* would become 0 as a float */
        write_rows(path, r);
        read_all(path, mapped, x, y, m, h, msg);
        CHECK_CONTAINS(msg, "row 250: mass 1e-300 is too small for a float");
        fill(r);
        r[999].h = 1.0f / 0.0f;
        write_rows(path, r);
        read_all(path, mapped, x, y, m, h, msg);
        CHECK_CONTAINS(msg, "row 999: h = inf is not finite and non-negative");
    }
}

static void test_fortran_plain_mapped_and_streamed(void)
{
    static double cols[3 * N];
    for (int i = 0; i < N; i++) {
        cols[i] = i * 0.125;        /* x: column 0 first, Fortran order */
        cols[N + i] = -i * 0.5;     /* y */
        cols[2 * N + i] = i * 2.0;  /* z */
    }
    char path[512], msg[512];
    snprintf(path, sizeof path, "%s/f.npy", tmpdir);
    write_npy(path, "{'descr': '<f8', 'fortran_order': True, 'shape': (1000, 3), }", cols, sizeof cols);
    static float x[N], y[N], x2[N], y2[N];
    read_all(path, 0, x, y, NULL, NULL, msg);
    CHECK(msg[0] == '\0');
    read_all(path, 1, x2, y2, NULL, NULL, msg);
    CHECK(msg[0] == '\0');
    int same = 1;
    for (int i = 0; i < N; i++)
        same &= x[i] == (float)cols[i] && y[i] == (float)cols[N + i] && x2[i] == x[i] && y2[i] == y[i];
    CHECK(same);
}

int main(void)
{
    make_tmpdir();
    test_structured_fast_path_matches_conversion();
    test_bad_values_named_at_their_row();
    test_fortran_plain_mapped_and_streamed();
    remove_tmpdir();
    printf("%d checks, %d failures\n", check_count, check_failures);
    return check_failures != 0;
}
