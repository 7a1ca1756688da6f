/* The Tipsy reader: round trips through the test writer in both byte orders
 * and header sizes, type and field selection, chunking, the real reference
 * files, the probe, and each kind of bad file with its message. */
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "source/readers/formats.h"
#include "source/readers/tipsy.h"
#include "../support/tipsy_writer.h"

/* Until tests/support/ is a library linked into the unit tests, a CMake
 * build (which defines ORRERY_TEST_DATA) compiles the writer in here; a
 * static support library would not clash, as nothing pulls its copy in. */
#if defined(ORRERY_TEST_DATA) && !defined(ORRERY_TEST_SUPPORT)
#include "../support/tipsy_writer.c"
#endif

static char tmpdir[] = "/tmp/orrery-tipsy-XXXXXX";

static const char *tmp_path(const char *name)
{
    static char path[512];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    return path;
}

/* ---- a small three-family snapshot with distinctive values ---- */

enum { NSPH = 5, NDARK = 7, NSTAR = 3, NBODIES = NSPH + NDARK + NSTAR };
static float gas[NSPH * TIPSY_GAS_FLOATS];
static float dark[NDARK * TIPSY_DARK_FLOATS];
static float star[NSTAR * TIPSY_STAR_FLOATS];

static void fill_values(void)
{
    /* Values whose bits are easy to get wrong: signs, -0, subnormals, large. */
    static const float special[] = {-0.0f, 1e-40f, FLT_MAX, -FLT_MIN, 3.25f};
    float *arrays[3] = {gas, dark, star};
    const size_t sizes[3] = {sizeof gas / sizeof gas[0], sizeof dark / sizeof dark[0],
                             sizeof star / sizeof star[0]};
    uint32_t seed = 12345;
    for (int a = 0; a < 3; a++)
        for (size_t i = 0; i < sizes[a]; i++) {
            seed = seed * 1664525u + 1013904223u;
            arrays[a][i] = (float)((int32_t)seed) * 1e-7f;
        }
    /* Masses (column 0) are weights, which the reader refuses negative. */
    const int floats[3] = {TIPSY_GAS_FLOATS, TIPSY_DARK_FLOATS, TIPSY_STAR_FLOATS};
    for (int a = 0; a < 3; a++)
        for (size_t i = 0; i < sizes[a]; i += (size_t)floats[a])
            arrays[a][i] = fabsf(arrays[a][i]);
    for (int i = 0; i < 5; i++)
        dark[9 + 1 + i % 3] = special[i]; /* positions of dark particle 1 */
    gas[4] = special[1];
    star[11 * 2 + 10] = special[2];
}

/* The column of a named quantity in each family's record, written out here
 * independently of the reader's table; -1 when the family has none. */
static int column(int family, const char *name)
{
    static const char *const names[] = {"mass", "x",   "y",    "z",      "vx",    "vy",  "vz",
                                        "rho",  "temp", "h",   "metals", "tform", "eps", "phi"};
    static const int cols[3][14] = {
        {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, -1, -1, 11},
        {0, 1, 2, 3, 4, 5, 6, -1, -1, -1, -1, -1, 7, 8},
        {0, 1, 2, 3, 4, 5, 6, -1, -1, -1, 7, 8, 9, 10},
    };
    for (int i = 0; i < 14; i++)
        if (strcmp(names[i], name) == 0)
            return cols[family][i];
    return -1;
}

/* The value particle `index` (in file order) should have for a field; 0 for
 * a family without it. Also gives the family. */
static float expected_value(long index, const char *name, int *family)
{
    const float *rec;
    if (index < NSPH) {
        *family = 0;
        rec = gas + index * TIPSY_GAS_FLOATS;
    } else if (index < NSPH + NDARK) {
        *family = 1;
        rec = dark + (index - NSPH) * TIPSY_DARK_FLOATS;
    } else {
        *family = 2;
        rec = star + (index - NSPH - NDARK) * TIPSY_STAR_FLOATS;
    }
    int col = column(*family, name);
    return col >= 0 ? rec[col] : 0.0f;
}

static int same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static const char *write_sample(const char *name, int big_endian, int header_size)
{
    const char *path = tmp_path(name);
    tipsy_writer_header h = tipsy_writer_header_for(0.625, NSPH, NDARK, NSTAR, big_endian, header_size);
    CHECK(tipsy_write_file(path, &h, gas, dark, star) == 0);
    return path;
}

static orr_status open_tipsy(const char *path, size_t chunk, unsigned mask, const char *const *fields, int nfields,
                             orr_source **src, orr_error *err)
{
    orr_source_options opt = {.format = "tipsy", .chunk_size = chunk, .type_mask = mask, .fields = fields, .nfields = nfields};
    return orr_tipsy_source_open(path, &opt, src, err);
}

static const char *header_value(const orr_source *src, const char *key)
{
    for (int i = 0; i < src->info.nheader; i++)
        if (strcmp(src->info.header[i].key, key) == 0)
            return src->info.header[i].value;
    return "(missing)";
}

