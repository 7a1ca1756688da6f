#include "source/sequence.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ---- names ---- */

const orr_named orr_interpolation_names[] = {
    {"auto", ORR_INTERP_AUTO}, {"linear", ORR_INTERP_LINEAR}, {"hermite", ORR_INTERP_HERMITE}, {NULL, 0}};

const char *orr_interpolation_name(orr_interpolation k) { return orr_named_name(orr_interpolation_names, (int)k); }

ORR_NAMED_PARSER(orr_interpolation_from_name, orr_interpolation, orr_interpolation_names)

/* ---- file name patterns ---- */

/* Where a pattern's one conversion is: pattern[start, end) is "%03d". */
typedef struct pattern_spec {
    size_t start, end;
} pattern_spec;

static orr_status parse_pattern(const char *pattern, pattern_spec *spec, orr_error *err)
{
    int found = 0;
    for (size_t i = 0; pattern[i]; i++) {
        if (pattern[i] != '%')
            continue;
        if (pattern[i + 1] == '%') {
            i++;
            continue;
        }
        size_t j = i + 1;
        j += strspn(pattern + j, "0-+ #");
        j += strspn(pattern + j, "0123456789");
        if (pattern[j] == '.') {
            j++;
            j += strspn(pattern + j, "0123456789");
        }
        if (!pattern[j] || !strchr("diuxXo", pattern[j]))
            return orr_fail(err, ORR_ERR_USAGE,
                            "sequence pattern '%s': '%.*s' is not an integer conversion (use e.g. %%03d; "
                            "write a literal %% as %%%%)",
                            pattern, (int)(j - i + (pattern[j] != '\0')), pattern + i);
        if (found++)
            return orr_fail(err, ORR_ERR_USAGE,
                            "sequence pattern '%s': has more than one integer conversion; it needs exactly one",
                            pattern);
        spec->start = i;
        spec->end = j + 1;
        i = j;
    }
    if (!found)
        return orr_fail(err, ORR_ERR_USAGE,
                        "sequence pattern '%s': has no integer conversion (such as %%03d) for the snapshot number",
                        pattern);
    return ORR_OK;
}

orr_status orr_sequence_pattern_check(const char *pattern, orr_error *err)
{
    pattern_spec spec;
    return parse_pattern(pattern, &spec, err);
}

/* Appends text[0, n) to out with "%%" read as '%'. */
static void append_literal(char *out, size_t size, size_t *len, const char *text, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (text[i] == '%' && i + 1 < n && text[i + 1] == '%')
            i++;
        if (*len + 1 < size)
            out[*len] = text[i];
        (*len)++;
    }
}

orr_status orr_sequence_pattern_path(const char *pattern, long number, char *out, size_t size, orr_error *err)
{
    pattern_spec spec;
    orr_status st = parse_pattern(pattern, &spec, err);
    if (st)
        return st;
    /* The conversion alone, with an 'l' so that it takes a long: "%03ld". */
    char conv[64], digits[128];
    size_t clen = spec.end - spec.start;
    if (clen + 2 > sizeof conv)
        return orr_fail(err, ORR_ERR_USAGE, "sequence pattern '%s': its conversion is too long", pattern);
    memcpy(conv, pattern + spec.start, clen - 1);
    conv[clen - 1] = 'l';
    conv[clen] = pattern[spec.end - 1];
    conv[clen + 1] = '\0';
    int nd = snprintf(digits, sizeof digits, conv, number);
    if (nd < 0 || (size_t)nd >= sizeof digits)
        return orr_fail(err, ORR_ERR_USAGE, "sequence pattern '%s': number %ld is too wide", pattern, number);
    size_t len = 0;
    append_literal(out, size, &len, pattern, spec.start);
    append_literal(out, size, &len, digits, (size_t)nd);
    append_literal(out, size, &len, pattern + spec.end, strlen(pattern + spec.end));
    if (len >= size)
        return orr_fail(err, ORR_ERR_USAGE, "sequence pattern '%s': the path for %ld is too long", pattern, number);
    out[len] = '\0';
    return ORR_OK;
}

/* ---- the sequence ---- */

#define NVEL 3
static const char *const VEL_NAMES[NVEL] = {"vx", "vy", "vz"};

/* One snapshot held in memory, sorted by id. */
typedef struct snapshot {
    int index; /* which file of the sequence; -1: the slot is empty */
    size_t n;
    float *x, *y, *z, *mass, *h; /* h NULL when the file has none */
    uint64_t *id;
    uint8_t *type;
    int has_id, has_type;
    double h_support;
    int nextra;
    char names[ORR_MAX_EXTRA_FIELDS][ORR_FIELD_NAME_MAX];
    float *extra[ORR_MAX_EXTRA_FIELDS];
    int vel[NVEL]; /* indices of vx, vy, vz among the extras; -1 when absent */
} snapshot;

