/* The Gadget-1/2 reader: round trips through the test-only writer in every
 * layout it supports, type and field selection, chunking, the real files of
 * the shared reference data, and each kind of damaged file with its message. */
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "gadget_writer.h"
#include "source/readers/gadget.h"
#include "source/source.h"

static char tmpdir[] = "/tmp/orrery-gadget-XXXXXX";

static const char *tmp_path(const char *name)
{
    static char path[4][512];
    static int next;
    char *p = path[next++ % 4];
    snprintf(p, sizeof path[0], "%s/%s", tmpdir, name);
    return p;
}

/* ---- a snapshot held in memory, to write and to compare with ---- */

#define MAX_FILES 3
#define MAX_PARTICLES 400

typedef struct test_file {
    int32_t npart[6];
    gw_particle p[MAX_PARTICLES];
    int type[MAX_PARTICLES];
    int n;
} test_file;

typedef struct layout {
    int snapformat, big_endian, double_precision, id64, nfiles;
    int mass_table;   /* 1: every type's mass in massarr; 0: types 0 and 4 in the MASS block */
    unsigned blocks;  /* GW_* */
} layout;

typedef struct test_snap {
    layout lay;
    double massarr[6];
    test_file file[MAX_FILES];
} test_snap;

static uint64_t rng_state;

static uint64_t next_random(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* A double that float cannot hold exactly, so conversions are exercised. */
static double random_real(double scale)
{
    return scale * ((double)(next_random() >> 11) / 9007199254740992.0 - 0.5);
}

static const int32_t file_counts[MAX_FILES][6] = {
    {11, 23, 0, 0, 5, 2},
    {0, 17, 0, 0, 3, 0},
    {9, 31, 0, 1, 0, 4},
};

static void make_snapshot(test_snap *s, layout lay)
{
    memset(s, 0, sizeof *s);
    s->lay = lay;
    rng_state = 42;
    const double table[6] = {0.25, 1.5, 0, 2.0, 0.125, 7.0};
    for (int t = 0; t < 6; t++)
        s->massarr[t] = lay.mass_table ? table[t] : (t == 0 || t == 4 ? 0 : table[t]);
    uint64_t id = lay.id64 ? 0x100000000ull : 1;
    for (int f = 0; f < lay.nfiles; f++) {
        test_file *tf = &s->file[f];
        for (int t = 0; t < 6; t++) {
            tf->npart[t] = lay.nfiles == 1 ? file_counts[0][t] + file_counts[2][t] : file_counts[f][t];
            for (int j = 0; j < tf->npart[t]; j++) {
                gw_particle *p = &tf->p[tf->n];
                tf->type[tf->n++] = t;
                for (int k = 0; k < 3; k++) {
                    p->pos[k] = random_real(200);
                    p->vel[k] = random_real(1000);
                }
                p->id = id++ * 3;
                p->mass = 1e-3 + random_real(1e-3);
                p->u = random_real(50);
                p->rho = random_real(2);
                p->hsml = random_real(1);
                p->pot = random_real(1e4);
            }
        }
    }
    /* NaN positions are passed through untouched. */
    s->file[0].p[3].pos[1] = NAN;
}

static void particle_of(void *user, uint64_t i, int type, gw_particle *p)
{
    const test_file *f = user;
    (void)type;
    *p = f->p[i];
}

static void write_snapshot(const test_snap *s, const char *name)
{
    uint32_t total[6] = {0};
    for (int f = 0; f < s->lay.nfiles; f++)
        for (int t = 0; t < 6; t++)
            total[t] += (uint32_t)s->file[f].npart[t];
    for (int f = 0; f < s->lay.nfiles; f++) {
        gw_spec spec = {.snapformat = s->lay.snapformat,
                        .big_endian = s->lay.big_endian,
                        .double_precision = s->lay.double_precision,
                        .id64 = s->lay.id64,
                        .blocks = s->lay.blocks,
                        .num_files = s->lay.nfiles,
                        .time = 0.5,
                        .redshift = 1.0,
                        .box_size = 100,
                        .omega0 = 0.3,
                        .omega_lambda = 0.7,
                        .hubble_param = 0.7};
        memcpy(spec.npart, s->file[f].npart, sizeof spec.npart);
        memcpy(spec.massarr, s->massarr, sizeof spec.massarr);
        memcpy(spec.npart_total, total, sizeof total);
        char path[512];
        if (s->lay.nfiles == 1)
            snprintf(path, sizeof path, "%s", tmp_path(name));
        else
            snprintf(path, sizeof path, "%s.%d", tmp_path(name), f);
        CHECK(gw_write(path, &spec, particle_of, (void *)&s->file[f]) == 0);
    }
}

static int same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* What the reader should give for an extra field. */
static float expected_extra(const gw_particle *p, int type, const char *name)
{
    if (strcmp(name, "vx") == 0) return (float)p->vel[0];
    if (strcmp(name, "vy") == 0) return (float)p->vel[1];
    if (strcmp(name, "vz") == 0) return (float)p->vel[2];
    if (strcmp(name, "u") == 0) return type == 0 ? (float)p->u : 0.0f;
    if (strcmp(name, "rho") == 0) return type == 0 ? (float)p->rho : 0.0f;
    if (strcmp(name, "pot") == 0) return (float)p->pot;
    return -1.0f;
}

typedef struct cursor {
    int file, index;
} cursor;

/* Advances to the next particle of a wanted type; 0 at the end. */
static int next_expected(const test_snap *s, unsigned type_mask, cursor *c)
{
    for (;;) {
        c->index++;
        if (c->index >= s->file[c->file].n) {
            c->file++;
            c->index = 0;
            if (c->file >= s->lay.nfiles)
                return 0;
            if (s->file[c->file].n == 0) {
                c->index = -1;
                continue;
            }
        }
        if (!type_mask || (type_mask & (1u << s->file[c->file].type[c->index])))
            return 1;
    }
}

/* Checks one read particle against the expected one; returns 1 when equal. */
static int particle_matches(const test_snap *s, const orr_source *src, const orr_chunk *c, size_t i,
                            const cursor *at)
{
    const gw_particle *p = &s->file[at->file].p[at->index];
    int type = s->file[at->file].type[at->index];
    float mass = s->massarr[type] != 0 ? (float)s->massarr[type] : (float)p->mass;
    uint64_t id = s->lay.id64 ? p->id : (uint32_t)p->id;
    int ok = same_bits(c->x[i], (float)p->pos[0]) && same_bits(c->y[i], (float)p->pos[1]) &&
             same_bits(c->z[i], (float)p->pos[2]) && same_bits(c->mass[i], mass) && c->type[i] == type;
    if (src->info.has_id)
        ok = ok && c->id[i] == id;
    if (src->info.has_h)
        ok = ok && same_bits(c->h[i], type == 0 ? (float)p->hsml : 0.0f);
    for (int k = 0; k < c->nextra; k++)
        ok = ok && same_bits(c->extra[k].data[i], expected_extra(p, type, c->extra[k].name));
    return ok;
}

/* Reads the whole source and compares every particle; returns the count. */
static long read_and_compare(const test_snap *s, orr_source *src, unsigned type_mask, size_t chunk)
{
    orr_error err = {0};
    cursor at = {0, -1};
    long n = 0, bad = 0;
    int more = next_expected(s, type_mask, &at);
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        CHECK(c->n <= chunk);
        CHECK(c->first_index == (uint64_t)n);
        for (size_t i = 0; i < c->n; i++, n++) {
            if (!more || !particle_matches(s, src, c, i, &at))
                bad++;
            more = next_expected(s, type_mask, &at);
        }
    }
    CHECK(err.code == ORR_OK);
    CHECK(!more);
    CHECK(bad == 0);
    return n;
}

