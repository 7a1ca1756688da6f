/* What the scene asks of its particle source: the types and fields its
 * passes read (the source stage opens it, orr_input_open), for the plan,
 * the observer frame and the dust (render/render.h). Calls nothing else of
 * render/, so the entry points (render.c) and the plan that call them, and
 * the plan and this, make no circle. */
#include "render/render.h"

#include <string.h>

orr_status orr_scene_open_source(const orr_scene *s, const char *const *fields, int nfields, orr_source **out,
                                 orr_error *err)
{
    return orr_scene_open_share(s, fields, nfields, 0, 1, out, err);
}

int orr_blur_moves_particles(const orr_scene *s)
{
    if (!(s->animation.shutter > 0))
        return 0;
    if (s->animation.has_frame_interval)
        return s->animation.frame_interval > 0;
    /* A single snapshot's particles stand still from frame to frame, so
     * they do not move while the shutter is open either. */
    if (orr_scene_has_sequence(s))
        return 1;
    return s->input.insitu && s->animation.has_time && s->animation.time[0] != s->animation.time[1];
}

/* The types a reader keeps. The observer and reference particles may be of
 * types the scene does not draw: then the reader must not drop them (the
 * splat selects input.types itself); nor the dust (dust.types). */
static unsigned reader_types(const orr_scene *s)
{
    return s->observer.has_id ? 0 : s->input.type_mask | s->dust.types;
}

orr_status orr_scene_open_share(const orr_scene *s, const char *const *fields, int nfields, int part, int nparts,
                                orr_source **out, orr_error *err)
{
    /* A model generates only the types some pass reads (the markers always
     * are): the drawn stars, the dust, the particles whose spin gives the
     * observer's normal. With input.types: [2, 3] that leaves out the dark
     * halos, two thirds of the particles. */
    unsigned model_types = s->input.type_mask | s->dust.types | s->observer.normal_types;
    orr_input_request req = {s->path, reader_types(s), model_types, fields, nfields, part, nparts};
    return orr_input_open(&s->input, &req, out, err);
}

/* Appends name to fields[0..*n) unless it is empty, mass or h (never extra
 * fields), already there, or there is no room. */
static void add_field(const char **fields, int *n, const char *name)
{
    if (!name[0] || strcmp(name, "mass") == 0 || strcmp(name, "h") == 0 || *n >= ORR_RENDER_MAX_FIELDS)
        return;
    for (int i = 0; i < *n; i++)
        if (strcmp(fields[i], name) == 0)
            return;
    fields[(*n)++] = name;
}

int orr_render_fields(const orr_scene *s, const char *fields[ORR_RENDER_MAX_FIELDS])
{
    int nfields = 0;
    add_field(fields, &nfields, s->input.weight);
    /* Readers that load only the fields asked for (HDF5) must load these,
     * or a population choosing by stellar age would find no ages. */
    for (int i = 0; s->colour.has_populations && i < s->colour.populations.n; i++) {
        const orr_population *p = &s->colour.populations.pop[i];
        add_field(fields, &nfields, p->select.range_field);
        add_field(fields, &nfields, p->select.prob_field);
        if (p->colour.kind != ORR_POPCOLOUR_FIXED)
            add_field(fields, &nfields, p->colour.field);
        if (p->colour.kind == ORR_POPCOLOUR_SSP)
            add_field(fields, &nfields, p->colour.ssp.metallicity_field);
        if (p->lum.kind == ORR_POPLUM_FIELD || p->lum.kind == ORR_POPLUM_MAGNITUDE)
            add_field(fields, &nfields, p->lum.field);
    }
    if (s->dust.types)
        add_field(fields, &nfields, s->dust.metallicity);
    if ((s->observer.has_id && s->observer.normal_types) || orr_blur_moves_particles(s)) {
        add_field(fields, &nfields, "vx");
        add_field(fields, &nfields, "vy");
        add_field(fields, &nfields, "vz");
    }
    return nfields;
}
