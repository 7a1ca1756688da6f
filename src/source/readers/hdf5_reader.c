/* The HDF5 snapshot reader: finds the files of a snapshot, checks every
 * header, group and dataset shape before reading (so absurd particle counts
 * are caught before anything is allocated; hdf5_files.c), then streams
 * particles file by file and type by type with hyperslab reads of at most
 * one chunk. Only one file is open at a time. */
#include "source/readers/hdf5_reader.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source/readers/hdf5_internal.h"
#include "source/readers/mass_policy.h"

/* The extra fields' names, and the dataset each comes from. */
static const char *const extra_field_names[EX_COUNT] = {"vx", "vy", "vz", "u", "rho", "pot"};
static const h5r_dataset extra_source[EX_COUNT] = {DS_VEL, DS_VEL, DS_VEL, DS_U, DS_RHO, DS_POT};

int orr_hdf5_probe(const unsigned char *head, size_t n)
{
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    static const size_t offsets[] = {0, 512, 1024, 2048};
    for (size_t i = 0; i < sizeof offsets / sizeof offsets[0]; i++)
        if (offsets[i] + sizeof sig <= n && memcmp(head + offsets[i], sig, sizeof sig) == 0)
            return 1;
    return 0;
}

/* ---- Streaming ------------------------------------------------------ */

static void close_group(hdf5_state *st)
{
    for (int k = 0; k < DS_COUNT; k++)
        st->ds[k] = orr_h5_close(st->ds[k]);
    for (int i = 0; i < st->nnamed; i++)
        st->named[i].ds = orr_h5_close(st->named[i].ds);
    st->gid = orr_h5_close(st->gid);
}

static void close_file(hdf5_state *st)
{
    close_group(st);
    st->fid = orr_h5_close(st->fid);
}

static orr_status open_current_group(hdf5_state *st, orr_error *err)
{
    char why[256];
    if (st->fid < 0) {
        h5r_file_name(st, st->file, st->path, sizeof st->path);
        orr_status s = h5r_open_file(st->path, &st->fid, "", err);
        if (s)
            return s;
    }
    char gname[H5R_GROUP_NAME];
    snprintf(gname, sizeof gname, "PartType%d", st->type);
    st->gid = H5Gopen2(st->fid, gname, H5P_DEFAULT);
    if (st->gid < 0) {
        orr_h5_reason(why, sizeof why);
        return orr_fail(err, ORR_ERR_FORMAT, "%s: %s cannot be opened (%s)", st->path, gname, why);
    }
    for (int k = 0; k < DS_COUNT; k++) {
        const char *name = h5r_dataset_name_in(st->gid, (h5r_dataset)k);
        if (!name)
            continue;
        st->ds[k] = H5Dopen2(st->gid, name, H5P_DEFAULT);
        if (st->ds[k] < 0) {
            orr_h5_reason(why, sizeof why);
            return orr_fail(err, ORR_ERR_FORMAT, "%s: %s/%s cannot be opened (%s)", st->path, gname, name, why);
        }
    }
    for (int i = 0; i < st->nnamed; i++) {
        orr_status s = st->named[i].slot >= 0 ? h5r_named_open(&st->named[i], st->path, st->type, st->gid, err) : ORR_OK;
        if (s)
            return s;
    }
    return ORR_OK;
}

/* Reads n rows of dataset kind into buf; the message names file, dataset
 * and rows when HDF5 fails (typically a truncated or corrupt file). */
static orr_status read_rows(hdf5_state *st, h5r_dataset kind, size_t n, int ncols, hid_t memtype, void *buf,
                            orr_error *err)
{
    if (orr_h5_read_rows(st->ds[kind], st->row, n, ncols, memtype, buf) == 0)
        return ORR_OK;
    char why[256];
    orr_h5_reason(why, sizeof why);
    const char *name = h5r_dataset_name_in(st->gid, kind);
    return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s: reading rows %" PRIu64 " to %" PRIu64 " failed (%s)",
                    st->path, st->type, name ? name : h5r_dataset_names[kind][0], st->row, st->row + n - 1,
                    why[0] ? why : "no reason given");
}

static void fill(float *a, size_t n, float v)
{
    for (size_t i = 0; i < n; i++)
        a[i] = v;
}

/* Reads a float field into out, or fills it with missing when the group
 * has no such dataset. */
