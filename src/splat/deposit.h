/* Deposit of per-particle weights into a plane at projected positions.
 * Nearest grid point puts the whole weight into the pixel containing the
 * point; cloud-in-cell treats the particle as a square one pixel wide and
 * shares the weight among the (up to) four pixels it overlaps, in proportion
 * to the overlapping areas. Weight that falls off the image is counted, so
 * deposited + outside equals the total weight of the visible particles. */
#ifndef ORR_SPLAT_DEPOSIT_H
#define ORR_SPLAT_DEPOSIT_H

#include <stddef.h>
#include <stdint.h>

#include "frame/projection.h"
#include "splat/plane.h"

typedef enum {
    ORR_DEPOSIT_NGP,
    ORR_DEPOSIT_CIC,
    ORR_DEPOSIT_SPH, /* smoothing kernels: splat/sph.h; orr_deposit itself treats it as CIC */
} orr_deposit_kind;

typedef struct orr_deposit_stats {
    double deposited;        /* weight that landed in the image */
    double outside;          /* weight of visible particles that fell off the image */
    double culled;           /* weight of particles the projection did not draw */
    uint64_t n_particles;    /* particles offered */
    uint64_t n_culled;       /* particles the projection did not draw */
} orr_deposit_stats;

const char *orr_deposit_name(orr_deposit_kind kind);

/* Points to deposit: positions in pixels, whether the projection drew
 * each, and nw weights per point (the weight, or CIE X, Y, Z). */
typedef struct orr_point_batch {
    size_t n;
    const float *px, *py;
    const uint8_t *visible;
    const float *w[3];
    int nw;
} orr_point_batch;

/* What a point deposit adds, before it is added: pixel index and the share
 * of each weight. A point makes at most ORR_MAX_SHARES_PER_POINT. */
#define ORR_MAX_SHARES_PER_POINT 4
typedef struct orr_shares {
    int32_t *pixel;
    float *w[3];
    size_t n; /* shares so far: the next goes at index n */
} orr_shares;

/* Appends the shares of the batch's points for an image of width x height
 * pixels (with the pixel count below 2^31) to out, which has room for
 * ORR_MAX_SHARES_PER_POINT * b->n more; stats (b->nw of them) get what
 * landed, fell off and was culled. Shares keep the points' order, so adding
 * them in order gives the same sums as depositing point by point. proj may
 * be NULL. For a sky projection, shares that fall outside the map (past the
 * l = +-180 seam, the poles, the dome's rim, or off the image) are folded
 * back onto it with orr_projection_fold, so nothing is lost or drawn twice
 * and pixels outside the map stay empty. */
void orr_deposit_shares(orr_deposit_kind kind, const orr_point_batch *b, const orr_projection *proj, int width,
                        int height, orr_shares *out, orr_deposit_stats *stats);

/* Adds shares [first, end) to the planes, in order. */
void orr_shares_apply(const orr_shares *s, size_t first, size_t end, orr_plane *planes, int nplanes);

/* Deposits one weight per point into a plane: the shares, added at once. */
void orr_deposit(orr_deposit_kind kind, orr_plane *plane, size_t n, const float *px, const float *py,
                 const float *w, const uint8_t *visible, const orr_projection *proj, orr_deposit_stats *stats);

#endif
