#include "source/source.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

orr_status orr_source_next(orr_source *src, const orr_chunk **out, orr_error *err)
{
    src->chunk.n = 0;
    *out = &src->chunk;
    /* Checked here, between chunks, where every pass over the particles
     * (the splat, smoothing lengths, the observer's frame) asks for more. */
    if (src->cancel && atomic_load(src->cancel))
        return orr_fail(err, ORR_ERR_CANCELLED, "%s: the render was cancelled (orrery_cancel)", src->info.path);
    orr_status st = src->ops->next(src, err);
    *out = &src->chunk;
    return st;
}

orr_status orr_source_rewind(orr_source *src, orr_error *err)
{
    if (!src->ops->rewind)
        return orr_fail(err, ORR_ERR_USAGE, "%s: this source cannot be read twice", src->info.path);
    src->left_out = 0;
    return src->ops->rewind(src, err);
}

void orr_source_only_types(orr_source *src, unsigned mask)
{
    if (src->ops->only_types)
        src->ops->only_types(src, mask);
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

int orr_field_in_list(const char *name, const char *const *names, int n)
{
    for (int i = 0; i < n; i++)
        if (strcmp(name, names[i]) == 0)
            return 1;
    return 0;
}

int orr_field_is_own(const char *name)
{
    static const char *const own[] = {"x", "y", "z", "mass", "h", "id", "type"};
    return orr_field_in_list(name, own, (int)(sizeof own / sizeof own[0]));
}

int orr_field_split_column(const char *field, char *name, size_t size, int *column)
{
    size_t len = strlen(field);
    if (len == 0 || len >= size)
        return 0;
    snprintf(name, size, "%s", field);
    *column = -1;
    char *open = strchr(name, '[');
    if (!open)
        return 1;
    char *end = NULL;
    long k = open[1] >= '0' && open[1] <= '9' ? strtol(open + 1, &end, 10) : -1;
    if (open == name || k < 0 || k > 1000000 || !end || strcmp(end, "]") != 0)
        return 0;
    *open = '\0';
    *column = (int)k;
    return 1;
}

int orr_source_wants_type(const orr_source_options *opt, int type)
{
    return !opt || opt->type_mask == 0 || (type >= 0 && type < 32 && (opt->type_mask & (1u << type)));
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

orr_status orr_source_alloc_chunk(orr_source *src, const orr_source_options *opt, orr_error *err)
{
    size_t capacity = opt && opt->chunk_size ? opt->chunk_size : (size_t)1 << 20;
    if (src->info.count >= 0 && (uint64_t)src->info.count < capacity)
        capacity = src->info.count > 0 ? (size_t)src->info.count : 1;
    const char *names[ORR_MAX_EXTRA_FIELDS];
    for (int i = 0; i < src->info.nextra; i++)
        names[i] = src->info.extra_names[i];
    return orr_chunk_alloc(&src->chunk, capacity, src->info.has_h, names, src->info.nextra, err);
}
