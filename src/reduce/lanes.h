/* How the threads' splats are reduced into a view's planes, so that the
 * planes are the same bits on any number of threads.
 *
 * Lanes: threads splat a chunk's blocks in lanes; block b goes to lane
 * b % nlanes, each lane deposits its blocks in order into planes of its
 * own (lane 0 into the view's), and at the end of the frame the lanes are
 * added pixel by pixel in lane order (orr_lanes_merge). The number of
 * lanes comes from the image size (and for point deposits the source's
 * particle count) alone, never from the number of threads, so every pixel
 * sums the same terms in the same order whatever OMP_NUM_THREADS is.
 * Lanes past the first cost a copy of the view's planes each; they are
 * kept within ORR_LANE_BUDGET bytes per view (a 3600 x 3600 dome master
 * gets 4 lanes, with colour 2), but for a second one of up to
 * ORR_LANE_SECOND_MAX bytes (an 8192 x 8192 one with colour: 805 MB); an
 * image too large for even that is splatted by one thread.
 *
 * Bands: point deposits (NGP, CIC, on flat images and sky maps) into
 * images of more than ORR_BAND_MIN_PIXELS pixels are not splatted in lanes
 * but in bands (splat/bands.h): threads compute the shares of up to
 * ORR_BAND_WINDOW_BLOCKS blocks at once, then add them band by band. A
 * lane's copy of such an image would not fit in the cache (16 MB a plane
 * at the threshold), nor would the image itself: the bands keep the pixels
 * being added to in cache, and need no copies. Below it, lanes cost less
 * than sorting the shares (docs/performance.md). */
#ifndef ORR_REDUCE_LANES_H
#define ORR_REDUCE_LANES_H

#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "core/plane.h"

#define ORR_MAX_LANES 4
#define ORR_LANE_BUDGET ((size_t)256 << 20)
#define ORR_LANE_SECOND_MAX ((size_t)1 << 30) /* a second lane up to this size, past the budget */
#define ORR_LANE_SHARES_PER_PIXEL 4 /* point deposits: orr_lanes_for */

#define ORR_BAND_MIN_PIXELS ((size_t)1 << 22)
/* A window is a quarter of a million particles (64 blocks of 4096). A
 * band's pixels come from main memory about once a window, so larger
 * windows bring each more shares (measured at 10^7 particles on a dome
 * master, before the bands prefetched: 256 blocks 15 % faster than 64);
 * with the prefetch (bands.c) 64, 128, 256 and 512 blocks run within 4 %
 * of each other, and 64 keeps the window's shares to 2 MB for NGP, 8 MB
 * for CIC (one plane; 4 and 16 MB with colour). */
#define ORR_BAND_WINDOW_BLOCKS 64

/* A view's lanes: lanes 1 .. n-1 hold nplanes planes each; lane 0 is the
 * view's own planes. Zero-initialise; n 0 or 1 is one lane. */
typedef struct orr_lanes {
    int n;
    int nplanes;
    orr_plane *planes; /* (n - 1) * nplanes, or NULL */
} orr_lanes;

/* How many lanes a view of width x height pixels and nplanes planes
 * splats in: as many as ORR_MAX_LANES allows within ORR_LANE_BUDGET bytes
 * of extra planes, and for point deposits (shares_per_particle: NGP 1, CIC
 * ORR_MAX_SHARES_PER_POINT; 0 for kernels) no more than one for every
 * ORR_LANE_SHARES_PER_PIXEL shares a pixel, rounded down to a power of two
 * (1, 2 or 4, which two or four threads share out evenly); a function of
 * the image and the input (count: the source's particles, -1 when
 * unknown), never of the threads. */
int orr_lanes_for(int width, int height, int nplanes, int shares_per_particle, int64_t count);

/* Whether a view of npix pixels whose deposit could go either way (a point
 * deposit, nothing collected per lane) is splatted in bands. */
static inline int orr_lanes_use_bands(size_t npix)
{
    return npix > ORR_BAND_MIN_PIXELS;
}

/* Sets up nlanes lanes of nplanes planes of width x height (zeroed): no
 * planes for one lane. */
orr_status orr_lanes_alloc(orr_lanes *l, int nlanes, int nplanes, int width, int height, orr_error *err);
void orr_lanes_free(orr_lanes *l);

/* Lane `lane`'s planes: the view's own (view_planes) for lane 0. */
static inline orr_plane *orr_lane_planes(const orr_lanes *l, orr_plane *view_planes, int lane)
{
    return lane == 0 ? view_planes : &l->planes[(size_t)(lane - 1) * (size_t)l->nplanes];
}

/* Adds the lanes into the view's planes (npix pixels each), in lane order
 * at every pixel (the ordered reduction: the same sums whatever the
 * threads), then frees them: one lane is left. */
void orr_lanes_merge(orr_lanes *l, orr_plane *view_planes, size_t npix);

#endif
