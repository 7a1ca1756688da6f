/* The Gadget snapshot source: finds the parts of a multi-file snapshot, has
 * gadget_layout.c check each one, fills the info for `orrery info` (both in
 * gadget_parts.c), then streams particles: for each run of particles of one
 * wanted type in one file it seeks to that run in each block it needs and
 * converts in pieces of at most GADGET_PIECE values, so memory is the chunk
 * plus a fixed buffer. */
#include "source/readers/gadget.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "core/bytes.h"
#include "source/readers/gadget_internal.h"
#include "source/readers/mass_policy.h"
#include "source/readers/share.h"

#define GADGET_DEFAULT_CHUNK ((size_t)1 << 20)
/* Values converted per fread; bounds the raw buffer (8 bytes each). */
#define GADGET_PIECE ((size_t)3 << 16)

static const char *const extra_field_names[X_COUNT] = {"vx", "vy", "vz", "u", "rho", "pot"};

/* ---- byte decoding ---- */

static float load_f64_as_float(const unsigned char *p, int swap)
{
    return (float)orr_load_f64(p, swap);
}

/* Converts n values stride bytes apart (one component of an interleaved
 * block) to float. The common case, float in the host's order, is a plain
 * copy the compiler can vectorise. */
static void convert_reals(const unsigned char *p, size_t n, size_t stride, int elem, int swap, float *out)
{
    if (elem == 4 && !swap)
        for (size_t i = 0; i < n; i++)
            memcpy(&out[i], p + i * stride, 4);
    else if (elem == 4)
        for (size_t i = 0; i < n; i++)
            out[i] = orr_load_f32(p + i * stride, 1);
    else
        for (size_t i = 0; i < n; i++)
            out[i] = load_f64_as_float(p + i * stride, swap);
}

static void convert_ids(const unsigned char *p, size_t n, int elem, int swap, uint64_t *out)
{
    if (elem == 4)
        for (size_t i = 0; i < n; i++)
            out[i] = gadget_u32(p + 4 * i, swap);
    else
        for (size_t i = 0; i < n; i++)
            out[i] = orr_load_u64(p + 8 * i, swap);
}

/* ---- streaming ---- */

static orr_status open_part(orr_source *src, gadget_state *st, orr_error *err)
{
    if (st->fp_file == st->file)
        return ORR_OK;
    if (st->fp)
        fclose(st->fp);
    st->fp_file = -1;
    char path[ORR_PATH_MAX + 16];
    gadget_part_path(st, st->file, path, sizeof path);
    st->fp = fopen(path, "rb");
    if (!st->fp)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s (reading %s)", path, strerror(errno), src->info.path);
    st->fp_file = st->file;
    return ORR_OK;
}

/* Names the particle whose value number m of the MASS block breaks the mass
 * policy: the block holds only the types with massarr 0, type by type. */
static orr_status mass_error(const gadget_state *st, int64_t m, double mass, const char *problem, orr_error *err)
{
    const gadget_file *f = &st->files[st->file];
    int type = 0;
    for (int t = 0; t < GADGET_NTYPES; t++)
        if (f->h.massarr[t] == 0 && f->h.npart[t] > 0 && m >= f->mass_start[t])
            type = t;
    char path[ORR_PATH_MAX + 16];
    gadget_part_path(st, st->file, path, sizeof path);
    return orr_fail(err, ORR_ERR_FORMAT, "%s: block MASS: particle %lld of the file (type %d): mass %g %s", path,
                    (long long)(f->type_start[type] + m - f->mass_start[type]), type, mass, problem);
}

/* The mass policy on n MASS values as stored (before they become floats,
 * so a double that float cannot hold is caught); first is the first one's
 * number in the block. */
static orr_status check_masses(const gadget_state *st, const unsigned char *raw, size_t n, int elem, int64_t first,
                               orr_error *err)
{
    for (size_t i = 0; i < n; i++) {
        double m = elem == 8 ? orr_load_f64(raw + 8 * i, st->enc.swap) : orr_load_f32(raw + 4 * i, st->enc.swap);
        const char *problem = orr_mass_problem(m);
        if (problem)
            return mass_error(st, first + (int64_t)i, m, problem, err);
    }
    return ORR_OK;
}