static orr_source *open_gadget(const char *path, size_t chunk, unsigned type_mask, const char *const *fields,
                               int nfields, orr_error *err)
{
    orr_source_options opt = {.format = "gadget", .chunk_size = chunk, .type_mask = type_mask, .fields = fields,
                              .nfields = nfields};
    orr_source *src = NULL;
    orr_status st = orr_gadget_source_open(path, &opt, &src, err);
    CHECK((st == ORR_OK) == (src != NULL));
    return src;
}

static int has_extra(const orr_source *src, const char *name)
{
    for (int i = 0; i < src->info.nextra; i++)
        if (strcmp(src->info.extra_names[i], name) == 0)
            return 1;
    return 0;
}

static const char *header_value(const orr_source *src, const char *key)
{
    for (int i = 0; i < src->info.nheader; i++)
        if (strcmp(src->info.header[i].key, key) == 0)
            return src->info.header[i].value;
    return "";
}

static long total_particles(const test_snap *s)
{
    long n = 0;
    for (int f = 0; f < s->lay.nfiles; f++)
        n += s->file[f].n;
    return n;
}

/* Writes the layout, then reads it back with several chunk sizes. */
static void round_trip(layout lay, const char *name)
{
    static test_snap s;
    make_snapshot(&s, lay);
    write_snapshot(&s, name);
    const size_t chunks[] = {1, 7, 100000};
    for (int k = 0; k < 3; k++) {
        orr_error err = {0};
        orr_source *src = open_gadget(tmp_path(name), chunks[k], 0, NULL, 0, &err);
        if (!src) {
            fprintf(stderr, "%s: %s\n", name, err.msg);
            return;
        }
        CHECK(src->info.count == total_particles(&s));
        CHECK(src->info.time == 0.5);
        CHECK(strcmp(src->info.format, "gadget") == 0);
        CHECK(src->info.has_type && src->info.has_id == ((lay.blocks & GW_ID) != 0));
        CHECK(src->info.has_h == ((lay.blocks & GW_HSML) != 0));
        CHECK(has_extra(src, "vx") == ((lay.blocks & GW_VEL) != 0));
        CHECK(has_extra(src, "u") == ((lay.blocks & GW_U) != 0));
        CHECK(has_extra(src, "rho") == ((lay.blocks & GW_RHO) != 0));
        /* Without labels POT cannot be told from other blocks. */
        CHECK(has_extra(src, "pot") == ((lay.blocks & GW_POT) && lay.snapformat == 2));
        CHECK_CONTAINS(header_value(src, "byte order"), lay.big_endian ? "big" : "little");
        CHECK_CONTAINS(header_value(src, "precision"), lay.double_precision ? "double" : "float");
        CHECK_CONTAINS(header_value(src, "id width"), !(lay.blocks & GW_ID) ? "none" : lay.id64 ? "64" : "32");
        CHECK(atoi(header_value(src, "SnapFormat")) == lay.snapformat);
        long n = read_and_compare(&s, src, 0, chunks[k]);
        CHECK(n == total_particles(&s));
        if (k == 1) { /* reading again gives the same particles */
            orr_error e2 = {0};
            CHECK(orr_source_rewind(src, &e2) == ORR_OK);
            CHECK(read_and_compare(&s, src, 0, chunks[k]) == n);
        }
        orr_source_close(src);
    }
}

