#include "source/sequence.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "source/sequence_internal.h"

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

void orr_sequence_close(orr_sequence *seq)
{
    if (!seq)
        return;
    for (int i = 0; i < 2; i++)
        orr_seq_snapshot_free(&seq->slot[i]);
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

orr_status orr_seq_open_file(const orr_sequence *seq, int k, orr_source **src, orr_error *err)
{
    orr_source_options o = seq->opt.source;
    o.chunk_size = (size_t)1 << 20; /* how the file is read; the sources handed out use the caller's size */
    o.fields = seq->nfields < 0 ? NULL : seq->fields;
    o.nfields = seq->nfields < 0 ? 0 : seq->nfields;
    return orr_source_open_file(seq->paths[k], &o, src, err);
}

/* Positions, mass, id, type, then h and one float per extra field. */
size_t orr_seq_bytes_per_particle(const orr_source_info *info)
{
    return 3 * sizeof(float) + sizeof(float) + sizeof(uint64_t) + sizeof(uint8_t) +
           (info->has_h ? sizeof(float) : 0) + (size_t)info->nextra * sizeof(float);
}

/* Reads every file's header: its time, and its particle count for the
 * memory estimate. */
static orr_status read_headers(orr_sequence *seq, orr_error *err)
{
    int64_t prev_count = -1;
    for (int k = 0; k < seq->n; k++) {
        orr_source *src = NULL;
        orr_status st = orr_seq_open_file(seq, k, &src, err);
        if (st)
            return st;
        seq->times[k] = src->info.time;
        int64_t count = src->info.count;
        if (k == 0)
            seq->bytes_per_particle = orr_seq_bytes_per_particle(&src->info);
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