/* read_values for any block, named by label; is_mass applies the mass policy. */
static orr_status read_block_values(gadget_state *st, const gadget_block *b, const char *label, int is_mass,
                                    int64_t first, size_t count, int ncomp, float *const *dest, uint64_t *ids,
                                    orr_error *err)
{
    char path[ORR_PATH_MAX + 16];
    int64_t offset = b->offset + first * ncomp * b->elem;
    if (fseeko(st->fp, (off_t)offset, SEEK_SET) != 0) {
        gadget_part_path(st, st->file, path, sizeof path);
        return orr_fail(err, ORR_ERR_IO, "%s: block %s: cannot seek to offset %lld: %s", path, label,
                        (long long)offset, strerror(errno));
    }
    size_t per_piece = GADGET_PIECE / (size_t)ncomp;
    for (size_t done = 0; done < count;) {
        size_t n = count - done < per_piece ? count - done : per_piece;
        size_t bytes = n * (size_t)ncomp * (size_t)b->elem;
        if (fread(st->raw, 1, bytes, st->fp) != bytes) {
            gadget_part_path(st, st->file, path, sizeof path);
            return orr_fail(err, ORR_ERR_IO,
                            "%s: block %s: short read of %zu bytes near offset %lld (%s; did the file change "
                            "since it was opened?)",
                            path, label, bytes, (long long)offset,
                            ferror(st->fp) ? strerror(errno) : "end of file");
        }
        orr_status s;
        if (is_mass && (s = check_masses(st, st->raw, n, b->elem, first + (int64_t)done, err)))
            return s;
        if (ids)
            convert_ids(st->raw, n, b->elem, st->enc.swap, ids + done);
        else
            for (int c = 0; c < ncomp; c++)
                if (dest[c])
                    convert_reals(st->raw + (size_t)c * (size_t)b->elem, n, (size_t)ncomp * (size_t)b->elem,
                                  b->elem, st->enc.swap, dest[c] + done);
        done += n;
        offset += (int64_t)bytes;
    }
    return ORR_OK;
}

/* Reads count values of ncomp components each, starting at value number
 * first of block b, into dest[c][0..count) (dest[c] NULL: skip component).
 * ids != NULL reads integers into ids instead. */
static orr_status read_values(gadget_state *st, const gadget_block *b, gadget_block_kind k, int64_t first,
                              size_t count, int ncomp, float *const *dest, uint64_t *ids, orr_error *err)
{
    return read_block_values(st, b, gadget_block_names[k], k == BLK_MASS, first, count, ncomp, dest, ids, err);
}

static void fill(float *a, size_t n, float v)
{
    for (size_t i = 0; i < n; i++)
        a[i] = v;
}

static float *extra_at(orr_chunk *c, const gadget_state *st, int x, size_t at)
{
    return st->slot[x] >= 0 ? c->extra[st->slot[x]].data + at : NULL;
}

/* One gas-only scalar block (U, RHO, HSML): read for gas, 0 for the rest. */
static orr_status read_gas_field(gadget_state *st, const gadget_file *f, gadget_block_kind k, int type,
                                 int64_t within, size_t count, float *dest, orr_error *err)
{
    if (!dest)
        return ORR_OK;
    if (type != 0) {
        fill(dest, count, 0.0f);
        return ORR_OK;
    }
    float *d[1] = {dest};
    return read_values(st, &f->blk[k], k, within, count, 1, d, NULL, err);
}

/* One column of a named block for count particles of one type: 0 for the
 * types the block has no values for, as for every other field. */
static orr_status read_named(gadget_state *st, const gadget_file *f, const gadget_named_field *nf, int type,
                             int64_t within, size_t count, float *dest, orr_error *err)
{
    if (!(nf->layout.types >> type & 1u)) {
        fill(dest, count, 0.0f);
        return ORR_OK;
    }
    const gadget_named_block *nb = gadget_named_find(f, nf->layout.label);
    if (!nb)
        return orr_fail(err, ORR_ERR_INTERNAL, "block %s vanished from a part", nf->layout.label);
    gadget_block b = {1, nb->offset, nb->bytes, nf->layout.elem};
    float *d[GADGET_NAMED_MAX_COMPONENTS] = {NULL};
    d[nf->column] = dest;
    return read_block_values(st, &b, nf->layout.label, 0, gadget_named_row(&nf->layout, f, type, within), count,
                             nf->layout.ncomp, d, NULL, err);
}

/* Reads count particles of one type from the current file into the chunk
 * at c->n: first is the particle's index in the file, within its index in
 * its type. */
