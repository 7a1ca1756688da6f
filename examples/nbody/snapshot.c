#include "snapshot.h"

#include <dirent.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "source/readers/hdf5_util.h"
#include "source/writers/hdf5_write.h"

#define NB_TYPES_MIN 6  /* Gadget's PartType0..5, whichever are empty */
#define NB_TYPES_MAX NB_SNAPSHOT_TYPES /* orrery's reader reads at most 16 */
#define ORDER_DATASET "OrreryNbodyOrder"
#define LEVEL_DATASET "OrreryNbodyStepLevel"
#define RUN_GROUP "OrreryNbody"

/* The fields Gadget has names for are written under them, so orrery's
 * reader finds them (pot, u, rho); the others (the model's r and E0) under
 * their own names, which other readers pass over. */
static const char *dataset_of(const char *field)
{
    static const char *const names[][2] = {{"pot", "Potential"}, {"u", "InternalEnergy"}, {"rho", "Density"}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strcmp(field, names[i][0]) == 0)
            return names[i][1];
    return field;
}

int nb_snapshot_path(char *buf, size_t size, const char *dir, long number)
{
    int n = snprintf(buf, size, "%s/snapshot_%04ld.hdf5", dir, number);
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

/* ---- writing ------------------------------------------------------------ */

typedef struct write_ctx {
    const nb_particles *p;
    const nb_run_state *s;
    uint64_t count[NB_TYPES_MAX];
    int ntypes;
} write_ctx;

static int write_header(hid_t file, const write_ctx *w)
{
    hid_t h = orr_h5w_group(file, "Header");
    if (h < 0)
        return 1;
    uint32_t low[NB_TYPES_MAX], high[NB_TYPES_MAX];
    double mass_table[NB_TYPES_MAX] = {0}; /* 0: every group has Masses */
    const uint64_t *total = w->s->type_totals ? w->s->type_totals : w->count;
    for (int t = 0; t < w->ntypes; t++) {
        low[t] = (uint32_t)total[t];
        high[t] = (uint32_t)(total[t] >> 32);
    }
    int n = w->ntypes, nfiles = w->s->nfiles > 1 ? w->s->nfiles : 1;
    int bad = orr_h5w_attr(h, "NumPart_ThisFile", H5T_STD_U64LE, H5T_NATIVE_UINT64, w->count, n);
    bad |= orr_h5w_attr(h, "NumPart_Total", H5T_STD_U32LE, H5T_NATIVE_UINT32, low, n);
    bad |= orr_h5w_attr(h, "NumPart_Total_HighWord", H5T_STD_U32LE, H5T_NATIVE_UINT32, high, n);
    bad |= orr_h5w_attr(h, "MassTable", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, mass_table, n);
    bad |= orr_h5w_attr(h, "NumFilesPerSnapshot", H5T_STD_I32LE, H5T_NATIVE_INT, &nfiles, 0);
    bad |= orr_h5w_double(h, "Time", w->s->time);
    bad |= orr_h5w_double(h, "Redshift", 0.0);
    bad |= orr_h5w_double(h, "BoxSize", 0.0);
    H5Gclose(h);
    /* The model's units (and GADGET-2's examples'): kpc, 1e10 Msun, km/s,
     * in Gadget-4's place for them, which `orrery info` shows. */
    hid_t u = orr_h5w_group(file, "Parameters");
    if (u < 0)
        return 1;
    bad |= orr_h5w_double(u, "UnitLength_in_cm", 3.085678e21);
    bad |= orr_h5w_double(u, "UnitMass_in_g", 1.989e43);
    bad |= orr_h5w_double(u, "UnitVelocity_in_cm_per_s", 1e5);
    H5Gclose(u);
    return bad;
}

/* The fields' names in one attribute, separated by spaces. */
static int write_run_group(hid_t file, const write_ctx *w)
{
    const nb_run_state *s = w->s;
    hid_t g = orr_h5w_group(file, RUN_GROUP);
    if (g < 0)
        return 1;
    int64_t step = s->step, number = s->number, every = s->snapshot_every, neighbours = s->tracer_neighbours,
            ring = s->tracer_ring, mirror = s->tracer_mirror;
    char fields[ORR_ARRAYS_MAX_FIELDS * ORR_FIELD_NAME_MAX + 1] = "";
    for (int f = 0; f < w->p->nfields; f++) {
        strcat(fields, f ? " " : "");
        strcat(fields, w->p->field_name[f]);
    }
    int bad = orr_h5w_attr(g, "Step", H5T_STD_I64LE, H5T_NATIVE_INT64, &step, 0);
    bad |= orr_h5w_attr(g, "Number", H5T_STD_I64LE, H5T_NATIVE_INT64, &number, 0);
    bad |= orr_h5w_attr(g, "SnapshotEvery", H5T_STD_I64LE, H5T_NATIVE_INT64, &every, 0);
    bad |= orr_h5w_attr(g, "TracerNeighbours", H5T_STD_I64LE, H5T_NATIVE_INT64, &neighbours, 0);
    bad |= orr_h5w_attr(g, "TracerRing", H5T_STD_I64LE, H5T_NATIVE_INT64, &ring, 0);
    bad |= orr_h5w_attr(g, "TracerMirror", H5T_STD_I64LE, H5T_NATIVE_INT64, &mirror, 0);
    bad |= orr_h5w_double(g, "E0", s->e0);
    bad |= orr_h5w_attr(g, "Centre0", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, s->centre0, 3);
    bad |= orr_h5w_double(g, "Dt", s->dt);
    bad |= orr_h5w_double(g, "Eps", s->eps);
    bad |= orr_h5w_double(g, "EpsHalo", s->eps_halo);
    bad |= orr_h5w_double(g, "Theta", s->theta);
    bad |= orr_h5w_double(g, "Eta", s->eta);
    bad |= orr_h5w_double(g, "DtMin", s->dt_min);
    bad |= orr_h5w_string(g, "Fields", fields);
    H5Gclose(g);
    return bad;
}

/* Scratch rows of one type: the particles' places in memory order, and
 * one column at a time. */
typedef struct rows {
    size_t *at;
    double *v3; /* 3 per row */
    double *m;
    uint64_t *u;
    float *f;
    uint8_t *l;
} rows;

/* Group PartType<t>: its particles in memory order, with their place in
 * that order. */
static int write_type(hid_t file, const write_ctx *w, int t, rows *r)
{
    const nb_particles *p = w->p;
    size_t nt = 0;
    for (size_t i = 0; i < p->n; i++)
        if (p->type[i] == t)
            r->at[nt++] = i;
    char name[32];
    snprintf(name, sizeof name, "PartType%d", t);
    hid_t g = orr_h5w_group(file, name);
    if (g < 0)
        return 1;
    for (size_t k = 0; k < nt; k++)
        memcpy(&r->v3[3 * k], &p->pos[3 * r->at[k]], 3 * sizeof(double));
    int bad = orr_h5w_dataset(g, "Coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, r->v3, nt, 3);
    for (size_t k = 0; k < nt; k++)
        memcpy(&r->v3[3 * k], &p->vel[3 * r->at[k]], 3 * sizeof(double));
    bad |= orr_h5w_dataset(g, "Velocities", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, r->v3, nt, 3);
    for (size_t k = 0; k < nt; k++)
        r->m[k] = p->mass[r->at[k]];
    bad |= orr_h5w_dataset(g, "Masses", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, r->m, nt, 1);
    for (size_t k = 0; k < nt; k++)
        r->u[k] = p->id[r->at[k]];
    bad |= orr_h5w_dataset(g, "ParticleIDs", H5T_STD_U64LE, H5T_NATIVE_UINT64, r->u, nt, 1);
    for (size_t k = 0; k < nt; k++)
        r->u[k] = r->at[k];
    bad |= orr_h5w_dataset(g, ORDER_DATASET, H5T_STD_U64LE, H5T_NATIVE_UINT64, r->u, nt, 1);
    if (p->level) {
        for (size_t k = 0; k < nt; k++)
            r->l[k] = p->level[r->at[k]];
        bad |= orr_h5w_dataset(g, LEVEL_DATASET, H5T_STD_U8LE, H5T_NATIVE_UINT8, r->l, nt, 1);
    }
    for (int f = 0; f < p->nfields; f++) {
        for (size_t k = 0; k < nt; k++)
            r->f[k] = p->field[f][r->at[k]];
        bad |= orr_h5w_dataset(g, dataset_of(p->field_name[f]), H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, r->f, nt, 1);
    }
    H5Gclose(g);
    return bad;
}

static int write_body(hid_t file, void *ctx)
{
    const write_ctx *w = ctx;
    size_t most = 1;
    for (int t = 0; t < w->ntypes; t++)
        most = w->count[t] > most ? (size_t)w->count[t] : most;
    rows r = {malloc(most * sizeof *r.at), malloc(3 * most * sizeof *r.v3), malloc(most * sizeof *r.m),
              malloc(most * sizeof *r.u), malloc(most * sizeof *r.f), malloc(most)};
    int bad = !r.at || !r.v3 || !r.m || !r.u || !r.f || !r.l || write_header(file, w) || write_run_group(file, w);
    for (int t = 0; t < w->ntypes && !bad; t++)
        if (w->count[t])
            bad |= write_type(file, w, t, &r);
    free(r.at);
    free(r.v3);
    free(r.m);
    free(r.u);
    free(r.f);
    free(r.l);
    return bad;
}

orr_status nb_snapshot_write(const char *path, const nb_particles *p, const nb_run_state *s, orr_error *err)
{
    write_ctx w = {p, s, {0}, NB_TYPES_MIN};
    for (size_t i = 0; i < p->n; i++) {
        if (p->type[i] >= NB_TYPES_MAX)
            return orr_fail(err, ORR_ERR_USAGE, "%s: particle type %d: a snapshot holds types 0 to %d", path,
                            p->type[i], NB_TYPES_MAX - 1);
        w.count[p->type[i]]++;
        w.ntypes = p->type[i] >= w.ntypes ? p->type[i] + 1 : w.ntypes;
    }
    for (int t = 0; s->type_totals && t < NB_TYPES_MAX; t++) /* every file of a set: all the set's types */
        w.ntypes = s->type_totals[t] && t >= w.ntypes ? t + 1 : w.ntypes;
    return orr_h5w_write_file(path, write_body, &w, err);
}

int nb_snapshot_part_path(char *buf, size_t size, const char *dir, long number, int part, int nfiles)
{
    if (nfiles <= 1)
        return nb_snapshot_path(buf, size, dir, number);
    int n = snprintf(buf, size, "%s/snapshot_%04ld.%d.hdf5", dir, number, part);
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

/* ---- finding the newest ------------------------------------------------- */

/* The NNNN of "snapshot_NNNN.hdf5", or -1 for any other name (temporary
 * files of a write that was cut short among them). */
static long number_in(const char *name)
{
    long number;
    int end = 0;
    if (sscanf(name, "snapshot_%ld.hdf5%n", &number, &end) != 1 || name[end] != '\0' || number < 0 ||
        strncmp(name, "snapshot_", 9) != 0 || name[9] < '0' || name[9] > '9')
        return -1;
    return number;
}

/* The NNNN of "snapshot_NNNN.hdf5" or of a part "snapshot_NNNN.P.hdf5", or -1. */
static long set_number_in(const char *name)
{
    long number;
    int part, end = 0;
    if (strncmp(name, "snapshot_", 9) != 0 || name[9] < '0' || name[9] > '9')
        return -1;
    if (sscanf(name, "snapshot_%ld.%d.hdf5%n", &number, &part, &end) == 2 && name[end] == '\0' && number >= 0 &&
        part >= 0)
        return number;
    return number_in(name);
}

static int exists(const char *path)
{
    return access(path, F_OK) == 0;
}

/* Snapshot number's files in dir, when all are there: 1 for a single
 * file, NumFilesPerSnapshot of its part 0 for a set; 0 when some are not. */
static int complete_files(const char *dir, long number)
{
    char path[4096];
    if (nb_snapshot_path(path, sizeof path, dir, number) == 0 && exists(path))
        return 1;
    nb_run_state s = {0};
    orr_error err = {0};
    if (nb_snapshot_part_path(path, sizeof path, dir, number, 0, 2) != 0 || !exists(path) ||
        nb_snapshot_read_state(path, &s, NULL, &err) != ORR_OK || s.nfiles < 2)
        return 0;
    for (int part = 1; part < s.nfiles; part++)
        if (nb_snapshot_part_path(path, sizeof path, dir, number, part, s.nfiles) != 0 || !exists(path))
            return 0;
    return s.nfiles;
}

/* The largest number that number_of finds in a name in dir: -1 when
 * none, -2 when the folder cannot be read (said in err). */
static long largest_number_in(const char *dir, long (*number_of)(const char *), orr_error *err)
{
    DIR *d = opendir(dir);
    if (!d) {
        orr_fail(err, ORR_ERR_IO, "%s: cannot read the folder", dir);
        return -2;
    }
    long newest = -1;
    for (struct dirent *e; (e = readdir(d));) {
        long k = number_of(e->d_name);
        newest = k > newest ? k : newest;
    }
    closedir(d);
    return newest;
}

long nb_snapshot_newest_set(const char *dir, int *nfiles, orr_error *err)
{
    long newest = largest_number_in(dir, set_number_in, err);
    if (newest < -1)
        return -1;
    for (long k = newest; k >= 0; k--)
        if ((*nfiles = complete_files(dir, k)) > 0)
            return k;
    orr_fail(err, ORR_ERR_USAGE, "%s: holds no complete snapshot_NNNN.hdf5 or set of snapshot_NNNN.P.hdf5 to resume from",
             dir);
    return -1;
}

long nb_snapshot_newest(const char *dir, orr_error *err)
{
    long newest = largest_number_in(dir, number_in, err);
    if (newest < -1)
        return -1;
    if (newest < 0)
        orr_fail(err, ORR_ERR_USAGE, "%s: holds no snapshot_NNNN.hdf5 to resume from", dir);
    return newest;
}

/* ---- reading ------------------------------------------------------------ */

static int attr_double(hid_t loc, const char *name, double *v)
{
    int count = 0;
    return orr_h5_attr_numbers(loc, name, H5T_NATIVE_DOUBLE, v, 1, &count) == ORR_H5_FOUND && count == 1;
}

static int attr_long(hid_t loc, const char *name, long *v)
{
    int64_t x = 0;
    int count = 0;
    int ok = orr_h5_attr_numbers(loc, name, H5T_NATIVE_INT64, &x, 1, &count) == ORR_H5_FOUND && count == 1;
    *v = (long)x;
    return ok;
}

/* Dataset name of group g, n rows of cols columns (1: a vector), into buf. */
static int read_column(hid_t g, const char *name, size_t n, int cols, hid_t memtype, void *buf)
{
    hid_t ds = H5Dopen2(g, name, H5P_DEFAULT);
    hsize_t dims[ORR_H5_MAX_RANK];
    H5T_class_t cls;
    int rank = ds >= 0 ? orr_h5_dataset_shape(ds, dims, &cls) : -1;
    int ok = rank == (cols > 1 ? 2 : 1) && dims[0] == n && (cols == 1 || dims[1] == (hsize_t)cols) &&
             orr_h5_read_rows(ds, 0, n, cols > 1 ? cols : 0, memtype, buf) == 0;
    orr_h5_close(ds);
    return ok;
}

static int alloc_particles(nb_particles *p, size_t n)
{
    size_t m = n ? n : 1;
    p->n = n;
    p->pos = malloc(3 * m * sizeof *p->pos);
    p->vel = malloc(3 * m * sizeof *p->vel);
    p->mass = malloc(m * sizeof *p->mass);
    p->id = malloc(m * sizeof *p->id);
    p->type = malloc(m * sizeof *p->type);
    int ok = p->pos && p->vel && p->mass && p->id && p->type;
    for (int f = 0; f < p->nfields; f++)
        ok &= (p->field[f] = malloc(m * sizeof(float))) != NULL;
    return ok;
}

/* The names of the fields, from the run group's "Fields". */
static void read_field_names(hid_t run, nb_particles *p)
{
    char names[ORR_ARRAYS_MAX_FIELDS * ORR_FIELD_NAME_MAX + 1] = "";
    orr_h5_attr_string(run, "Fields", names, sizeof names);
    p->nfields = 0;
    for (char *tok = strtok(names, " "); tok && p->nfields < ORR_ARRAYS_MAX_FIELDS; tok = strtok(NULL, " "))
        snprintf(p->field_name[p->nfields++], ORR_FIELD_NAME_MAX, "%s", tok);
}

/* The block-step levels of group g's nt particles into their places at[]. */
static int read_levels(hid_t g, size_t nt, const uint64_t *at, uint8_t *level)
{
    uint8_t *l = malloc(nt ? nt : 1);
    int ok = l && read_column(g, LEVEL_DATASET, nt, 1, H5T_NATIVE_UINT8, l);
    for (size_t k = 0; ok && k < nt; k++)
        level[at[k]] = l[k];
    free(l);
    return ok;
}

/* The nt particles of group g, each put back at its place in memory order
 * (every place taken once: seen[]). */
static const char *read_type(hid_t g, int t, size_t nt, nb_particles *p, unsigned char *seen)
{
    double *v3 = malloc(3 * nt * sizeof *v3), *w3 = malloc(3 * nt * sizeof *w3), *m = malloc(nt * sizeof *m);
    uint64_t *id = malloc(nt * sizeof *id), *at = malloc(nt * sizeof *at);
    float *f = malloc(nt * sizeof *f);
    const char *bad = NULL;
    if (!v3 || !w3 || !m || !id || !at || !f)
        bad = "out of memory";
    else if (!read_column(g, ORDER_DATASET, nt, 1, H5T_NATIVE_UINT64, at))
        bad = ORDER_DATASET;
    else if (!read_column(g, "Coordinates", nt, 3, H5T_NATIVE_DOUBLE, v3))
        bad = "Coordinates";
    else if (!read_column(g, "Velocities", nt, 3, H5T_NATIVE_DOUBLE, w3))
        bad = "Velocities";
    else if (!read_column(g, "Masses", nt, 1, H5T_NATIVE_DOUBLE, m))
        bad = "Masses";
    else if (!read_column(g, "ParticleIDs", nt, 1, H5T_NATIVE_UINT64, id))
        bad = "ParticleIDs";
    for (size_t k = 0; k < nt && !bad; k++) {
        if (at[k] >= p->n || seen[at[k]]++) {
            bad = ORDER_DATASET " (not a permutation of the particles)";
            break;
        }
        size_t i = (size_t)at[k];
        memcpy(&p->pos[3 * i], &v3[3 * k], 3 * sizeof(double));
        memcpy(&p->vel[3 * i], &w3[3 * k], 3 * sizeof(double));
        p->mass[i] = m[k];
        p->id[i] = id[k];
        p->type[i] = (uint8_t)t;
    }
    if (!bad && p->level && !read_levels(g, nt, at, p->level))
        bad = LEVEL_DATASET;
    for (int fi = 0; fi < p->nfields && !bad; fi++) {
        if (!read_column(g, dataset_of(p->field_name[fi]), nt, 1, H5T_NATIVE_FLOAT, f))
            bad = dataset_of(p->field_name[fi]);
        for (size_t k = 0; k < nt && !bad; k++)
            p->field[fi][at[k]] = f[k];
    }
    free(v3);
    free(w3);
    free(m);
    free(id);
    free(at);
    free(f);
    return bad;
}

/* Whether the snapshot keeps block steps' levels: a run in block steps
 * writes them for every type, others for none, so the first group with
 * particles says. */
static int has_levels(hid_t file, const uint64_t *count, int ntypes)
{
    int t = 0;
    while (t < ntypes && !count[t])
        t++;
    char name[32];
    snprintf(name, sizeof name, "PartType%d", t);
    hid_t g = t < ntypes && orr_h5_has_link(file, name) ? H5Gopen2(file, name, H5P_DEFAULT) : -1;
    int has = g >= 0 && orr_h5_has_link(g, LEVEL_DATASET);
    orr_h5_close(g);
    return has;
}

/* The header's files (NumFilesPerSnapshot: 1 when absent) and total count. */
static void read_set_header(hid_t h, nb_run_state *s)
{
    int64_t nfiles = 1;
    uint32_t low[NB_TYPES_MAX] = {0}, high[NB_TYPES_MAX] = {0};
    int n = 0, nl = 0, nh = 0;
    if (orr_h5_attr_numbers(h, "NumFilesPerSnapshot", H5T_NATIVE_INT64, &nfiles, 1, &n) != ORR_H5_FOUND || n != 1)
        nfiles = 1;
    s->nfiles = nfiles > 1 && nfiles < 1 << 20 ? (int)nfiles : 1;
    orr_h5_attr_numbers(h, "NumPart_Total", H5T_NATIVE_UINT32, low, NB_TYPES_MAX, &nl);
    orr_h5_attr_numbers(h, "NumPart_Total_HighWord", H5T_NATIVE_UINT32, high, NB_TYPES_MAX, &nh);
    s->total = 0;
    for (int t = 0; t < nl; t++)
        s->total += (uint64_t)low[t] | (t < nh ? (uint64_t)high[t] << 32 : 0);
}

static orr_status read_file(hid_t file, const char *path, nb_particles *p, nb_run_state *s, nb_particles *names,
                            orr_error *err)
{
    hid_t h = H5Gopen2(file, "Header", H5P_DEFAULT), run = -1;
    uint64_t count[NB_TYPES_MAX] = {0};
    int ntypes = 0;
    orr_status st = ORR_OK;
    if (h < 0 || orr_h5_attr_numbers(h, "NumPart_ThisFile", H5T_NATIVE_UINT64, count, NB_TYPES_MAX, &ntypes) !=
                     ORR_H5_FOUND || !attr_double(h, "Time", &s->time))
        st = orr_fail(err, ORR_ERR_FORMAT, "%s: no Gadget header (NumPart_ThisFile, Time)", path);
    else if ((run = orr_h5_has_link(file, RUN_GROUP) ? H5Gopen2(file, RUN_GROUP, H5P_DEFAULT) : -1) < 0 ||
             !attr_long(run, "Step", &s->step) || !attr_long(run, "Number", &s->number) ||
             !attr_long(run, "SnapshotEvery", &s->snapshot_every) || !attr_double(run, "E0", &s->e0) ||
             !attr_double(run, "Dt", &s->dt) || !attr_double(run, "Eps", &s->eps) ||
             !attr_double(run, "EpsHalo", &s->eps_halo) || !attr_double(run, "Theta", &s->theta))
        st = orr_fail(err, ORR_ERR_FORMAT,
                      "%s: not a snapshot orrery-nbody wrote (no complete /%s group): --ic reads it as "
                      "new initial conditions instead",
                      path, RUN_GROUP);
    if (!st && !attr_double(run, "Eta", &s->eta))
        s->eta = 0; /* one global step */
    if (!st && !attr_double(run, "DtMin", &s->dt_min))
        s->dt_min = 0; /* no shortest block step */
    if (!st && !attr_long(run, "TracerNeighbours", &s->tracer_neighbours))
        s->tracer_neighbours = 0; /* written before tracers were softened apart */
    if (!st && !attr_long(run, "TracerRing", &s->tracer_ring))
        s->tracer_ring = 0; /* written before tracers' rings */
    if (!st && !attr_long(run, "TracerMirror", &s->tracer_mirror))
        s->tracer_mirror = 0; /* written before mirrored rings */
    int ncentre = 0;
    s->has_centre0 = !st && orr_h5_attr_numbers(run, "Centre0", H5T_NATIVE_DOUBLE, s->centre0, 3, &ncentre) ==
                                ORR_H5_FOUND && ncentre == 3;
    if (!st)
        read_set_header(h, s);
    size_t n = 0;
    for (int t = 0; t < ntypes; t++)
        n += (size_t)count[t];
    unsigned char *seen = NULL;
    if (!p) { /* the state only, and the fields' names */
        if (!st && names)
            read_field_names(run, names);
        orr_h5_close(run);
        orr_h5_close(h);
        return st;
    }
    if (!st) {
        read_field_names(run, p);
        seen = calloc(n ? n : 1, 1);
        if (!seen || !alloc_particles(p, n) || (has_levels(file, count, ntypes) && !(p->level = calloc(n ? n : 1, 1))))
            st = orr_fail(err, ORR_ERR_NOMEM, "%s: cannot hold %zu particles", path, n);
    }
    for (int t = 0; t < ntypes && !st; t++) {
        if (!count[t])
            continue;
        char name[32];
        snprintf(name, sizeof name, "PartType%d", t);
        hid_t g = H5Gopen2(file, name, H5P_DEFAULT);
        const char *bad = g < 0 ? name : read_type(g, t, (size_t)count[t], p, seen);
        orr_h5_close(g);
        if (bad)
            st = orr_fail(err, ORR_ERR_FORMAT, "%s: %s: missing or unreadable %s", path, name, bad);
    }
    free(seen);
    orr_h5_close(run);
    orr_h5_close(h);
    return st;
}

orr_status nb_snapshot_read_state(const char *path, nb_run_state *s, nb_particles *names, orr_error *err)
{
    orr_h5_quiet();
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open it as an HDF5 file", path);
    if (names)
        memset(names, 0, sizeof *names);
    orr_status st = read_file(file, path, NULL, s, names, err);
    H5Fclose(file);
    return st;
}

orr_status nb_snapshot_read(const char *path, nb_particles *p, nb_run_state *s, orr_error *err)
{
    orr_h5_quiet();
    memset(p, 0, sizeof *p);
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open it as an HDF5 file", path);
    orr_status st = read_file(file, path, p, s, NULL, err);
    H5Fclose(file);
    if (st)
        nb_particles_free(p);
    return st;
}

/* Grows *a (n entries of `size` bytes) by q's m, appended; frees q's. */
static int append_array(void **a, void **q, size_t n, size_t m, size_t size)
{
    unsigned char *g = realloc(*a, (n + m) * size + 1);
    if (g) {
        memcpy(g + n * size, *q, m * size);
        *a = g;
    }
    free(*q);
    *q = NULL;
    return g != NULL;
}

int nb_particles_append(nb_particles *p, nb_particles *q)
{
    if (!p->pos) { /* the first */
        nb_particles_free(p);
        *p = *q;
        memset(q, 0, sizeof *q);
        return 0;
    }
    int ok = p->nfields == q->nfields;
    for (int f = 0; ok && f < p->nfields; f++)
        ok = strcmp(p->field_name[f], q->field_name[f]) == 0;
    if (!ok) {
        nb_particles_free(q);
        return -1;
    }
    size_t n = p->n, m = q->n;
    ok &= append_array((void **)&p->pos, (void **)&q->pos, n, m, 3 * sizeof(double));
    ok &= append_array((void **)&p->vel, (void **)&q->vel, n, m, 3 * sizeof(double));
    ok &= append_array((void **)&p->mass, (void **)&q->mass, n, m, sizeof(double));
    ok &= append_array((void **)&p->id, (void **)&q->id, n, m, sizeof(uint64_t));
    ok &= append_array((void **)&p->type, (void **)&q->type, n, m, 1);
    if (p->level && q->level) {
        ok &= append_array((void **)&p->level, (void **)&q->level, n, m, 1);
    } else {
        free(p->level);
        p->level = NULL;
    }
    for (int f = 0; f < p->nfields; f++)
        ok &= append_array((void **)&p->field[f], (void **)&q->field[f], n, m, sizeof(float));
    p->n = n + m;
    nb_particles_free(q);
    return ok ? 0 : -1;
}

void nb_particles_free(nb_particles *p)
{
    free(p->pos);
    free(p->vel);
    free(p->mass);
    free(p->id);
    free(p->type);
    free(p->level);
    for (int f = 0; f < p->nfields; f++)
        free(p->field[f]);
    memset(p, 0, sizeof *p);
}
