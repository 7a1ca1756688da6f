#include "source/readers/text_reader.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/numbers.h"
#include "source/readers/mass_policy.h"

/* What each column of the table feeds. */
typedef enum { COL_X, COL_Y, COL_Z, COL_MASS, COL_H, COL_ID, COL_TYPE, COL_EXTRA } column_role;

#define TEXT_MAX_COLUMNS (7 + ORR_MAX_EXTRA_FIELDS)

typedef struct text_state {
    FILE *fp;
    long data_offset;   /* file offset of the first line after the header */
    long header_line;   /* line number of the header */
    long line;          /* line number of the last line read */
    uint64_t next_index;
    int ncolumns;
    column_role role[TEXT_MAX_COLUMNS];
    int extra_slot[TEXT_MAX_COLUMNS];
    char names[TEXT_MAX_COLUMNS][ORR_FIELD_NAME_MAX];
    int has_mass;
    char *buf;
    size_t bufsize;
    /* A stream (standard input, a FIFO) is read once: format detection
     * already took its first bytes, kept here to be read first. */
    int is_stream, owns_fp;
    unsigned char *peek;
    size_t peek_len, peek_pos;
} text_state;

static int is_separator(char c)
{
    return c == ',' || isspace((unsigned char)c);
}

/* Splits line in place into at most max tokens; returns the count, or
 * max + 1 when there are more. */
static int split_fields(char *line, char **tokens, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        while (*p && is_separator(*p))
            p++;
        if (!*p)
            return n;
        if (n == max)
            return max + 1;
        tokens[n++] = p;
        while (*p && !is_separator(*p))
            p++;
        if (*p)
            *p++ = '\0';
    }
}

static int is_blank(const char *s)
{
    while (*s && isspace((unsigned char)*s))
        s++;
    return *s == '\0';
}

static int is_comment(const char *s)
{
    while (*s && isspace((unsigned char)*s))
        s++;
    return *s == '#';
}

static column_role role_of(const char *name)
{
    if (strcmp(name, "x") == 0) return COL_X;
    if (strcmp(name, "y") == 0) return COL_Y;
    if (strcmp(name, "z") == 0) return COL_Z;
    if (strcmp(name, "mass") == 0 || strcmp(name, "m") == 0) return COL_MASS;
    if (strcmp(name, "h") == 0) return COL_H;
    if (strcmp(name, "id") == 0) return COL_ID;
    if (strcmp(name, "type") == 0) return COL_TYPE;
    return COL_EXTRA;
}

static int valid_name(const char *name)
{
    if (!isalpha((unsigned char)name[0]) && name[0] != '_')
        return 0;
    for (const char *p = name; *p; p++)
        if (!isalnum((unsigned char)*p) && *p != '_')
            return 0;
    return strlen(name) < ORR_FIELD_NAME_MAX;
}

/* Makes st->buf hold at least size bytes; returns 0 when memory runs out. */
static int reserve(text_state *st, size_t size)
{
    if (st->bufsize >= size)
        return 1;
    char *buf = realloc(st->buf, size);
    if (!buf)
        return 0;
    st->buf = buf;
    st->bufsize = size;
    return 1;
}

/* Takes the next line from the peeked bytes into st->buf; a line the peek
 * cuts short is finished from the stream. Returns 0 when memory runs out. */
static int peeked_line(text_state *st)
{
    const unsigned char *p = st->peek + st->peek_pos;
    size_t left = st->peek_len - st->peek_pos;
    const unsigned char *nl = memchr(p, '\n', left);
    size_t take = nl ? (size_t)(nl - p) + 1 : left;
    if (!reserve(st, take + 1))
        return 0;
    memcpy(st->buf, p, take);
    st->buf[take] = '\0';
    st->peek_pos += take;
    if (nl)
        return 1;
    char *rest = NULL;
    size_t rest_size = 0;
    ssize_t more = getline(&rest, &rest_size, st->fp);
    int ok = more <= 0 || reserve(st, take + (size_t)more + 1);
    if (ok && more > 0)
        memcpy(st->buf + take, rest, (size_t)more + 1);
    free(rest);
    return ok;
}

/* Reads the next line into st->buf; returns 0 at end of file. */
static int read_line(text_state *st)
{
    if (st->peek_pos < st->peek_len) {
        if (!peeked_line(st))
            return 0;
    } else if (getline(&st->buf, &st->bufsize, st->fp) < 0) {
        return 0;
    }
    st->line++;
    /* Editors on Windows start UTF-8 files with a byte-order mark; it is
     * not part of the first column's name. */
    size_t len = strlen(st->buf);
    if (st->line == 1 && len >= 3 && memcmp(st->buf, "\xEF\xBB\xBF", 3) == 0)
        memmove(st->buf, st->buf + 3, len - 2);
    return 1;
}