struct orr_sequence {
    int n;
    char **paths;
    double *times;
    orr_sequence_options opt;
    int nfields;                  /* fields asked of the reader (caller's plus velocities), -1: all */
    const char *fields[ORR_MAX_EXTRA_FIELDS + NVEL];
    char field_store[ORR_MAX_EXTRA_FIELDS + NVEL][ORR_FIELD_NAME_MAX];
    int ncaller;                  /* the caller's own fields: the first ncaller of them; -1: all */
    size_t bytes_per_particle;
    snapshot slot[2];
    unsigned long generation;     /* bumped by every orr_sequence_source_at */
    orr_sequence_stats stats;
};

int orr_sequence_count(const orr_sequence *seq) { return seq->n; }
const char *orr_sequence_path(const orr_sequence *seq, int k) { return seq->paths[k]; }
double orr_sequence_time(const orr_sequence *seq, int k) { return seq->times[k]; }
size_t orr_sequence_bytes_per_particle(const orr_sequence *seq) { return seq->bytes_per_particle; }
orr_sequence_stats orr_sequence_get_stats(const orr_sequence *seq) { return seq->stats; }

void orr_sequence_time_range(const orr_sequence *seq, double *t0, double *t1)
{
    *t0 = seq->times[0];
    *t1 = seq->times[seq->n - 1];
}

static void snapshot_free(snapshot *sn)
{
    free(sn->x);
    free(sn->y);
    free(sn->z);
    free(sn->mass);
    free(sn->h);
    free(sn->id);
    free(sn->type);
    for (int e = 0; e < sn->nextra; e++)
        free(sn->extra[e]);
    memset(sn, 0, sizeof *sn);
    sn->index = -1;
}

void orr_sequence_close(orr_sequence *seq)
{
    if (!seq)
        return;
    for (int i = 0; i < 2; i++)
        snapshot_free(&seq->slot[i]);
    for (int k = 0; seq->paths && k < seq->n; k++)
        free(seq->paths[k]);
    free(seq->paths);
    free(seq->times);
    free(seq);
}

static int wants_velocities(const orr_sequence *seq) { return seq->opt.interpolation != ORR_INTERP_LINEAR; }

/* The fields to ask the readers for: the caller's, plus vx, vy, vz when
 * hermite may be used. NULL (every field) stays NULL. */
static orr_status copy_fields(orr_sequence *seq, const orr_source_options *src, orr_error *err)
{
    seq->ncaller = seq->nfields = -1;
    if (!src->fields)
        return ORR_OK;
    if (src->nfields < 0 || src->nfields > ORR_MAX_EXTRA_FIELDS)
        return orr_fail(err, ORR_ERR_USAGE, "sequence: %d extra fields asked for (at most %d)", src->nfields,
                        ORR_MAX_EXTRA_FIELDS);
    int n = 0;
    for (int i = 0; i < src->nfields; i++)
        snprintf(seq->field_store[n++], ORR_FIELD_NAME_MAX, "%s", src->fields[i]);
    seq->ncaller = n;
    for (int v = 0; v < NVEL && wants_velocities(seq); v++) {
        int have = 0;
        for (int i = 0; i < n; i++)
            have |= strcmp(seq->field_store[i], VEL_NAMES[v]) == 0;
        if (!have)
            snprintf(seq->field_store[n++], ORR_FIELD_NAME_MAX, "%s", VEL_NAMES[v]);
    }
    for (int i = 0; i < n; i++)
        seq->fields[i] = seq->field_store[i];
    seq->nfields = n;
    return ORR_OK;
}

static orr_status open_file(const orr_sequence *seq, int k, orr_source **src, orr_error *err)
{
    orr_source_options o = seq->opt.source;
    o.chunk_size = (size_t)1 << 20; /* how the file is read; the sources handed out use the caller's size */
    o.fields = seq->nfields < 0 ? NULL : seq->fields;
    o.nfields = seq->nfields < 0 ? 0 : seq->nfields;
    return orr_source_open_file(seq->paths[k], &o, src, err);
}

/* Positions, mass, id, type, then h and one float per extra field. */
static size_t bytes_per_particle(const orr_source_info *info)
{
    return 3 * sizeof(float) + sizeof(float) + sizeof(uint64_t) + sizeof(uint8_t) +
           (info->has_h ? sizeof(float) : 0) + (size_t)info->nextra * sizeof(float);
}

static double gib(double bytes) { return bytes / (1024.0 * 1024.0 * 1024.0); }

