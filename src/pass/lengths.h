/* Smoothing lengths for the SPH deposit when a snapshot has none: one pass
 * over the source gathers the positions of the particles the scene draws,
 * a k-d tree finds each one's k-th nearest neighbour (particles/smoothing.h)
 * and the source is rewound for the splat pass, which takes the lengths in
 * the same order. Memory: 12 bytes a particle for the positions and about
 * 20 for the tree while the lengths are computed, then 4 for the lengths. */
#ifndef ORR_PASS_LENGTHS_H
#define ORR_PASS_LENGTHS_H

#include <math.h>
#include <stddef.h>

#include "core/vecmath.h"
#include "reduce/parallel.h"
#include "pass/splat_settings.h"
#include "source/source.h"
#include "stars/stars.h"

typedef struct orr_lengths {
    float *h;   /* one per particle of a drawn type with a finite position, in source order */
    size_t n;
    double seconds; /* time the neighbour search took */
    size_t skipped;  /* lengths left at a bound (orr_lengths_bound) instead of searched */
    int angular;     /* glow (glow.threshold): the neighbours are those in direction seen from
                      * centre, and h an angle (radians, as a chord of the unit sphere) */
    orr_vec3 centre;
} orr_lengths;

/* Which of the glow's lengths only need to be known up to a limit. A
 * particle that spawns stars (stars.types) glows over the wider of its
 * neighbours' angle times its distance r and its own kernel, own
 * (splat_gather.c, stars_glow_length: h r > own ? h r : own, h the length
 * times h_scale). Where own is the wider for any angle up to some limit,
 * the neighbour search is skipped when a cheap upper bound on the angle is
 * within it (particles/smoothing.h, orr_smoothing_lengths_bounded), and the
 * bound stands in for the length: the glow is own either way, the same
 * bits. The limit is own / (r h_scale) less a relative 1e-5, which covers
 * the splat's float rounding of r and of the products (a few 1e-7). Only
 * for views that all glow from centre, with these stars, no periodic
 * copies (farther than the particle itself) and one process. */
typedef struct orr_lengths_bound {
    const orr_stars *stars; /* the frame's stars stage: which types spawn, their kernels */
    float h_scale;          /* the largest of the views' (smoothing.h_scale) */
} orr_lengths_bound;

/* Whether the scene's SPH deposit needs lengths from the neighbours: it asks
 * for them, or (lengths: auto) the source has none of its own, or the glow
 * (glow.threshold) needs their angular lengths. An error when it insists
 * on the file's and the source has none. */
orr_status orr_lengths_needed(const orr_splat_settings *s, const orr_source *src, int *needed, orr_error *err);

/* Computes the lengths (smoothing.neighbours, half the k-th neighbour's
 * distance: the kernel's support reaches it) and rewinds src. With centre
 * (not NULL) the angular lengths of the glow: the neighbours in direction
 * as seen from there, h half the chord to the k-th of them on the unit
 * sphere. With par (several processes, each rendering its share of the
 * particles; collective) every process gathers all the positions (12
 * bytes a particle, exchanged as sums of doubles) and finds the neighbours
 * among them, keeping its own particles' lengths, so they do not depend on
 * the number of processes; NULL: this process alone. With bound (NULL:
 * every length exact; used only with centre and no par) the lengths that
 * cannot change a glow are left at a bound (orr_lengths_bound);
 * out->skipped says how many. */
orr_status orr_lengths_compute_bounded(const orr_splat_settings *s, orr_source *src, const orr_vec3 *centre,
                                       const orr_parallel *par, const orr_lengths_bound *bound, orr_lengths *out,
                                       orr_error *err);
void orr_lengths_free(orr_lengths *l);

/* Whether particle i of chunk c takes a length from the array: it is of a
 * type drawn (type_mask: input.types) and has a finite position. Both
 * passes use it. */
static inline int orr_lengths_counts(unsigned type_mask, const orr_chunk *c, size_t i)
{
    return (type_mask & (1u << c->type[i])) && isfinite(c->x[i]) && isfinite(c->y[i]) && isfinite(c->z[i]);
}

#endif
