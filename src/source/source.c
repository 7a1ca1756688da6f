#include "source/source.h"

#include <stdlib.h>
#include <string.h>

#include "source/text_reader.h"

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

orr_status orr_source_open_file(const char *path, const char *format, size_t chunk_size,
                                orr_source **out, orr_error *err)
{
    *out = NULL;
    if (format == NULL || strcmp(format, "auto") == 0 || strcmp(format, "text") == 0)
        return orr_text_source_open(path, chunk_size, out, err);
    return orr_fail(err, ORR_ERR_USAGE, "%s: unknown input format '%s' (known: auto, text)", path,
                    format);
}
