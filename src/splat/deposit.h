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
#include "core/cards.h"
#include "core/plane.h"
#include "core/names.h"
#include "particles/smoothing.h"
#include "splat/kernel.h"

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

extern const orr_named orr_deposit_names[];
const char *orr_deposit_name(orr_deposit_kind kind);

/* The splat stage's settings: the scene's deposit and smoothing.* keys. */
typedef struct orr_deposit_settings {
    orr_deposit_kind kind;        /* deposit: ngp | cic | sph (default cic) */
    orr_kernel_kind kernel;       /* smoothing.kernel: cubic | wendland-c2 | wendland-c4 (default cubic) */
    orr_smoothing_source lengths; /* smoothing.lengths: auto | file | neighbours (default auto: the
                                   * file's when it has them, else from the neighbours) */
    int neighbours;               /* smoothing.neighbours: k of the k-th nearest neighbour (default 32) */
    double h_scale;               /* smoothing.h_scale: multiplies every smoothing length (default 1) */
} orr_deposit_settings;

/* Fills d with the defaults above. */
void orr_deposit_settings_defaults(orr_deposit_settings *d);

/* The deposit's cards for a view's files (core/cards.h): its method and,
 * when the view draws kernels (deposit: sph, or a sky map's PSF that
 * widens each particle into one), the kernel and smoothing.h_scale, with
 * where the smoothing lengths come from reserved for each frame to give
 * (orr_deposit_frame_cards). */
void orr_deposit_cards(const orr_deposit_settings *d, int kernels, orr_cards *h);
/* The frame's values of the cards reserved: the lengths came from the
 * neighbours (from_neighbours; then smoothing.neighbours) or the file. */
void orr_deposit_frame_cards(const orr_deposit_settings *d, int from_neighbours, orr_cards *h);

/* Points to deposit: positions in pixels, whether the projection drew
 * each, and nw weights per point (the weight, or CIE X, Y, Z). */
typedef struct orr_point_batch {
    size_t n;
    const float *px, *py;
    const uint8_t *visible;
    const float *w[ORR_PLANES_MAX];
    int nw;
} orr_point_batch;

/* What a point deposit adds, before it is added: pixel index and the share
 * of each weight. A point makes at most ORR_MAX_SHARES_PER_POINT. */
#define ORR_MAX_SHARES_PER_POINT 4
typedef struct orr_shares {
    int32_t *pixel;
    float *w[ORR_PLANES_MAX];
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

/* ---- Nearest pixel, by pixel indices ----
 * NGP deposits go through one pixel index a point: a pixel of the image,
 * or one of these. The indices are made from projected positions
 * (orr_deposit, orr_deposit_shares) or, for the renderer's commonest
 * blocks, in the same loop that reads and projects the particles
 * (pass/ngp_gather.c); both use the inline functions below. */
#define ORR_NGP_OFF (-1)    /* visible, but not surely on a pixel: off a flat image (its weight is \
                             * lost), or near a sky map's rim or seam (orr_ngp_place folds it on) */
#define ORR_NGP_CULLED (-2) /* not drawn by the projection (ORR_NGP_OFF - 1) */

/* The image's map, set up once per batch so the per-point test is a few
 * multiplications: inside the ellipse or circle of a sky map, or the whole
 * image (ax = ay = 0). */
typedef struct orr_map_outline {
    int width, height;
    float cx, cy;
    float ax, ay; /* squared reciprocal semi-axes; 0 for a rectangular map */
} orr_map_outline;

/* The outline of a width x height image under proj (NULL: a flat image). */
orr_map_outline orr_map_outline_of(const orr_projection *proj, int width, int height);

/* The pixel of a point on a flat width x height image. Branch-free, so
 * loops over it vectorise: a point outside is clamped to pixel 0 before
 * the conversion (converting a float that does not fit an int is
 * undefined) and its index then replaced. For non-negative values
 * truncation is floor, and the bounds test is done in float first, so
 * the conversions are exact. */
static inline int32_t orr_ngp_flat_index(int width, int height, float x, float y, int visible)
{
    int in = (visible != 0) & (x >= 0.0f) & (x < (float)width) & (y >= 0.0f) & (y < (float)height);
    int32_t ix = (int32_t)(in ? x : 0.0f), iy = (int32_t)(in ? y : 0.0f);
    return in ? iy * width + ix : ORR_NGP_CULLED + (visible != 0); /* not a ternary: it vectorises */
}

/* The same on a sky map: a pixel only when surely on the map; near the
 * rim, the seam or off the image ORR_NGP_OFF, for orr_ngp_place. */
static inline int32_t orr_ngp_sky_index(const orr_map_outline *m, float x, float y, int visible)
{
    int on_image = (visible != 0) & (x >= 0.0f) & (x < (float)m->width) & (y >= 0.0f) & (y < (float)m->height);
    int32_t ix = (int32_t)(on_image ? x : 0.0f), iy = (int32_t)(on_image ? y : 0.0f);
    /* The pixel centre's offsets, (ix + 0.5) - cx, in a form that is exact
     * too but that GCC does not turn into a truncf call, which would keep
     * the loop from vectorising. */
    float u = 0.5f * ((float)(2 * ix + 1) - 2.0f * m->cx), v = 0.5f * ((float)(2 * iy + 1) - 2.0f * m->cy);
    int sure = on_image & (u * u * m->ax + v * v * m->ay <= 0.9999f);
    return sure ? iy * m->width + ix : ORR_NGP_CULLED + (visible != 0);
}

/* Points with their NGP indices, and nw weights each. */
typedef struct orr_ngp_batch {
    size_t n;
    int32_t *index;       /* a pixel, ORR_NGP_OFF or ORR_NGP_CULLED */
    const float *px, *py; /* sky maps: positions, read for the points ORR_NGP_OFF */
    const float *w[ORR_PLANES_MAX];
    int nw;
    size_t n_missing;     /* set by orr_ngp_place: points left without a pixel */
} orr_ngp_batch;

/* Completes the batch's indices for the image of outline m under proj
 * (NULL: flat): on a sky map every visible point gets a pixel (folded onto
 * the map where it falls outside, so nothing is lost or drawn twice); adds
 * to stats (nw of them) what lands, falls off and is culled. */
void orr_ngp_place(const orr_projection *proj, const orr_map_outline *m, orr_ngp_batch *b,
                   orr_deposit_stats *stats);

/* Adds the placed batch's weights at their pixels into planes [0, nw). */
void orr_ngp_add(const orr_ngp_batch *b, orr_plane *planes);

/* Appends the placed batch's shares (one a point with a pixel) to out. The
 * batch's index may be out's own pixel array from out->n on. */
void orr_ngp_shares(const orr_ngp_batch *b, orr_shares *out);

#endif