static orr_status parse_header(orr_source *src, text_state *st, orr_error *err)
{
    const char *path = src->info.path;
    do {
        if (!read_line(st)) {
            if (ferror(st->fp))
                return orr_fail(err, ORR_ERR_IO, "%s: read error: %s", path, strerror(errno));
            return orr_fail(err, ORR_ERR_FORMAT,
                            "%s: no header line: a text table starts with a line naming its columns, e.g. 'x y z mass'",
                            path);
        }
    } while (is_blank(st->buf));
    st->header_line = st->line;
    char *line = st->buf;
    while (isspace((unsigned char)*line))
        line++;
    if (*line == '#') /* "# x y z mass" is a common way to write a header */
        line++;
    char *tokens[TEXT_MAX_COLUMNS];
    int n = split_fields(line, tokens, TEXT_MAX_COLUMNS);
    if (n > TEXT_MAX_COLUMNS)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: more than %d columns in the header", path, st->line,
                        TEXT_MAX_COLUMNS);
    int seen[COL_EXTRA] = {0};
    for (int i = 0; i < n; i++) {
        if (!valid_name(tokens[i]))
            return orr_fail(err, ORR_ERR_FORMAT,
                            "%s:%ld: column %d name '%s' is not a name (letters, digits, '_', at most %d characters); "
                            "the first line must name the columns, e.g. 'x y z mass'",
                            path, st->line, i + 1, tokens[i], ORR_FIELD_NAME_MAX - 1);
        for (int j = 0; j < i; j++)
            if (strcmp(st->names[j], tokens[i]) == 0)
                return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column '%s' is named twice", path, st->line,
                                tokens[i]);
        snprintf(st->names[i], ORR_FIELD_NAME_MAX, "%s", tokens[i]);
        st->role[i] = role_of(tokens[i]);
        if (st->role[i] == COL_MASS && seen[COL_MASS])
            return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: both 'm' and 'mass' columns", path, st->line);
        if (st->role[i] == COL_EXTRA) {
            if (src->info.nextra == ORR_MAX_EXTRA_FIELDS)
                return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: more than %d extra columns", path, st->line,
                                ORR_MAX_EXTRA_FIELDS);
            st->extra_slot[i] = src->info.nextra;
            snprintf(src->info.extra_names[src->info.nextra++], ORR_FIELD_NAME_MAX, "%s", tokens[i]);
        } else {
            seen[st->role[i]] = 1;
        }
    }
    st->ncolumns = n;
    static const char *const required[] = {"x", "y", "z"};
    for (int r = COL_X; r <= COL_Z; r++)
        if (!seen[r])
            return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: the header has no '%s' column (found: %s%s%s ...)",
                            path, st->line, required[r], n > 0 ? st->names[0] : "nothing", n > 1 ? " " : "",
                            n > 1 ? st->names[1] : "");
    st->has_mass = seen[COL_MASS];
    src->info.has_h = seen[COL_H];
    src->info.has_id = seen[COL_ID];
    src->info.has_type = seen[COL_TYPE];
    st->data_offset = ftell(st->fp);
    return ORR_OK;
}

static orr_status parse_number(const char *path, long line, const char *column, const char *tok, double *out,
                               orr_error *err)
{
    char *end;
    errno = 0;
    double v = orr_strtod(tok, &end);
    if (end == tok || *end != '\0')
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column '%s': '%s' is not a number", path, line, column,
                        tok);
    *out = v;
    return ORR_OK;
}

static orr_status parse_id(const char *path, long line, const char *tok, uint64_t *out, orr_error *err)
{
    char *end;
    errno = 0;
    if (tok[0] == '-')
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column 'id': '%s' is negative", path, line, tok);
    unsigned long long v = strtoull(tok, &end, 10);
    if (end == tok || *end != '\0' || errno == ERANGE)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column 'id': '%s' is not an unsigned 64-bit integer",
                        path, line, tok);
    *out = v;
    return ORR_OK;
}

/* Parses one data row into slot k of the chunk. */
static orr_status parse_row(orr_source *src, text_state *st, size_t k, orr_error *err)
{
    const char *path = src->info.path;
    orr_chunk *c = &src->chunk;
    char *tokens[TEXT_MAX_COLUMNS];
    int n = split_fields(st->buf, tokens, st->ncolumns);
    if (n != st->ncolumns)
        return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: row has %s%d values; the header (line %ld) names %d columns",
                        path, st->line, n > st->ncolumns ? "more than " : "", n > st->ncolumns ? st->ncolumns : n,
                        st->header_line, st->ncolumns);
    c->mass[k] = 1.0f;
    c->id[k] = st->next_index;
    c->type[k] = 0;
    for (int i = 0; i < n; i++) {
        orr_status s;
        double v = 0;
        if (st->role[i] == COL_ID) {
            if ((s = parse_id(path, st->line, tokens[i], &c->id[k], err)))
                return s;
            continue;
        }
        if ((s = parse_number(path, st->line, st->names[i], tokens[i], &v, err)))
            return s;
        switch (st->role[i]) {
        case COL_X: c->x[k] = (float)v; break;
        case COL_Y: c->y[k] = (float)v; break;
        case COL_Z: c->z[k] = (float)v; break;
        case COL_MASS: {
            const char *problem = orr_mass_problem(v);
            if (problem)
                return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column '%s': particle %llu: mass %s %s", path,
                                st->line, st->names[i], (unsigned long long)st->next_index, tokens[i], problem);
            c->mass[k] = (float)v;
            break;
        }
        case COL_H:
            if (!isfinite(v) || v < 0)
                return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column '%s': %s must be finite and not negative",
                                path, st->line, st->names[i], tokens[i]);
            c->h[k] = (float)v;
            break;
        case COL_TYPE:
            if (v != floor(v) || v < 0 || v > 5)
                return orr_fail(err, ORR_ERR_FORMAT, "%s:%ld: column 'type': %s is not a type from 0 to 5", path,
                                st->line, tokens[i]);
            c->type[k] = (uint8_t)v;
            break;
        case COL_EXTRA: c->extra[st->extra_slot[i]].data[k] = (float)v; break;
        case COL_ID: break;
        }
    }
    return ORR_OK;
}