#define ALL_BLOCKS (GW_VEL | GW_ID | GW_U | GW_RHO | GW_HSML | GW_POT)

static void test_round_trip_format2_little_float(void)
{
    round_trip((layout){2, 0, 0, 0, 1, 0, ALL_BLOCKS}, "f2_le_float");
}

static void test_round_trip_format2_big_double_id64(void)
{
    round_trip((layout){2, 1, 1, 1, 1, 0, ALL_BLOCKS}, "f2_be_double");
}

static void test_round_trip_format1_little_and_big(void)
{
    round_trip((layout){1, 0, 0, 0, 1, 0, ALL_BLOCKS}, "f1_le");
    round_trip((layout){1, 1, 0, 1, 1, 1, GW_VEL | GW_ID}, "f1_be_table");
    round_trip((layout){1, 1, 1, 0, 1, 0, GW_VEL | GW_ID | GW_U}, "f1_be_double_u");
}

static void test_round_trip_mass_table_and_minimal_blocks(void)
{
    round_trip((layout){2, 0, 0, 0, 1, 1, GW_VEL | GW_ID}, "f2_table");
    round_trip((layout){2, 1, 0, 0, 1, 0, 0}, "f2_pos_mass_only");
}

static void test_round_trip_three_files(void)
{
    round_trip((layout){2, 0, 0, 0, 3, 0, ALL_BLOCKS}, "multi2");
    round_trip((layout){1, 1, 1, 1, 3, 0, GW_VEL | GW_ID | GW_U | GW_RHO | GW_HSML}, "multi1");
    /* The first part's name works as well as the base name. */
    static test_snap s;
    make_snapshot(&s, (layout){2, 0, 0, 0, 3, 0, ALL_BLOCKS});
    orr_error err = {0};
    orr_source *src = open_gadget(tmp_path("multi2.0"), 5, 0, NULL, 0, &err);
    CHECK(src && src->info.count == total_particles(&s));
    if (src)
        CHECK(read_and_compare(&s, src, 0, 5) == total_particles(&s));
    CHECK_CONTAINS(src ? header_value(src, "npart (file 2)") : "", "9 31 0 1 0 4");
    orr_source_close(src);
}

static void test_type_mask_and_fields(void)
{
    static test_snap s;
    layout lay = {2, 0, 0, 0, 3, 0, ALL_BLOCKS};
    make_snapshot(&s, lay);
    write_snapshot(&s, "select");
    const char *const fields[] = {"vy", "rho"};
    const unsigned masks[] = {1u << 1, (1u << 0) | (1u << 4), 1u << 2, (1u << 5) | (1u << 3)};
    for (int m = 0; m < 4; m++) {
        orr_error err = {0};
        orr_source *src = open_gadget(tmp_path("select"), 3, masks[m], fields, 2, &err);
        if (!src)
            return;
        CHECK(src->info.nextra == 2 && has_extra(src, "vy") && has_extra(src, "rho") && !has_extra(src, "vx"));
        long expected = 0;
        for (int f = 0; f < 3; f++)
            for (int i = 0; i < s.file[f].n; i++)
                expected += (masks[m] >> s.file[f].type[i]) & 1;
        CHECK(src->info.count == expected);
        CHECK(read_and_compare(&s, src, masks[m], 3) == expected);
        orr_source_close(src);
    }
    /* An empty field list loads no extra field. */
    orr_error err = {0};
    orr_source *src = open_gadget(tmp_path("select"), 64, 0, fields, 0, &err);
    CHECK(src && src->info.nextra == 0 && src->info.has_h);
    if (src)
        CHECK(read_and_compare(&s, src, 0, 64) == total_particles(&s));
    orr_source_close(src);
}

