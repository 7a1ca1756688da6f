/* A block of particles as the splat pass works on it: gathered into the
 * camera frame and projected (splat_gather.c), deposited (splat_deposit.c),
 * by lanes or bands (splat_pass.c) or, for a periodic box's copies, on one
 * thread (splat_periodic.c). Private to the splat pass. */
#ifndef ORR_PASS_SPLAT_BLOCK_H
#define ORR_PASS_SPLAT_BLOCK_H

#include <stddef.h>
#include <stdint.h>

#include "core/timings.h"
#include "pass/splat_view.h"
#include "splat/bands.h"
#include "splat/deposit.h"

/* Particles are processed in blocks of this many: the block's scratch arrays
 * (about 100 KiB) stay in L2 cache between the gather, project and deposit
 * passes. */
#define BLOCK 4096

typedef struct block_buffers {
    float x[BLOCK], y[BLOCK], z[BLOCK], h[BLOCK];
    float w[ORR_PLANES_MAX][BLOCK]; /* the weight, or X, Y, Z with colour */
    float px[BLOCK], py[BLOCK], scale[BLOCK];
    uint8_t visible[BLOCK];
    uint8_t keep[BLOCK]; /* omni-directional stereo: 0 inside the eye circle */
    /* Point deposits: the block's shares, before they are sorted by band. */
    int32_t share_pixel[ORR_MAX_SHARES_PER_POINT * BLOCK];
    float share_w[ORR_PLANES_MAX][ORR_MAX_SHARES_PER_POINT * BLOCK];
    uint32_t band_cursor[ORR_MAX_BANDS];
    /* The block's weights, as the deposits read them: the source's arrays
     * themselves for a block taken whole (take_weights), otherwise w. */
    const float *wp[ORR_PLANES_MAX];
    /* A block of the fused NGP gather (pass/ngp_gather.h): its pixel
     * indices are in share_pixel. */
    int indexed;
    /* Motion blur: x, y, z hold where each streak starts and sx, sy, sz
     * the vector to its end (camera frame); the streaks' samples are
     * drawn from the buffers of *samples, a block at a time. */
    float sx[BLOCK], sy[BLOCK], sz[BLOCK];
    struct block_buffers *samples;
} block_buffers;

/* What one block added to the view's tally, kept per block and summed in block
 * order, so the sums do not depend on which thread took which block. */
typedef struct block_tally {
    uint64_t n_selected, n_nonfinite, n_stereo_skipped;
    orr_deposit_stats deposit[2]; /* of the first two planes: the tally's deposit and deposit_y */
} block_tally;

/* Gathers particles [start, end) of c (moved by shift) into the block and
 * projects them: positions in pixels and what the projection (and an eye
 * of omni-directional stereo) draws. Returns how many, or -1 (err set)
 * (splat_gather.c). */
long orr_splat_project_block(const orr_splat_view *v, const orr_source *src, const orr_chunk *c,
                             const float *const *wts, size_t start, size_t end, orr_vec3 shift, int fading,
                             size_t lengths_next, block_buffers *b, block_tally *t, orr_error *err);

/* Projects the block's n points (camera frame): positions in pixels and
 * what the projection (and an eye of omni-directional stereo) draws
 * (splat_gather.c). */
void orr_splat_project_points(const orr_splat_view *v, size_t n, block_buffers *b, block_tally *t);

/* A block of the fused gather as an NGP batch, its indices completed (a
 * sky map's rim folded) and its report in t (splat_deposit.c). */
orr_ngp_batch orr_splat_place_indexed(const orr_splat_view *v, size_t n, block_buffers *b, block_tally *t);
/* Deposits the gathered block into planes (lane's: the view's own or a
 * private copy): as the fused gather's pixels, as streaks, or as its
 * projected points (splat_deposit.c). */
void orr_splat_deposit_block(const orr_splat_view *v, orr_plane *planes, int lane, size_t n, block_buffers *b,
                             block_tally *t);
/* Adds what one block added to the view's tally (splat_deposit.c). */
void orr_splat_add_tally(orr_splat_tally *r, const block_tally *t);

/* A periodic box: the chunk drawn once per copy of the box, on one thread,
 * into the view's own planes (splat_periodic.c). */
orr_status orr_splat_chunk_periodic(orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *w,
                                    block_buffers *b, double *split, orr_error *err);

/* Adds this thread's CPU time since `since` to split[part]; returns now. */
static inline double orr_splat_split_mark(double *split, int part, double since)
{
    double now = orr_thread_cpu_seconds();
    split[part] += now - since;
    return now;
}

#endif