/* Reads every chunk and checks each particle against the sample, bit for
 * bit, for every field the chunk has; returns the particle count. */
static long check_against_sample(orr_source *src, size_t chunk)
{
    static const uint8_t type_of[3] = {0, 1, 4};
    const orr_chunk *c;
    orr_error err = {0};
    long total = 0;
    int bad = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        CHECK(c->n <= chunk);
        CHECK(c->first_index == c->id[0]);
        for (size_t i = 0; i < c->n; i++) {
            long index = (long)c->id[i];
            int fam;
            static const char *const base[] = {"mass", "x", "y", "z"};
            const float *arrays[] = {c->mass, c->x, c->y, c->z};
            for (int f = 0; f < 4; f++)
                bad += !same_bits(arrays[f][i], expected_value(index, base[f], &fam));
            bad += c->type[i] != type_of[fam];
            if (c->h)
                bad += !same_bits(c->h[i], expected_value(index, "h", &fam));
            for (int e = 0; e < c->nextra; e++)
                bad += !same_bits(c->extra[e].data[i], expected_value(index, c->extra[e].name, &fam));
        }
        total += (long)c->n;
    }
    CHECK(err.code == ORR_OK);
    CHECK(bad == 0);
    return total;
}

static void test_round_trip_both_orders_and_header_sizes(void)
{
    for (int big = 0; big <= 1; big++)
        for (int hs = 28; hs <= 32; hs += 4) {
            char name[64];
            snprintf(name, sizeof name, "sample-%d-%d.bin", big, hs);
            const char *path = write_sample(name, big, hs);
            orr_source *src;
            orr_error err = {0};
            CHECK(open_tipsy(path, 4, 0, NULL, 0, &src, &err) == ORR_OK);
            if (!src) {
                fprintf(stderr, "  %s\n", err.msg);
                continue;
            }
            CHECK(strcmp(src->info.format, "tipsy") == 0);
            CHECK(src->info.count == NBODIES);
            CHECK(src->info.time == 0.625);
            CHECK(src->info.has_h && src->info.has_type && !src->info.has_id);
            /* Every extra field: each exists in some family of this file. */
            CHECK(src->info.nextra == 9);
            CHECK_CONTAINS(header_value(src, "byte order"), big ? "big-endian" : "little-endian");
            CHECK_CONTAINS(header_value(src, "header size"), hs == 32 ? "32" : "28");
            CHECK(strcmp(header_value(src, "nbodies"), "15") == 0);
            CHECK(strcmp(header_value(src, "nsph"), "5") == 0);
            CHECK(strcmp(header_value(src, "ndark"), "7") == 0);
            CHECK(strcmp(header_value(src, "nstar"), "3") == 0);
            CHECK(strcmp(header_value(src, "time"), "0.625") == 0);
            CHECK(check_against_sample(src, 4) == NBODIES);
            CHECK(orr_source_rewind(src, &err) == ORR_OK);
            CHECK(check_against_sample(src, 4) == NBODIES);
            orr_source_close(src);
        }
}

