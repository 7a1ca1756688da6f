/* The HDF5 snapshot reader: round trips through the test-only writer in the
 * Gadget-4 (NTYPES=2), 6-type Gadget and SWIFT layouts, multi-file
 * snapshots, type and field selection, chunking; the real Gadget-4 and SWIFT
 * files of the shared data; and each kind of bad file with its message. */
#include <hdf5.h>
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#include "check.h"
#include "hdf5_writer.h"
#include "source/readers/hdf5_reader.h"
#include "source/source.h"

static char tmpdir[] = "/tmp/orrery-hdf5-XXXXXX";

static const char *tmp_path(const char *name)
{
    static char paths[4][512];
    static int next;
    char *p = paths[next++ % 4];
    snprintf(p, sizeof paths[0], "%s/%s", tmpdir, name);
    return p;
}

/* Every HDF5 handle the reader opened must be closed again. */
static void check_no_open_hdf5(void)
{
    CHECK(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) == 0);
}

/* ---- All the particles of a source, flattened ----------------------- */

#define NEXTRA 6
static const char *const extra_names[NEXTRA] = {"vx", "vy", "vz", "u", "rho", "pot"};

typedef struct flat {
    size_t n, cap;
    float *x, *y, *z, *mass, *h, *ex[NEXTRA];
    uint64_t *id;
    uint8_t *type;
} flat;

static void flat_grow(flat *f, size_t n)
{
    if (f->n + n <= f->cap)
        return;
    size_t cap = (f->n + n) * 2;
    float **arrays[] = {&f->x, &f->y, &f->z, &f->mass, &f->h, &f->ex[0], &f->ex[1], &f->ex[2], &f->ex[3], &f->ex[4], &f->ex[5]};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++) {
        *arrays[i] = realloc(*arrays[i], cap * sizeof(float));
        memset(*arrays[i] + f->cap, 0, (cap - f->cap) * sizeof(float));
    }
    f->id = realloc(f->id, cap * sizeof *f->id);
    f->type = realloc(f->type, cap);
    f->cap = cap;
}

static void flat_free(flat *f)
{
    float *arrays[] = {f->x, f->y, f->z, f->mass, f->h, f->ex[0], f->ex[1], f->ex[2], f->ex[3], f->ex[4], f->ex[5]};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        free(arrays[i]);
    free(f->id);
    free(f->type);
    memset(f, 0, sizeof *f);
}

static void flat_add_chunk(flat *f, const orr_chunk *c)
{
    flat_grow(f, c->n);
    memcpy(f->x + f->n, c->x, c->n * sizeof(float));
    memcpy(f->y + f->n, c->y, c->n * sizeof(float));
    memcpy(f->z + f->n, c->z, c->n * sizeof(float));
    memcpy(f->mass + f->n, c->mass, c->n * sizeof(float));
    if (c->h)
        memcpy(f->h + f->n, c->h, c->n * sizeof(float));
    memcpy(f->id + f->n, c->id, c->n * sizeof(uint64_t));
    memcpy(f->type + f->n, c->type, c->n);
    for (int e = 0; e < NEXTRA; e++) {
        const float *v = orr_chunk_field(c, extra_names[e]);
        if (v)
            memcpy(f->ex[e] + f->n, v, c->n * sizeof(float));
    }
    f->n += c->n;
}

/* Reads a whole source; *largest gets the largest chunk seen. */
static orr_status read_all(orr_source *src, flat *f, size_t *largest, orr_error *err)
{
    const orr_chunk *c;
    uint64_t expect_first = 0;
    *largest = 0;
    for (;;) {
        orr_status s = orr_source_next(src, &c, err);
        if (s)
            return s;
        if (c->n == 0)
            return ORR_OK;
        CHECK(c->n <= c->capacity);
        CHECK(c->first_index == expect_first);
        expect_first += c->n;
        if (c->n > *largest)
            *largest = c->n;
        flat_add_chunk(f, c);
    }
}

static orr_status open_and_read(const char *path, const orr_source_options *opt, flat *f, orr_source **src,
                                orr_error *err)
{
    size_t largest;
    orr_status s = orr_hdf5_source_open(path, opt, src, err);
    if (s)
        return s;
    s = read_all(*src, f, &largest, err);
    if (opt && opt->chunk_size)
        CHECK(largest <= opt->chunk_size);
    return s;
}

/* What the reader should give for snapshot files written from snaps[],
 * file by file and type by type: floats as (float) of the doubles written. */