static orr_status read_run(orr_source *src, gadget_state *st, int type, int64_t within, size_t count,
                           orr_error *err)
{
    const gadget_file *f = &st->files[st->file];
    orr_chunk *c = &src->chunk;
    size_t at = c->n;
    int64_t first = f->type_start[type] + within;
    orr_status s = open_part(src, st, err);
    if (s)
        return s;
    float *pos[3] = {c->x + at, c->y + at, c->z + at};
    if ((s = read_values(st, &f->blk[BLK_POS], BLK_POS, first, count, 3, pos, NULL, err)))
        return s;
    float *vel[3] = {extra_at(c, st, X_VX, at), extra_at(c, st, X_VY, at), extra_at(c, st, X_VZ, at)};
    if ((vel[0] || vel[1] || vel[2]) &&
        (s = read_values(st, &f->blk[BLK_VEL], BLK_VEL, first, count, 3, vel, NULL, err)))
        return s;
    if (st->has_id) {
        if ((s = read_values(st, &f->blk[BLK_ID], BLK_ID, first, count, 1, NULL, c->id + at, err)))
            return s;
    } else {
        uint64_t index = 0; /* the particle's place in the whole snapshot */
        for (int i = 0; i < st->file; i++)
            index += (uint64_t)st->files[i].n;
        for (size_t i = 0; i < count; i++)
            c->id[at + i] = index + (uint64_t)first + i;
    }
    if (f->h.massarr[type] != 0) {
        fill(c->mass + at, count, (float)f->h.massarr[type]);
    } else {
        float *m[1] = {c->mass + at};
        if ((s = read_values(st, &f->blk[BLK_MASS], BLK_MASS, f->mass_start[type] + within, count, 1, m, NULL,
                             err)))
            return s;
    }
    if ((s = read_gas_field(st, f, BLK_HSML, type, within, count, st->has_h ? c->h + at : NULL, err)) ||
        (s = read_gas_field(st, f, BLK_U, type, within, count, extra_at(c, st, X_U, at), err)) ||
        (s = read_gas_field(st, f, BLK_RHO, type, within, count, extra_at(c, st, X_RHO, at), err)))
        return s;
    float *pot[1] = {extra_at(c, st, X_POT, at)};
    if (pot[0] && (s = read_values(st, &f->blk[BLK_POT], BLK_POT, first, count, 1, pot, NULL, err)))
        return s;
    for (int i = 0; i < st->nnamed; i++)
        if ((s = read_named(st, f, &st->named[i], type, within, count, c->extra[st->named[i].slot].data + at, err)))
            return s;
    memset(c->type + at, type, count);
    return ORR_OK;
}

orr_status gadget_next(orr_source *src, orr_error *err)
{
    gadget_state *st = src->state;
    orr_chunk *c = &src->chunk;
    c->first_index = st->next_index;
    while (c->n < c->capacity && st->file < st->nfiles) {
        if (st->type == GADGET_NTYPES) {
            st->file++;
            st->type = 0;
            st->done = 0;
            continue;
        }
        size_t run = (size_t)st->file * GADGET_NTYPES + (size_t)st->type;
        if (st->done < st->share.lo[run])
            st->done = st->share.lo[run]; /* the rows before are other processes' */
        int64_t left = st->share.hi[run] - st->done;
        if (left <= 0) {
            st->type++;
            st->done = 0;
            continue;
        }
        size_t room = c->capacity - c->n;
        size_t count = (uint64_t)left < room ? (size_t)left : room;
        orr_status s = read_run(src, st, st->type, st->done, count, err);
        if (s)
            return s;
        c->n += count;
        st->done += (int64_t)count;
        st->next_index += count;
    }
    return ORR_OK;
}

orr_status gadget_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    gadget_state *st = src->state;
    st->file = st->type = 0;
    st->done = 0;
    st->next_index = st->share.first;
    return ORR_OK;
}

void gadget_close(orr_source *src)
{
    gadget_state *st = src->state;
    if (!st)
        return;
    if (st->fp)
        fclose(st->fp);
    free(st->files);
    orr_share_free(&st->share);
    free(st->raw);
    free(st);
    src->state = NULL;
}

static const orr_source_ops gadget_ops = {.next = gadget_next, .rewind = gadget_rewind, .close = gadget_close};

static int64_t block_values(const gadget_file *f, gadget_block_kind k)
{
    if (k == BLK_U || k == BLK_RHO || k == BLK_HSML)
        return f->h.npart[0];
    if (k != BLK_MASS)
        return f->n;
    int64_t nvar = 0;
    for (int t = 0; t < GADGET_NTYPES; t++)
        if (f->h.massarr[t] == 0)
            nvar += f->h.npart[t];
    return nvar;
}

/* A block is usable when every part that has values for it has it; a
 * snapshot whose parts disagree is damaged. Returns -1 after failing. */