static void test_type_mask_skips_families(void)
{
    const char *path = write_sample("mask.bin", 1, 32);
    orr_source *src;
    orr_error err = {0};
    /* Dark and star only: no gas, so no smoothing lengths and no gas fields. */
    CHECK(open_tipsy(path, 100, 1u << 1 | 1u << 4, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->info.count == NDARK + NSTAR);
    CHECK(!src->info.has_h);
    CHECK(src->info.nextra == 7); /* vx vy vz metals tform eps phi */
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == NDARK + NSTAR);
    CHECK(c->h == NULL && c->id[0] == NSPH && c->first_index == NSPH && c->type[0] == 1 && c->type[NDARK] == 4);
    CHECK(orr_source_rewind(src, &err) == ORR_OK);
    CHECK(check_against_sample(src, 100) == NDARK + NSTAR);
    orr_source_close(src);

    /* Star only. */
    CHECK(open_tipsy(path, 2, 1u << 4, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->info.count == NSTAR);
    CHECK(check_against_sample(src, 2) == NSTAR);
    orr_source_close(src);

    /* Gas only: no tform or eps. */
    CHECK(open_tipsy(path, 3, 1u << 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->info.count == NSPH && src->info.has_h);
    CHECK(orr_chunk_field(&src->chunk, "tform") == NULL && orr_chunk_field(&src->chunk, "eps") == NULL);
    CHECK(orr_chunk_field(&src->chunk, "rho") != NULL);
    CHECK(check_against_sample(src, 3) == NSPH);
    orr_source_close(src);

    /* A type the file does not have: nothing to read. */
    CHECK(open_tipsy(path, 3, 1u << 2, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->info.count == 0);
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 0);
    orr_source_close(src);
}

static void test_fields_load_only_what_is_asked(void)
{
    const char *path = write_sample("fields.bin", 0, 32);
    orr_source *src;
    orr_error err = {0};
    const char *const fields[] = {"eps", "rho", "luminosity"};
    CHECK(open_tipsy(path, 6, 0, fields, 3, &src, &err) == ORR_OK);
    /* In the reader's order; names Tipsy does not have are not invented. */
    CHECK(src->info.nextra == 2);
    CHECK(strcmp(src->info.extra_names[0], "rho") == 0 && strcmp(src->info.extra_names[1], "eps") == 0);
    CHECK(src->chunk.nextra == 2);
    CHECK(check_against_sample(src, 6) == NBODIES); /* gas eps and dark/star rho are 0 */
    orr_source_close(src);

    /* An empty list: no extra fields at all. */
    CHECK(open_tipsy(path, 6, 0, fields, 0, &src, &err) == ORR_OK);
    CHECK(src->info.nextra == 0 && src->chunk.nextra == 0);
    CHECK(check_against_sample(src, 6) == NBODIES);
    orr_source_close(src);

    /* Dark only: rho is asked for but no family read has it. */
    CHECK(open_tipsy(path, 6, 1u << 1, fields, 3, &src, &err) == ORR_OK);
    CHECK(src->info.nextra == 1 && strcmp(src->info.extra_names[0], "eps") == 0);
    orr_source_close(src);
}

/* Reads the whole file into flat arrays (x, mass, id, phi) for comparison. */
static long read_flat(const char *path, size_t chunk, float *x, float *mass, uint64_t *id, float *phi, long max)
{
    orr_source *src;
    orr_error err = {0};
    if (open_tipsy(path, chunk, 0, NULL, 0, &src, &err) != ORR_OK)
        return -1;
    const orr_chunk *c;
    long n = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        const float *p = orr_chunk_field(c, "phi");
        for (size_t i = 0; i < c->n && n < max; i++, n++) {
            x[n] = c->x[i];
            mass[n] = c->mass[i];
            id[n] = c->id[i];
            phi[n] = p[i];
        }
        CHECK(c->n <= chunk);
    }
    orr_source_close(src);
    return n;
}

static void test_chunk_sizes_give_identical_particles(void)
{
    const char *path = write_sample("chunks.bin", 1, 28);
    enum { MAX = 64 };
    float x[3][MAX], m[3][MAX], phi[3][MAX];
    uint64_t id[3][MAX];
    const size_t sizes[3] = {1, 7, (size_t)1 << 24};
    for (int k = 0; k < 3; k++)
        CHECK(read_flat(path, sizes[k], x[k], m[k], id[k], phi[k], MAX) == NBODIES);
    for (int k = 1; k < 3; k++) {
        CHECK(memcmp(x[0], x[k], NBODIES * sizeof(float)) == 0);
        CHECK(memcmp(m[0], m[k], NBODIES * sizeof(float)) == 0);
        CHECK(memcmp(phi[0], phi[k], NBODIES * sizeof(float)) == 0);
        CHECK(memcmp(id[0], id[k], NBODIES * sizeof(uint64_t)) == 0);
    }
    for (int i = 0; i < NBODIES; i++)
        CHECK(id[0][i] == (uint64_t)i);
    /* A large chunk size does not allocate for more particles than exist. */
    orr_source *src;
    orr_error err = {0};
    CHECK(open_tipsy(path, 0, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->chunk.capacity == NBODIES);
    orr_source_close(src);
    CHECK(open_tipsy(path, SIZE_MAX, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->chunk.capacity == NBODIES);
    orr_source_close(src);
}

static void test_empty_file_is_valid(void)
{
    const char *path = tmp_path("empty.bin");
    tipsy_writer_header h = tipsy_writer_header_for(2.0, 0, 0, 0, 1, 32);
    CHECK(tipsy_write_file(path, &h, NULL, NULL, NULL) == 0);
    orr_source *src;
    orr_error err = {0};
    CHECK(open_tipsy(path, 10, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src->info.count == 0 && src->info.time == 2.0 && !src->info.has_h && src->info.nextra == 0);
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 0);
    orr_source_close(src);
}

/* ---- the real reference files ---- */

typedef struct file_stats {
    long n[6];
    double mass_sum;
    float mass_min, mass_max;
    float lo[3], hi[3];
    float field_min[3], field_max[3]; /* for the fields named in the call */
    float first[9];                   /* mass, x, y, z, then the named fields of particle 0 */
} file_stats;

static int read_stats(const char *path, const char *const fields[3], file_stats *s, orr_source_info *info)
{
    orr_source *src;
    orr_error err = {0};
    if (open_tipsy(path, 4096, 0, NULL, 0, &src, &err) != ORR_OK) {
        fprintf(stderr, "  %s\n", err.msg);
        return -1;
    }
    *info = src->info;
    memset(s, 0, sizeof *s);
    s->mass_min = s->lo[0] = s->lo[1] = s->lo[2] = FLT_MAX;
    s->mass_max = s->hi[0] = s->hi[1] = s->hi[2] = -FLT_MAX;
    for (int f = 0; f < 3; f++) {
        s->field_min[f] = FLT_MAX;
        s->field_max[f] = -FLT_MAX;
    }
    const orr_chunk *c;
    long total = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        const float *pos[3] = {c->x, c->y, c->z};
        const float *fv[3];
        for (int f = 0; f < 3; f++)
            fv[f] = fields[f] ? orr_chunk_field(c, fields[f]) : NULL;
        for (size_t i = 0; i < c->n; i++, total++) {
            s->n[c->type[i]]++;
            s->mass_sum += c->mass[i];
            s->mass_min = fminf(s->mass_min, c->mass[i]);
            s->mass_max = fmaxf(s->mass_max, c->mass[i]);
            for (int d = 0; d < 3; d++) {
                s->lo[d] = fminf(s->lo[d], pos[d][i]);
                s->hi[d] = fmaxf(s->hi[d], pos[d][i]);
            }
            for (int f = 0; f < 3; f++)
                if (fv[f]) {
                    s->field_min[f] = fminf(s->field_min[f], fv[f][i]);
                    s->field_max[f] = fmaxf(s->field_max[f], fv[f][i]);
                }
            if (total == 0) {
                const float first[4] = {c->mass[i], c->x[i], c->y[i], c->z[i]};
                memcpy(s->first, first, sizeof first);
                for (int f = 0; f < 3; f++)
                    s->first[4 + f] = fv[f] ? fv[f][i] : 0;
            }
        }
    }
    CHECK(err.code == ORR_OK);
    orr_source_close(src);
    return 0;
}

static void test_king_soft(void)
{
    char buf[1024];
    const char *path = shared_data_path(buf, sizeof buf, "tipsy/king_soft.bin");
    if (!path)
        return;
    const char *const fields[3] = {"eps", "vx", "phi"};
    file_stats s;
    orr_source_info info;
    if (read_stats(path, fields, &s, &info) != 0) {
        CHECK(!"king_soft.bin opens");
        return;
    }
    CHECK(info.count == 36000 && info.time == 0.0 && !info.has_h);
    CHECK(s.n[1] == 36000);
    CHECK_NEAR(s.mass_min, 0.000695946219, 1e-12);
    CHECK_NEAR(s.mass_max, 0.000695946219, 1e-12);
    CHECK_NEAR(s.mass_sum, 25.0540639, 1e-5);
    CHECK_NEAR(s.field_min[0], 0.204217, 1e-6); /* every eps */
    CHECK_NEAR(s.field_max[0], 0.204217, 1e-6);
    const double lo[3] = {-28.4283, -28.2056, -24.7133}, hi[3] = {28.247, 25.9446, 28.8793};
    for (int d = 0; d < 3; d++) {
        CHECK_NEAR(s.lo[d], lo[d], 1e-4);
        CHECK_NEAR(s.hi[d], hi[d], 1e-4);
    }
    /* First record: mass, pos, (vel x), eps, phi. */
    CHECK_NEAR(s.first[0], 0.00069594622, 1e-11);
    CHECK_NEAR(s.first[1], 0.076561362, 1e-8);
    CHECK_NEAR(s.first[2], 0.041483238, 1e-8);
    CHECK_NEAR(s.first[3], 0.0023723219, 1e-9);
    CHECK_NEAR(s.first[4], 0.20421657, 1e-7);
    CHECK_NEAR(s.first[5], 0.19059131, 1e-7);
    CHECK(s.first[6] == 0.0f);
}

static void test_lambs(void)
{
    char buf[1024];
    const char *path = shared_data_path(buf, sizeof buf, "tipsy/lambs.00200_subsamp_30K");
    if (!path)
        return;
    const char *const fields[3] = {"eps", NULL, NULL};
    file_stats s;
    orr_source_info info;
    if (read_stats(path, fields, &s, &info) != 0) {
        CHECK(!"lambs opens");
        return;
    }
    CHECK(info.time == 1.0000000000000009);
    CHECK(info.count == 30000 && s.n[1] == 30000);
    CHECK_NEAR(s.mass_min, 9.99309304e-06, 1e-13);
    CHECK_NEAR(s.mass_max, 9.99309304e-06, 1e-13);
    CHECK_NEAR(s.mass_sum, 0.299792791, 1e-6);
    CHECK_NEAR(s.field_min[0], 0.00025, 1e-9);
    CHECK_NEAR(s.field_max[0], 0.00025, 1e-9);
    CHECK_NEAR(s.first[1], 0.050259911, 1e-8);
    CHECK_NEAR(s.first[2], -0.054038722, 1e-8);
    CHECK_NEAR(s.first[3], 0.46079588, 1e-7);
    for (int d = 0; d < 3; d++)
        CHECK(s.lo[d] >= -0.5f && s.hi[d] < 0.5f);
}

static void test_test4_variable_masses(void)
{
    char buf[1024];
    const char *path = shared_data_path(buf, sizeof buf, "tipsy/test4.tbin");
    if (!path)
        return;
    const char *const fields[3] = {"eps", NULL, NULL};
    file_stats s;
    orr_source_info info;
    if (read_stats(path, fields, &s, &info) != 0) {
        CHECK(!"test4.tbin opens");
        return;
    }
    CHECK(info.count == 67495 && s.n[1] == 67495);
    CHECK_NEAR(info.time, 1.000219, 1e-9);
    CHECK_NEAR(s.mass_min, 3.34898e-07, 1e-12);
    CHECK_NEAR(s.mass_max, 0.00137174199, 1e-11);
    CHECK_NEAR(s.mass_sum, 0.999999971, 1e-6);
    CHECK_NEAR(s.field_min[0], 0.0002, 1e-9);
    CHECK_NEAR(s.field_max[0], 0.0032, 1e-8);
    for (int d = 0; d < 3; d++)
        CHECK(s.lo[d] >= -0.5f && s.hi[d] < 0.5f);
    /* The default chunk holds the whole file, read in two fread blocks
     * (65536 records, then the rest): the same particles in one chunk. */
    orr_source *src;
    orr_error err = {0};
    CHECK(open_tipsy(path, 0, 0, NULL, 0, &src, &err) == ORR_OK);
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 67495);
    double sum = 0;
    for (size_t i = 0; i < c->n; i++)
        sum += c->mass[i];
    CHECK(sum == s.mass_sum && c->id[67494] == 67494);
    CHECK(orr_source_next(src, &c, &err) == ORR_OK && c->n == 0);
    orr_source_close(src);
}

static void test_onestar_gas_and_star(void)
{
    char buf[1024];
    const char *path = shared_data_path(buf, sizeof buf, "tipsy/onestar.tbin");
    if (!path)
        return;
    orr_source *src;
    orr_error err = {0};
    if (open_tipsy(path, 100, 0, NULL, 0, &src, &err) != ORR_OK) {
        fprintf(stderr, "  %s\n", err.msg);
        CHECK(!"onestar.tbin opens");
        return;
    }
    CHECK(src->info.count == 1089 && src->info.has_h && src->info.time == 0.0);
    float rho_lo = FLT_MAX, rho_hi = -FLT_MAX, t_lo = FLT_MAX, t_hi = -FLT_MAX;
    float h_lo = FLT_MAX, h_hi = -FLT_MAX;
    double gas_mass = 0, total = 0;
    long ngas = 0, nstar = 0, chunks = 0;
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        chunks++;
        const float *rho = orr_chunk_field(c, "rho"), *temp = orr_chunk_field(c, "temp");
        const float *eps = orr_chunk_field(c, "eps");
        for (size_t i = 0; i < c->n; i++) {
            total += c->mass[i];
            if (c->type[i] == 0) {
                ngas++;
                gas_mass += c->mass[i];
                rho_lo = fminf(rho_lo, rho[i]);
                rho_hi = fmaxf(rho_hi, rho[i]);
                t_lo = fminf(t_lo, temp[i]);
                t_hi = fmaxf(t_hi, temp[i]);
                h_lo = fminf(h_lo, c->h[i]);
                h_hi = fmaxf(h_hi, c->h[i]);
                CHECK(c->id[i] < 1088);
            } else {
                CHECK(c->type[i] == 4 && c->id[i] == 1088);
                nstar++;
                CHECK_NEAR(c->mass[i], 0.0002757, 1e-9);
                CHECK(c->x[i] == 0 && c->y[i] == 0 && c->z[i] == 0);
                CHECK_NEAR(eps[i], 0.00125, 1e-9);
                CHECK(c->h[i] == 0.0f && rho[i] == 0.0f); /* stars have no hsmooth or rho */
            }
        }
    }
    CHECK(err.code == ORR_OK);
    CHECK(chunks == 11);
    CHECK(ngas == 1088 && nstar == 1);
    CHECK_NEAR(rho_lo, 0.130821, 1e-6);
    CHECK_NEAR(rho_hi, 14.3781, 1e-4);
    CHECK_NEAR(t_lo, 3940, 0.5);
    CHECK_NEAR(t_hi, 28507.3, 0.05);
    CHECK_NEAR(h_lo, 0.00125, 1e-9);
    CHECK_NEAR(h_hi, 0.00125, 1e-9);
    CHECK_NEAR(gas_mass, 0.999872014, 1e-6);
    CHECK_NEAR(total, 1.00014771, 1e-6);
    orr_source_close(src);
}