static void expect_from(const h5w_snapshot *snaps, int nsnaps, unsigned type_mask, flat *e)
{
    uint64_t index = 0;
    for (int s = 0; s < nsnaps; s++)
        for (int t = 0; t < snaps[s].ntypes; t++) {
            const h5w_part *p = &snaps[s].part[t];
            if (type_mask && !(type_mask >> t & 1u))
                continue;
            flat_grow(e, p->n);
            for (size_t i = 0; i < p->n; i++, e->n++, index++) {
                size_t k = e->n;
                e->x[k] = (float)p->pos[3 * i];
                e->y[k] = (float)p->pos[3 * i + 1];
                e->z[k] = (float)p->pos[3 * i + 2];
                e->mass[k] = p->mass ? (float)p->mass[i] : (float)snaps[s].mass_table[t];
                e->h[k] = p->h ? (float)p->h[i] : 0.0f;
                e->id[k] = p->id ? p->id[i] : index;
                e->type[k] = (uint8_t)t;
                for (int a = 0; a < 3; a++)
                    e->ex[a][k] = p->vel ? (float)p->vel[3 * i + (size_t)a] : 0.0f;
                e->ex[3][k] = p->u ? (float)p->u[i] : 0.0f;
                e->ex[4][k] = p->rho ? (float)p->rho[i] : 0.0f;
                e->ex[5][k] = p->pot ? (float)p->pot[i] : 0.0f;
            }
        }
}

/* Bit-for-bit comparison of the fields the source has. */
static void check_same(const flat *a, const flat *e, const orr_source_info *info)
{
    CHECK(a->n == e->n);
    if (a->n != e->n)
        return;
    size_t fb = a->n * sizeof(float);
    CHECK(memcmp(a->x, e->x, fb) == 0);
    CHECK(memcmp(a->y, e->y, fb) == 0);
    CHECK(memcmp(a->z, e->z, fb) == 0);
    CHECK(memcmp(a->mass, e->mass, fb) == 0);
    CHECK(memcmp(a->id, e->id, a->n * sizeof(uint64_t)) == 0);
    CHECK(memcmp(a->type, e->type, a->n) == 0);
    if (info->has_h)
        CHECK(memcmp(a->h, e->h, fb) == 0);
    for (int i = 0; i < info->nextra; i++)
        for (int k = 0; k < NEXTRA; k++)
            if (strcmp(info->extra_names[i], extra_names[k]) == 0)
                CHECK(memcmp(a->ex[k], e->ex[k], fb) == 0);
}

static const char *header_value(const orr_source_info *info, const char *key)
{
    for (int i = 0; i < info->nheader; i++)
        if (strcmp(info->header[i].key, key) == 0)
            return info->header[i].value;
    return "(absent)";
}

static int has_extra(const orr_source_info *info, const char *name)
{
    for (int i = 0; i < info->nextra; i++)
        if (strcmp(info->extra_names[i], name) == 0)
            return 1;
    return 0;
}

/* ---- Test data -------------------------------------------------------- */

#define MAXN 64

/* Arrays for one group of n particles; values distinct per type and seed,
 * with doubles that are not floats, so conversion is exercised. */
typedef struct part_data {
    double pos[3 * MAXN], vel[3 * MAXN], mass[MAXN], h[MAXN], u[MAXN], rho[MAXN], pot[MAXN];
    uint64_t id[MAXN];
} part_data;

static h5w_part make_part(part_data *d, size_t n, int seed, uint64_t first_id)
{
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            d->pos[3 * i + (size_t)a] = seed * 100.0 + (double)i * 0.1 + a * 1e-7 + 1.0 / 3.0;
            d->vel[3 * i + (size_t)a] = -50.0 + (double)i * 1.7 - a + seed * 0.01;
        }
        d->mass[i] = 0.001 * (double)(i + 1) + seed * 1e-5;
        d->h[i] = 0.25 + (double)i * 0.01;
        d->u[i] = 1000.0 + (double)i;
        d->rho[i] = 1e-3 * (double)(i + 1);
        d->pot[i] = -1e4 + (double)i * 3.3;
        d->id[i] = first_id + i;
    }
    return (h5w_part){.n = n, .pos = d->pos, .vel = d->vel, .id = d->id, .mass = d->mass, .h = d->h,
                      .u = d->u, .rho = d->rho, .pot = d->pot};
}

/* Gadget-4 built with NTYPES=2: gas with SPH fields, DM from the mass table,
 * Gadget-4 unit attributes. */
static h5w_snapshot gadget4_snapshot(part_data d[2])
{
    h5w_snapshot s = {.style = H5W_GADGET, .ntypes = 2, .time = 0.5, .redshift = 1.0, .box = 100.0,
                      .gadget4_units = 1, .mass_table = {0.125, 0.875}};
    s.part[0] = make_part(&d[0], 13, 0, 1);
    s.part[0].mass = NULL;
    s.part[0].pot = NULL;
    s.part[1] = make_part(&d[1], 11, 1, 14);
    s.part[1].mass = s.part[1].h = s.part[1].u = s.part[1].rho = s.part[1].pot = NULL;
    return s;
}

/* Six types: Masses for gas and stars, the mass table for DM, types 2, 3, 5
 * empty; double coordinates and 64-bit ids above 2^32. */
