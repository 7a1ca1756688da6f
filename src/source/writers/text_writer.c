#include "source/writers/text_writer.h"

#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "core/numbers.h"
#include "core/atomic.h"

/* Column names the reader gives a fixed meaning; an extra field with one of
 * these names would be read back as something else. */
static const char *const RESERVED[] = {"x", "y", "z", "mass", "m", "h", "id", "type"};

/* An extra field name is written only when the reader will take it back as
 * the same extra field: an identifier that is not a reserved column. */
static int writable_name(const char *name)
{
    if (!isalpha((unsigned char)name[0]) && name[0] != '_')
        return 0;
    for (const char *p = name; *p; p++)
        if (!isalnum((unsigned char)*p) && *p != '_')
            return 0;
    for (size_t i = 0; i < sizeof RESERVED / sizeof RESERVED[0]; i++)
        if (strcmp(name, RESERVED[i]) == 0)
            return 0;
    return 1;
}

static orr_status check_names(const orr_source_info *info, const char *path, orr_error *err)
{
    for (int k = 0; k < info->nextra; k++)
        if (!writable_name(info->extra_names[k]))
            return orr_fail(err, ORR_ERR_USAGE,
                            "%s: particle field '%s' cannot be written as a text column (names must be "
                            "letters, digits and '_', and not one of x y z mass m h id type)",
                            path, info->extra_names[k]);
    return ORR_OK;
}

/* errno after a failed stdio call; some libcs leave it 0 (then say "I/O
 * error" rather than "Success"). */
static orr_status write_failed(const char *path, int e, orr_error *err)
{
    return orr_fail(err, ORR_ERR_IO, "cannot write %s: %s", path, e ? strerror(e) : "I/O error");
}

static orr_status write_header(FILE *f, const orr_source_info *info, const char *path, orr_error *err)
{
    errno = 0;
    int bad = fputs(info->has_h ? "x y z mass h id type" : "x y z mass id type", f) == EOF;
    for (int k = 0; k < info->nextra && !bad; k++)
        bad = fprintf(f, " %s", info->extra_names[k]) < 0;
    bad = bad || fputc('\n', f) == EOF;
    return bad ? write_failed(path, errno, err) : ORR_OK;
}

/* The chunk's arrays for the info's extra fields, in header order. A chunk
 * that lacks a field the source announced is the source's bug. */
static orr_status extra_arrays(const orr_chunk *c, const orr_source_info *info, const float **cols,
                               const char *path, orr_error *err)
{
    for (int k = 0; k < info->nextra; k++) {
        cols[k] = orr_chunk_field(c, info->extra_names[k]);
        if (!cols[k])
            return orr_fail(err, ORR_ERR_INTERNAL, "%s: the source announced field '%s' but did not provide it",
                            path, info->extra_names[k]);
    }
    if (info->has_h && !c->h)
        return orr_fail(err, ORR_ERR_INTERNAL, "%s: the source announced smoothing lengths but did not provide them",
                        path);
    return ORR_OK;
}

/* Room for one row: 9 significant digits, sign, point and exponent take at
 * most 16 characters per float; 20 digits per id. */
#define ROW_MAX (16 * (5 + ORR_MAX_EXTRA_FIELDS) + 24 + 4 + 64)

/* Appends " %.9g" to a row. "%.9g" is the shortest fixed precision that
 * round-trips every float32 (FLT_DECIMAL_DIG = 9). */
static size_t put_float(char *row, size_t len, float v)
{
    return len + (size_t)snprintf(row + len, ROW_MAX - len, " %.9g", (double)v);
}

/* One particle per line, formatted in memory and written with one call:
 * stdio's per-call locking would otherwise cost as much as the formatting. */
static int write_row(FILE *f, const orr_chunk *c, size_t i, int has_h, const float **cols, int ncols)
{
    char row[ROW_MAX];
    size_t len = (size_t)snprintf(row, sizeof row, "%.9g", (double)c->x[i]);
    len = put_float(row, len, c->y[i]);
    len = put_float(row, len, c->z[i]);
    len = put_float(row, len, c->mass[i]);
    if (has_h)
        len = put_float(row, len, c->h[i]);
    len += (size_t)snprintf(row + len, sizeof row - len, " %" PRIu64 " %u", c->id[i], (unsigned)c->type[i]);
    for (int k = 0; k < ncols; k++)
        len = put_float(row, len, cols[k][i]);
    row[len++] = '\n';
    return fwrite(row, 1, len, f) == len;
}

static orr_status write_rows(FILE *f, orr_source *src, const char *path, orr_error *err)
{
    const orr_source_info *info = &src->info;
    const float *cols[ORR_MAX_EXTRA_FIELDS];
    for (;;) {
        const orr_chunk *c;
        orr_status st = orr_source_next(src, &c, err);
        if (st != ORR_OK)
            return st;
        if (c->n == 0)
            return ORR_OK;
        if ((st = extra_arrays(c, info, cols, path, err)) != ORR_OK)
            return st;
        /* '.' as the decimal point whatever the host program's locale, so
         * the reader (and other programs) read the numbers back. */
        void *locale = orr_c_locale_enter();
        errno = 0;
        size_t i = 0;
        while (i < c->n && write_row(f, c, i, info->has_h, cols, info->nextra))
            i++;
        int e = errno;
        orr_c_locale_leave(locale);
        if (i < c->n)
            return write_failed(path, e, err);
    }
}

static orr_status write_table(FILE *f, orr_source *src, const char *path, orr_error *err)
{
    orr_status st = check_names(&src->info, path, err);
    if (st == ORR_OK)
        st = write_header(f, &src->info, path, err);
    if (st == ORR_OK)
        st = write_rows(f, src, path, err);
    /* Buffered data may fail to reach the disk only now (disk full). */
    errno = 0;
    if (st == ORR_OK && fflush(f) != 0)
        st = write_failed(path, errno, err);
    return st;
}

orr_status orr_text_write_source(orr_source *src, const char *path, orr_error *err)
{
    orr_atomic_file af;
    orr_status st = orr_atomic_begin(&af, path, err);
    if (st != ORR_OK)
        return st;
    FILE *f = fopen(af.temp_path, "w");
    if (!f) {
        st = write_failed(path, errno, err);
        orr_atomic_abort(&af);
        return st;
    }
    /* A large buffer: rows are short and there are millions of them. */
    setvbuf(f, NULL, _IOFBF, 1 << 20);
    st = write_table(f, src, path, err);
    errno = 0;
    if (fclose(f) != 0 && st == ORR_OK)
        st = write_failed(path, errno, err);
    if (st == ORR_OK)
        st = orr_atomic_commit(&af, err);
    if (st != ORR_OK)
        orr_atomic_abort(&af);
    return st;
}