/* ---- the probe ---- */

static size_t read_head(const char *path, unsigned char *head)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return 0;
    size_t n = fread(head, 1, ORR_PROBE_BYTES, fp);
    fclose(fp);
    return n;
}

static void test_probe(void)
{
    unsigned char head[ORR_PROBE_BYTES];
    for (int big = 0; big <= 1; big++)
        for (int hs = 28; hs <= 32; hs += 4) {
            char name[64];
            snprintf(name, sizeof name, "probe-%d-%d.bin", big, hs);
            size_t n = read_head(write_sample(name, big, hs), head);
            CHECK(orr_tipsy_probe(head, n));
            CHECK(!orr_tipsy_probe(head, n - 1)); /* a whole small file must have the exact size */
        }
    const char *names[] = {"tipsy/king_soft.bin", "tipsy/onestar.tbin"};
    for (int i = 0; i < 2; i++) {
        char buf[1024];
        const char *path = shared_data_path(buf, sizeof buf, names[i]);
        if (path)
            CHECK(orr_tipsy_probe(head, read_head(path, head)));
    }
    const char *text = "x y z mass\n1 2 3 4\n5 6 7 8\n9 10 11 12\n";
    CHECK(!orr_tipsy_probe((const unsigned char *)text, strlen(text)));
    CHECK(!orr_tipsy_probe(head, 0));
    CHECK(!orr_tipsy_probe(head, 27));
    /* A large head whose counts do not add up. */
    memset(head, 0, sizeof head);
    head[15] = 3;  /* ndim, big-endian */
    head[11] = 10; /* nbodies 10, but no family counts */
    CHECK(!orr_tipsy_probe(head, sizeof head));
    head[23] = 10; /* ndark 10: consistent; a large file is only checked when opened */
    CHECK(orr_tipsy_probe(head, sizeof head));
}

