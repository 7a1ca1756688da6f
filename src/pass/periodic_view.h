/* A view of a periodic box drawn as copies (input.periodic.*): which copies
 * a view draws, and per block of particles the summary (bounds, largest
 * kernel, weights) that lets the renderer skip a copy of the block, or a
 * whole copy of the chunk, the view cannot see (docs/periodic.md). */
#ifndef ORR_PASS_PERIODIC_VIEW_H
#define ORR_PASS_PERIODIC_VIEW_H

#include "frame/replicas.h"
#include "particles/chunk.h"
#include "pass/lengths.h"
#include "pass/splat_settings.h"
#include "source/source.h"

typedef struct orr_periodic_view {
    int active;   /* input.periodic.replicas > 1 */
    int cull;     /* copies and blocks out of view are skipped */
    int cull_sphere; /* ... and those beyond the sphere of centre: camera */
    double box;   /* the box side used */
    orr_replicas replicas;
    orr_view_cull view;
    orr_replica_sphere sphere; /* centre: camera: the images within it are drawn (radius 0: all, centre: origin) */
} orr_periodic_view;

/* The side of the box: input.periodic.box (ps), or else the file's BoxSize
 * header (one number, or three equal ones). An error naming the file (and
 * the scene, scene_path, when the file has no BoxSize) when neither gives
 * one. */
orr_status orr_periodic_box_side(const orr_periodic_settings *ps, const char *scene_path, const orr_source_info *info,
                                 double *box, orr_error *err);

/* Sets up a view's copies around its camera: with centre: camera, those
 * whose cell reaches into the sphere of input.periodic.radius. can_cull is 0 when particles
 * may be drawn away from where they are (omni-directional stereo, a sky
 * map's PSF widening, observer.dim's weights): then nothing is skipped.
 * The environment variable ORRERY_NO_CULL=1 turns skipping off too (to
 * check that it changes nothing, and to time it). */
orr_status orr_periodic_view_setup(orr_periodic_view *pv, const orr_splat_settings *set, const orr_source_info *info,
                                   const orr_projection *p, const orr_camera *cam, int can_cull, orr_error *err);

/* What the renderer needs to know of a block without touching its
 * particles again: the bounds of its drawn particles, the largest kernel
 * radius around them, their count and weights (per plane), how many
 * neighbour lengths it consumes, and whether it has a particle the gather
 * must see (a non-finite one: an error or a skip to count). */
typedef struct orr_block_summary {
    orr_vec3 lo, hi;
    double radius;
    double w[ORR_PLANES_MAX];
    uint64_t n;
    size_t lengths_used;
    int must_gather;
} orr_block_summary;

/* Where a block's smoothing lengths come from, as the gather takes them. */
typedef struct orr_block_lengths {
    const orr_lengths *lengths; /* from the neighbours, or NULL: the file's (c->h), or none */
    size_t next;                /* the first of them for this block */
    float h_scale;
    int use_kernel;             /* kernels are deposited (else no radius) */
} orr_block_lengths;

/* Summarises particles [start, end) of c, with weights w[0..nw). */
void orr_block_summarise(const orr_splat_settings *set, const orr_chunk *c, size_t start, size_t end,
                         const orr_block_lengths *bl, const float *const *w, int nw, orr_block_summary *out);

/* a grown to hold b as well. */
void orr_block_summary_merge(orr_block_summary *a, const orr_block_summary *b);

#endif
