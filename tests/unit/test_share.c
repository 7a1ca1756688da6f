/* Readers that read only their share of a snapshot (orr_source_options'
 * part and nparts): for Gadget and HDF5 snapshots of one file and of three,
 * and for Tipsy files, the parts 0..n-1 of n = 1..5 together give every
 * particle exactly once, in the order of the whole file, with the count and
 * the total mass the test wrote; each part reads only about its share of
 * the file's bytes; orr_source_partition passes such a share through (and
 * refuses to deal it out again among another number of parts). */
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "gadget_writer.h"
#include "hdf5_writer.h"
#include "source/partition.h"
#include "source/readers/share.h"
#include "source/source.h"
#include "tipsy_writer.h"
#include "tmpdir.h"

#define NFILES 3
#define MAX_N 200000

/* Particles per file and type in the test snapshots (types 0, 1 and 4, as
 * Tipsy has them: gas, dark, star). The middle file has no gas. */
static const int32_t counts[NFILES][6] = {{13, 40, 0, 0, 7, 0}, {0, 25, 0, 0, 3, 0}, {9, 31, 0, 0, 5, 0}};

/* What particle g of the whole snapshot (in file order) holds: values that
 * float keeps exactly, so the sums below are exact. */
static double mass_of(uint64_t g) { return 1.0 + (double)(g % 7) * 0.25; }
static double x_of(uint64_t g) { return (double)g; }

/* Everything read from a source, in order. */
typedef struct flat {
    size_t n;
    uint64_t id[MAX_N];
    float x[MAX_N], mass[MAX_N];
    unsigned char type[MAX_N];
    float h[MAX_N];
} flat;

static flat whole, parts;

static void read_all(orr_source *src, flat *into)
{
    const orr_chunk *c;
    orr_error err = {0};
    for (;;) {
        CHECK(orr_source_next(src, &c, &err) == ORR_OK);
        if (c->n == 0)
            break;
        for (size_t i = 0; i < c->n && into->n < MAX_N; i++, into->n++) {
            into->id[into->n] = c->id[i];
            into->x[into->n] = c->x[i];
            into->mass[into->n] = c->mass[i];
            into->type[into->n] = c->type[i];
            into->h[into->n] = c->h ? c->h[i] : 0;
        }
    }
}

static orr_source *open_part(const char *path, unsigned mask, int part, int nparts, size_t chunk)
{
    orr_source_options opt = {.format = "auto", .chunk_size = chunk, .type_mask = mask, .part = part, .nparts = nparts};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_source_open_file(path, &opt, &src, &err) == ORR_OK);
    if (!src)
        fprintf(stderr, "%s\n", err.msg);
    return src;
}

static int same(const flat *a, const flat *b)
{
    if (a->n != b->n)
        return 0;
    for (size_t i = 0; i < a->n; i++)
        if (a->id[i] != b->id[i] || a->x[i] != b->x[i] || a->mass[i] != b->mass[i] || a->type[i] != b->type[i] ||
            a->h[i] != b->h[i])
            return 0;
    return 1;
}

/* Reads path whole, then in 1..5 parts; the parts in turn must give the
 * whole, and the whole must hold want_n particles of total mass want_mass. */
static void check_shares(const char *label, const char *path, unsigned mask, int64_t want_n, double want_mass)
{
    whole.n = 0;
    orr_source *src = open_part(path, mask, 0, 0, 10);
    if (!src)
        return;
    read_all(src, &whole);
    orr_source_close(src);
    double mass = 0;
    for (size_t i = 0; i < whole.n; i++)
        mass += whole.mass[i];
    CHECK((int64_t)whole.n == want_n);
    CHECK(mass == want_mass);
    for (int nparts = 1; nparts <= 5; nparts++) {
        parts.n = 0;
        int64_t count_sum = 0;
        double mass_sum = 0;
        for (int part = 0; part < nparts; part++) {
            size_t before = parts.n;
            src = open_part(path, mask, part, nparts, 4);
            if (!src)
                return;
            CHECK(src->info.share_part == part && src->info.share_nparts == nparts);
            count_sum += src->info.count;
            /* Twice, rewound: the second pass gives the same share. */
            for (int pass = 0; pass < 2; pass++) {
                parts.n = before;
                const orr_chunk *c;
                orr_error err = {0};
                CHECK(orr_source_rewind(src, &err) == ORR_OK);
                CHECK(orr_source_next(src, &c, &err) == ORR_OK);
                /* A share's first index is where it starts in the whole. */
                CHECK(c->n == 0 || c->first_index == (uint64_t)before);
                CHECK(orr_source_rewind(src, &err) == ORR_OK);
                read_all(src, &parts);
            }
            CHECK((int64_t)(parts.n - before) == src->info.count);
            for (size_t i = before; i < parts.n; i++)
                mass_sum += parts.mass[i];
            /* The partition wrapper passes a share through untouched. */
            orr_source *same_src = NULL;
            orr_error err = {0};
            CHECK(orr_source_partition(src, part, nparts, &same_src, &err) == ORR_OK && same_src == src);
            orr_source_close(same_src);
        }
        if (!same(&whole, &parts) || count_sum != want_n || mass_sum != want_mass)
            fprintf(stderr, "%s, %d parts: the parts do not add up to the whole (%lld of %lld particles)\n", label,
                    nparts, (long long)count_sum, (long long)want_n);
        CHECK(same(&whole, &parts));
        CHECK(count_sum == want_n);
        CHECK(mass_sum == want_mass);
    }
}