/* ---- bad files ---- */

static void expect_error(const char *path, orr_status code, const char *needle1, const char *needle2)
{
    orr_source *src = NULL;
    orr_error err = {0};
    orr_status s = open_tipsy(path, 10, 0, NULL, 0, &src, &err);
    CHECK(s == code);
    CHECK(src == NULL);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, needle1);
    if (needle2)
        CHECK_CONTAINS(err.msg, needle2);
    orr_source_close(src);
}

static const char *write_header_only(const char *name, tipsy_writer_header h, size_t extra_bytes)
{
    const char *path = tmp_path(name);
    FILE *fp = fopen(path, "wb");
    CHECK(tipsy_write_header(fp, &h) == 0);
    for (size_t i = 0; i < extra_bytes; i++)
        fputc(0, fp);
    fclose(fp);
    return path;
}

static void test_truncated_file(void)
{
    const char *path = write_sample("truncated.bin", 1, 32);
    CHECK(truncate(path, 32 + 48 * NSPH + 36 * NDARK + 44 * NSTAR - 1) == 0);
    expect_error(path, ORR_ERR_FORMAT, "needs a file of 656 bytes", "the file has 655 bytes");
    CHECK(truncate(path, 20) == 0);
    expect_error(path, ORR_ERR_FORMAT, "20 bytes is shorter than a Tipsy header", NULL);
    CHECK(truncate(path, 0) == 0);
    expect_error(path, ORR_ERR_FORMAT, "0 bytes is shorter", NULL);
    /* Trailing bytes are as wrong as missing ones. */
    const char *longer = write_header_only("longer.bin", tipsy_writer_header_for(0, 0, 1, 0, 0, 32), 37);
    expect_error(longer, ORR_ERR_FORMAT, "needs a file of 68 bytes", "the file has 69 bytes");
}