static int block_available(const gadget_state *st, gadget_block_kind k, orr_error *err)
{
    int have = -1, missing = -1;
    for (int i = 0; i < st->nfiles; i++) {
        const gadget_file *f = &st->files[i];
        int64_t needed = block_values(f, k);
        if (f->blk[k].present && have < 0)
            have = i;
        if (!f->blk[k].present && needed > 0 && missing < 0)
            missing = i;
    }
    if (have >= 0 && missing >= 0) {
        orr_fail(err, ORR_ERR_FORMAT, "snapshot %s: part %d has no %s block, but part %d has one", st->base,
                 missing, gadget_block_names[k], have);
        return -1;
    }
    return have >= 0;
}

/* The fields every Gadget file may give without a named block. */
static int standard_field(const char *name)
{
    return orr_field_is_own(name) || orr_field_in_list(name, extra_field_names, X_COUNT);
}

/* "AGE NHP Z": the named blocks of the snapshot's first part that has any. */
static void named_labels(const gadget_state *st, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int i = 0; i < st->nfiles && !buf[0]; i++)
        for (int b = 0; b < st->files[i].nnamed; b++) {
            size_t used = strlen(buf);
            snprintf(buf + used, size - used, "%s%s", used ? " " : "", st->files[i].named[b].label);
        }
}

/* Whether some part has a block of this label. */
static int named_anywhere(const gadget_state *st, const char *label)
{
    for (int i = 0; i < st->nfiles; i++)
        if (gadget_named_find(&st->files[i], label))
            return 1;
    return 0;
}

/* One field asked for by name that is no standard one: a column of a named
 * block whose layout is known, else an error naming what is wrong. */
static orr_status add_named(orr_source *src, gadget_state *st, const char *field, orr_error *err)
{
    char label[ORR_FIELD_NAME_MAX], labels[GADGET_MAX_NAMED * 5 + 1];
    int column;
    if (!orr_field_split_column(field, label, sizeof label, &column))
        return orr_fail(err, ORR_ERR_USAGE, "snapshot %s: field %s: not a block label (LABEL or LABEL[k])",
                        st->base, field);
    named_labels(st, labels, sizeof labels);
    if (strlen(label) > 4 || !named_anywhere(st, label)) {
        if (st->enc.snapformat == 1)
            return orr_fail(err, ORR_ERR_USAGE,
                            "snapshot %s: field %s: a SnapFormat 1 file has no block labels, so only its standard "
                            "blocks are fields (x y z mass h id type vx vy vz u rho pot)",
                            st->base, field);
        return orr_fail(err, ORR_ERR_USAGE, "snapshot %s: field %s: no block %s (other blocks: %s)", st->base, field,
                        label, labels[0] ? labels : "none");
    }
    gadget_named_field *nf = &st->named[st->nnamed];
    gadget_named_infer(st->files, st->nfiles, label, &nf->layout);
    if (!nf->layout.ok)
        return orr_fail(err, ORR_ERR_FORMAT, "snapshot %s: field %s: block %s: %s", st->base, field, label,
                        nf->layout.why);
    if (column < 0 && nf->layout.ncomp > 1)
        return orr_fail(err, ORR_ERR_USAGE,
                        "snapshot %s: field %s: block %s holds %d values per particle: name one as %s[k], k from 0",
                        st->base, field, label, nf->layout.ncomp, label);
    if (column >= nf->layout.ncomp)
        return orr_fail(err, ORR_ERR_USAGE,
                        "snapshot %s: field %s: block %s holds %d value%s per particle: no column %d", st->base,
                        field, label, nf->layout.ncomp, nf->layout.ncomp == 1 ? "" : "s", column);
    if (src->info.nextra >= ORR_MAX_EXTRA_FIELDS)
        return orr_fail(err, ORR_ERR_USAGE, "snapshot %s: field %s: at most %d fields at once", st->base, field,
                        ORR_MAX_EXTRA_FIELDS);
    nf->column = column < 0 ? 0 : column;
    nf->slot = src->info.nextra;
    snprintf(src->info.extra_names[src->info.nextra++], ORR_FIELD_NAME_MAX, "%s", field);
    st->nnamed++;
    return ORR_OK;
}

/* The fields the caller names that are not standard ones come from named
 * blocks. A caller naming no fields (all of them) gets the standard ones
 * only; `orrery info` lists the named blocks (describe_named). */
static orr_status choose_named(orr_source *src, gadget_state *st, const orr_source_options *opt, orr_error *err)
{
    st->nnamed = 0;
    for (int i = 0; opt && opt->fields && i < opt->nfields; i++) {
        const char *field = opt->fields[i];
        int seen = standard_field(field);
        for (int j = 0; j < i && !seen; j++)
            seen = strcmp(opt->fields[j], field) == 0;
        orr_status s = seen ? ORR_OK : add_named(src, st, field, err);
        if (s)
            return s;
    }
    return ORR_OK;
}