static h5w_snapshot gadget6_snapshot(part_data d[6])
{
    h5w_snapshot s = {.style = H5W_GADGET, .ntypes = 6, .time = 0.25, .redshift = 3.0, .box = 1000.0,
                      .pos_type = H5T_IEEE_F64LE, .id_type = H5T_STD_U64LE,
                      .mass_table = {0, 2.5, 0, 0, 0, 0}};
    s.part[0] = make_part(&d[0], 9, 0, 5000000000ull);
    s.part[1] = make_part(&d[1], 17, 1, 1);
    s.part[1].mass = s.part[1].h = s.part[1].u = s.part[1].rho = NULL;
    s.part[4] = make_part(&d[4], 5, 4, 100);
    s.part[4].h = s.part[4].u = s.part[4].rho = s.part[4].pot = NULL;
    return s;
}

/* SWIFT: 7 types with gas and type 6, plural names, 1-element attributes. */
static h5w_snapshot swift_snapshot(part_data d[7])
{
    h5w_snapshot s = {.style = H5W_SWIFT, .ntypes = 7, .time = 1.0, .redshift = 0.0, .box = 6.25,
                      .pos_type = H5T_IEEE_F64LE, .id_type = H5T_STD_U64LE};
    s.part[0] = make_part(&d[0], 21, 0, 1);
    s.part[6] = make_part(&d[6], 3, 6, 1000);
    s.part[6].h = s.part[6].u = s.part[6].rho = NULL;
    return s;
}

/* Writes snap and checks a read of it against what was written. */
static void round_trip(const char *name, const h5w_snapshot *snap, const orr_source_options *opt,
                       orr_source_info *info_out)
{
    const char *path = tmp_path(name);
    CHECK(h5w_write(path, snap) == 0);
    flat got = {0}, want = {0};
    orr_source *src = NULL;
    orr_error err = {0};
    orr_status s = open_and_read(path, opt, &got, &src, &err);
    CHECK(s == ORR_OK);
    if (s)
        fprintf(stderr, "  %s\n", err.msg);
    if (src) {
        expect_from(snap, 1, opt ? opt->type_mask : 0, &want);
        check_same(&got, &want, &src->info);
        CHECK(src->info.count == (int64_t)want.n);
        if (info_out)
            *info_out = src->info;
    }
    orr_source_close(src);
    flat_free(&got);
    flat_free(&want);
    check_no_open_hdf5();
}

/* ---- Round trips ------------------------------------------------------ */

static void test_gadget4_two_types(void)
{
    part_data d[2];
    h5w_snapshot snap = gadget4_snapshot(d);
    static orr_source_info info;
    orr_source_options opt = {.chunk_size = 5};
    round_trip("g4.hdf5", &snap, &opt, &info);
    CHECK(info.has_h && info.has_id && info.has_type);
    CHECK(info.nextra == 5 && has_extra(&info, "vx") && has_extra(&info, "rho") && !has_extra(&info, "pot"));
    CHECK(info.time == 0.5);
    CHECK(strcmp(info.format, "hdf5") == 0);
    CHECK_CONTAINS(header_value(&info, "MassTable"), "0.125 0.875");
    CHECK(strcmp(header_value(&info, "BoxSize"), "100") == 0);
    CHECK(strcmp(header_value(&info, "NumPart_Total"), "13 11") == 0);
    CHECK(strcmp(header_value(&info, "units.length_cgs"), "3.085678e+21") == 0);
    CHECK(strcmp(header_value(&info, "units.velocity_cgs"), "100000") == 0);
    CHECK(strcmp(header_value(&info, "Coordinates"), "a^1 h^-1 (to cgs 3.085678e+21)") == 0);
    CHECK(strcmp(header_value(&info, "HubbleParam"), "0.7") == 0);
}

static void test_gadget6_mass_table_and_masses(void)
{
    part_data d[6];
    h5w_snapshot snap = gadget6_snapshot(d);
    static orr_source_info info;
    round_trip("g6.hdf5", &snap, NULL, &info);
    CHECK(info.nextra == 6 && info.count == 31);
    /* u32 ids and float coordinates in the same layout */
    snap.pos_type = H5T_IEEE_F32LE;
    snap.id_type = H5T_STD_U32LE;
    snap.part[0].id = d[1].id;
    round_trip("g6-u32.hdf5", &snap, NULL, NULL);
    /* signed ids */
    snap.id_type = H5T_STD_I64LE;
    round_trip("g6-i64.hdf5", &snap, NULL, NULL);
    snap.id_type = H5T_STD_I32LE;
    round_trip("g6-i32.hdf5", &snap, NULL, NULL);
}

static void test_swift_seven_types(void)
{
    part_data d[7];
    h5w_snapshot snap = swift_snapshot(d);
    static orr_source_info info;
    orr_source_options opt = {.chunk_size = 4};
    round_trip("swift.hdf5", &snap, &opt, &info);
    CHECK(info.count == 24 && info.has_h);
    CHECK(strcmp(header_value(&info, "Code"), "SWIFT") == 0);
    CHECK(strcmp(header_value(&info, "Code Version"), "1.0.0") == 0);
    CHECK(strcmp(header_value(&info, "BoxSize"), "6.25 6.25 6.25") == 0);
    CHECK(strcmp(header_value(&info, "units.length_cgs"), "1") == 0);
    CHECK(strcmp(header_value(&info, "units.temperature_cgs"), "1") == 0);
    CHECK(strcmp(header_value(&info, "Coordinates"), "a U_L [ cm ] (to cgs 1)") == 0);
    CHECK(strcmp(header_value(&info, "SmoothingLengths"), "a U_L [ cm ] (to cgs 1)") == 0);
    CHECK(strcmp(header_value(&info, "Time"), "1") == 0);
}