static orr_status read_floats(hdf5_state *st, h5r_dataset kind, size_t n, float *out, float missing,
                              orr_error *err)
{
    if (st->ds[kind] < 0) {
        fill(out, n, missing);
        return ORR_OK;
    }
    return read_rows(st, kind, n, 0, H5T_NATIVE_FLOAT, out, err);
}

/* Masses: the Masses dataset read as doubles, so that the mass policy sees
 * the stored values before they become floats (a double too small or too
 * large for a float is refused, not turned into 0 or infinity), else the
 * type's MassTable entry (checked when the file was opened). */
static orr_status read_masses(hdf5_state *st, size_t n, float *out, orr_error *err)
{
    if (st->ds[DS_MASS] < 0) {
        fill(out, n, (float)st->mass_table[st->type]);
        return ORR_OK;
    }
    /* scratch holds 3 floats a chunk particle: room for n doubles. */
    double *m = (double *)(void *)st->scratch;
    orr_status s = read_rows(st, DS_MASS, n, 0, H5T_NATIVE_DOUBLE, m, err);
    for (size_t i = 0; i < n && !s; i++) {
        const char *problem = orr_mass_problem(m[i]);
        if (problem)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s row %" PRIu64 ": mass %g %s", st->path,
                            st->type, h5r_dataset_name_in(st->gid, DS_MASS), st->row + i, m[i], problem);
        out[i] = (float)m[i];
    }
    return s;
}

/* Smoothing lengths become kernel sizes: reject the values that would
 * silently spoil an image. */
static orr_status check_non_negative(hdf5_state *st, h5r_dataset kind, const float *v, size_t n, orr_error *err)
{
    for (size_t i = 0; i < n; i++)
        if (!(v[i] >= 0) || isinf(v[i]))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: PartType%d/%s row %" PRIu64 ": %g is not finite and non-negative",
                            st->path, st->type, h5r_dataset_name_in(st->gid, kind), st->row + i, (double)v[i]);
    return ORR_OK;
}

static orr_status read_positions(hdf5_state *st, orr_chunk *c, size_t n, orr_error *err)
{
    orr_status s = read_rows(st, DS_POS, n, 3, H5T_NATIVE_FLOAT, st->scratch, err);
    for (size_t i = 0; i < n && !s; i++) {
        c->x[c->n + i] = st->scratch[3 * i];
        c->y[c->n + i] = st->scratch[3 * i + 1];
        c->z[c->n + i] = st->scratch[3 * i + 2];
    }
    return s;
}

static orr_status read_velocities(hdf5_state *st, orr_chunk *c, size_t n, orr_error *err)
{
    if (st->slot[EX_VX] < 0 && st->slot[EX_VY] < 0 && st->slot[EX_VZ] < 0)
        return ORR_OK;
    if (st->ds[DS_VEL] < 0)
        memset(st->scratch, 0, 3 * n * sizeof *st->scratch);
    else {
        orr_status s = read_rows(st, DS_VEL, n, 3, H5T_NATIVE_FLOAT, st->scratch, err);
        if (s)
            return s;
    }
    for (int axis = 0; axis < 3; axis++) {
        int slot = st->slot[EX_VX + axis];
        if (slot < 0)
            continue;
        float *out = c->extra[slot].data + c->n;
        for (size_t i = 0; i < n; i++)
            out[i] = st->scratch[3 * i + (size_t)axis];
    }
    return ORR_OK;
}

static orr_status read_ids(hdf5_state *st, orr_chunk *c, size_t n, orr_error *err)
{
    if (st->ds[DS_ID] >= 0)
        return read_rows(st, DS_ID, n, 0, H5T_NATIVE_UINT64, c->id + c->n, err);
    for (size_t i = 0; i < n; i++)
        c->id[c->n + i] = st->emitted + i;
    return ORR_OK;
}

