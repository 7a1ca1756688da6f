/* What the splat pass reads of a view's settings (splat_*.c, ngp_gather.c,
 * star_pass.c, coarse_glow.c, lengths.c, periodic_view.c, dust_view.c):
 * compiled once per view by the plan (plan_view.c: splat_settings_of, the only
 * reader of the scene, with plan.c), so the pass reads no scene. Copies,
 * not pointers into the scene, which may go once the plan is made
 * (the dust's curve file is the copy's own string, freed with the plan's
 * view); the path for messages is the view's own copy, which lives as long
 * as the view. */
#ifndef ORR_PASS_SPLAT_SETTINGS_H
#define ORR_PASS_SPLAT_SETTINGS_H

#include <stdint.h>

#include "core/limits.h"
#include "dust/dust.h"
#include "frame/replicas.h"
#include "post/colour.h"
#include "splat/deposit.h"

typedef struct orr_splat_settings {
    const char *path;          /* the scene file, for messages: the view's own copy */
    /* The particles drawn and their weight (input.*). */
    unsigned type_mask;        /* input.types: bit t set for a type drawn */
    int skip_nonfinite;        /* input.nonfinite: skip (else a particle not finite is an error) */
    char weight[ORR_FIELD_NAME_MAX]; /* input.weight: the field splatted without colour */
    /* The observer particle is never drawn (observer.id). */
    int skip_observer;
    uint64_t observer_id;
    /* Weights fall off as 1/r^2 from the camera (observer.dim with an
     * observer, or camera.dim), flat within dim_near. */
    int dim;
    double dim_near;
    int dims_from_observer;    /* observer.dim with an observer (a periodic box's copies are then not culled) */
    /* The glow (glow.*): lengths as angles, points where bright. */
    int has_glow;
    double glow_max_arcmin, glow_threshold;
    orr_deposit_settings deposit;   /* deposit, smoothing.* */
    orr_periodic_settings periodic; /* input.periodic.* */
    orr_dust_settings dust;         /* dust.* */
    /* colour.populations: each particle's X, Y, Z from its population. */
    int has_populations;
    orr_population_set populations;
    int only_index;            /* colour.only's index, -1 for all */
    int stereo;                /* the view is an eye of stereo.* */
} orr_splat_settings;

#endif
