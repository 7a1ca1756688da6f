/* orrery.h's particle files read by a caller (the Python package's
 * orrery.open): any file orrery reads, through the same readers as
 * `orrery render`, one chunk at a time. */
#include "orrery.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source/source.h"

struct orrery_reader {
    orr_source *src;
    const orr_chunk *chunk; /* the last chunk read; NULL before the first */
    orr_error err;          /* a failed chunk's: the file is read no further */
};

int orrery_reader_open(orrery_reader **out, const char *path, const char *format, size_t chunk_size,
                       const char *const *fields, int nfields, char *msg, size_t msg_size)
{
    orr_error err = {0};
    orr_status st = ORR_OK;
    orrery_reader *rd = NULL;
    if (!out || !path || nfields < 0 || nfields > ORR_MAX_EXTRA_FIELDS)
        st = orr_fail(&err, ORR_ERR_USAGE, "orrery_reader_open: no reader pointer or path, or %d fields (at most %d)",
                      nfields, ORR_MAX_EXTRA_FIELDS);
    if (!st && !(rd = calloc(1, sizeof *rd)))
        st = orr_fail(&err, ORR_ERR_NOMEM, "out of memory opening %s", path);
    if (!st) {
        orr_source_options opt = {.format = format && format[0] ? format : "auto",
                                  .chunk_size = chunk_size,
                                  .fields = fields,
                                  .nfields = fields ? nfields : 0};
        st = orr_source_open_file(path, &opt, &rd->src, &err);
    }
    if (msg && msg_size)
        snprintf(msg, msg_size, "%s", st ? err.msg : "");
    if (st) {
        free(rd);
        if (out)
            *out = NULL;
        return (int)st;
    }
    *out = rd;
    return ORRERY_OK;
}

const char *orrery_reader_format(const orrery_reader *rd) { return rd ? rd->src->info.format : ""; }

long long orrery_reader_count(const orrery_reader *rd) { return rd ? (long long)rd->src->info.count : -1; }

double orrery_reader_time(const orrery_reader *rd) { return rd ? rd->src->info.time : 0.0; }

double orrery_reader_h_support(const orrery_reader *rd)
{
    return rd && rd->src->info.h_support > 0 ? rd->src->info.h_support : 2.0;
}

int orrery_reader_has(const orrery_reader *rd, const char *what)
{
    if (!rd || !what)
        return 0;
    const orr_source_info *info = &rd->src->info;
    return strcmp(what, "h") == 0 ? info->has_h : strcmp(what, "id") == 0 ? info->has_id
                                                : strcmp(what, "type") == 0 ? info->has_type : 0;
}

int orrery_reader_field_count(const orrery_reader *rd) { return rd ? rd->src->info.nextra : 0; }

const char *orrery_reader_field_name(const orrery_reader *rd, int i)
{
    return rd && i >= 0 && i < rd->src->info.nextra ? rd->src->info.extra_names[i] : NULL;
}

int orrery_reader_next(orrery_reader *rd, size_t *n)
{
    if (!rd || !n)
        return ORRERY_ERR_USAGE;
    *n = 0;
    if (rd->err.code)
        return (int)rd->err.code;
    orr_status st = orr_source_next(rd->src, &rd->chunk, &rd->err);
    if (st) {
        rd->chunk = NULL;
        return (int)st;
    }
    *n = rd->chunk->n;
    return ORRERY_OK;
}

const float *orrery_reader_field(const orrery_reader *rd, const char *name)
{
    return rd && rd->chunk && name ? orr_chunk_field(rd->chunk, name) : NULL;
}

const uint64_t *orrery_reader_ids(const orrery_reader *rd) { return rd && rd->chunk ? rd->chunk->id : NULL; }

const uint8_t *orrery_reader_types(const orrery_reader *rd) { return rd && rd->chunk ? rd->chunk->type : NULL; }

const char *orrery_reader_error(const orrery_reader *rd) { return rd ? rd->err.msg : "no reader"; }

void orrery_reader_close(orrery_reader *rd)
{
    if (rd)
        orr_source_close(rd->src);
    free(rd);
}
