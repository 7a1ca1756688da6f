/* What a frame is drawn from and what it reports: the types the render
 * driver (render.h), the plan (plan.h), runs of frames (animation.h) and
 * their markers share, in a header of their own so that none of those
 * modules includes another's to name them. */
#ifndef ORR_RENDER_REPORT_H
#define ORR_RENDER_REPORT_H

#include <stddef.h>
#include <stdint.h>

#include "frame/camera.h"
#include "frame/observer.h"
#include "frame/timeline.h"
#include "source/source.h"
#include "splat/deposit.h"
#include "core/plane.h"
#include "reduce/parallel.h" /* orr_parallel: how several processes render a frame together */
#include "core/timings.h"

/* The scenes the entry points render: only the plan (plan.c, plan_view.c)
 * reads them (scene/scene.h declares them; their callers load them from
 * there). */
typedef struct orr_scene orr_scene;

#define ORR_RENDER_MAX_OUTPUTS 10 /* stereo.mode: separate writes each format twice */

typedef struct orr_render_report {
    char source[ORR_PATH_MAX];   /* what was read */
    uint64_t n_read;             /* particles read from the source */
    uint64_t n_stars;            /* stars spawned from them and drawn (stars.*) */
    int stars_capped;            /* stars.max was reached: the stars past it were left in the glow */
    long stars_capped_frames;    /* a run (orr_render_animation): how many of its frames rendered reached
                                  * stars.max, and the first of them (-1: none) */
    long stars_capped_first;
    uint64_t n_lengths;          /* smoothing lengths from the neighbours the frame found */
    uint64_t n_lengths_bounded;  /* of those, left at a bound without a search (pass/lengths.h) */
    uint64_t n_selected;         /* of those, of a selected type (the observer excluded) */
    uint64_t n_nonfinite;        /* skipped for a non-finite position or weight */
    uint64_t n_stereo_skipped;   /* omni-directional stereo: not drawn, inside the eye circle
                                  * (counted in deposit.n_culled too) */
    int n_replicas;              /* input.periodic: copies of the box drawn (0 when not periodic);
                                  * n_selected and deposit count every copy */
    uint64_t n_replicas_culled;  /* copies of a chunk skipped whole, out of view or beyond input.periodic.radius
                                  * (chunks x copies) */
    uint64_t n_blocks;           /* blocks of particles offered (blocks x copies, periodic only) */
    uint64_t n_blocks_culled;    /* of those, skipped out of view or beyond the radius (whole copies' blocks
                                  * included) */
    orr_deposit_stats deposit;   /* weights deposited, off the image, culled (with colour: of X) */
    orr_deposit_stats deposit_y; /* with colour: the same for Y, the luminance */
    double sim_time;
    long frame, nframes;         /* the frame rendered, of a run of nframes (1 for a still) */
    double white;                /* the PNG stretch's white level (with colour: Y0) */
    int has_sky_frame;           /* an observer frame was built */
    orr_sky_frame sky;           /* ... this one */
    orr_camera camera;           /* the camera used (a stereo eye's, for an eye) */
    double stereo_convergence;   /* perspective stereo: the zero-parallax distance used */
    int noutputs;
    char outputs[ORR_RENDER_MAX_OUTPUTS][ORR_PATH_MAX];
    orr_stage_times times;       /* where the frame's time went: every view of the frame together, the same
                                  * in each view's report (core/timings.h) */
} orr_render_report;

struct orr_cards;

/* A caller that wants each view's images in memory (the in-situ API's
 * orrery_keep_images): called once per view, each eye of a stereo view
 * being one, in order, after the view's outputs are written, with its final
 * planes (what the FITS file holds), its graded picture (sRGB, row 0 at the
 * top, width * height * 3) and its FITS cards. Only on the process that
 * writes (rank 0). */
typedef orr_status (*orr_keep_fn)(void *user, int view, const orr_plane *planes, int nplanes, const float *rgb,
                                  const struct orr_cards *cards, orr_error *err);

/* What one frame of a run is drawn from. */
typedef struct orr_frame_input {
    orr_frame_time time; /* where the frame sits in the run: moves camera paths */
    orr_source *source;  /* the particles at that time (rewound and read, not closed), or NULL:
                          * open the scene's input (each process takes its share) */
    const orr_parallel *parallel; /* NULL: this process alone */
    orr_keep_fn keep;             /* NULL: the images are only written */
    void *keep_user;
} orr_frame_input;

#endif