static void test_probe(void)
{
    unsigned char f1[264] = {0}, f2[16] = {8, 0, 0, 0, 'H', 'E', 'A', 'D', 8, 1, 0, 0, 8, 0, 0, 0};
    f1[1] = 1;
    f1[261] = 1; /* 256 little endian at both ends of the header */
    CHECK(orr_gadget_probe(f1, sizeof f1));
    f1[261] = 2;
    CHECK(!orr_gadget_probe(f1, sizeof f1));
    CHECK(orr_gadget_probe(f2, sizeof f2));
    unsigned char be[8] = {0, 0, 0, 8, 'H', 'E', 'A', 'D'};
    CHECK(orr_gadget_probe(be, sizeof be));
    CHECK(!orr_gadget_probe((const unsigned char *)"x y z\n1 2 3\n", 12));
    CHECK(!orr_gadget_probe(f2, 3));
}

/* ---- the shared reference files ---- */

typedef struct totals {
    long n, per_type[6];
    double mass;
    float first[3];
    uint64_t first_id, id_min, id_max;
} totals;

static int read_totals(const char *path, size_t chunk, totals *t, orr_source **keep)
{
    orr_error err = {0};
    memset(t, 0, sizeof *t);
    t->id_min = UINT64_MAX;
    orr_source *src = open_gadget(path, chunk, 0, NULL, 0, &err);
    if (!src) {
        fprintf(stderr, "%s\n", err.msg);
        return 0;
    }
    const orr_chunk *c;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
        for (size_t i = 0; i < c->n; i++) {
            if (t->n == 0) {
                t->first[0] = c->x[i];
                t->first[1] = c->y[i];
                t->first[2] = c->z[i];
                t->first_id = c->id[i];
            }
            t->n++;
            t->per_type[c->type[i]]++;
            t->mass += c->mass[i];
            t->id_min = c->id[i] < t->id_min ? c->id[i] : t->id_min;
            t->id_max = c->id[i] > t->id_max ? c->id[i] : t->id_max;
        }
    CHECK(err.code == ORR_OK);
    *keep = src;
    return 1;
}

static int shared_skipped;

static void test_shared_galaxy(void)
{
    char buf[1024];
    const char *path = shared_data_path(buf, sizeof buf, "gadget2/gadget2_examples/galaxy_littleendian.dat");
    if (!path) {
        shared_skipped = 1;
        return;
    }
    totals t;
    orr_source *src;
    if (!read_totals(path, 4096, &t, &src))
        return;
    CHECK(t.n == 60000 && src->info.count == 60000);
    CHECK(t.per_type[1] == 40000 && t.per_type[2] == 20000);
    CHECK_NEAR(t.mass, 46.5039423, 1e-4);
    CHECK(t.first[0] == -94.1338501f && t.first[1] == -10.240922f && t.first[2] == -7.94286728f);
    CHECK(t.id_min == 1 && t.id_max == 60000 && t.first_id == 1);
    CHECK(src->info.has_id && !src->info.has_h && src->info.nextra == 3);
    CHECK_CONTAINS(header_value(src, "num_files"), "0 (read as a single file)");
    CHECK_CONTAINS(header_value(src, "npart"), "0 40000 20000 0 0 0");
    CHECK_CONTAINS(header_value(src, "SnapFormat"), "1");
    CHECK_CONTAINS(header_value(src, "massarr"), "0.0010463387006893754");
    orr_source_close(src);
}

static void test_shared_gassphere_both_byte_orders(void)
{
    const char *names[2] = {"gadget2/gadget2_examples/gassphere_littleendian.dat",
                            "gadget2/gadget2_examples/gassphere_bigendian.dat"};
    for (int e = 0; e < 2; e++) {
        char buf[1024];
        const char *path = shared_data_path(buf, sizeof buf, names[e]);
        if (!path) {
            shared_skipped = 1;
            return;
        }
        totals t;
        orr_source *src;
        if (!read_totals(path, 100, &t, &src))
            return;
        CHECK(t.n == 1472 && t.per_type[0] == 1472);
        CHECK_NEAR(t.mass, 1.00000002, 1e-5);
        CHECK(t.first[0] == -0.0713372901f && t.first[1] == -0.356686443f && t.first[2] == -0.927384734f);
        CHECK(t.id_min == 1 && t.id_max == 1472);
        CHECK(has_extra(src, "u") && !has_extra(src, "rho"));
        CHECK_CONTAINS(header_value(src, "byte order"), e ? "big endian" : "little endian");
        CHECK_CONTAINS(header_value(src, "note"), "npartTotal is all 0");
        orr_source_close(src);
    }
}

/* The gas-only blocks GadgetReader's files carry beyond the standard ones
 * (NHP NHEP NHEQ NH NHE SFR) as named fields. Reference values read from
 * the files with Python's struct (not this reader): NHP's first value in
 * part 0 is 0.99999607, its sums over the gas are 1993.92150 (part 0) and
 * 2044.94499 (part 1); every SFR value is 0. */