/* Reads the next n rows of the current group into the chunk at c->n. */
static orr_status read_segment(hdf5_state *st, orr_chunk *c, size_t n, orr_error *err)
{
    orr_status s = read_positions(st, c, n, err);
    if (!s)
        s = read_velocities(st, c, n, err);
    if (!s)
        s = read_ids(st, c, n, err);
    if (!s)
        s = read_masses(st, n, c->mass + c->n, err);
    if (!s && c->h)
        s = read_floats(st, DS_H, n, c->h + c->n, 0.0f, err);
    if (!s && c->h && st->ds[DS_H] >= 0)
        s = check_non_negative(st, DS_H, c->h + c->n, n, err);
    for (int e = EX_U; e < EX_COUNT && !s; e++)
        if (st->slot[e] >= 0)
            s = read_floats(st, extra_source[e], n, c->extra[st->slot[e]].data + c->n, 0.0f, err);
    for (int i = 0; i < st->nnamed && !s; i++) {
        const h5r_named *f = &st->named[i];
        if (f->slot >= 0)
            s = h5r_named_read(f, st->path, st->type, st->row, n, c->extra[f->slot].data + c->n, err);
    }
    if (!s)
        memset(c->type + c->n, st->type, n);
    return s;
}

/* Moves the cursor to the next group with particles left to read; returns 0
 * at the end of the snapshot. */
static int advance(hdf5_state *st)
{
    while (st->file < st->nfiles) {
        if (st->type < st->ntypes) {
            size_t run = (size_t)st->file * (size_t)st->ntypes + (size_t)st->type;
            if (st->row < (uint64_t)st->share.lo[run])
                st->row = (uint64_t)st->share.lo[run]; /* the rows before are other processes' */
            if (st->row < (uint64_t)st->share.hi[run])
                return 1;
            close_group(st);
            st->type++;
            st->row = 0;
            continue;
        }
        close_file(st);
        st->file++;
        st->type = 0;
    }
    return 0;
}

static orr_status hdf5_next(orr_source *src, orr_error *err)
{
    hdf5_state *st = src->state;
    orr_chunk *c = &src->chunk;
    c->first_index = st->emitted;
    orr_h5_quiet();
    while (c->n < c->capacity && advance(st)) {
        orr_status s = st->gid < 0 ? open_current_group(st, err) : ORR_OK;
        if (s)
            return s;
        uint64_t left = (uint64_t)st->share.hi[(size_t)st->file * (size_t)st->ntypes + (size_t)st->type] - st->row;
        size_t n = c->capacity - c->n;
        if (left < n)
            n = (size_t)left;
        if ((s = read_segment(st, c, n, err)))
            return s;
        c->n += n;
        st->row += n;
        st->emitted += n;
    }
    return ORR_OK;
}

static orr_status hdf5_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    hdf5_state *st = src->state;
    close_file(st);
    st->file = st->type = 0;
    st->row = 0;
    st->emitted = st->share.first;
    return ORR_OK;
}

static void hdf5_close(orr_source *src)
{
    hdf5_state *st = src->state;
    if (!st)
        return;
    close_file(st);
    free(st->npart);
    orr_share_free(&st->share);
    free(st->scratch);
    free(st);
    src->state = NULL;
}

static const orr_source_ops hdf5_ops = {.next = hdf5_next, .rewind = hdf5_rewind, .close = hdf5_close};

/* ---- Opening -------------------------------------------------------- */

/* Whether the reader gives name without looking for a dataset of that name. */
static int known_field(const char *name)
{
    return orr_field_is_own(name) || orr_field_in_list(name, extra_field_names, EX_COUNT);
}

/* The fields the caller names that may be datasets of their own: looked
 * for in every group read (check_group). A caller naming no fields (all of
 * them) gets the known ones only: a snapshot may hold dozens of datasets. */
static void ask_named(hdf5_state *st, const orr_source_options *opt)
{
    for (int i = 0; opt && opt->fields && i < opt->nfields && st->nnamed < H5R_MAX_NAMED; i++)
        if (!known_field(opt->fields[i]) && h5r_named_parse(opt->fields[i], &st->named[st->nnamed]))
            st->nnamed++;
}