/* Three files base.0/1/2.hdf5, found from any of the names users give. */
static void test_multi_file(void)
{
    part_data d[3][6];
    h5w_snapshot snaps[3];
    for (int f = 0; f < 3; f++) {
        snaps[f] = gadget6_snapshot(d[f]);
        snaps[f].nfiles = 3;
        snaps[f].part[1].n = (size_t)(5 + f);
        snaps[f].part[4].n = f == 1 ? 0 : 2; /* a file without stars */
        for (int t = 0; t < 6; t++)
            snaps[f].total[t] = t == 0 ? 27 : t == 1 ? 18 : t == 4 ? 4 : 0;
        char name[32];
        snprintf(name, sizeof name, "multi.%d.hdf5", f);
        CHECK(h5w_write(tmp_path(name), &snaps[f]) == 0);
    }
    flat want = {0};
    expect_from(snaps, 3, 0, &want);
    CHECK(want.n == 27 + 18 + 4);
    static const char *const names[] = {"multi.hdf5", "multi.0.hdf5", "multi", "multi.2.hdf5"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        flat got = {0};
        orr_source *src = NULL;
        orr_error err = {0};
        orr_source_options opt = {.chunk_size = 7};
        CHECK(open_and_read(tmp_path(names[i]), &opt, &got, &src, &err) == ORR_OK);
        if (src) {
            check_same(&got, &want, &src->info);
            CHECK(src->info.count == (int64_t)want.n);
            CHECK_CONTAINS(header_value(&src->info, "files"), "multi.2.hdf5");
        } else {
            fprintf(stderr, "  %s: %s\n", names[i], err.msg);
        }
        orr_source_close(src);
        flat_free(&got);
    }
    flat_free(&want);
    check_no_open_hdf5();
}

static void test_type_mask_and_fields(void)
{
    part_data d[6];
    h5w_snapshot snap = gadget6_snapshot(d);
    static orr_source_info info;
    orr_source_options dm_only = {.type_mask = 1u << 1, .chunk_size = 3};
    round_trip("mask.hdf5", &snap, &dm_only, &info);
    CHECK(info.count == 17);
    /* DM has neither smoothing lengths nor SPH fields */
    CHECK(!info.has_h && info.nextra == 4 && has_extra(&info, "pot") && !has_extra(&info, "rho"));

    const char *const rho_only[] = {"rho", "pot"};
    orr_source_options some = {.fields = rho_only, .nfields = 1};
    round_trip("fields.hdf5", &snap, &some, &info);
    CHECK(info.nextra == 1 && strcmp(info.extra_names[0], "rho") == 0);
    orr_source_options none = {.fields = rho_only, .nfields = 0};
    round_trip("nofields.hdf5", &snap, &none, &info);
    CHECK(info.nextra == 0 && info.has_h);
    orr_source_options stars_gas = {.type_mask = (1u << 4) | 1u};
    round_trip("mask2.hdf5", &snap, &stars_gas, &info);
    CHECK(info.count == 14);
}

/* Chunk sizes 1, 7 and larger than the file give the same particles, and a
 * rewound source reads the same again. */
static void test_chunk_sizes(void)
{
    part_data d[6];
    h5w_snapshot snap = gadget6_snapshot(d);
    const char *path = tmp_path("chunks.hdf5");
    CHECK(h5w_write(path, &snap) == 0);
    flat want = {0};
    expect_from(&snap, 1, 0, &want);
    static const size_t sizes[] = {1, 7, 1 << 20};
    for (size_t i = 0; i < 3; i++) {
        flat got = {0}, again = {0};
        orr_source *src = NULL;
        orr_error err = {0};
        orr_source_options opt = {.chunk_size = sizes[i]};
        CHECK(open_and_read(path, &opt, &got, &src, &err) == ORR_OK);
        if (!src)
            continue;
        check_same(&got, &want, &src->info);
        size_t largest;
        CHECK(orr_source_rewind(src, &err) == ORR_OK);
        CHECK(read_all(src, &again, &largest, &err) == ORR_OK);
        check_same(&again, &want, &src->info);
        CHECK(src->chunk.capacity <= 31); /* never more than the snapshot */
        orr_source_close(src);
        flat_free(&got);
        flat_free(&again);
    }
    flat_free(&want);
    check_no_open_hdf5();
}