static void test_shared_named_blocks(const char *path)
{
    const char *const fields[] = {"NHP", "SFR", "u"};
    orr_error err = {0};
    orr_source *src = open_gadget(path, 1000, 0, fields, 3, &err);
    CHECK(src != NULL);
    if (!src) {
        fprintf(stderr, "  %s\n", err.msg);
        return;
    }
    CHECK(has_extra(src, "NHP") && has_extra(src, "SFR") && src->info.nextra == 3);
    CHECK_CONTAINS(header_value(src, "NHP"), "type 0, 1 float each: field NHP");
    CHECK_CONTAINS(header_value(src, "SFR"), "type 0, 1 float each: field SFR");
    const orr_chunk *c;
    double nhp_gas = 0, nhp_other = 0, sfr = 0;
    float first = -1;
    int64_t n = 0;
    while (orr_source_next(src, &c, &err) == ORR_OK && c->n > 0) {
        const float *nhp = orr_chunk_field(c, "NHP"), *rate = orr_chunk_field(c, "SFR");
        for (size_t i = 0; i < c->n; i++, n++) {
            if (n == 0)
                first = nhp[i];
            *(c->type[i] == 0 ? &nhp_gas : &nhp_other) += nhp[i];
            sfr += fabs(rate[i]);
        }
    }
    CHECK(n == 8192);
    CHECK(first == 0.99999607f);
    CHECK_NEAR(nhp_gas, 1993.92150 + 2044.94499, 1e-3);
    CHECK(nhp_other == 0 && sfr == 0);
    orr_source_close(src);
}

static void test_shared_format2_two_files(void)
{
    char buf[1024];
    const char *path = shared_data_path(buf, sizeof buf, "gadget2/gadgetreader_format2/test_g2_snap.0");
    if (!path) {
        shared_skipped = 1;
        return;
    }
    /* Both the base name and the first part's name. */
    for (int form = 0; form < 2; form++) {
        char name[1024];
        snprintf(name, sizeof name, "%s", path);
        if (form == 0)
            name[strlen(name) - 2] = '\0';
        totals t;
        orr_source *src;
        if (!read_totals(name, 1000, &t, &src))
            return;
        CHECK(t.n == 8192 && src->info.count == 8192);
        CHECK(t.per_type[0] == 4039 && t.per_type[1] == 4096 && t.per_type[4] == 57);
        CHECK_NEAR(t.mass, 200.0107394, 1e-3);
        CHECK(t.first_id == 3859 && t.id_min == 1 && t.id_max == 8192);
        CHECK(src->info.time == 0.2777777798158637);
        CHECK(src->info.has_h && has_extra(src, "u") && has_extra(src, "rho") && !has_extra(src, "pot"));
        CHECK_CONTAINS(header_value(src, "redshift"), "2.5999999735864066");
        CHECK_CONTAINS(header_value(src, "BoxSize"), "3000");
        CHECK_CONTAINS(header_value(src, "Omega0"), "0.2669");
        CHECK_CONTAINS(header_value(src, "HubbleParam"), "0.71");
        CHECK_CONTAINS(header_value(src, "npart (file 1)"), "2045 2046 0 0 18 0");
        CHECK_CONTAINS(header_value(src, "flags"), "sfr=1 feedback=1 cooling=1");
        /* The junk high word is noticed and ignored. */
        CHECK_CONTAINS(header_value(src, "warning"), "npartTotalHighWord[2] = 228 ignored");
        orr_source_close(src);
    }
    /* Only the gas, with only u. */
    const char *const fields[] = {"u"};
    orr_error err = {0};
    orr_source *src = open_gadget(path, 512, 1u << 0, fields, 1, &err);
    CHECK(src && src->info.count == 4039 && src->info.nextra == 1);
    orr_source_close(src);
    test_shared_named_blocks(path);
}

/* ---- damaged files ---- */

static void patch(const char *path, long offset, const void *bytes, size_t n)
{
    FILE *fp = fopen(path, "r+b");
    CHECK(fp != NULL);
    if (!fp)
        return;
    fseek(fp, offset, SEEK_SET);
    fwrite(bytes, 1, n, fp);
    fclose(fp);
}

static void patch_u32le(const char *path, long offset, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    patch(path, offset, b, 4);
}

/* A small little-endian snapshot: 2 gas + 3 type-1 particles. */
static void write_small(const char *name, int snapformat, int32_t num_files)
{
    static test_file f;
    memset(&f, 0, sizeof f);
    f.npart[0] = 2;
    f.npart[1] = 3;
    for (int i = 0; i < 5; i++) {
        f.p[i].pos[0] = i;
        f.p[i].id = (uint64_t)i + 1;
        f.p[i].mass = 0.5;
    }
    gw_spec spec = {.snapformat = snapformat, .blocks = GW_VEL | GW_ID | GW_U, .num_files = num_files,
                    .massarr = {0, 2.0}};
    memcpy(spec.npart, f.npart, sizeof spec.npart);
    CHECK(gw_write(tmp_path(name), &spec, particle_of, &f) == 0);
}