/* Chooses the extra fields: those some group has and the caller wants. */
static void choose_fields(hdf5_state *st, orr_source *src, const orr_source_options *opt)
{
    for (int e = 0; e < EX_COUNT; e++) {
        st->slot[e] = -1;
        if (st->present[extra_source[e]] && orr_source_wants_field(opt, extra_field_names[e])) {
            st->slot[e] = src->info.nextra;
            snprintf(src->info.extra_names[src->info.nextra++], ORR_FIELD_NAME_MAX, "%s", extra_field_names[e]);
        }
    }
    for (int i = 0; i < st->nnamed; i++)
        if (st->named[i].present && src->info.nextra < ORR_MAX_EXTRA_FIELDS) {
            st->named[i].slot = src->info.nextra;
            snprintf(src->info.extra_names[src->info.nextra++], ORR_FIELD_NAME_MAX, "%s", st->named[i].field);
        }
    src->info.has_h = st->present[DS_H];
    /* Gadget, AREPO and GIZMO store the radius where the kernel ends; SWIFT
     * stores h with that radius at gamma h, gamma = 1.825742 for its default
     * cubic spline (Dehnen & Aly 2012, table 1). */
    src->info.h_support = st->swift_h ? 1.825742 : 1.0;
    src->info.has_id = st->present[DS_ID];
    src->info.has_type = 1;
}

/* Which rows of each group this process reads; the count becomes theirs. */
static orr_status choose_share(hdf5_state *st, orr_source *src, const orr_source_options *opt, orr_error *err)
{
    size_t nruns = (size_t)st->nfiles * (size_t)st->ntypes;
    orr_status s = orr_share_alloc(&st->share, nruns, err);
    if (s)
        return s;
    for (size_t r = 0; r < nruns; r++)
        st->share.hi[r] = st->type_mask >> (r % (size_t)st->ntypes) & 1u ? st->npart[r] : 0;
    s = orr_share_divide(&st->share, nruns, src, opt, err);
    st->emitted = st->share.first;
    return s;
}

static orr_status alloc_buffers(hdf5_state *st, orr_source *src, const orr_source_options *opt, orr_error *err)
{
    orr_status s = orr_source_alloc_chunk(src, opt, err); /* a small snapshot needs no more than its own size */
    if (s)
        return s;
    st->scratch = orr_malloc(3 * src->chunk.capacity * sizeof *st->scratch, "HDF5 read buffer", err);
    return st->scratch ? ORR_OK : ORR_ERR_NOMEM;
}

static orr_status open_snapshot(hdf5_state *st, orr_source *src, const orr_source_options *opt, orr_error *err)
{
    hid_t fid = -1, header = -1;
    char example[DS_COUNT][H5R_GROUP_NAME] = {{0}};
    orr_status s = h5r_open_file(st->first, &fid, "", err);
    if (!s)
        s = h5r_open_header(st->first, fid, &header, err);
    if (!s)
        s = h5r_read_main_header(st, header, src, err);
    for (int t = 0; !s && t < st->ntypes; t++)
        if (orr_source_wants_type(opt, t))
            st->type_mask |= 1u << t;
    ask_named(st, opt);
    if (!s)
        s = h5r_check_files(st, fid, src, example, err);
    for (int i = 0; i < st->nnamed && !s; i++)
        if (!st->named[i].present)
            s = h5r_named_missing(&st->named[i], st->first, fid, st->type_mask, st->ntypes, err);
    if (!s) {
        h5r_describe(&src->info, fid, st->ntypes, (const char(*)[H5R_GROUP_NAME])example);
        h5r_find_units(&src->info, fid, (const char(*)[H5R_GROUP_NAME])example);
        if (st->nfiles > 1)
            orr_source_add_header(&src->info, "files", "%d (%s.0%s .. %s.%d%s)", st->nfiles, st->base, st->ext,
                                  st->base, st->nfiles - 1, st->ext);
    }
    orr_h5_close(header);
    orr_h5_close(fid);
    return s;
}

orr_status orr_hdf5_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err)
{
    *out = NULL;
    orr_source *src = orr_source_new("hdf5", path, &hdf5_ops, sizeof(hdf5_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    hdf5_state *st = src->state;
    st->fid = st->gid = -1;
    for (int k = 0; k < DS_COUNT; k++)
        st->ds[k] = -1;
    orr_h5_quiet();
    orr_status s = h5r_resolve_first_file(st, path, err);
    if (!s) {
        snprintf(src->info.path, sizeof src->info.path, "%s", st->first);
        s = open_snapshot(st, src, opt, err);
    }
    if (!s) {
        choose_fields(st, src, opt);
        s = choose_share(st, src, opt, err);
    }
    if (!s) {
        s = alloc_buffers(st, src, opt, err);
    }
    if (s) {
        orr_source_close(src);
        return s;
    }
    *out = src;
    return ORR_OK;
}
