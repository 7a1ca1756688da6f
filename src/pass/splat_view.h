/* One view as the splat pass draws it: its projection, planes, kernel,
 * PSF and the frame's particles' path into them (splat_pass.c,
 * splat_gather.c, splat_deposit.c, splat_periodic.c, coarse_glow.c,
 * star_pass.c, dust_view.c). The renderer's plan (render/plan.c) plans it
 * once per run inside its view (render/view_state.h), sets the frame's
 * part each frame (the camera, the lengths, the dust, the stars) and
 * copies what the pass counted (tally) into the view's report. */
#ifndef ORR_PASS_SPLAT_VIEW_H
#define ORR_PASS_SPLAT_VIEW_H

#include <stdint.h>

#include "core/plane.h"
#include "core/timings.h"
#include "encode/fits.h"
#include "frame/observer.h"
#include "frame/stereo.h"
#include "pass/lengths.h"
#include "pass/motion_blur.h"
#include "pass/periodic_view.h"
#include "pass/progress.h"
#include "pass/splat_settings.h"
#include "post/view_psf.h"
#include "reduce/lanes.h"
#include "splat/bands.h"
#include "splat/deposit.h"
#include "splat/sph.h"
#include "stars/stars.h"

struct orr_dust_frame;

/* What the splat pass counted in a frame: the plan copies it into the
 * view's report (orr_render_report, render/render.h, says what each is). */
typedef struct orr_splat_tally {
    uint64_t n_read, n_stars;
    int stars_capped;
    uint64_t n_selected, n_nonfinite, n_stereo_skipped;
    uint64_t n_replicas_culled, n_blocks, n_blocks_culled;
    orr_deposit_stats deposit, deposit_y;
} orr_splat_tally;

/* One view as the splat pass draws it. */
typedef struct orr_splat_view {
    /* Planned once per run: the projection as set up, the planes, the
     * kernel, the PSF, the SPH deposit (a sky map's index and core stamps).
     * The rest is the frame's. */
    orr_splat_settings splat;   /* what the splat pass reads of the view's settings */
    orr_projection proj;        /* planned once (orr_projection_plan); a perspective stereo eye
                                 * plans it again each frame, its principal point shifted
                                 * (frame/stereo.c) */
    orr_mat3 world_to_camera;
    orr_vec3 camera_position;   /* this frame's camera (a stereo eye's), where world_to_camera starts */
    orr_plane planes[ORR_PLANES_MAX]; /* the weight plane, or CIE X, Y, Z with colour (then each
                                      * population's Y with output.exr_population_layers) */
    int nplanes;
    orr_splat_tally tally;      /* the frame's counts */
    /* Kernel deposit (deposit: sph, or a sky map's PSF): its kernel, the
     * deposit's set-up, and where the smoothing lengths come from. */
    int use_sph, kernel_ready, sph_ready;
    orr_kernel kernel;
    orr_sph sph;
    const orr_lengths *lengths; /* lengths from the neighbours, or NULL: the file's */
    size_t lengths_next;        /* the next of them in source order */
    float h_scale;              /* file lengths: to orrery's h (support 2h), times smoothing.h_scale */
    orr_view_psf psf;
    int use_ods;        /* an eye of omni-directional stereo: its per-block transform */
    orr_stereo_ods ods;
    orr_periodic_view periodic; /* input.periodic: the box's copies and what is culled */
    orr_motion_blur blur;       /* animation.shutter: particles drawn as streaks */
    int banded;                 /* a point deposit, splatted in bands (splat_pass.c) */
    int ngp_fused;              /* NGP blocks taken whole go through the fused gather */
    orr_map_outline outline;    /* the image's map, for NGP indices */
    orr_bands bands;
    orr_lanes lanes;            /* lanes of the splat (reduce/lanes.h): lane 0 is planes[] */
    orr_frame_timer *timer;     /* the frame's stage timings (every view's), or NULL: not measured */
    struct orr_dust_frame *dust; /* dust.types: the frame's dust, which dims the weights (dust/dust.h), or NULL */
    struct frame_stars *stars;  /* stars.*: the stars spawned from the particles (star_pass.c), or NULL */
    struct coarse_glow *coarse; /* with stars: the widest glows on a coarser map (coarse_glow.c), or NULL */
    int drawing_stars;          /* splatting spawned stars: points, dimmed from their own distance */
} orr_splat_view;

/* Charges stage s the time since the last stage ended (core/timings.h). */
static inline void orr_splat_charge(const orr_splat_view *v, orr_stage s)
{
    orr_frame_timer_charge(v->timer, s);
}

/* ---- the widest glows on a coarser map (coarse_glow.c) ---- */

/* The coarse maps: each the sky map's copy `factor` times coarser each
 * way, with its planes per lane and what its interpolation gives the fine
 * map (coarse_glow.c). */
#define ORR_COARSE_LEVELS 4
typedef struct coarse_level {
    int factor;
    float min_pixels; /* the narrowest kernel it takes: h in its pixels */
    orr_projection proj;
    orr_sph sph;
    int sph_ready;
    orr_plane planes[ORR_MAX_LANES][3]; /* the first nlanes lanes' (coarse_glow.nlanes) */
    int *col0;      /* per fine column: the left coarse column of its interpolation */
    float *col_a;   /* per fine column: the right one's weight */
    uint8_t *on_map; /* per coarse pixel: whether its centre is on the map */
    double *norm;   /* per coarse pixel: what its light is divided by to give its brightness (level_norm) */
} coarse_level;

