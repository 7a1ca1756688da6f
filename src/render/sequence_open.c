#include "render/sequence_open.h"

#include <stdio.h>
#include <stdlib.h>

#include "pass/periodic_view.h"

/* The side of a periodic box whose snapshots wrap: input.periodic.box, or
 * with copies (input.periodic.replicas) and box auto the first snapshot's
 * BoxSize; 0 when the scene does not say the box is periodic. */
static orr_status sequence_box(const orr_scene *s, double *box, orr_error *err)
{
    *box = s->periodic.box;
    if (s->periodic.box > 0 || s->periodic.replicas <= 1)
        return ORR_OK;
    char first[ORR_PATH_MAX];
    orr_status st = s->input.sequence.pattern ? orr_sequence_pattern_path(s->input.sequence.pattern, (long)s->input.sequence.first, first,
                                                                   sizeof first, err)
                                      : ORR_OK;
    if (!s->input.sequence.pattern)
        snprintf(first, sizeof first, "%s", orr_scene_sequence_file(s, 0));
    orr_source_options o = {.format = s->input.format, .chunk_size = 1};
    orr_source *src = NULL;
    if (!st)
        st = orr_source_open_file(first, &o, &src, err);
    if (!st)
        st = orr_periodic_box_side(&s->periodic, s->path, &src->info, box, err);
    orr_source_close(src);
    return st;
}

orr_status orr_sequence_open_scene(const orr_scene *s, const char *const *fields, int nfields, orr_sequence **out,
                                   orr_error *err)
{
    *out = NULL;
    if (!orr_scene_has_sequence(s))
        return orr_fail(err, ORR_ERR_USAGE, "%s: the input is not a sequence (no input.sequence.pattern or .files)",
                        s->path);
    orr_sequence_options opt = {
        /* As orr_scene_open_source: keep the observer's particles whatever their type. */
        .source = {.format = s->input.format,
                   .chunk_size = (size_t)s->input.chunk_size,
                   .type_mask = s->observer.has_id ? 0 : s->input.type_mask,
                   .fields = fields,
                   .nfields = nfields},
        .interpolation = s->input.sequence.interpolation,
        .max_memory = s->input.sequence.max_memory * 1024.0 * 1024.0 * 1024.0,
    };
    orr_status st = sequence_box(s, &opt.box, err);
    if (st) {
        orr_fail_prefix(err, "%s: ", s->path);
        return st;
    }
    if (s->input.sequence.pattern) {
        st = orr_sequence_open_pattern(s->input.sequence.pattern, (long)s->input.sequence.first, (long)s->input.sequence.last, (long)s->input.sequence.step,
                                       &opt, out, err);
    } else {
        const char **paths = orr_malloc((size_t)s->input.sequence.nfiles * sizeof *paths, "the sequence's paths", err);
        if (!paths)
            return ORR_ERR_NOMEM;
        for (int i = 0; i < s->input.sequence.nfiles; i++)
            paths[i] = orr_scene_sequence_file(s, i);
        st = orr_sequence_open(paths, s->input.sequence.nfiles, &opt, out, err);
        free(paths);
    }
    if (st)
        orr_fail_prefix(err, "%s: ", s->path);
    return st;
}