static void test_probe(void)
{
    unsigned char buf[4096] = {0};
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    CHECK(!orr_hdf5_probe(buf, sizeof buf));
    memcpy(buf + 512, sig, 8);
    CHECK(orr_hdf5_probe(buf, sizeof buf));
    CHECK(!orr_hdf5_probe(buf, 515)); /* cut short */
    memset(buf, 0, sizeof buf);
    memcpy(buf + 100, sig, 8);
    CHECK(!orr_hdf5_probe(buf, sizeof buf));
    memcpy(buf, sig, 8);
    CHECK(orr_hdf5_probe(buf, 8));
    CHECK(!orr_hdf5_probe(buf, 7));
}

/* ---- Real files ------------------------------------------------------- */

typedef struct stats {
    double mass;
    uint64_t id_min[8], id_max[8], id_sum[8], count[8];
    float lo[3], hi[3], hlo, hhi;
} stats;

static void add_stats(stats *s, const flat *f)
{
    memset(s, 0, sizeof *s);
    for (int a = 0; a < 3; a++)
        s->lo[a] = INFINITY, s->hi[a] = -INFINITY;
    s->hlo = INFINITY;
    s->hhi = -INFINITY;
    for (int t = 0; t < 8; t++)
        s->id_min[t] = UINT64_MAX;
    for (size_t i = 0; i < f->n; i++) {
        int t = f->type[i] & 7;
        s->mass += f->mass[i];
        s->count[t]++;
        s->id_sum[t] += f->id[i];
        s->id_min[t] = f->id[i] < s->id_min[t] ? f->id[i] : s->id_min[t];
        s->id_max[t] = f->id[i] > s->id_max[t] ? f->id[i] : s->id_max[t];
        const float p[3] = {f->x[i], f->y[i], f->z[i]};
        for (int a = 0; a < 3; a++) {
            s->lo[a] = p[a] < s->lo[a] ? p[a] : s->lo[a];
            s->hi[a] = p[a] > s->hi[a] ? p[a] : s->hi[a];
        }
        if (t == 0) {
            s->hlo = f->h[i] < s->hlo ? f->h[i] : s->hlo;
            s->hhi = f->h[i] > s->hhi ? f->h[i] : s->hhi;
        }
    }
}

static int test_gadget4_real_files(void)
{
    char buf[4096];
    const char *p0 = shared_data_path(buf, sizeof buf, "hdf5/gadget4_lcdm_gas/snapshot_000.hdf5");
    if (!p0)
        return SKIP_CODE;
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_hdf5_source_open(p0, NULL, &src, &err) == ORR_OK);
    if (src) {
        CHECK(src->info.count == 65536);
        CHECK(src->info.time == 0.1655600262003402);
        CHECK(strcmp(header_value(&src->info, "Redshift"), "5.04010535") == 0);
    }
    orr_source_close(src);

    const char *p4 = shared_data_path(buf, sizeof buf, "hdf5/gadget4_lcdm_gas/snapshot_004.hdf5");
    flat f = {0};
    orr_source_options opt = {.chunk_size = 10000};
    CHECK(open_and_read(p4, &opt, &f, &src, &err) == ORR_OK);
    if (!src)
        return 1;
    const orr_source_info *info = &src->info;
    CHECK(info->count == 65536 && f.n == 65536 && info->time == 1.0);
    CHECK(strcmp(header_value(info, "MassTable"), "4.235076385 27.5279965") == 0);
    CHECK(strcmp(header_value(info, "BoxSize"), "50000") == 0);
    CHECK(strcmp(header_value(info, "Redshift"), "0") == 0);
    CHECK(strcmp(header_value(info, "units.length_cgs"), "3.085678e+21") == 0);
    CHECK(strcmp(header_value(info, "units.mass_cgs"), "1.989e+43") == 0);
    CHECK(strcmp(header_value(info, "Coordinates"), "a^1 h^-1 (to cgs 3.085678e+21)") == 0);
    CHECK(info->has_h && has_extra(info, "u") && has_extra(info, "rho") && has_extra(info, "vz"));
    CHECK(f.x[0] == 2524.42724609375f && f.y[0] == 18178.09375f && f.z[0] == 9965.4384765625f);
    CHECK(f.type[32768] == 1);
    CHECK(f.x[32768] == 447.2301940917969f && f.y[32768] == 18008.21484375f && f.z[32768] == 10209.8896484375f);
    stats s;
    add_stats(&s, &f);
    CHECK_NEAR(s.mass, 1040812.37, 0.5);
    CHECK(s.count[0] == 32768 && s.count[1] == 32768);
    CHECK(s.id_min[0] == 1 && s.id_max[0] == 32768 && s.id_sum[0] == 32768ull * 32769 / 2);
    CHECK(s.id_min[1] == 32769 && s.id_max[1] == 65536 && s.id_sum[1] == 65536ull * 65537 / 2 - 32768ull * 32769 / 2);
    for (int a = 0; a < 3; a++)
        CHECK(s.lo[a] >= 0 && s.hi[a] < 50000);
    CHECK(f.mass[0] == (float)4.235076384894417 && f.mass[65535] == (float)27.52799650181371);
    orr_source_close(src);
    flat_free(&f);
    check_no_open_hdf5();
    return 0;
}

