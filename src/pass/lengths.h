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

typedef struct orr_lengths {
    float *h;   /* one per particle of a drawn type with a finite position, in source order */
    size_t n;
    double seconds; /* time the neighbour search took */
    int angular;     /* glow (glow.threshold): the neighbours are those in direction seen from
                      * centre, and h an angle (radians, as a chord of the unit sphere) */
    orr_vec3 centre;
} orr_lengths;

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
 * the number of processes; NULL: this process alone. */
orr_status orr_lengths_compute(const orr_splat_settings *s, orr_source *src, const orr_vec3 *centre,
                               const orr_parallel *par, orr_lengths *out, orr_error *err);
void orr_lengths_free(orr_lengths *l);

/* Whether particle i of chunk c takes a length from the array: it is of a
 * type drawn (type_mask: input.types) and has a finite position. Both
 * passes use it. */
static inline int orr_lengths_counts(unsigned type_mask, const orr_chunk *c, size_t i)
{
    return (type_mask & (1u << c->type[i])) && isfinite(c->x[i]) && isfinite(c->y[i]) && isfinite(c->z[i]);
}

#endif
