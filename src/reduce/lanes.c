/* The lanes of a view's splat (reduce/lanes.h): how many, their planes and
 * their ordered sum. */
#include "reduce/lanes.h"

#include <stdlib.h>

/* The largest power of two not above n (n >= 1). The threads share a
 * chunk's lanes out whole, so three lanes on two threads leave one thread
 * two of them: the chunk takes two thirds of its one-thread time, where two
 * lanes take a half (and one copy of the planes fewer is zeroed and
 * merged). The README's main job's 4096 x 2048 panorama took three lanes
 * before: on two threads its frame is 4-13 % faster on two
 * (docs/performance.md, "Lanes in powers of two"). */
static int power_of_two_at_most(int n)
{
    int p = 1;
    while (p * 2 <= n)
        p *= 2;
    return p;
}

int orr_lanes_for(int width, int height, int nplanes, int shares_per_particle, int64_t count)
{
    size_t npix = (size_t)width * (size_t)height;
    size_t lane_bytes = npix * sizeof(float) * (size_t)nplanes;
    size_t extra = lane_bytes ? ORR_LANE_BUDGET / lane_bytes : 0;
    int lanes = extra + 1 < ORR_MAX_LANES ? (int)extra + 1 : ORR_MAX_LANES;
    /* A second lane even past the budget, up to ORR_LANE_SECOND_MAX: with
     * one lane a view is splatted by one thread, and an 8192^2 dome
     * master's three planes (805 MB a copy) took 4.2 s to deposit 10^7
     * stars' cores that way (docs/performance.md). */
    if (lanes == 1 && lane_bytes <= ORR_LANE_SECOND_MAX)
        lanes = 2;
    /* A lane's planes are zeroed and merged every frame, passes over every
     * pixel that cost about as much as adding four shares to it (measured:
     * 10^7 particles NGP on 1024^2, two threads, splat 7-20 % faster on 2
     * lanes than on 4; 4e6 particles on a 3600^2 dome slower on 4 lanes
     * than on 1; docs/performance.md). So point deposits take a lane for
     * every four shares a pixel (NGP one a particle, CIC four). Kernels
     * cost many pixels a particle, so SPH keeps its lanes. The particle
     * count is the source's, not the threads': the result still does not
     * depend on them. */
    if (shares_per_particle > 0 && count >= 0 && npix > 0) {
        const int64_t shares = shares_per_particle * count;
        int64_t by_count = shares / (ORR_LANE_SHARES_PER_PIXEL * (int64_t)npix);
        if (by_count < lanes)
            lanes = by_count > 1 ? (int)by_count : 1;
    }
    return power_of_two_at_most(lanes);
}

orr_status orr_lanes_alloc(orr_lanes *l, int nlanes, int nplanes, int width, int height, orr_error *err)
{
    l->n = nlanes;
    l->nplanes = nplanes;
    if (nlanes == 1)
        return ORR_OK;
    size_t n = (size_t)(nlanes - 1) * (size_t)nplanes;
    l->planes = orr_calloc(n, sizeof *l->planes, "splat lanes", err);
    if (!l->planes)
        return ORR_ERR_NOMEM;
    orr_status st = ORR_OK;
    for (size_t i = 0; i < n && !st; i++)
        st = orr_plane_alloc(&l->planes[i], width, height, "lane", "", err);
    return st;
}

void orr_lanes_free(orr_lanes *l)
{
    if (l->planes)
        for (int i = 0; i < (l->n - 1) * l->nplanes; i++)
            orr_plane_free(&l->planes[i]);
    free(l->planes);
    l->planes = NULL;
}

void orr_lanes_merge(orr_lanes *l, orr_plane *view_planes, size_t npix_in)
{
    if (l->n == 1)
        return;
    const long npix = (long)npix_in;
    const int nlanes = l->n;
    for (int k = 0; k < l->nplanes; k++) {
        float *out = view_planes[k].data;
        const float *lane_data[ORR_MAX_LANES] = {NULL};
        for (int lane = 1; lane < nlanes; lane++)
            lane_data[lane] = orr_lane_planes(l, view_planes, lane)[k].data;
#pragma omp parallel for schedule(static)
        for (long i = 0; i < npix; i++) {
            float sum = out[i];
            for (int lane = 1; lane < nlanes; lane++)
                sum += lane_data[lane][i];
            out[i] = sum;
        }
    }
    orr_lanes_free(l);
    l->n = 1;
}