/* Reads every file's header: its time, and its particle count for the
 * memory estimate. */
static orr_status read_headers(orr_sequence *seq, orr_error *err)
{
    int64_t prev_count = -1;
    for (int k = 0; k < seq->n; k++) {
        orr_source *src = NULL;
        orr_status st = open_file(seq, k, &src, err);
        if (st)
            return st;
        seq->times[k] = src->info.time;
        int64_t count = src->info.count;
        if (k == 0)
            seq->bytes_per_particle = bytes_per_particle(&src->info);
        orr_source_close(src);
        if (!isfinite(seq->times[k]))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: its time is not a finite number", seq->paths[k]);
        if (k > 0 && !(seq->times[k] > seq->times[k - 1]))
            return orr_fail(err, ORR_ERR_USAGE,
                            "sequence: snapshot times must strictly increase, but %s has time %.17g and the "
                            "next, %s, has time %.17g",
                            seq->paths[k - 1], seq->times[k - 1], seq->paths[k], seq->times[k]);
        double pair = (double)(prev_count + count) * (double)seq->bytes_per_particle;
        if (k > 0 && prev_count >= 0 && count >= 0 && pair > seq->opt.max_memory)
            return orr_fail(err, ORR_ERR_USAGE,
                            "sequence: %s and %s together need about %.2f GiB in memory (%zu bytes per "
                            "particle), more than input.sequence.max_memory (%.2f GiB)",
                            seq->paths[k - 1], seq->paths[k], gib(pair), seq->bytes_per_particle,
                            gib(seq->opt.max_memory));
        prev_count = count;
    }
    return ORR_OK;
}

orr_status orr_sequence_open(const char *const *paths, int npaths, const orr_sequence_options *opt,
                             orr_sequence **out, orr_error *err)
{
    *out = NULL;
    if (npaths < 2)
        return orr_fail(err, ORR_ERR_USAGE, "sequence: needs at least 2 snapshots, got %d", npaths);
    if (!(opt->box >= 0 && isfinite(opt->box)))
        return orr_fail(err, ORR_ERR_USAGE, "sequence: the periodic box's side is %g; it must be a positive number "
                        "(or 0: not periodic)", opt->box);
    orr_sequence *seq = orr_calloc(1, sizeof *seq, "a snapshot sequence", err);
    if (!seq)
        return ORR_ERR_NOMEM;
    seq->slot[0].index = seq->slot[1].index = -1;
    seq->opt = *opt;
    if (!(seq->opt.max_memory > 0))
        seq->opt.max_memory = ORR_SEQUENCE_DEFAULT_MAX_MEMORY;
    if (seq->opt.source.chunk_size == 0)
        seq->opt.source.chunk_size = (size_t)1 << 20;
    orr_status st = copy_fields(seq, &opt->source, err);
    seq->paths = st ? NULL : orr_calloc((size_t)npaths, sizeof *seq->paths, "the sequence's paths", err);
    seq->times = seq->paths ? orr_calloc((size_t)npaths, sizeof *seq->times, "the sequence's times", err) : NULL;
    if (!st && !seq->times)
        st = ORR_ERR_NOMEM;
    for (int k = 0; !st && k < npaths; k++) {
        seq->paths[k] = strdup(paths[k]);
        seq->n = k + 1;
        if (!seq->paths[k])
            st = orr_fail(err, ORR_ERR_NOMEM, "out of memory for the sequence's paths");
    }
    if (!st)
        st = read_headers(seq, err);
    if (st) {
        orr_sequence_close(seq);
        return st;
    }
    *out = seq;
    return ORR_OK;
}

orr_status orr_sequence_open_pattern(const char *pattern, long first, long last, long step,
                                     const orr_sequence_options *opt, orr_sequence **out, orr_error *err)
{
    *out = NULL;
    if (first < 0 || step < 1 || last < first)
        return orr_fail(err, ORR_ERR_USAGE,
                        "sequence pattern '%s': needs 0 <= first <= last and step >= 1 (got first %ld, last %ld, "
                        "step %ld)",
                        pattern, first, last, step);
    long count = (last - first) / step + 1;
    if (count > 1000000)
        return orr_fail(err, ORR_ERR_USAGE, "sequence pattern '%s': %ld files are too many (at most 1000000)",
                        pattern, count);
    char **paths = orr_calloc((size_t)count, sizeof *paths, "the sequence's paths", err);
    if (!paths)
        return ORR_ERR_NOMEM;
    orr_status st = ORR_OK;
    char buf[ORR_PATH_MAX];
    long made = 0;
    for (; !st && made < count; made++) {
        long number = first + made * step;
        st = orr_sequence_pattern_path(pattern, number, buf, sizeof buf, err);
        struct stat sb;
        if (!st && stat(buf, &sb) != 0)
            st = orr_fail(err, ORR_ERR_IO, "sequence pattern '%s': snapshot %ld, %s: cannot open: %s", pattern,
                          number, buf, strerror(errno));
        if (!st && !(paths[made] = strdup(buf)))
            st = orr_fail(err, ORR_ERR_NOMEM, "out of memory for the sequence's paths");
    }
    if (!st)
        st = orr_sequence_open((const char *const *)paths, (int)count, opt, out, err);
    for (long k = 0; k < count; k++)
        free(paths[k]);
    free(paths);
    return st;
}

