#include "source/source.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source/formats.h"

orr_status orr_source_next(orr_source *src, const orr_chunk **out, orr_error *err)
{
    src->chunk.n = 0;
    orr_status st = src->ops->next(src, err);
    *out = &src->chunk;
    return st;
}

orr_status orr_source_rewind(orr_source *src, orr_error *err)
{
    if (!src->ops->rewind)
        return orr_fail(err, ORR_ERR_USAGE, "%s: this source cannot be read twice", src->info.path);
    return src->ops->rewind(src, err);
}

void orr_source_close(orr_source *src)
{
    if (!src)
        return;
    if (src->ops && src->ops->close)
        src->ops->close(src);
    orr_chunk_free(&src->chunk);
    free(src);
}

void orr_source_add_header(orr_source_info *info, const char *key, const char *fmt, ...)
{
    if (info->nheader >= ORR_SOURCE_MAX_HEADER)
        return;
    orr_header_entry *e = &info->header[info->nheader++];
    snprintf(e->key, sizeof e->key, "%s", key);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->value, sizeof e->value, fmt, ap);
    va_end(ap);
}

int orr_source_wants_field(const orr_source_options *opt, const char *name)
{
    if (!opt || !opt->fields)
        return 1;
    for (int i = 0; i < opt->nfields; i++)
        if (strcmp(opt->fields[i], name) == 0)
            return 1;
    return 0;
}

int orr_source_wants_type(const orr_source_options *opt, int type)
{
    return !opt || opt->type_mask == 0 || (type >= 0 && type < 32 && (opt->type_mask & (1u << type)));
}

const char *orr_source_format_names(void)
{
    static char names[256];
    if (!names[0])
        for (int i = 0; i < orr_nformats; i++) {
            if (i)
                strncat(names, " ", sizeof names - strlen(names) - 1);
            strncat(names, orr_formats[i].name, sizeof names - strlen(names) - 1);
        }
    return names;
}

orr_source *orr_source_new(const char *format, const char *path, const orr_source_ops *ops, size_t state_size,
                           orr_error *err)
{
    char what[64];
    snprintf(what, sizeof what, "%s source", format);
    orr_source *src = orr_calloc(1, sizeof *src, what, err);
    if (!src)
        return NULL;
    snprintf(what, sizeof what, "%s reader state", format);
    src->state = orr_calloc(1, state_size, what, err);
    if (!src->state) {
        free(src);
        return NULL;
    }
    src->ops = ops;
    snprintf(src->info.format, sizeof src->info.format, "%s", format);
    snprintf(src->info.path, sizeof src->info.path, "%s", path);
    return src;
}

int orr_source_format_known(const char *name)
{
    for (int i = 0; i < orr_nformats; i++)
        if (strcmp(name, orr_formats[i].name) == 0)
            return 1;
    return 0;
}

/* A multi-file snapshot may be named by its base ("snap_010") when only its
 * parts exist ("snap_010.0", "snap_010.0.hdf5"): the probes then look at the
 * first part. */
static FILE *open_first_part(const char *path)
{
    static const char *const suffixes[] = {"", ".0", ".0.hdf5"};
    char part[4096];
    for (size_t k = 0; k < sizeof suffixes / sizeof suffixes[0]; k++) {
        if (snprintf(part, sizeof part, "%s%s", path, suffixes[k]) >= (int)sizeof part)
            break;
        FILE *fp = fopen(part, "rb");
        if (fp || errno != ENOENT)
            return fp;
    }
    errno = ENOENT;
    return NULL;
}

/* Reads up to size bytes from the start of path for the probes; returns the
 * count, or -1 with err set when the file cannot be read. */
static long read_head(const char *path, unsigned char *buf, size_t size, orr_error *err)
{
    FILE *fp = open_first_part(path);
    if (!fp) {
        orr_fail(err, ORR_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    size_t n = fread(buf, 1, size, fp);
    int bad = ferror(fp);
    int saved = errno;
    fclose(fp);
    if (bad) {
        orr_fail(err, ORR_ERR_IO, "%s: read error: %s", path, strerror(saved));
        return -1;
    }
    return (long)n;
}

orr_status orr_source_open_file(const char *path, const orr_source_options *opt, orr_source **out,
                                orr_error *err)
{
    *out = NULL;
    const char *format = opt && opt->format ? opt->format : "auto";
    if (strcmp(format, "auto") != 0) {
        for (int i = 0; i < orr_nformats; i++)
            if (strcmp(format, orr_formats[i].name) == 0)
                return orr_formats[i].open(path, opt, out, err);
        return orr_fail(err, ORR_ERR_USAGE, "%s: unknown input format '%s' (known: auto %s)", path, format,
                        orr_source_format_names());
    }
    unsigned char head[ORR_PROBE_BYTES];
    long n = read_head(path, head, sizeof head, err);
    if (n < 0)
        return err ? err->code : ORR_ERR_IO;
    for (int i = 0; i < orr_nformats; i++)
        if (orr_formats[i].probe(head, (size_t)n))
            return orr_formats[i].open(path, opt, out, err);
    return orr_fail(err, ORR_ERR_FORMAT,
                    "%s: not a particle file orrery recognises (formats: %s); name one with --format "
                    "or input.format if it is one of them",
                    path, orr_source_format_names());
}
