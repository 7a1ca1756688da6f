/* Eight stars' optical depths at once over one list of candidate kernels,
 * a star a lane of an AVX-512 vector (docs/dust.md#method). Internal to
 * dust/: column_group.c hands each group's stars here eight at a time.
 *
 * Why a star a lane: each star's column is a sum over the candidates in
 * their order, one addition after another (so that it is the star's own
 * walk's bit for bit, column_group.c). With four candidates a lane
 * (sum_terms4) the four terms still wait on each other to be added; with a
 * star a lane each lane adds its own star's terms in that same order, the
 * eight chains side by side, and a candidate that no lane's segment meets
 * is skipped whole. */
#ifndef ORR_DUST_COLUMN_LANES_H
#define ORR_DUST_COLUMN_LANES_H

#include <stddef.h>

#include "dust/column.h"

#define ORR_DUST_STAR_LANES 8

/* The segments of up to eight stars from one eye: unit directions d and
 * lengths len, a star a lane (unused lanes repeat a used one's). */
typedef struct orr_dust_star_lanes {
    double d[3][ORR_DUST_STAR_LANES];
    double len[ORR_DUST_STAR_LANES];
} orr_dust_star_lanes;

/* The candidate kernels a group's stars may meet, in the order their
 * terms are added: centres v from the eye (v2 = |v|^2), 1/h and k/h^2. */
typedef struct orr_dust_candidate_view {
    size_t n;
    const double *vx, *vy, *vz, *v2;
    const float *ih, *kih2;
} orr_dust_candidate_view;

/* Whether this CPU runs orr_dust_star_lanes_tau with AVX-512F (else it
 * takes the lanes one after another, a term at a time). */
int orr_dust_star_lanes_available(void);

/* tau[l] for each lane l: the sum of the candidates' terms along lane l's
 * segment, each term as orr_dust_share makes it, added in the candidates'
 * order: bit for bit what each star's own walk gives, provided the list
 * holds every kernel the segment meets. */
void orr_dust_star_lanes_tau(const orr_dust_set *s, const orr_dust_candidate_view *c, const orr_dust_star_lanes *g,
                             double tau[ORR_DUST_STAR_LANES]);

/* The same one lane and one term at a time, what it does on CPUs without
 * AVX-512 (and what the tests compare it with). */
void orr_dust_star_lanes_tau_plain(const orr_dust_set *s, const orr_dust_candidate_view *c,
                                   const orr_dust_star_lanes *g, double tau[ORR_DUST_STAR_LANES]);

#endif