/* ---- loading a snapshot ---- */

static orr_status snapshot_reserve(snapshot *sn, size_t cap, orr_error *err)
{
    float **floats[] = {&sn->x, &sn->y, &sn->z, &sn->mass};
    for (size_t i = 0; i < sizeof floats / sizeof floats[0]; i++) {
        float *p = realloc(*floats[i], cap * sizeof(float));
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
        *floats[i] = p;
    }
    if (sn->h) {
        float *p = realloc(sn->h, cap * sizeof(float));
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
        sn->h = p;
    }
    for (int e = 0; e < sn->nextra; e++) {
        float *p = realloc(sn->extra[e], cap * sizeof(float));
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
        sn->extra[e] = p;
    }
    uint64_t *id = realloc(sn->id, cap * sizeof *id);
    if (id)
        sn->id = id;
    uint8_t *type = id ? realloc(sn->type, cap) : NULL;
    if (!type)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
    sn->type = type;
    return ORR_OK;
}

static void snapshot_describe(snapshot *sn, const orr_source_info *info)
{
    sn->has_id = info->has_id;
    sn->has_type = info->has_type;
    sn->h_support = info->h_support;
    sn->nextra = info->nextra;
    for (int v = 0; v < NVEL; v++)
        sn->vel[v] = -1;
    for (int e = 0; e < info->nextra; e++) {
        snprintf(sn->names[e], ORR_FIELD_NAME_MAX, "%s", info->extra_names[e]);
        for (int v = 0; v < NVEL; v++)
            if (strcmp(sn->names[e], VEL_NAMES[v]) == 0)
                sn->vel[v] = e;
    }
}

/* Appends the wanted particles of chunk c. */
static orr_status snapshot_append(snapshot *sn, const orr_chunk *c, const orr_source_options *opt, size_t *cap,
                                  orr_error *err)
{
    const float *fields[ORR_MAX_EXTRA_FIELDS];
    for (int e = 0; e < sn->nextra; e++)
        fields[e] = orr_chunk_field(c, sn->names[e]);
    for (size_t i = 0; i < c->n; i++) {
        if (!orr_source_wants_type(opt, c->type[i]))
            continue;
        if (sn->n == *cap) {
            *cap = *cap ? 2 * *cap : 1024;
            orr_status st = snapshot_reserve(sn, *cap, err);
            if (st)
                return st;
        }
        size_t j = sn->n++;
        sn->x[j] = c->x[i];
        sn->y[j] = c->y[i];
        sn->z[j] = c->z[i];
        sn->mass[j] = c->mass[i];
        sn->id[j] = c->id[i];
        sn->type[j] = c->type[i];
        if (sn->h)
            sn->h[j] = c->h ? c->h[i] : 0.0f;
        for (int e = 0; e < sn->nextra; e++)
            sn->extra[e][j] = fields[e] ? fields[e][i] : 0.0f;
    }
    return ORR_OK;
}

typedef struct id_key {
    uint64_t id;
    size_t index;
} id_key;

#define RADIX_BITS 11
#define RADIX_SIZE (1u << RADIX_BITS)

/* Sorts keys by id: a least-significant-digit radix sort, 11 bits a pass,
 * which is stable (so duplicate ids end up side by side) and several times
 * faster than qsort for millions of keys. Digits that are the same in every
 * id (the high bits of ids below 2^32, say) take no pass. tmp holds n keys.
 * Returns the array that holds the result (keys or tmp). */