static int test_swift_real_file(void)
{
    char buf[4096];
    const char *path = shared_data_path(buf, sizeof buf, "hdf5/swift_robertsflow/g32_randB_withVP.hdf5");
    if (!path)
        return SKIP_CODE;
    flat f = {0};
    orr_source *src = NULL;
    orr_error err = {0};
    orr_source_options opt = {.chunk_size = 4096};
    CHECK(open_and_read(path, &opt, &f, &src, &err) == ORR_OK);
    if (!src) {
        fprintf(stderr, "  %s\n", err.msg);
        return 1;
    }
    const orr_source_info *info = &src->info;
    CHECK(info->count == 32768 && f.n == 32768);
    CHECK(strcmp(header_value(info, "Code"), "SWIFT") == 0);
    CHECK(strcmp(header_value(info, "Code Version"), "1.0.0") == 0);
    CHECK(strcmp(header_value(info, "units.length_cgs"), "1") == 0);
    CHECK(strcmp(header_value(info, "units.mass_cgs"), "1") == 0);
    CHECK(strcmp(header_value(info, "units.time_cgs"), "1") == 0);
    CHECK(strcmp(header_value(info, "Coordinates"), "a U_L [ cm ] (to cgs 1)") == 0);
    CHECK(strcmp(header_value(info, "BoxSize"), "6.283185307 6.283185307 6.283185307") == 0);
    CHECK(info->nextra == 6 && info->has_h && info->has_id);
    stats s;
    add_stats(&s, &f);
    CHECK_NEAR(s.mass, 248.050217, 1e-3);
    CHECK(s.count[0] == 32768);
    CHECK(s.id_min[0] == 1 && s.id_max[0] == 32768 && s.id_sum[0] == 32768ull * 32769 / 2);
    /* README rounds to 4 places: 0.2675-0.2690 */
    CHECK_NEAR(s.hlo, 0.2675, 5e-5);
    CHECK_NEAR(s.hhi, 0.2690, 5e-5);
    for (int a = 0; a < 3; a++)
        CHECK(s.lo[a] > 0 && s.hi[a] < 6.2831853f); /* inside the 2 pi box */
    CHECK_NEAR(fmaxf(s.hi[0], fmaxf(s.hi[1], s.hi[2])), 6.28310, 5e-6);
    orr_source_close(src);
    flat_free(&f);
    check_no_open_hdf5();
    return 0;
}

/* ---- Bad files -------------------------------------------------------- */

/* Opens path expecting failure with code and a message naming what. */
static void expect_failure(const char *path, orr_status code, const char *what, const char *what2)
{
    orr_source *src = NULL;
    orr_error err = {0};
    orr_status s = orr_hdf5_source_open(path, NULL, &src, &err);
    if (s == ORR_OK) {
        /* Some faults only show when the data are read. */
        flat f = {0};
        size_t largest;
        s = read_all(src, &f, &largest, &err);
        flat_free(&f);
        orr_source_close(src);
    } else {
        CHECK(src == NULL);
    }
    CHECK(s == code);
    if (getenv("ORRERY_TEST_VERBOSE"))
        fprintf(stderr, "  -> %s\n", err.msg);
    CHECK_CONTAINS(err.msg, path);
    CHECK_CONTAINS(err.msg, what);
    if (what2)
        CHECK_CONTAINS(err.msg, what2);
    check_no_open_hdf5();
}

/* A good 6-type file to spoil. */
static const char *good_file(const char *name)
{
    part_data d[6];
    h5w_snapshot snap = gadget6_snapshot(d);
    const char *path = tmp_path(name);
    CHECK(h5w_write(path, &snap) == 0);
    return path;
}

static void test_not_hdf5(void)
{
    const char *path = tmp_path("text.hdf5");
    FILE *fp = fopen(path, "w");
    fputs("x y z\n1 2 3\n", fp);
    fclose(fp);
    expect_failure(path, ORR_ERR_FORMAT, "not an HDF5 file", NULL);
    fp = fopen(tmp_path("empty.hdf5"), "w");
    fclose(fp);
    expect_failure(tmp_path("empty.hdf5"), ORR_ERR_FORMAT, "not an HDF5 file", NULL);
    expect_failure(tmp_path("absent.hdf5"), ORR_ERR_IO, "cannot open", "absent.0.hdf5");
}

static void test_no_header_or_groups(void)
{
    const char *const groups[] = {"Config", "PartType0", NULL};
    const char *path = tmp_path("noheader.hdf5");
    CHECK(h5w_write_groups(path, groups) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "no Header group", NULL);

    path = good_file("nogroups.hdf5");
    CHECK(h5w_delete(path, "PartType0") == 0);
    CHECK(h5w_delete(path, "PartType1") == 0);
    CHECK(h5w_delete(path, "PartType4") == 0);
    expect_failure(path, ORR_ERR_FORMAT, "no PartType0..PartType5 group", NULL);

    path = good_file("nogas.hdf5");
    CHECK(h5w_delete(path, "PartType0") == 0);
    expect_failure(path, ORR_ERR_FORMAT, "Header/NumPart_ThisFile[0] = 9 but there is no PartType0 group", NULL);

    path = good_file("noheader2.hdf5");
    CHECK(h5w_delete(path, "Header") == 0);
    expect_failure(path, ORR_ERR_FORMAT, "no Header group", NULL);
}

