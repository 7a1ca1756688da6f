#include "render/sequence_open.h"

#include <stdio.h>
#include <stdlib.h>

#include "pass/periodic_view.h"

/* The side of a periodic box whose snapshots wrap: input.periodic.box, or
 * with copies (input.periodic.replicas) and box auto the first snapshot's
 * BoxSize; 0 when the scene does not say the box is periodic. */
static orr_status sequence_box(const orr_source_request *r, double *box, orr_error *err)
{
    const orr_sequence_settings *seq = &r->input->sequence;
    *box = r->periodic->box;
    if (r->periodic->box > 0 || r->periodic->replicas <= 1)
        return ORR_OK;
    char first[ORR_PATH_MAX];
    orr_status st = seq->pattern ? orr_sequence_pattern_path(seq->pattern, (long)seq->first, first, sizeof first, err)
                                 : ORR_OK;
    if (!seq->pattern)
        snprintf(first, sizeof first, "%s", orr_sequence_file(seq, 0));
    orr_source_options o = {.format = r->input->format, .chunk_size = 1};
    orr_source *src = NULL;
    if (!st)
        st = orr_source_open_file(first, &o, &src, err);
    if (!st)
        st = orr_periodic_box_side(r->periodic, r->scene_path, &src->info, box, err);
    orr_source_close(src);
    return st;
}

/* The sequence listed by input.sequence.files; its errors prefixed with
 * the scene's path (not a lack of memory for the list). */
static orr_status open_listed(const orr_source_request *r, const orr_sequence_options *opt, orr_sequence **out,
                              orr_error *err)
{
    const orr_sequence_settings *seq = &r->input->sequence;
    const char **paths = orr_malloc((size_t)seq->nfiles * sizeof *paths, "the sequence's paths", err);
    if (!paths)
        return ORR_ERR_NOMEM;
    for (int i = 0; i < seq->nfiles; i++)
        paths[i] = orr_sequence_file(seq, i);
    orr_status st = orr_sequence_open(paths, seq->nfiles, opt, out, err);
    free(paths);
    if (st)
        orr_fail_prefix(err, "%s: ", r->scene_path);
    return st;
}

orr_status orr_sequence_open_request(const orr_source_request *r, const char *const *fields, int nfields,
                                     orr_sequence **out, orr_error *err)
{
    *out = NULL;
    const orr_input_settings *in = r->input;
    const orr_sequence_settings *seq = &in->sequence;
    if (!orr_input_has_sequence(in))
        return orr_fail(err, ORR_ERR_USAGE, "%s: the input is not a sequence (no input.sequence.pattern or .files)",
                        r->scene_path);
    orr_sequence_options opt = {
        .source = {.format = in->format,
                   .chunk_size = (size_t)in->chunk_size,
                   .type_mask = r->sequence_types,
                   .fields = fields,
                   .nfields = nfields},
        .interpolation = seq->interpolation,
        .max_memory = seq->max_memory * 1024.0 * 1024.0 * 1024.0,
    };
    orr_status st = sequence_box(r, &opt.box, err);
    if (st) {
        orr_fail_prefix(err, "%s: ", r->scene_path);
        return st;
    }
    if (!seq->pattern)
        return open_listed(r, &opt, out, err);
    st = orr_sequence_open_pattern(seq->pattern, (long)seq->first, (long)seq->last, (long)seq->step, &opt, out, err);
    if (st)
        orr_fail_prefix(err, "%s: ", r->scene_path);
    return st;
}