static orr_status text_next(orr_source *src, orr_error *err)
{
    text_state *st = src->state;
    orr_chunk *c = &src->chunk;
    c->first_index = st->next_index;
    while (c->n < c->capacity && read_line(st)) {
        if (is_blank(st->buf) || is_comment(st->buf))
            continue;
        orr_status s = parse_row(src, st, c->n, err);
        if (s)
            return s;
        c->n++;
        st->next_index++;
    }
    if (ferror(st->fp))
        return orr_fail(err, ORR_ERR_IO, "%s:%ld: read error: %s", src->info.path, st->line, strerror(errno));
    return ORR_OK;
}

static orr_status text_rewind(orr_source *src, orr_error *err)
{
    text_state *st = src->state;
    if (st->is_stream)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: this scene reads its particles twice, but a pipe can be read only once: save them "
                        "to a file and name that",
                        src->info.path);
    if (fseek(st->fp, st->data_offset, SEEK_SET) != 0)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot seek back to the first row: %s", src->info.path,
                        strerror(errno));
    st->line = st->header_line;
    st->next_index = 0;
    return ORR_OK;
}

static void text_close(orr_source *src)
{
    text_state *st = src->state;
    if (!st)
        return;
    if (st->fp && st->owns_fp)
        fclose(st->fp);
    free(st->buf);
    free(st->peek);
    free(st);
    src->state = NULL;
}

static const orr_source_ops text_ops = {.next = text_next, .rewind = text_rewind, .close = text_close};

int orr_text_probe(const unsigned char *head, size_t n)
{
    if (n == 0)
        return 0;
    for (size_t i = 0; i < n; i++)
        if (head[i] < 0x20 && head[i] != '\n' && head[i] != '\r' && head[i] != '\t' && head[i] != '\f')
            return 0;
    return 1;
}

/* Unless s says opening already failed, reads the header from the source's
 * stream and allocates its chunk; closes the source on failure. */
static orr_status finish_open(orr_source *src, orr_status s, const orr_source_options *opt, orr_source **out,
                              orr_error *err)
{
    size_t chunk_size = opt && opt->chunk_size ? opt->chunk_size : (size_t)1 << 20;
    text_state *st = src->state;
    if (!s)
        s = parse_header(src, st, err);
    if (!s) {
        const char *names[ORR_MAX_EXTRA_FIELDS];
        for (int i = 0; i < src->info.nextra; i++)
            names[i] = src->info.extra_names[i];
        s = orr_chunk_alloc(&src->chunk, chunk_size, src->info.has_h, names, src->info.nextra, err);
    }
    if (s) {
        orr_source_close(src);
        return s;
    }
    *out = src;
    return ORR_OK;
}

orr_status orr_text_source_open(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err)
{
    *out = NULL;
    orr_source *src = orr_source_new("text", path, &text_ops, sizeof(text_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    text_state *st = src->state;
    src->info.count = -1;
    st->owns_fp = 1;
    st->fp = fopen(path, "r");
    orr_status s = ORR_OK;
    if (!st->fp)
        s = orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    return finish_open(src, s, opt, out, err);
}

orr_status orr_text_source_open_stream(const char *name, FILE *fp, int owns_fp, const unsigned char *head,
                                       size_t n, const orr_source_options *opt, orr_source **out, orr_error *err)
{
    *out = NULL;
    orr_source *src = orr_source_new("text", name, &text_ops, sizeof(text_state), err);
    if (!src) {
        if (owns_fp)
            fclose(fp);
        return ORR_ERR_NOMEM;
    }
    text_state *st = src->state;
    src->info.count = -1;
    st->fp = fp;
    st->owns_fp = owns_fp;
    st->is_stream = 1;
    orr_status s = ORR_OK;
    if (n && !(st->peek = orr_malloc(n, "peeked input", err)))
        s = ORR_ERR_NOMEM;
    if (!s && n) {
        memcpy(st->peek, head, n);
        st->peek_len = n;
    }
    return finish_open(src, s, opt, out, err);
}
