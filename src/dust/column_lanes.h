/* Eight stars' optical depths at once over one list of candidate kernels,
 * a star a lane of an AVX-512 vector or of two AVX2 vectors
 * (docs/dust.md#method). Internal to
 * dust/: column_group.c hands each group's stars here eight at a time.
 *
 * Why a star a lane: each star's column is a sum over the candidates in
 * their order, one addition after another (so that it is the star's own
 * walk's bit for bit, column_group.c). With four candidates of one star a
 * lane (as the walk once went on AVX2) the four terms still wait on each
 * other to be added; with a star a lane each lane adds its own star's
 * terms in that same order, the eight chains side by side, and a candidate
 * that no lane's segment meets is skipped whole. */
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

/* How the eight lanes are computed: in one AVX-512 register, in two AVX2
 * registers of four, or one lane and one term at a time (PLAIN, what CPUs
 * without AVX2 do); the same bits every way. */
typedef enum { ORR_DUST_LANES_PLAIN, ORR_DUST_LANES_AVX2, ORR_DUST_LANES_AVX512 } orr_dust_lanes_way;

/* Whether this CPU runs the way; the fastest way it runs. */
int orr_dust_star_lanes_runs(orr_dust_lanes_way way);
orr_dust_lanes_way orr_dust_star_lanes_best(void);

/* tau[l] for each lane l: the sum of the candidates' terms along lane l's
 * segment, each term as orr_dust_share makes it, added in the candidates'
 * order: bit for bit what each star's own walk gives, provided the list
 * holds every kernel the segment meets. A way this CPU does not run is
 * done PLAIN. */
void orr_dust_star_lanes_tau(orr_dust_lanes_way way, const orr_dust_set *s, const orr_dust_candidate_view *c,
                             const orr_dust_star_lanes *g, double tau[ORR_DUST_STAR_LANES]);

#endif