static void test_bad_shapes(void)
{
    const char *path = good_file("shape.hdf5");
    CHECK(h5w_replace_dataset(path, "PartType0/Coordinates", 9, 2, 1.0) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType0/Coordinates has shape (9, 2); expected (9, 3)", NULL);

    path = good_file("flat.hdf5");
    CHECK(h5w_replace_dataset(path, "PartType1/Coordinates", 51, 0, 1.0) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType1/Coordinates has shape (51,); expected (17, 3)", NULL);

    path = good_file("rows.hdf5");
    CHECK(h5w_replace_dataset(path, "PartType4/Masses", 4, 0, 1.0) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType4/Masses has 4 rows but Header/NumPart_ThisFile[4] = 5", NULL);

    path = good_file("nocoords.hdf5");
    CHECK(h5w_delete(path, "PartType4/Coordinates") == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType4 has no Coordinates dataset", NULL);

    path = good_file("nomass.hdf5");
    CHECK(h5w_delete(path, "PartType0/Masses") == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType0 has no Masses dataset and Header/MassTable[0] is 0", NULL);

    path = good_file("floatids.hdf5");
    CHECK(h5w_replace_dataset(path, "PartType1/ParticleIDs", 17, 0, 1.0) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType1/ParticleIDs holds float values; expected integers", NULL);

    path = good_file("negmass.hdf5");
    CHECK(h5w_replace_dataset(path, "PartType4/Masses", 5, 0, -1.0) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType4/Masses row 0", "mass -1 is negative");
}

/* The mass policy every reader shares (docs/input.md): negative, non-finite
 * and float-unrepresentable masses are errors naming file, row and value,
 * whether from Masses (read as stored, before the float conversion) or a
 * MassTable entry standing in for it; 0 and tiny floats are read. */
static void test_mass_policy(void)
{
    static const struct {
        double value;
        const char *needle;
    } bad[] = {
        {NAN, "PartType0/Masses row 3: mass nan is not a finite number"},
        {-2.0, "PartType0/Masses row 3: mass -2 is negative"},
        {1e-300, "PartType0/Masses row 3: mass 1e-300 is too small for a float (it would become 0"},
        {1e300, "PartType0/Masses row 3: mass 1e+300 is too large for a float"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *path = good_file("masses.hdf5");
        const double values[9] = {1, 1, 1, bad[k].value, 1, 1, 1, 1, 1};
        h5w_dataset_spec spec = {.type = H5T_IEEE_F64LE, .rank = 1, .dims = {9}, .write_rows = 9,
                                 .values = values, .nvalues = 9};
        hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
        CHECK(h5w_replace_dataset_spec(file, "PartType0/Masses", &spec) == 0);
        H5Fclose(file);
        expect_failure(path, ORR_ERR_FORMAT, bad[k].needle, NULL);
    }
    const char *path = good_file("tinytable.hdf5");
    const double table[6] = {0, 1e-300, 0, 0, 0, 0};
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    CHECK(h5w_set_attr(file, "Header", "MassTable", H5T_IEEE_F64LE, 1, table, 6) == 0);
    H5Fclose(file);
    expect_failure(path, ORR_ERR_FORMAT, "PartType1 has no Masses dataset and Header/MassTable[1] = 1e-300 is too small",
                   NULL);
    /* 0 and a float subnormal are masses like any other. */
    path = good_file("zeromasses.hdf5");
    const double fine[2] = {0.0, 1e-40};
    h5w_dataset_spec spec = {.type = H5T_IEEE_F64LE, .rank = 1, .dims = {9}, .write_rows = 9,
                             .values = fine, .nvalues = 2};
    file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    CHECK(h5w_replace_dataset_spec(file, "PartType0/Masses", &spec) == 0);
    H5Fclose(file);
    orr_source *src = NULL;
    orr_error err = {0};
    flat f = {0};
    CHECK(open_and_read(path, NULL, &f, &src, &err) == ORR_OK);
    CHECK(f.n == 31 && f.mass[0] == 0.0f && f.mass[1] == 1e-40f);
    flat_free(&f);
    orr_source_close(src);
    check_no_open_hdf5();
}

static void test_bad_counts(void)
{
    const char *path = good_file("absurd.hdf5");
    const int64_t absurd[6] = {1000000000000000ll, 17, 0, 0, 5, 0};
    CHECK(h5w_set_int64_attr(path, "Header", "NumPart_ThisFile", absurd, 6) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "PartType0/Coordinates has 9 rows but Header/NumPart_ThisFile[0] = 1000000000000000",
                   NULL);

    path = good_file("negative.hdf5");
    const int64_t negative[6] = {9, -17, 0, 0, 5, 0};
    CHECK(h5w_set_int64_attr(path, "Header", "NumPart_ThisFile", negative, 6) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "Header/NumPart_ThisFile[1] = -17 is negative", NULL);

    path = good_file("toomany.hdf5");
    const int64_t many[20] = {9, 17, 0, 0, 5};
    CHECK(h5w_set_int64_attr(path, "Header", "NumPart_ThisFile", many, 20) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "Header/NumPart_ThisFile has 20 entries; expected at most 16", NULL);

    path = good_file("masstable.hdf5");
    const int64_t three[3] = {1, 2, 3};
    CHECK(h5w_set_int64_attr(path, "Header", "MassTable", three, 3) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "Header/MassTable has 3 entries but NumPart_ThisFile has 6", NULL);

    /* A header that counts nothing while the groups hold rows: an error
     * naming the header field and a dataset with its rows, not 0 particles. */
    path = good_file("zerocounts.hdf5");
    const int64_t zeros[6] = {0, 0, 0, 0, 0, 0};
    CHECK(h5w_set_int64_attr(path, "Header", "NumPart_ThisFile", zeros, 6) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "Header/NumPart_ThisFile[0] = 0 but PartType0/Coordinates has 9 rows",
                   NULL);
    /* One type uncounted while the others agree. */
    path = good_file("onezero.hdf5");
    const int64_t no_stars[6] = {9, 17, 0, 0, 0, 0};
    CHECK(h5w_set_int64_attr(path, "Header", "NumPart_ThisFile", no_stars, 6) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "Header/NumPart_ThisFile[4] = 0 but PartType4/Coordinates has 5 rows",
                   NULL);

    path = good_file("nonumpart.hdf5");
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    H5Adelete_by_name(file, "Header", "NumPart_ThisFile", H5P_DEFAULT);
    H5Fclose(file);
    expect_failure(path, ORR_ERR_FORMAT, "Header has no NumPart_ThisFile attribute", NULL);
}

/* A NaN or infinite time would be written into every image's FITS header,
 * which cfitsio refuses at the end of each render: refused when opening. */
static void test_time_not_finite(void)
{
    const double times[2] = {NAN, INFINITY};
    for (int k = 0; k < 2; k++) {
        const char *path = good_file(k ? "inftime.hdf5" : "nantime.hdf5");
        hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
        CHECK(file >= 0);
        CHECK(h5w_set_attr(file, "Header", "Time", H5T_IEEE_F64LE, 0, &times[k], 1) == 0);
        H5Fclose(file);
        expect_failure(path, ORR_ERR_FORMAT, "Header/Time = ", "is not a finite number");
    }
}

static void test_missing_file_of_snapshot(void)
{
    part_data d[6];
    for (int f = 0; f < 2; f++) {
        h5w_snapshot snap = gadget6_snapshot(d);
        snap.nfiles = 3;
        char name[32];
        snprintf(name, sizeof name, "broken.%d.hdf5", f);
        CHECK(h5w_write(tmp_path(name), &snap) == 0);
    }
    expect_failure(tmp_path("broken.0.hdf5"), ORR_ERR_IO, "broken.2.hdf5: cannot open", "file 3 of 3");
}

static void test_truncated(void)
{
    const char *path = good_file("truncated.hdf5");
    FILE *fp = fopen(path, "rb");
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    fclose(fp);
    CHECK(truncate(path, size / 2) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "truncated", NULL);
    CHECK(truncate(path, 100) == 0);
    expect_failure(path, ORR_ERR_FORMAT, "HDF5 cannot open it", NULL);
}

int main(void)
{
    if (!mkdtemp(tmpdir)) {
        perror("mkdtemp");
        return 1;
    }
    RUN(test_probe);
    RUN(test_gadget4_two_types);
    RUN(test_gadget6_mass_table_and_masses);
    RUN(test_swift_seven_types);
    RUN(test_multi_file);
    RUN(test_type_mask_and_fields);
    RUN(test_chunk_sizes);
    RUN(test_not_hdf5);
    RUN(test_no_header_or_groups);
    RUN(test_bad_shapes);
    RUN(test_bad_counts);
    RUN(test_mass_policy);
    RUN(test_time_not_finite);
    RUN(test_missing_file_of_snapshot);
    RUN(test_truncated);
    int skipped = 0;
    int r = test_gadget4_real_files();
    fprintf(stderr, "%s test_gadget4_real_files\n", r == SKIP_CODE ? "skip" : r ? "FAIL" : "ok  ");
    skipped |= r == SKIP_CODE;
    r = test_swift_real_file();
    fprintf(stderr, "%s test_swift_real_file\n", r == SKIP_CODE ? "skip" : r ? "FAIL" : "ok  ");
    skipped |= r == SKIP_CODE;
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmpdir);
    H5close(); /* frees HDF5's global state before LeakSanitizer looks */
    int failed = check_summary();
    if (failed)
        return failed;
    return skipped ? SKIP_CODE : 0;
}