static void test_huge_counts_checked_before_allocating(void)
{
    /* 2.1e9 particles claimed (the most 32-bit counts allow) in a 100-byte
     * file: rejected from the size, nothing allocated for them. */
    tipsy_writer_header h = tipsy_writer_header_for(0, 700000000, 700000000, 700000000, 1, 32);
    const char *path = write_header_only("huge.bin", h, 68);
    expect_error(path, ORR_ERR_FORMAT, "needs a file of 89600000032 bytes", "the file has 100 bytes");
    /* Counts that overflow a 32-bit sum do not wrap around to a match. */
    /* (2^31 - 1) + (2^31 - 1) + 2 wraps to 0 in 32 bits. */
    h = (tipsy_writer_header){0, 0, 3, 2147483647, 2147483647, 2, 1, 32};
    path = write_header_only("wrap.bin", h, 0);
    expect_error(path, ORR_ERR_FORMAT, "nbodies 0 is not nsph 2147483647 + ndark 2147483647 + nstar 2 = 4294967296",
                 NULL);
}

static void test_bad_headers(void)
{
    tipsy_writer_header h = tipsy_writer_header_for(0, 1, 1, 1, 1, 32);
    h.ndark = -1;
    h.nbodies = 1;
    expect_error(write_header_only("negative.bin", h, 0), ORR_ERR_FORMAT, "negative ndark -1", "big-endian");

    h = tipsy_writer_header_for(0, 0, 0, 0, 1, 32);
    h.nbodies = -4;
    expect_error(write_header_only("negative-n.bin", h, 0), ORR_ERR_FORMAT, "big-endian: negative nbodies -4",
                 NULL);

    h = tipsy_writer_header_for(0, 0, 2, 0, 0, 32);
    h.ndim = 2;
    expect_error(write_header_only("ndim.bin", h, 72), ORR_ERR_FORMAT, "ndim is 2, not 3", "little-endian");

    h = tipsy_writer_header_for(0, 1, 2, 3, 1, 32);
    h.nbodies = 7;
    expect_error(write_header_only("sum.bin", h, 0), ORR_ERR_FORMAT,
                 "big-endian: nbodies 7 is not nsph 1 + ndark 2 + nstar 3 = 6", "not consistent in either byte order");

    /* A wrong byte order guess: a little-endian file whose ndim was written
     * big-endian looks consistent in big-endian, and the size says no. */
    h = tipsy_writer_header_for(0, 0, 1, 0, 0, 32);
    const char *path = write_header_only("mixed.bin", h, 36);
    FILE *fp = fopen(path, "r+b");
    fseek(fp, 12, SEEK_SET);
    fwrite("\0\0\0\3", 1, 4, fp);
    fclose(fp);
    expect_error(path, ORR_ERR_FORMAT, "the big-endian header (nbodies 16777216 = nsph 0 + ndark 16777216",
                 "needs a file of 603979808 bytes (603979804 with the unpadded 28-byte header), but the file has "
                 "68 bytes");

    /* A consistent big-endian header whose file is sized for no layout. */
    h = tipsy_writer_header_for(0, 0, 3, 0, 1, 32);
    expect_error(write_header_only("order.bin", h, 10), ORR_ERR_FORMAT, "the big-endian header (nbodies 3",
                 "needs a file of 140 bytes (136 with the unpadded 28-byte header)");
}