/* ---- Gadget ---- */

typedef struct gadget_fill {
    uint64_t base; /* the file's first particle in the whole snapshot */
} gadget_fill;

static void gadget_particle(void *user, uint64_t i, int type, gw_particle *p)
{
    const gadget_fill *f = user;
    uint64_t g = f->base + i;
    memset(p, 0, sizeof *p);
    p->pos[0] = x_of(g);
    p->id = g + 1;
    p->mass = mass_of(g);
    p->hsml = type == 0 ? 0.5 * (double)g : 0;
}

/* Writes counts[0..nfiles) as a Gadget snapshot (types 0 and 4 in the MASS
 * block, type 1 by massarr 2.0) and returns its count and mass for mask. */
static void write_gadget(const char *path, int nfiles, unsigned mask, int64_t *n, double *mass)
{
    const double massarr[6] = {0, 2.0, 0, 0, 0, 0};
    uint64_t base = 0;
    *n = 0;
    *mass = 0;
    for (int f = 0; f < nfiles; f++) {
        gw_spec spec = {.snapformat = 2, .blocks = GW_ID | GW_HSML, .num_files = nfiles, .time = 1};
        memcpy(spec.npart, counts[f], sizeof spec.npart);
        memcpy(spec.massarr, massarr, sizeof massarr);
        gadget_fill fill = {base};
        char name[700];
        snprintf(name, sizeof name, nfiles > 1 ? "%.600s.%d" : "%.600s", path, f);
        CHECK(gw_write(name, &spec, gadget_particle, &fill) == 0);
        for (int t = 0; t < 6; t++)
            for (int j = 0; j < counts[f][t]; j++, base++)
                if (!mask || (mask >> t & 1u)) {
                    ++*n;
                    *mass += massarr[t] != 0 ? massarr[t] : mass_of(base);
                }
    }
}

/* ---- HDF5 ---- */

/* Writes base.hdf5, or base.0.hdf5 .. for several files; open names what
 * to open. */
static void write_hdf5(const char *base, int nfiles, char open[700], int64_t *n, double *mass)
{
    uint64_t g = 0;
    *n = 0;
    *mass = 0;
    for (int f = 0; f < nfiles; f++) {
        h5w_snapshot s = {.style = H5W_GADGET, .ntypes = 6, .time = 1, .nfiles = nfiles};
        static double pos[6][3 * 64], m[6][64], h[6][64];
        static uint64_t id[6][64];
        for (int t = 0; t < 6; t++) {
            for (int j = 0; j < counts[f][t]; j++, g++) {
                pos[t][3 * j] = x_of(g);
                pos[t][3 * j + 1] = pos[t][3 * j + 2] = 0;
                m[t][j] = mass_of(g);
                h[t][j] = 0.5 * (double)g;
                id[t][j] = g + 1;
                *mass += m[t][j];
                ++*n;
            }
            s.part[t] = (h5w_part){.n = (size_t)counts[f][t], .pos = pos[t], .id = id[t], .mass = m[t],
                                   .h = t == 0 ? h[t] : NULL};
        }
        char name[700];
        snprintf(name, sizeof name, nfiles > 1 ? "%.600s.%d.hdf5" : "%.600s.hdf5", base, f);
        CHECK(h5w_write(name, &s) == 0);
    }
    snprintf(open, 700, nfiles > 1 ? "%.600s" : "%.600s.hdf5", base);
}

/* ---- Tipsy ---- */

static void write_tipsy(const char *path, int64_t *n, double *mass)
{
    int nsph = counts[0][0], ndark = counts[0][1], nstar = counts[0][4];
    static float gas[64 * TIPSY_GAS_FLOATS], dark[64 * TIPSY_DARK_FLOATS], star[64 * TIPSY_STAR_FLOATS];
    memset(gas, 0, sizeof gas);
    memset(dark, 0, sizeof dark);
    memset(star, 0, sizeof star);
    uint64_t g = 0;
    *mass = 0;
    struct {
        float *rec;
        int count, floats;
    } fam[3] = {{gas, nsph, TIPSY_GAS_FLOATS}, {dark, ndark, TIPSY_DARK_FLOATS}, {star, nstar, TIPSY_STAR_FLOATS}};
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < fam[k].count; j++, g++) {
            float *r = fam[k].rec + (size_t)j * (size_t)fam[k].floats;
            r[0] = (float)mass_of(g);
            r[1] = (float)x_of(g);
            if (k == 0)
                r[9] = (float)(0.5 * (double)g); /* hsmooth */
            *mass += mass_of(g);
        }
    *n = (int64_t)g;
    tipsy_writer_header hdr = tipsy_writer_header_for(1.0, nsph, ndark, nstar, 1, 32);
    CHECK(tipsy_write_file(path, &hdr, gas, dark, star) == 0);
}

