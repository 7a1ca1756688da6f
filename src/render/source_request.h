/* What a render asks of its particle source, compiled from a scene by the
 * plan (orr_plan_source_request, render/plan.h), so that what opens the
 * source (scene_source.c) and a run's snapshot sequence (sequence_open.c)
 * reads this, not the scene: the input settings, the particle types and
 * extra fields the passes read, and a sequence's periodic box. */
#ifndef ORR_RENDER_SOURCE_REQUEST_H
#define ORR_RENDER_SOURCE_REQUEST_H

#include "core/error.h"
#include "frame/replicas.h"
#include "source/settings.h"

#define ORR_RENDER_MAX_FIELDS ORR_MAX_EXTRA_FIELDS

typedef struct orr_source_request {
    const char *scene_path;                /* for messages */
    const orr_input_settings *input;       /* input.*: the scene's (which outlives the request) or, in a
                                            * plan, the plan's copy */
    const orr_periodic_settings *periodic; /* its input.periodic.*: the box a sequence's snapshots wrap in */
    unsigned reader_types;   /* the types a file's reader keeps (0: all): the drawn ones and the dust's,
                              * all when there is an observer (its particle may be of any type) */
    unsigned model_types;    /* the types a built-in model generates: the drawn ones, the dust's, the
                              * spinning ones that give the observer's normal */
    unsigned sequence_types; /* the types a sequence's snapshots keep (0: all): as reader_types, the
                              * drawn ones and the dust's (a sequence without them drew no dust) */
    /* The extra fields a frame asks its source for: the weight (when not
     * mass or h), the fields the colour populations select, colour and
     * weigh by, the dust's metallicity, and velocities for the observer's
     * spin normal and for a motion blur that moves particles. Each name
     * once; pointers into the scene, or into the plan's copies. */
    const char *fields[ORR_RENDER_MAX_FIELDS];
    int nfields;
} orr_source_request;

/* Opens the requested particle source (file or built-in model), asking for
 * the given extra fields only (NULL: all; r->fields: what a frame needs). */
orr_status orr_source_request_open(const orr_source_request *r, const char *const *fields, int nfields,
                                   orr_source **out, orr_error *err);
/* The same, asking a file's reader for part `part` of `nparts` only
 * (orr_source_options): readers that can seek read just that share, the
 * others (and the generators) give everything, to be dealt out by
 * orr_source_partition. */
orr_status orr_source_request_open_share(const orr_source_request *r, const char *const *fields, int nfields,
                                         int part, int nparts, orr_source **out, orr_error *err);

#endif