typedef struct coarse_glow {
    int nlevels;
    int nlanes; /* the view's lanes: a kernel deposit's depend on its image alone (reduce/lanes.h) */
    coarse_level level[ORR_COARSE_LEVELS]; /* coarsest first */
    struct block_buffers *buffers;         /* per lane: a block's wide kernels */
} coarse_glow;

/* Plans the coarse map of a planned view (v->coarse; none where the view
 * is no sky map in colour drawn with kernels, or is a stereo eye). */
orr_status orr_coarse_glow_plan(orr_splat_view *v, orr_error *err);
void orr_coarse_glow_free(orr_splat_view *v);
/* Zeroes the coarse planes for a frame. */
void orr_coarse_glow_begin(orr_splat_view *v);
/* Draws the block's wide kernels on lane's coarse planes and takes them out
 * of the block (not visible); returns how many, their weights per plane in
 * moved[] and the coarse deposit's statistics in coarse[]. */
size_t orr_coarse_glow_split(const orr_splat_view *v, int lane, size_t n, struct block_buffers *b,
                             orr_deposit_stats *coarse, double *moved);
/* Adds the lanes' coarse planes to the view's planes (after the lanes'
 * merge). */
orr_status orr_coarse_glow_finish(orr_splat_view *v, orr_error *err);

/* ---- stars from particles (star_pass.c) ---- */

/* The stars of a run's frames: the stage prepared once, a chunk's stars,
 * and the frame's list of every star drawn (in the order drawn). */
typedef struct frame_stars {
    orr_stars stage;
    orr_star_batch batch;
    orr_vec3 eye;           /* the frame's observer */
    uint64_t observer_id;   /* spawns no stars */
    orr_sky_frame sky;      /* the frame's sky frame, for the list's l, b */
    int whole_list;         /* the list holds every star of the frame: one process drew them all */
    /* Per particle of the chunk, its glow's dimming (1/length^2: stars.h,
     * orr_stars_glow_dimming), for the spawning types */
    float *glow_dimming;
    size_t glow_cap;
    /* The list */
    size_t n, cap;
    double *l, *b;
    float *v, *bv, *abs_v, *dist_pc;
    float *px, *py, *pz;    /* positions, for each view's test of what it shows */
    int64_t *parent;
    int32_t *index;
} frame_stars;

/* Prepares the stars of stars.* (set; observer_id: the observer particle,
 * which spawns none; scene_path for messages); frees what it holds. */
orr_status orr_frame_stars_prepare(frame_stars *fs, const orr_stars_settings *set, uint64_t observer_id,
                                   const char *scene_path, orr_error *err);
void orr_frame_stars_free(frame_stars *fs);
/* Starts a frame seen from the observer frame sky. */
void orr_frame_stars_begin(frame_stars *fs, const orr_sky_frame *sky);
/* The stars of chunk c (its weights xyz reduced to the glow's), into
 * fs->batch. */
orr_status orr_frame_stars_spawn(frame_stars *fs, const orr_chunk *c, float *const *xyz, orr_error *err);
/* The batch's stars into the frame's list, their V dimmed as the dust
 * dimmed their Y weights (dimmed_y: after the dust of the first view;
 * NULL without dust). */
orr_status orr_frame_stars_record(frame_stars *fs, const float *dimmed_y, orr_error *err);
/* The list's stars that view v shows, as a table (*scratch holds its
 * columns: free it after). */
orr_status orr_frame_stars_view_table(const frame_stars *fs, const orr_splat_view *v, orr_star_table *t, void **scratch,
                                      orr_error *err);

/* ---- a sky map's PSF widening the kernels (splat_deposit.c) ---- */

/* The view's kernel deposit, planned once its PSF is (post/view_psf.h, which
 * fixes psf.h_per_r): kernels are drawn for deposit: sph and wherever the
 * PSF widens every particle; then the SPH deposit is set up, and a sky
 * map's PSF core stamps (splat/sky_cores.h). v->kernel must be made. */
orr_status orr_splat_plan_kernels(orr_splat_view *v, orr_error *err);

/* Whether the frame may skip what is out of view (a periodic box's copies,
 * pass/periodic_view.h): only while particles are drawn where they are,
 * not with omni-directional stereo, a PSF widening kernels with distance,
 * or weights dimmed with distance from the observer. */
int orr_splat_can_cull(const orr_splat_view *v);

/* ---- the splat pass (splat_pass.c) ---- */

/* Chooses how the set-up view is splatted (bands, lanes, the fused NGP
 * gather). */
void orr_splat_choose_path(orr_splat_view *v);
/* Splats every chunk of src into each view's planes (and its tally). */
orr_status orr_splat_views(orr_splat_view *const *views, int nviews, orr_source *src, orr_progress_fn progress,
                           void *progress_user, orr_error *err);
void orr_splat_free_lanes(orr_splat_view *v);

/* ---- dust (dust_view.c) ---- */

/* The frame's dust (dust.types) from src (every particle of the input:
 * on MPI ranks the whole input, not the process's share), and
 * views[0..n)->dust set to it. */
orr_status orr_dust_view_prepare(orr_splat_view *const *views, int n, orr_source *src, struct orr_dust_frame *dust,
                                 orr_error *err);

#endif