/* A NaN or infinite time would be written into every image's FITS header,
 * which cfitsio refuses at the end of each render: refused when opening. */
static void test_time_not_finite(void)
{
    const double times[2] = {NAN, INFINITY};
    for (int k = 0; k < 2; k++) {
        tipsy_writer_header h = tipsy_writer_header_for(times[k], 0, 1, 0, 1, 32);
        const char *path = write_header_only(k ? "inftime.bin" : "nantime.bin", h, 36);
        expect_error(path, ORR_ERR_FORMAT, "header time = ", "is not a finite number");
    }
}

/* The mass policy every reader shares (docs/input.md): a negative or
 * non-finite mass is an error naming file, particle and value. */
static void test_mass_policy(void)
{
    static const struct {
        float *array;
        size_t at;
        float value;
        const char *needle;
    } bad[] = {
        {dark, 2 * TIPSY_DARK_FLOATS, -1.5f, "dark particle 2 (particle 7 of the file): mass -1.5 is negative"},
        {gas, 4 * TIPSY_GAS_FLOATS, NAN, "gas particle 4 (particle 4 of the file): mass nan is not a finite number"},
        {star, 0, -INFINITY, "star particle 0 (particle 12 of the file): mass -inf is not a finite number"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        float saved = bad[k].array[bad[k].at];
        bad[k].array[bad[k].at] = bad[k].value;
        const char *path = write_sample("badmass.bin", (int)k % 2, 32);
        bad[k].array[bad[k].at] = saved;
        orr_source *src = NULL;
        orr_error err = {0};
        orr_status s = open_tipsy(path, 4, 0, NULL, 0, &src, &err);
        const orr_chunk *c;
        while (!s && !(s = orr_source_next(src, &c, &err)) && c->n > 0) {
        }
        orr_source_close(src);
        CHECK(s == ORR_ERR_FORMAT);
        CHECK_CONTAINS(err.msg, path);
        CHECK_CONTAINS(err.msg, bad[k].needle);
    }
}

static void test_not_tipsy_and_missing(void)
{
    const char *path = tmp_path("table.txt");
    FILE *fp = fopen(path, "w");
    fputs("x y z mass\n1 2 3 4\n5 6 7 8\n9 10 11 12\n", fp);
    fclose(fp);
    expect_error(path, ORR_ERR_FORMAT, "not consistent in either byte order", NULL);
    expect_error(tmp_path("no-such-file.bin"), ORR_ERR_IO, "cannot open", NULL);
    expect_error(tmpdir, ORR_ERR_IO, tmpdir, NULL); /* a directory */
}

static void test_file_shrinking_after_open(void)
{
    const char *path = write_sample("shrink.bin", 0, 32);
    orr_source *src;
    orr_error err = {0};
    CHECK(open_tipsy(path, 4, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(truncate(path, 32 + 48 * 2 + 10) == 0);
    const orr_chunk *c;
    CHECK(orr_source_next(src, &c, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "unexpected end of file in gas particle 2");
    CHECK_CONTAINS(err.msg, "expected 656 bytes");
    orr_source_close(src);
}

/* ---- SNAPSHOT.iord: the particles' permanent ids ---- */

static uint64_t iord_id(long i) { return 900000 + 7 * (uint64_t)(NBODIES - i); } /* not the file order */

static void write_iord_binary(const char *snapshot, int big_endian, int width)
{
    char path[600];
    snprintf(path, sizeof path, "%s.iord", snapshot);
    FILE *fp = fopen(path, "wb");
    unsigned char b[8];
    uint64_t v = NBODIES;
    for (long i = -1; fp && i < NBODIES; i++) {
        int w = i < 0 ? 4 : width; /* the count is 32 bits */
        v = i < 0 ? NBODIES : iord_id(i);
        for (int k = 0; k < w; k++)
            b[big_endian ? w - 1 - k : k] = (unsigned char)(v >> (8 * k));
        fwrite(b, 1, (size_t)w, fp);
    }
    if (fp)
        fclose(fp);
}

static void write_iord_text(const char *snapshot, const char *bad_line, long bad_at, long count)
{
    char path[600];
    snprintf(path, sizeof path, "%s.iord", snapshot);
    FILE *fp = fopen(path, "w");
    fprintf(fp, "%ld\n", count);
    for (long i = 0; i < NBODIES; i++)
        if (i == bad_at)
            fprintf(fp, "%s\n", bad_line);
        else
            fprintf(fp, " %llu\n", (unsigned long long)iord_id(i));
    fclose(fp);
}

/* Reads the snapshot in chunks of 4 (families split across chunks), twice
 * (a rewind in between), and checks every id against the .iord's. */
static void check_iord_ids(const char *snapshot, unsigned mask, const char *form)
{
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(open_tipsy(snapshot, 4, mask, NULL, 0, &src, &err) == ORR_OK);
    if (!src) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    CHECK(src->info.has_id);
    CHECK_CONTAINS(header_value(src, "ids"), form);
    for (int pass = 0; pass < 2; pass++) {
        long seen = 0, ok = 1;
        const orr_chunk *c;
        while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
            for (size_t i = 0; i < c->n; i++, seen++) /* all, or the stars: file positions run on */
                ok &= c->id[i] == iord_id((long)c->first_index + (long)i);
        CHECK(ok);
        CHECK(seen == (mask == 0 ? NBODIES : NSTAR));
        CHECK(orr_source_rewind(src, &err) == ORR_OK);
    }
    orr_source_close(src);
}

static void test_iord_ids(void)
{
    const char *path = write_sample("iord.bin", 1, 32);
    write_iord_binary(path, 1, 4);
    check_iord_ids(path, 0, "binary, 32-bit");
    check_iord_ids(path, 1u << 4, "binary, 32-bit"); /* stars only: their ids, not the first ones */
    write_iord_binary(path, 0, 8);
    check_iord_ids(path, 0, "binary, 64-bit");
    write_iord_text(path, NULL, -1, NBODIES);
    check_iord_ids(path, 0, "ASCII");
    check_iord_ids(path, 1u << 4, "ASCII");

    /* Bad arrays: named, with the line or the particle. */
    write_iord_text(path, NULL, -1, NBODIES + 1);
    expect_error(path, ORR_ERR_FORMAT, "iord: line 1 says 16 particles", "has 15");
    write_iord_text(path, "-3", 6, NBODIES);
    orr_source *src = NULL;
    orr_error err = {0};
    const orr_chunk *c;
    CHECK(open_tipsy(path, 100, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src && orr_source_next(src, &c, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "iord:8: not an id");
    orr_source_close(src);
    write_iord_text(path, "12 13", 2, NBODIES);
    src = NULL;
    CHECK(open_tipsy(path, 100, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src && orr_source_next(src, &c, &err) == ORR_ERR_FORMAT);
    CHECK_CONTAINS(err.msg, "iord:4: not an id");
    orr_source_close(src);
    char iord[600];
    snprintf(iord, sizeof iord, "%s.iord", path);
    FILE *fp = fopen(iord, "w");
    fputs("junk\n", fp);
    fclose(fp);
    expect_error(path, ORR_ERR_FORMAT, "neither a binary id array", "nor an ASCII one");
    remove(iord);

    /* Without one, ids are file positions. */
    src = NULL;
    CHECK(open_tipsy(path, 100, 0, NULL, 0, &src, &err) == ORR_OK);
    CHECK(src && !src->info.has_id && orr_source_next(src, &c, &err) == ORR_OK && c->id[NBODIES - 1] == NBODIES - 1);
    orr_source_close(src);
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    fill_values();
    RUN(test_round_trip_both_orders_and_header_sizes);
    RUN(test_type_mask_skips_families);
    RUN(test_fields_load_only_what_is_asked);
    RUN(test_chunk_sizes_give_identical_particles);
    RUN(test_empty_file_is_valid);
    RUN(test_probe);
    RUN(test_truncated_file);
    RUN(test_huge_counts_checked_before_allocating);
    RUN(test_bad_headers);
    RUN(test_time_not_finite);
    RUN(test_mass_policy);
    RUN(test_not_tipsy_and_missing);
    RUN(test_file_shrinking_after_open);
    RUN(test_iord_ids);
    char buf[1024];
    int have_shared = shared_data_path(buf, sizeof buf, "tipsy/king_soft.bin") != NULL;
    if (have_shared) {
        RUN(test_king_soft);
        RUN(test_lambs);
        RUN(test_test4_variable_masses);
        RUN(test_onestar_gas_and_star);
    }
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    int status = check_summary();
    if (!have_shared && status == 0)
        return SKIP_CODE;
    return status;
}