/* Opening must fail with code and a message naming the file and needle. */
static void expect_failure(const char *path, orr_status code, const char *needle)
{
    orr_error err = {0};
    orr_source *src = (orr_source *)&err; /* must be reset to NULL */
    orr_source_options opt = {.format = "gadget"};
    orr_status st = orr_gadget_source_open(path, &opt, &src, &err);
    CHECK(st == code && err.code == code);
    CHECK(src == NULL);
    CHECK_CONTAINS(err.msg, needle);
    if (st != code)
        fprintf(stderr, "  for %s: got %d: %s\n", path, st, err.msg);
}

/* Offsets in the small format-1 file: header data at 4, POS marker at 264,
 * POS data (5 x 12 bytes) at 268, its closing marker at 328. */
static void test_truncated_files(void)
{
    write_small("trunc", 1, 1);
    const char *path = tmp_path("trunc");
    CHECK(truncate(path, 300) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "block #1 after the header: record marker at offset 264 says 60 bytes");
    expect_failure(path, ORR_ERR_FORMAT, "past the end of the file (size 300)");
    expect_failure(path, ORR_ERR_FORMAT, "trunc");
    CHECK(truncate(path, 100) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "header record: needs 264 bytes at offset 0 but the file ends at 100");
    CHECK(truncate(path, 2) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "2 bytes is too short");
    CHECK(truncate(path, 0) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "0 bytes is too short");
    write_small("trunc2", 2, 1);
    path = tmp_path("trunc2");
    CHECK(truncate(path, 296 + 30) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "block POS: record marker at offset 296 says 60 bytes");
}

static void test_markers_that_disagree(void)
{
    write_small("closing", 1, 1);
    const char *path = tmp_path("closing");
    patch_u32le(path, 328, 61);
    expect_failure(path, ORR_ERR_FORMAT, "opening record marker says 60 bytes, the closing marker at offset 328 says 61");
    write_small("head", 1, 1);
    path = tmp_path("head");
    patch_u32le(path, 260, 255);
    expect_failure(path, ORR_ERR_FORMAT, "block HEAD: record markers 256 and 255, expected 256 and 256");
    write_small("head2", 2, 1);
    path = tmp_path("head2");
    patch_u32le(path, 16, 260);
    expect_failure(path, ORR_ERR_FORMAT, "block HEAD: record markers 260 and 256");
    write_small("label", 2, 1);
    path = tmp_path("label");
    patch_u32le(path, 280 + 8, 100); /* POS label record announces 100 bytes */
    expect_failure(path, ORR_ERR_FORMAT, "block POS: the label record announces 100 bytes, the data record holds 60");
    write_small("labelm", 2, 1);
    path = tmp_path("labelm");
    patch_u32le(path, 280, 9);
    expect_failure(path, ORR_ERR_FORMAT, "block label record at offset 280: markers 9 and 8");
    write_small("nohead", 2, 1);
    path = tmp_path("nohead");
    patch(path, 4, "HEAX", 4);
    expect_failure(path, ORR_ERR_FORMAT, "first block label is 'HEAX', expected 'HEAD'");
}

static void test_wrong_byte_order_or_not_gadget(void)
{
    write_small("order", 1, 1);
    const char *path = tmp_path("order");
    patch_u32le(path, 0, 0x01000100);
    expect_failure(path, ORR_ERR_FORMAT, "first record marker is 16777472 read little endian and 65537 read big endian");
    FILE *fp = fopen(tmp_path("text"), "w");
    fputs("x y z\n1 2 3\n", fp);
    fclose(fp);
    expect_failure(tmp_path("text"), ORR_ERR_FORMAT, "not a Gadget file");
}

static void test_counts_that_disagree(void)
{
    /* npart[1] 3 -> 4: POS no longer fits. */
    write_small("count", 1, 1);
    const char *path = tmp_path("count");
    patch_u32le(path, 4 + 4, 4);
    expect_failure(path, ORR_ERR_FORMAT, "block POS holds 60 bytes; 6 particles need 72 (float) or 144 (double)");
    /* A header claiming ~10^15 particles: caught by the block lengths,
     * before anything is allocated. */
    write_small("huge", 2, 1);
    path = tmp_path("huge");
    for (int t = 1; t < 6; t++) {
        patch_u32le(path, 20 + 4 * t, 0x7fffffff);
        patch_u32le(path, 20 + 168 + 4 * t, 50000);
    }
    expect_failure(path, ORR_ERR_FORMAT, "block POS holds 60 bytes; 10737418237 particles need");
    /* A negative count. */
    write_small("negative", 1, 1);
    path = tmp_path("negative");
    patch_u32le(path, 4 + 12, 0xffffffffu);
    expect_failure(path, ORR_ERR_FORMAT, "header npart[3] = -1 is negative");
    /* massarr[1] -> 0: the type-1 masses should be in MASS, which holds only gas. */
    write_small("massblk", 2, 1);
    path = tmp_path("massblk");
    patch(path, 20 + 24 + 8, "\0\0\0\0\0\0\0\0", 8);
    expect_failure(path, ORR_ERR_FORMAT, "block MASS holds 8 bytes; 5 particles of types with massarr 0 need 20");
    /* No MASS block at all: type 1's massarr patched to 0. */
    static test_file f;
    memset(&f, 0, sizeof f);
    f.npart[1] = 3;
    f.n = 3;
    gw_spec spec = {.snapformat = 1, .blocks = GW_VEL | GW_ID, .massarr = {0, 2.0}, .npart = {0, 3}};
    path = tmp_path("nomass");
    CHECK(gw_write(path, &spec, particle_of, &f) == 0);
    patch(path, 4 + 24 + 8, "\0\0\0\0\0\0\0\0", 8);
    expect_failure(path, ORR_ERR_FORMAT, "types 1 have massarr 0, so their 3 masses must be in a MASS block");
}

