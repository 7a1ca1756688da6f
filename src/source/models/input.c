/* The scene's input (input.*, source/settings.h) opened as a source: a
 * built-in model of this folder, else a file (or a sequence's first
 * snapshot) through the readers' orr_source_open_file. */
#include <stdio.h>
#include <string.h>

#include "source/models/king.h"
#include "source/models/model.h"
#include "source/settings.h"

/* A sequence's frames come from orr_sequence_open, which opens it once for
 * a run; alone (a path overview), its first snapshot, whole. */
static orr_status open_first_snapshot(const orr_input_settings *in, const orr_input_request *req, orr_source **out,
                                      orr_error *err)
{
    char first[ORR_PATH_MAX];
    orr_status st = ORR_OK;
    if (in->sequence.nfiles > 0)
        snprintf(first, sizeof first, "%s", orr_sequence_file(&in->sequence, 0));
    else
        st = orr_sequence_pattern_path(in->sequence.pattern, in->sequence.first, first, sizeof first, err);
    orr_source_options opt = {in->format, (size_t)in->chunk_size, req->reader_types, req->fields, req->nfields, 0, 1};
    return st ? st : orr_source_open_file(first, &opt, out, err);
}

orr_status orr_input_open(const orr_input_settings *in, const orr_input_request *req, orr_source **out,
                          orr_error *err)
{
    if (orr_input_has_sequence(in))
        return open_first_snapshot(in, req, out, err);
    if (!in->model.name[0] && !in->file)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: an in-situ scene (input.insitu) has no particles of its own: a running simulation "
                        "hands them over through orrery.h; set input.file or input.model.name to render it here",
                        req->scene_path);
    const orr_model_settings *m = &in->model;
    if (strcmp(m->name, "king") == 0) {
        orr_king_params kp = {m->particles, m->seed, m->w0, m->core_radius, m->mass};
        return orr_king_source_open(&kp, (size_t)in->chunk_size, out, err);
    }
    if (m->name[0]) {
        orr_model_params mp = {m->particles, m->seed,          m->separation, m->galaxies,
                               m->disc_q,    req->model_types, m->dust_clumping, m->m31_weight};
        return orr_model_source_open_dust(&mp, m->dust_particles, (size_t)in->chunk_size, out, err);
    }
    orr_source_options opt = {in->format,   (size_t)in->chunk_size, req->reader_types, req->fields,
                              req->nfields, req->part,              req->nparts};
    return orr_source_open_file(in->file, &opt, out, err);
}