static id_key *radix_sort(id_key *keys, id_key *tmp, size_t n)
{
    uint64_t any = 0, every = ~(uint64_t)0;
    for (size_t i = 0; i < n; i++) {
        any |= keys[i].id;
        every &= keys[i].id;
    }
    const uint64_t varying = any ^ every;
    size_t count[RADIX_SIZE];
    for (unsigned shift = 0; shift < 64; shift += RADIX_BITS) {
        if (((varying >> shift) & (RADIX_SIZE - 1)) == 0)
            continue;
        memset(count, 0, sizeof count);
        for (size_t i = 0; i < n; i++)
            count[(keys[i].id >> shift) & (RADIX_SIZE - 1)]++;
        size_t sum = 0;
        for (size_t d = 0; d < RADIX_SIZE; d++) {
            size_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            tmp[count[(keys[i].id >> shift) & (RADIX_SIZE - 1)]++] = keys[i];
        id_key *swap = keys;
        keys = tmp;
        tmp = swap;
    }
    return keys;
}

/* Reorders a float array by keys (scratch holds n floats). */
static void permute_floats(float *v, float *scratch, const id_key *keys, size_t n)
{
    for (size_t i = 0; i < n; i++)
        scratch[i] = v[keys[i].index];
    memcpy(v, scratch, n * sizeof *v);
}

/* Sorts the snapshot by id (two arrays of 16-byte keys while it runs, the
 * second reused as scratch for reordering the fields), and rejects
 * duplicate ids. */
static orr_status snapshot_sort(snapshot *sn, const char *path, orr_error *err)
{
    size_t n = sn->n;
    int sorted = 1;
    for (size_t i = 1; i < n && sorted; i++)
        sorted = sn->id[i - 1] < sn->id[i];
    if (sorted)
        return ORR_OK; /* snapshots are often written in id order */
    id_key *buf = orr_malloc(2 * n * sizeof *buf, "sorting a snapshot by id", err);
    if (!buf)
        return ORR_ERR_NOMEM;
    for (size_t i = 0; i < n; i++)
        buf[i] = (id_key){sn->id[i], i};
    id_key *keys = radix_sort(buf, buf + n, n);
    void *scratch = keys == buf ? (void *)(buf + n) : (void *)buf;
    orr_status st = ORR_OK;
    for (size_t i = 1; i < n && !st; i++)
        if (keys[i].id == keys[i - 1].id)
            st = orr_fail(err, ORR_ERR_DATA, "%s: particle id %llu appears more than once; a sequence matches "
                          "particles by id, so ids must be unique", path, (unsigned long long)keys[i].id);
    if (!st) {
        float *arrays[4 + 1 + ORR_MAX_EXTRA_FIELDS] = {sn->x, sn->y, sn->z, sn->mass, sn->h};
        for (int e = 0; e < sn->nextra; e++)
            arrays[5 + e] = sn->extra[e];
        for (int a = 0; a < 5 + sn->nextra; a++)
            if (arrays[a])
                permute_floats(arrays[a], scratch, keys, n);
        uint8_t *ts = scratch;
        for (size_t i = 0; i < n; i++)
            ts[i] = sn->type[keys[i].index];
        memcpy(sn->type, ts, n);
        for (size_t i = 0; i < n; i++)
            sn->id[i] = keys[i].id;
    }
    free(buf);
    return st;
}

/* Bytes a loaded snapshot holds. */
static double snapshot_bytes(const snapshot *sn)
{
    return (double)sn->n * (double)(4 * sizeof(float) + sizeof(uint64_t) + 1 +
                                    (sn->h ? sizeof(float) : 0) + (size_t)sn->nextra * sizeof(float));
}

static orr_status check_memory(const orr_sequence *seq, int k, const snapshot *other, const orr_source_info *info,
                               orr_error *err)
{
    if (info->count < 0)
        return ORR_OK; /* unknown until read: checked after reading */
    double mine = (double)info->count * (double)bytes_per_particle(info);
    double theirs = other->index >= 0 ? snapshot_bytes(other) : 0;
    if (mine + theirs <= seq->opt.max_memory)
        return ORR_OK;
    return orr_fail(err, ORR_ERR_USAGE,
                    "sequence: %s needs about %.2f GiB in memory next to the %.2f GiB already held, more than "
                    "input.sequence.max_memory (%.2f GiB)",
                    seq->paths[k], gib(mine), gib(theirs), gib(seq->opt.max_memory));
}

static orr_status load_snapshot(orr_sequence *seq, int k, snapshot *sn, const snapshot *other, orr_error *err)
{
    snapshot_free(sn);
    orr_source *src = NULL;
    orr_status st = open_file(seq, k, &src, err);
    if (!st)
        st = check_memory(seq, k, other, &src->info, err);
    size_t cap = 0;
    if (!st) {
        snapshot_describe(sn, &src->info);
        if (src->info.has_h && !(sn->h = malloc(sizeof(float))))
            st = orr_fail(err, ORR_ERR_NOMEM, "out of memory");
        cap = src->info.count > 0 ? (size_t)src->info.count : 0;
        if (!st && cap)
            st = snapshot_reserve(sn, cap, err);
    }
    while (!st) {
        const orr_chunk *c;
        st = orr_source_next(src, &c, err);
        if (st || c->n == 0)
            break;
        st = snapshot_append(sn, c, &seq->opt.source, &cap, err);
    }
    orr_source_close(src);
    if (!st && snapshot_bytes(sn) + (other->index >= 0 ? snapshot_bytes(other) : 0) > seq->opt.max_memory)
        st = orr_fail(err, ORR_ERR_USAGE, "sequence: %s takes %.2f GiB in memory, more than input.sequence.max_memory "
                      "(%.2f GiB) allows beside the snapshot already held", seq->paths[k], gib(snapshot_bytes(sn)),
                      gib(seq->opt.max_memory));
    if (!st)
        st = snapshot_sort(sn, seq->paths[k], err);
    if (st) {
        snapshot_free(sn);
        return st;
    }
    sn->index = k;
    seq->stats.loads++;
    return ORR_OK;
}

/* Makes snapshots a and b (b = -1: none) resident, reading only those not
 * held already and evicting only what is in the way, so that time stepping
 * forward reads every snapshot once. */
static orr_status require(orr_sequence *seq, int a, int b, snapshot **sa, snapshot **sb, orr_error *err)
{
    int want[2] = {a, b};
    snapshot *got[2] = {NULL, NULL};
    for (int w = 0; w < 2; w++)
        for (int i = 0; i < 2; i++)
            if (want[w] >= 0 && seq->slot[i].index == want[w])
                got[w] = &seq->slot[i];
    for (int w = 0; w < 2; w++) {
        if (want[w] < 0 || got[w])
            continue;
        /* A slot that holds neither wanted snapshot. */
        snapshot *free_slot = NULL;
        for (int i = 0; i < 2 && !free_slot; i++)
            if (&seq->slot[i] != got[0] && &seq->slot[i] != got[1])
                free_slot = &seq->slot[i];
        snapshot *other = free_slot == &seq->slot[0] ? &seq->slot[1] : &seq->slot[0];
        if (other != got[0] && other != got[1])
            snapshot_free(other); /* not needed either: free it before reading, to keep the peak low */
        orr_status st = load_snapshot(seq, want[w], free_slot, other, err);
        if (st)
            return st;
        got[w] = free_slot;
    }
    *sa = got[0];
    *sb = got[1];
    return ORR_OK;
}

/* ---- the source handed out ---- */

typedef struct seq_cursor {
    orr_sequence *seq;
    unsigned long generation;
    const snapshot *a, *b; /* b NULL: snapshot a exactly */
    double dt, s;
    int hermite;
    size_t ia, ib;         /* where the walk over a and b (both in id order) is */
    uint64_t emitted;
    int nyield;
    int yield[ORR_MAX_EXTRA_FIELDS]; /* indices into a's extras, in the chunk's order */
} seq_cursor;

static orr_status cursor_check(const orr_source *src, orr_error *err)
{
    const seq_cursor *cur = src->state;
    if (cur->generation != cur->seq->generation)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: this source is stale: the sequence has since been moved to another time", src->info.path);
    return ORR_OK;
}

/* The standard cubic Hermite basis on [0, 1]. */
static void hermite_basis(double s, double h[4])
{
    double s2 = s * s, s3 = s2 * s;
    h[0] = 2 * s3 - 3 * s2 + 1; /* h00: x0 */
    h[1] = s3 - 2 * s2 + s;     /* h10: dt v0 */
    h[2] = -2 * s3 + 3 * s2;    /* h01: x1 */
    h[3] = s3 - s2;             /* h11: dt v1 */
}

/* The later position x1 of a particle at x0 before, as seen from x0: in a
 * periodic box (box > 0) its nearest image, so that a particle that wrapped
 * through a face is interpolated through that face. */
static double later_image(double x0, double x1, double box)
{
    return box > 0 ? x0 + (x1 - x0) - box * round((x1 - x0) / box) : x1;
}

/* An interpolated coordinate back into [0, box) (box > 0), where the
 * snapshots keep their particles, and to float. */
static float wrap_coordinate(double x, double box)
{
    if (!(box > 0))
        return (float)x;
    float f = (float)(x - box * floor(x / box));
    return f < (float)box ? f : 0.0f; /* x a hair below a multiple of box rounds up to it */
}

/* Writes particle (i of a, j of b) into slot k of the chunk. */
static void emit_pair(const seq_cursor *cur, orr_chunk *c, size_t k, size_t i, size_t j)
{
    const snapshot *a = cur->a, *b = cur->b;
    const float *pa[3] = {a->x, a->y, a->z}, *pb[3] = {b->x, b->y, b->z};
    float *out[3] = {c->x, c->y, c->z};
    const double s = cur->s, box = cur->seq->opt.box;
    double h[4];
    if (cur->hermite)
        hermite_basis(s, h);
    for (int d = 0; d < 3; d++) {
        const double x0 = pa[d][i], x1 = later_image(x0, pb[d][j], box);
        double x;
        if (cur->hermite)
            x = h[0] * x0 + h[1] * cur->dt * a->extra[a->vel[d]][i] + h[2] * x1 +
                h[3] * cur->dt * b->extra[b->vel[d]][j];
        else
            x = (1 - s) * x0 + s * x1;
        out[d][k] = wrap_coordinate(x, box);
    }
    if (c->h)
        c->h[k] = (float)((1 - s) * a->h[i] + s * b->h[j]);
}

static void emit_common(const seq_cursor *cur, orr_chunk *c, size_t k, size_t i)
{
    const snapshot *a = cur->a;
    c->mass[k] = a->mass[i];
    c->id[k] = a->id[i];
    c->type[k] = a->type[i];
    for (int e = 0; e < cur->nyield; e++)
        c->extra[e].data[k] = a->extra[cur->yield[e]][i];
}

static orr_status seq_next(orr_source *src, orr_error *err)
{
    orr_status st = cursor_check(src, err);
    if (st)
        return st;
    seq_cursor *cur = src->state;
    orr_chunk *c = &src->chunk;
    const snapshot *a = cur->a, *b = cur->b;
    c->first_index = cur->emitted;
    size_t k = 0;
    while (k < c->capacity && cur->ia < a->n) {
        size_t i = cur->ia;
        if (!b) {
            c->x[k] = a->x[i];
            c->y[k] = a->y[i];
            c->z[k] = a->z[i];
            if (c->h)
                c->h[k] = a->h[i];
            emit_common(cur, c, k++, i);
            cur->ia++;
            continue;
        }
        if (cur->ib >= b->n)
            break;
        size_t j = cur->ib;
        if (a->id[i] < b->id[j]) {
            cur->ia++;
        } else if (a->id[i] > b->id[j]) {
            cur->ib++;
        } else {
            emit_pair(cur, c, k, i, j);
            emit_common(cur, c, k++, i);
            cur->ia++;
            cur->ib++;
        }
    }
    c->n = k;
    cur->emitted += k;
    return ORR_OK;
}

static orr_status seq_rewind(orr_source *src, orr_error *err)
{
    orr_status st = cursor_check(src, err);
    if (st)
        return st;
    seq_cursor *cur = src->state;
    cur->ia = cur->ib = 0;
    cur->emitted = 0;
    return ORR_OK;
}

static void seq_close(orr_source *src)
{
    /* Only the cursor: the snapshots belong to the sequence, which keeps
     * them for the next frame. orr_source_close frees the chunk. */
    free(src->state);
    src->state = NULL;
}

static const orr_source_ops SEQ_OPS = {.next = seq_next, .rewind = seq_rewind, .close = seq_close};

static int has_velocities(const snapshot *sn) { return sn->vel[0] >= 0 && sn->vel[1] >= 0 && sn->vel[2] >= 0; }

/* Whether the pair [a, b] is interpolated with Hermite; an error when the
 * scene asks for hermite and a file has no velocities. */
static orr_status choose_hermite(const orr_sequence *seq, const snapshot *a, const snapshot *b, int *hermite,
                                 orr_error *err)
{
    *hermite = 0;
    if (seq->opt.interpolation == ORR_INTERP_LINEAR)
        return ORR_OK;
    const snapshot *lacking = !has_velocities(a) ? a : !has_velocities(b) ? b : NULL;
    if (lacking && seq->opt.interpolation == ORR_INTERP_HERMITE)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: has no velocities (vx, vy, vz), which interpolation: hermite needs; use linear",
                        seq->paths[lacking->index]);
    *hermite = lacking == NULL;
    return ORR_OK;
}