/* A NaN or infinite time would be written into every image's FITS header,
 * which cfitsio refuses at the end of each render: refused when opening. */
static void test_time_not_finite(void)
{
    const double times[2] = {NAN, -INFINITY};
    for (int k = 0; k < 2; k++) {
        const char *name = k ? "inftime" : "nantime";
        write_small(name, 1, 1);
        unsigned char b[8];
        uint64_t bits;
        memcpy(&bits, &times[k], 8);
        for (int i = 0; i < 8; i++)
            b[i] = (unsigned char)(bits >> (8 * i));
        patch(tmp_path(name), 4 + 72, b, 8); /* header time, little endian */
        expect_failure(tmp_path(name), ORR_ERR_FORMAT, "header time = ");
        expect_failure(tmp_path(name), ORR_ERR_FORMAT, "is not a finite number");
    }
}

/* Writes 2 gas particles (massarr 0: masses in the MASS block, the second
 * one given) and 3 of type 1 (massarr given), in float or double. */
static const char *write_masses(const char *name, int double_precision, double gas_mass, double massarr1)
{
    static test_file f;
    memset(&f, 0, sizeof f);
    f.npart[0] = 2;
    f.npart[1] = 3;
    for (int i = 0; i < 5; i++) {
        f.p[i].pos[0] = i;
        f.p[i].mass = i == 1 ? gas_mass : 0.5;
    }
    gw_spec spec = {.snapformat = 2, .double_precision = double_precision, .blocks = GW_ID, .num_files = 1,
                    .massarr = {0, massarr1}, .npart = {2, 3}};
    CHECK(gw_write(tmp_path(name), &spec, particle_of, &f) == 0);
    return tmp_path(name);
}

/* Reads the whole file; returns the status and the sum of the masses. */
static orr_status read_masses(const char *path, double *sum, orr_error *err)
{
    orr_source *src = open_gadget(path, 2, 0, NULL, 0, err);
    if (!src)
        return err->code;
    const orr_chunk *c;
    orr_status st;
    *sum = 0;
    while (!(st = orr_source_next(src, &c, err)) && c->n > 0)
        for (size_t i = 0; i < c->n; i++)
            *sum += c->mass[i];
    orr_source_close(src);
    return st;
}

/* The mass policy every reader shares (docs/input.md): negative, non-finite
 * and float-unrepresentable masses are errors naming file, particle, value;
 * 0 and tiny but representable masses are read. */
