/* One view being rendered, as the parts of the renderer share it: plan.c
 * (the plan: each view planned once, then each frame), view_camera.c (the
 * observer frame, the cameras), splat_*.c (the particles into the
 * view's planes), view_outputs.c (the planes into the view's files) and
 * compose.c (raw planes re-graded). Private to render/. */
#ifndef ORR_RENDER_VIEW_STATE_H
#define ORR_RENDER_VIEW_STATE_H

#include "core/atomic.h"
#include "encode/fits.h"
#include "post/view_psf.h"
#include "reduce/lanes.h"
#include "pass/lengths.h"
#include "pass/motion_blur.h"
#include "pass/periodic_view.h"
#include "render/render.h"
#include "pass/splat_settings.h"
#include "render/stereo_view.h"
#include "core/timings.h"
#include "render/view_files.h"
#include "splat/bands.h"
#include "splat/sph.h"
#include "stars/stars.h"

/* How a view's camera is found each frame (view_camera.c): compiled by the
 * plan from the view's scene (plan.c: camera_plan_of). */
typedef struct view_camera_plan {
    char path[ORR_PATH_MAX];     /* the scene file, for messages */
    orr_camera_settings camera;  /* camera.*: a static camera, a path, a sky map's orientation */
    orr_projection_kind kind;    /* camera.projection: a sky map follows the sky frame */
    orr_stereo_settings stereo;  /* stereo.*: the eye (0: none), its separation, convergence, fade */
    double shutter;              /* animation.shutter: motion blur's share of the frame interval (0: none) */
    int has_frame_interval;      /* animation.frame_interval given ... */
    double frame_interval;       /* ... and its value */
    int blur_moves_particles;    /* the shutter moves the particles too (orr_blur_moves_particles) */
} view_camera_plan;

/* One view being rendered. */
typedef struct view_state {
    /* Planned once per run (plan.c: plan_view): the projection as set up,
     * the planes, the kernel, the PSF, the SPH deposit (a sky map's index
     * and core stamps). The rest is the frame's. */
    orr_splat_settings splat;   /* what the splat pass reads of the view's settings */
    view_files files;           /* what its files are and how its picture is graded */
    view_camera_plan camera_plan; /* how its camera is found each frame */
    orr_projection base_proj;   /* the scene's projection, set up */
    orr_projection proj;        /* this frame's: base_proj, with a stereo eye's principal point */
    orr_mat3 world_to_camera;
    char length_unit[ORR_NAME_MAX]; /* the frame's unit of scene lengths: the scene's, else its file's, or "" */
    orr_plane planes[ORR_PLANES_MAX]; /* the weight plane, or CIE X, Y, Z with colour (then each
                                      * population's Y with output.exr_population_layers) */
    int nplanes;
    orr_render_report *rep;
    /* Kernel deposit (deposit: sph, or a sky map's PSF): its kernel, the
     * deposit's set-up, and where the smoothing lengths come from. */
    int use_sph, kernel_ready, sph_ready;
    orr_kernel kernel;
    orr_sph sph;
    const orr_lengths *lengths; /* lengths from the neighbours, or NULL: the file's */
    size_t lengths_next;        /* the next of them in source order */
    float h_scale;              /* file lengths: to orrery's h (support 2h), times smoothing.h_scale */
    orr_view_psf psf;
    double tint_t;      /* the position along colour.tint.path in this frame */
    int use_ods;        /* an eye of omni-directional stereo: its per-block transform */
    orr_stereo_ods ods;
    orr_periodic_view periodic; /* input.periodic: the box's copies and what is culled */
    orr_motion_blur blur;       /* animation.shutter: particles drawn as streaks */
    int banded;                 /* a point deposit, splatted in bands (splat_pass.c) */
    int ngp_fused;              /* NGP blocks taken whole go through the fused gather */
    orr_map_outline outline;    /* the image's map, for NGP indices */
    orr_bands bands;
    orr_lanes lanes;            /* lanes of the splat (reduce/lanes.h): lane 0 is planes[] */
    /* The view's FITS cards (view_cards.c): made once by the plan, with the
     * frame's values reserved in place, and after the WCS the stereo ones;
     * the frame's own, filled in for its files. */
    orr_cards cards, stereo_cards, frame_cards;
    orr_output_batch *outputs;  /* the frame's outputs, renamed into place together */
    struct frame_timer *timer;  /* the frame's stage timings (every view's), or NULL: not measured */
    struct orr_dust_frame *dust; /* dust.types: the frame's dust, which dims the weights (dust/dust.h), or NULL */
    struct frame_stars *stars;  /* stars.*: the stars spawned from the particles (star_pass.c), or NULL */
    struct coarse_glow *coarse; /* with stars: the widest glows on a coarser map (coarse_glow.c), or NULL */
    int drawing_stars;          /* splatting spawned stars: points, dimmed from their own distance */
} view_state;

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
    orr_plane planes[ORR_MAX_LANES][3];
    int *col0;      /* per fine column: the left coarse column of its interpolation */
    float *col_a;   /* per fine column: the right one's weight */
    uint8_t *on_map; /* per coarse pixel: whether its centre is on the map */
    double *norm;   /* per coarse pixel: what its light is divided by to give its brightness (level_norm) */
} coarse_level;

typedef struct coarse_glow {
    int nlevels;
    coarse_level level[ORR_COARSE_LEVELS]; /* coarsest first */
    struct block_buffers *buffers;         /* per lane: a block's wide kernels */
} coarse_glow;

/* Plans the coarse map of a planned view (v->coarse; none where the view
 * is no sky map in colour drawn with kernels, or is a stereo eye). */