/* Counts the particles of a and b with and without a partner. */
static void count_matches(const snapshot *a, const snapshot *b, orr_sequence_stats *stats)
{
    size_t i = 0, j = 0;
    int64_t both = 0;
    while (i < a->n && j < b->n) {
        if (a->id[i] < b->id[j])
            i++;
        else if (a->id[i] > b->id[j])
            j++;
        else {
            both++;
            i++;
            j++;
        }
    }
    stats->matched = both;
    stats->only_earlier = (int64_t)a->n - both;
    stats->only_later = (int64_t)b->n - both;
}

/* Which of a's extra fields the caller gets. */
static void choose_yield(const orr_sequence *seq, seq_cursor *cur)
{
    cur->nyield = 0;
    for (int e = 0; e < cur->a->nextra; e++) {
        int wanted = seq->ncaller < 0;
        for (int f = 0; f < seq->ncaller && !wanted; f++)
            wanted = strcmp(seq->field_store[f], cur->a->names[e]) == 0;
        if (wanted)
            cur->yield[cur->nyield++] = e;
    }
}

/* The last k with times[k] <= t (t within the range). */
static int bracket(const orr_sequence *seq, double t)
{
    int lo = 0, hi = seq->n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (seq->times[mid] <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static orr_status make_source(orr_sequence *seq, seq_cursor *proto, double time, orr_source **out, orr_error *err)
{
    char what[ORR_PATH_MAX];
    snprintf(what, sizeof what, "sequence %.1000s ... %.1000s at time %.17g", seq->paths[0], seq->paths[seq->n - 1],
             time);
    orr_source *src = orr_source_new("sequence", what, &SEQ_OPS, sizeof(seq_cursor), err);
    if (!src)
        return ORR_ERR_NOMEM;
    seq_cursor *cur = src->state;
    *cur = *proto;
    choose_yield(seq, cur);
    const snapshot *a = cur->a, *b = cur->b;
    orr_source_info *info = &src->info;
    info->count = b ? seq->stats.matched : (int64_t)a->n;
    info->time = time;
    info->has_h = a->h && (!b || b->h);
    info->has_id = a->has_id;
    info->has_type = a->has_type;
    info->h_support = a->h_support;
    info->nextra = cur->nyield;
    const char *names[ORR_MAX_EXTRA_FIELDS];
    for (int e = 0; e < cur->nyield; e++) {
        snprintf(info->extra_names[e], ORR_FIELD_NAME_MAX, "%s", a->names[cur->yield[e]]);
        names[e] = info->extra_names[e];
    }
    orr_source_add_header(info, "snapshots", "%d, times %.17g to %.17g", seq->n, seq->times[0], seq->times[seq->n - 1]);
    if (seq->opt.box > 0)
        orr_source_add_header(info, "BoxSize", "%.17g", seq->opt.box);
    orr_source_add_header(info, "earlier", "%s", seq->paths[a->index]);
    if (b) {
        orr_source_add_header(info, "later", "%s", seq->paths[b->index]);
        orr_source_add_header(info, "interpolation", "%s", cur->hermite ? "hermite" : "linear");
        orr_source_add_header(info, "dropped", "%lld only in the earlier, %lld only in the later",
                              (long long)seq->stats.only_earlier, (long long)seq->stats.only_later);
    }
    /* No larger than the particles there are: a frame allocates its chunk anew. */
    size_t capacity = seq->opt.source.chunk_size;
    if (info->count >= 0 && (uint64_t)info->count < capacity)
        capacity = info->count > 0 ? (size_t)info->count : 1;
    orr_status st = orr_chunk_alloc(&src->chunk, capacity, info->has_h, names, cur->nyield, err);
    if (st) {
        orr_source_close(src);
        return st;
    }
    *out = src;
    return ORR_OK;
}

orr_status orr_sequence_source_at(orr_sequence *seq, double time, orr_source **out, orr_error *err)
{
    *out = NULL;
    seq->generation++; /* sources handed out earlier may read evicted snapshots: retire them */
    double t0 = seq->times[0], t1 = seq->times[seq->n - 1];
    if (!(time >= t0 && time <= t1))
        return orr_fail(err, ORR_ERR_USAGE, "sequence: time %.17g is outside the snapshots' times, %.17g (%s) to %.17g (%s)",
                        time, t0, seq->paths[0], t1, seq->paths[seq->n - 1]);
    int k = bracket(seq, time);
    seq_cursor proto;
    memset(&proto, 0, sizeof proto);
    proto.seq = seq;
    proto.generation = seq->generation;
    snapshot *a = NULL, *b = NULL;
    orr_status st;
    if (seq->times[k] == time) {
        st = require(seq, k, -1, &a, &b, err);
        if (st)
            return st;
        seq->stats.matched = (int64_t)a->n;
        seq->stats.only_earlier = seq->stats.only_later = 0;
        seq->stats.hermite = 0;
    } else {
        st = require(seq, k, k + 1, &a, &b, err);
        if (!st)
            st = choose_hermite(seq, a, b, &proto.hermite, err);
        if (st)
            return st;
        count_matches(a, b, &seq->stats);
        seq->stats.hermite = proto.hermite;
        proto.dt = seq->times[k + 1] - seq->times[k];
        proto.s = (time - seq->times[k]) / proto.dt;
    }
    proto.a = a;
    proto.b = b;
    return make_source(seq, &proto, time, out, err);
}