/* ---- bytes read ---- */

/* Bytes this process has read (rchar of /proc/self/io), or -1 without it. */
static long long bytes_read(void)
{
    FILE *fp = fopen("/proc/self/io", "r");
    if (!fp)
        return -1;
    char key[32];
    long long v, rchar = -1;
    while (fscanf(fp, "%31s %lld", key, &v) == 2)
        if (strcmp(key, "rchar:") == 0)
            rchar = v;
    fclose(fp);
    return rchar;
}

static void big_particle(void *user, uint64_t i, int type, gw_particle *p)
{
    (void)user;
    (void)type;
    memset(p, 0, sizeof *p);
    p->pos[0] = (double)i;
    p->id = i;
    p->mass = 1;
}

/* A part of 4 of a 150000-particle single-file snapshot reads about a
 * quarter of the file (its ranges of POS, ID and MASS, and the record walk's
 * few bytes), not all of it as dealing out chunks did. */
static void check_bytes_read(void)
{
    if (bytes_read() < 0) {
        printf("no /proc/self/io: bytes read not checked\n");
        return;
    }
    char path[600];
    snprintf(path, sizeof path, "%s/big", tmpdir);
    gw_spec spec = {.snapformat = 2, .blocks = GW_ID, .num_files = 1, .time = 1};
    spec.npart[1] = 150000;
    CHECK(gw_write(path, &spec, big_particle, NULL) == 0);
    FILE *fp = fopen(path, "rb");
    CHECK(fp && fseek(fp, 0, SEEK_END) == 0);
    double size = fp ? (double)ftell(fp) : 0;
    if (fp)
        fclose(fp);
    for (int nparts = 1; nparts <= 4; nparts *= 2) {
        long long before = bytes_read();
        orr_source *src = open_part(path, 0, nparts - 1, nparts, 1 << 16);
        const orr_chunk *c;
        orr_error err = {0};
        size_t n = 0;
        while (src && orr_source_next(src, &c, &err) == ORR_OK && c->n > 0)
            n += c->n;
        orr_source_close(src);
        double fraction = (double)(bytes_read() - before) / size;
        printf("part %d of %d: %zu particles, read %.3f of the file's %.0f bytes\n", nparts - 1, nparts, n, fraction,
               size);
        CHECK(n == 150000 / (size_t)nparts);
        CHECK(fraction > 0.9 / nparts && fraction < 1.0 / nparts + 0.02);
    }
}

int main(void)
{
    make_tmpdir();
    char path[600];
    int64_t n;
    double mass;
    for (int nfiles = 1; nfiles <= NFILES; nfiles += NFILES - 1) {
        snprintf(path, sizeof path, "%s/gadget%d", tmpdir, nfiles);
        write_gadget(path, nfiles, 0, &n, &mass);
        check_shares("gadget", path, 0, n, mass);
        unsigned dark_stars = 1u << 1 | 1u << 4;
        write_gadget(path, nfiles, dark_stars, &n, &mass);
        check_shares("gadget, types 1 and 4", path, dark_stars, n, mass);

        snprintf(path, sizeof path, "%s/hdf%d", tmpdir, nfiles);
        char hdf5_path[700];
        write_hdf5(path, nfiles, hdf5_path, &n, &mass);
        check_shares("hdf5", hdf5_path, 0, n, mass);
    }
    snprintf(path, sizeof path, "%s/t.tipsy", tmpdir);
    write_tipsy(path, &n, &mass);
    check_shares("tipsy", path, 0, n, mass);

    check_bytes_read();

    /* A share cannot be dealt out again among another number of parts. */
    orr_source *half = open_part(path, 0, 0, 2, 8), *dealt = NULL;
    orr_error deal_err = {0};
    CHECK(half && orr_source_partition(half, 0, 3, &dealt, &deal_err) == ORR_ERR_USAGE && !dealt);
    CHECK_CONTAINS(deal_err.msg, "share of 2 parts");

    /* A part outside the parts is an error naming the file. */
    orr_source_options opt = {.format = "tipsy", .part = 3, .nparts = 3};
    orr_source *src = NULL;
    orr_error err = {0};
    CHECK(orr_source_open_file(path, &opt, &src, &err) == ORR_ERR_USAGE && !src);
    CHECK_CONTAINS(err.msg, "t.tipsy");
    CHECK_CONTAINS(err.msg, "share 3 of 3");
    remove_tmpdir();
    return check_summary();
}