static void test_mass_policy(void)
{
    static const struct {
        int dbl;
        double gas, table;
        const char *needle;
    } bad[] = {
        {0, -2.0, 2.0, "block MASS: particle 1 of the file (type 0): mass -2 is negative"},
        {0, NAN, 2.0, "particle 1 of the file (type 0): mass nan is not a finite number"},
        {1, INFINITY, 2.0, "particle 1 of the file (type 0): mass inf is not a finite number"},
        {1, 1e-300, 2.0, "particle 1 of the file (type 0): mass 1e-300 is too small for a float"},
        {1, 1e300, 2.0, "particle 1 of the file (type 0): mass 1e+300 is too large for a float"},
        {0, 1.0, -2.0, "header massarr[1] = -2 is negative (the mass of its 3 particles)"},
        {1, 1.0, NAN, "header massarr[1] = nan is not a finite number"},
        {1, 1.0, 1e-300, "header massarr[1] = 1e-300 is too small for a float"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char name[32];
        snprintf(name, sizeof name, "badmass%zu", k);
        const char *path = write_masses(name, bad[k].dbl, bad[k].gas, bad[k].table);
        orr_error err = {0};
        double sum;
        CHECK(read_masses(path, &sum, &err) == ORR_ERR_FORMAT);
        CHECK_CONTAINS(err.msg, path);
        CHECK_CONTAINS(err.msg, bad[k].needle);
    }
    /* 0 and 1e-40 (a float subnormal) are masses like any other. */
    const double good[2] = {0.0, 1e-40};
    for (int k = 0; k < 2; k++) {
        const char *path = write_masses(k ? "tinymass" : "zeromass", 1, good[k], 2.0);
        orr_error err = {0};
        double sum = 0;
        CHECK(read_masses(path, &sum, &err) == ORR_OK);
        CHECK(sum == 0.5 + (float)good[k] + 3 * 2.0);
    }
}

static void test_multi_file_problems(void)
{
    /* A missing part. */
    static test_snap s;
    make_snapshot(&s, (layout){2, 0, 0, 0, 3, 0, GW_VEL | GW_ID});
    write_snapshot(&s, "gap");
    char part[600];
    snprintf(part, sizeof part, "%s.1", tmp_path("gap"));
    unlink(part);
    expect_failure(tmp_path("gap"), ORR_ERR_IO, "part 1 of 3: ");
    expect_failure(tmp_path("gap"), ORR_ERR_IO, "gap.1: cannot open: No such file");
    expect_failure(tmp_path("gap.0"), ORR_ERR_IO, "part 1 of 3");
    /* A part with another num_files. */
    write_snapshot(&s, "nf");
    snprintf(part, sizeof part, "%s.2", tmp_path("nf"));
    patch_u32le(part, 16 + 4 + 124, 4);
    expect_failure(tmp_path("nf"), ORR_ERR_FORMAT, "nf.2: header num_files = 4, but part 0 says 3");
    /* A part that is not part of anything: no .N suffix. */
    write_small("lonely", 2, 3);
    expect_failure(tmp_path("lonely"), ORR_ERR_FORMAT, "num_files = 3, but the name does not end in .0");
    /* A part past num_files. */
    write_small("far.7", 2, 3);
    expect_failure(tmp_path("far.7"), ORR_ERR_FORMAT, "part 7 of a snapshot whose header says num_files = 3");
    expect_failure(tmp_path("absent"), ORR_ERR_IO, "absent: cannot open: No such file or directory (nor is there a");
    expect_failure(tmpdir, ORR_ERR_IO, "not a regular file");
}

/* GADGET-2 writes a MASS block only into the parts that hold particles of
 * a type with massarr 0: part 0 here has gas (massarr 0) and type 1, part 1
 * only type 1 (massarr 2), so part 1 has no MASS block and needs none. */
static void test_mass_block_only_where_needed(void)
{
    static test_snap s;
    memset(&s, 0, sizeof s);
    s.lay = (layout){1, 0, 0, 0, 2, 0, GW_VEL | GW_ID};
    s.massarr[1] = 2.0;
    const int32_t counts[2][6] = {{2, 3}, {0, 4}};
    for (int f = 0; f < 2; f++) {
        test_file *tf = &s.file[f];
        for (int t = 0; t < 2; t++)
            for (int j = 0; j < counts[f][t]; j++) {
                gw_particle *p = &tf->p[tf->n];
                tf->type[tf->n++] = t;
                p->pos[0] = tf->n + 10 * f;
                p->id = (uint64_t)(tf->n + 10 * f);
                p->mass = 0.25 * tf->n;
            }
        memcpy(tf->npart, counts[f], sizeof tf->npart);
    }
    for (int format = 1; format <= 2; format++) {
        s.lay.snapformat = format;
        const char *name = format == 1 ? "massparts1" : "massparts2";
        write_snapshot(&s, name);
        orr_error err = {0};
        orr_source *src = open_gadget(tmp_path(name), 4, 0, NULL, 0, &err);
        CHECK(src != NULL);
        if (!src) {
            fprintf(stderr, "  %s: %s\n", name, err.msg);
            continue;
        }
        CHECK(src->info.count == 9);
        CHECK(read_and_compare(&s, src, 0, 4) == 9);
        orr_source_close(src);
    }
}

static void test_block_twice(void)
{
    write_small("twice", 2, 1);
    const char *path = tmp_path("twice");
    patch(path, 280 + 4 + 16 + 60 + 4 + 4, "POS ", 4); /* VEL's label */
    expect_failure(path, ORR_ERR_FORMAT, "block POS appears twice");
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    RUN(test_probe);
    RUN(test_round_trip_format2_little_float);
    RUN(test_round_trip_format2_big_double_id64);
    RUN(test_round_trip_format1_little_and_big);
    RUN(test_round_trip_mass_table_and_minimal_blocks);
    RUN(test_round_trip_three_files);
    RUN(test_type_mask_and_fields);
    RUN(test_truncated_files);
    RUN(test_markers_that_disagree);
    RUN(test_wrong_byte_order_or_not_gadget);
    RUN(test_counts_that_disagree);
    RUN(test_time_not_finite);
    RUN(test_mass_policy);
    RUN(test_multi_file_problems);
    RUN(test_block_twice);
    RUN(test_mass_block_only_where_needed);
    RUN(test_shared_galaxy);
    RUN(test_shared_gassphere_both_byte_orders);
    RUN(test_shared_format2_two_files);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    int status = check_summary();
    if (status == 0 && shared_skipped)
        return SKIP_CODE;
    return status;
}