orr_status orr_coarse_glow_plan(view_state *v, orr_error *err);
void orr_coarse_glow_free(view_state *v);
/* Zeroes the coarse planes for a frame. */
void orr_coarse_glow_begin(view_state *v);
/* Draws the block's wide kernels on lane's coarse planes and takes them out
 * of the block (not visible); returns how many, their weights per plane in
 * moved[] and the coarse deposit's statistics in coarse[]. */
size_t orr_coarse_glow_split(const view_state *v, int lane, size_t n, struct block_buffers *b,
                             orr_deposit_stats *coarse, double *moved);
/* Adds the lanes' coarse planes to the view's planes (after the lanes'
 * merge). */
orr_status orr_coarse_glow_finish(view_state *v, orr_error *err);

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
orr_status orr_frame_stars_view_table(const frame_stars *fs, const view_state *v, orr_star_table *t, void **scratch,
                                      orr_error *err);


/* A frame's stage timings and the clock reading the last stage ended at:
 * each stage is charged the time since then (core/timings.h). */
typedef struct frame_timer {
    orr_stage_times times;
    orr_clock at;
} frame_timer;

/* The planes a view's FITS files (and an in-situ keeper) get: the weight,
 * or X, Y, Z. A population's Y (output.exr_population_layers) is the
 * EXR's alone. */
static inline int fits_nplanes(const view_state *v)
{
    return v->nplanes < 3 ? v->nplanes : 3;
}

static inline void charge(const view_state *v, orr_stage s)
{
    if (v->timer)
        orr_stage_charge(&v->timer->times, s, &v->timer->at);
}


/* ---- the observer frame and the cameras (view_camera.c) ---- */

/* The observer frame of the frame (observer.*, o; scene_path for
 * messages): the observer and reference particles found in a pass over src
 * (from its start, with the velocities the spin normal needs), the spin
 * normal when asked; *velocity the observer's. st is how opening src went:
 * with several processes every one must reach the collective check. */
orr_status orr_view_sky_frame(const orr_observer_settings *o, const char *scene_path, orr_source *src, orr_status st,
                              long frame, const orr_parallel *par, orr_sky_frame *f, orr_vec3 *velocity,
                              orr_error *err);
/* The camera of a view (c) in this frame, and the sky frame it looks from. */
orr_status orr_view_camera(const view_camera_plan *c, const orr_sky_frame *observer, const orr_frame_time *when,
                           orr_camera *cam, orr_sky_frame *sky, orr_error *err);
/* Motion blur's shutter cameras for the view (animation.shutter; nothing
 * without a shutter); v->proj must be the frame's. */
orr_status orr_view_plan_blur(view_state *v, const orr_sky_frame *observer, orr_vec3 observer_velocity,
                              const orr_frame_time *when, orr_error *err);

/* ---- the splat pass (splat_pass.c) ---- */

/* Chooses how the set-up view is splatted (bands, lanes, the fused NGP
 * gather). */
void orr_splat_choose_path(view_state *v);
/* Splats every chunk of src into each view's planes (and its report). */
orr_status orr_splat_views(view_state *views, int nviews, orr_source *src, orr_progress_fn progress,
                           void *progress_user, orr_error *err);
void orr_splat_free_lanes(view_state *v);

/* ---- dust (dust_view.c) ---- */

/* The frame's dust (dust.types) from src (every particle of the input:
 * on MPI ranks the whole input, not the process's share), and
 * views[0..n).dust set to it. */
orr_status orr_dust_view_prepare(view_state *views, int n, orr_source *src, struct orr_dust_frame *dust,
                                 orr_error *err);

/* ---- the view's FITS cards (view_cards.c) ---- */

/* The cards of the planned view (v->cards, v->stereo_cards): each stage's,
 * from the view's compiled settings and the input.* and observer.* the
 * views share, the frame's reserved; after the camera plan, the files'
 * grading, the deposit and the PSF are planned. */
void orr_view_plan_cards(view_state *v, const orr_input_settings *input, const orr_observer_settings *observer);
/* The frame's cards (v->frame_cards): the plan's with the frame's camera,
 * counts, time and source, the WCS and the stereo cards; call when the
 * frame's planes are final (the reductions done, the bright stars drawn). */
void orr_view_frame_cards(view_state *v);

/* ---- the view's files (view_outputs.c) ---- */

/* The graded picture (linear RGB in [0, 1]) and its description. */
orr_status orr_view_graded_rgb(const view_state *v, float *rgb, char *desc, size_t size, orr_error *err);
orr_status orr_view_write_pictures(view_state *v, orr_error *err);
orr_status orr_view_write_fits_planes(view_state *v, const char *ext, orr_error *err);
/* A stereo pair's two eyes (views l and r) into one set of files. */
orr_status orr_view_write_stereo_pair(view_state *l, view_state *r, orr_error *err);
/* A left eye's white level (its report's) given to the right eye's
 * grading, so that separate eyes and a pair's picture are graded alike. */
void orr_view_share_white(const view_state *l, view_state *r);
orr_status orr_view_write_outputs(view_state *v, orr_error *err);
/* orrery compose for a view begun as a frame: its raw planes (or layers)
 * read back, the PSF (unless NAME.fits already has it), the pictures. */
orr_status orr_view_compose(view_state *v, orr_error *err);
/* A HEALPix view's map description (nside, order, COORDSYS when known). */
orr_healpix_info orr_view_healpix_info(const view_state *v);

/* A compose that reads its raw planes (no compose.layers: nlayers 0) reads
 * them from output.dir: fails, naming the folder and what compose reads,
 * when the folder is not there (it is not made empty). */
orr_status orr_compose_check_raw_dir(const char *output_dir, int nlayers, orr_error *err);
/* DIR/NAME.ext of output.* o. */
orr_status orr_view_output_path(const orr_output_settings *o, const char *ext, char *path, orr_error *err);

#endif