static orr_status choose_fields(orr_source *src, gadget_state *st, const orr_source_options *opt,
                                orr_error *err)
{
    static const gadget_block_kind field_block[X_COUNT] = {BLK_VEL, BLK_VEL, BLK_VEL, BLK_U, BLK_RHO, BLK_POT};
    int avail[BLK_COUNT];
    for (int k = 0; k < BLK_COUNT; k++)
        if ((avail[k] = block_available(st, (gadget_block_kind)k, err)) < 0)
            return ORR_ERR_FORMAT;
    st->has_id = avail[BLK_ID];
    st->has_h = avail[BLK_HSML];
    for (int x = 0; x < X_COUNT; x++) {
        st->slot[x] = -1;
        if (avail[field_block[x]] && orr_source_wants_field(opt, extra_field_names[x])) {
            st->slot[x] = src->info.nextra;
            snprintf(src->info.extra_names[src->info.nextra++], ORR_FIELD_NAME_MAX, "%s", extra_field_names[x]);
        }
    }
    src->info.has_id = st->has_id;
    src->info.has_h = st->has_h;
    src->info.h_support = 1.0; /* HSML is where Gadget's kernel ends */
    src->info.has_type = 1;
    return choose_named(src, st, opt, err);
}

/* Which rows of each file and type this process reads (all of the wanted
 * types' when the options ask for no share). */
static orr_status choose_share(orr_source *src, gadget_state *st, const orr_source_options *opt, orr_error *err)
{
    size_t nruns = (size_t)st->nfiles * GADGET_NTYPES;
    orr_status s = orr_share_alloc(&st->share, nruns, err);
    if (s)
        return s;
    for (int i = 0; i < st->nfiles; i++)
        for (int t = 0; t < GADGET_NTYPES; t++)
            st->share.hi[(size_t)i * GADGET_NTYPES + (size_t)t] = st->want_type[t] ? st->files[i].h.npart[t] : 0;
    s = orr_share_divide(&st->share, nruns, src, opt, err);
    st->next_index = st->share.first;
    return s;
}

static orr_status setup(orr_source *src, gadget_state *st, const char *path, const orr_source_options *opt,
                        orr_error *err)
{
    orr_status s = gadget_find_parts(path, st, err);
    if (s || (s = choose_fields(src, st, opt, err)))
        return s;
    int64_t sum[GADGET_NTYPES] = {0}, wanted = 0;
    for (int i = 0; i < st->nfiles; i++)
        for (int t = 0; t < GADGET_NTYPES; t++)
            sum[t] += st->files[i].h.npart[t];
    for (int t = 0; t < GADGET_NTYPES; t++) {
        st->want_type[t] = orr_source_wants_type(opt, t);
        if (st->want_type[t])
            wanted += sum[t];
    }
    src->info.time = st->files[0].h.time;
    gadget_describe(src, st, sum);
    if ((s = choose_share(src, st, opt, err)))
        return s;
    wanted = src->info.count;
    size_t chunk_size = opt && opt->chunk_size ? opt->chunk_size : GADGET_DEFAULT_CHUNK;
    size_t capacity = wanted < 1 ? 1 : (uint64_t)wanted < chunk_size ? (size_t)wanted : chunk_size;
    const char *names[ORR_MAX_EXTRA_FIELDS];
    for (int i = 0; i < src->info.nextra; i++)
        names[i] = src->info.extra_names[i];
    if ((s = orr_chunk_alloc(&src->chunk, capacity, st->has_h, names, src->info.nextra, err)))
        return s;
    st->raw = orr_malloc(GADGET_PIECE * 8, "Gadget read buffer", err);
    return st->raw ? ORR_OK : ORR_ERR_NOMEM;
}

int orr_gadget_probe(const unsigned char *head, size_t n)
{
    if (n < 4)
        return 0;
    for (int swap = 0; swap < 2; swap++) {
        uint32_t m = gadget_u32(head, swap);
        if (m == GADGET_HEADER_BYTES)
            return n < 264 || gadget_u32(head + 260, swap) == GADGET_HEADER_BYTES;
        if (m == 8)
            return n >= 8 && memcmp(head + 4, "HEAD", 4) == 0;
    }
    return 0;
}

orr_status orr_gadget_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                  orr_error *err)
{
    *out = NULL;
    orr_source *src = orr_source_new("gadget", path, &gadget_ops, sizeof(gadget_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    gadget_state *st = src->state;
    st->fp_file = -1;
    orr_status s = setup(src, st, path, opt, err);
    if (s) {
        orr_source_close(src);
        return s;
    }
    *out = src;
    return ORR_OK;
}
