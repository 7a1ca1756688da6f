/* One view being rendered, as the parts of the renderer share it: the plan
 * (plan_view.c: each view planned once and begun each frame; plan.c: the
 * frames), view_camera.c (the observer frame, the cameras), view_outputs.c
 * (the planes into the view's files) and compose.c (raw planes re-graded);
 * the splat pass (pass/) sees only its part, view_state.pass. Private to
 * render/. */
#ifndef ORR_RENDER_VIEW_STATE_H
#define ORR_RENDER_VIEW_STATE_H

#include "core/atomic.h"
#include "core/cards.h"
#include "encode/fits.h"
#include "frame/camera_settings.h"
#include "frame/observer.h"
#include "pass/splat_view.h"
#include "render/report.h"
#include "render/stereo_view.h"
#include "render/view_files.h"
#include "source/settings.h"

/* How a view's camera is found each frame (view_camera.c): compiled by the
 * plan from the view's scene (plan_view.c: camera_plan_of). */
typedef struct view_camera_plan {
    const char *path;            /* the scene file, for messages: the view's own (view_files.path) */
    orr_camera_settings camera;  /* camera.*: a static camera, a path, a sky map's orientation; a copy
                                  * with its own strings (freed with the plan) */
    orr_projection_kind kind;    /* camera.projection: a sky map follows the sky frame */
    orr_stereo_settings stereo;  /* stereo.*: the eye (0: none), its separation, convergence, fade */
    double shutter;              /* animation.shutter: motion blur's share of the frame interval (0: none) */
    int has_frame_interval;      /* animation.frame_interval given ... */
    double frame_interval;       /* ... and its value */
    int blur_moves_particles;    /* the shutter moves the particles too (orr_scene_blur_moves_particles, scene/scene.h) */
} view_camera_plan;

/* The units a view's planes and WCS are in: the scene's, when it states
 * them (output.bunit, output.length_unit, a built-in model's), else the
 * frame's file's (an HDF5 snapshot's), found each frame (plan.c
 * frame_units). */
typedef struct view_units {
    char weight[ORR_NAME_MAX]; /* the unit of a particle's weight, when the scene states it ... */
    int weight_from_file;      /* ... else the frame's file's mass unit */
    char length[ORR_NAME_MAX]; /* the unit of scene lengths, when the scene states it ... */
    int length_from_file;      /* ... else the frame's file's length unit */
} view_units;

/* One view being rendered. */
typedef struct view_state {
    orr_splat_view pass;        /* what the splat pass draws the view with (pass/splat_view.h) */
    view_files files;           /* what its files are and how its picture is graded */
    view_camera_plan camera_plan; /* how its camera is found each frame */
    view_units units;           /* its units as planned */
    char length_unit[ORR_NAME_MAX]; /* the frame's unit of scene lengths: the scene's, else its file's, or "" */
    orr_render_report *rep;     /* the frame's report: the pass's tally copied in after the splat */
    double tint_t;      /* the position along colour.tint.path in this frame */
    /* The view's FITS cards (view_cards.c): made once by the plan, with the
     * frame's values reserved in place, and after the WCS the stereo ones;
     * the frame's own, filled in for its files. */
    orr_cards cards, stereo_cards, frame_cards;
    orr_output_batch *outputs;  /* the frame's outputs, renamed into place together */
    int planes_zeroed;          /* the planes are as allocated, all zeros: the first frame need not clear them */
} view_state;

/* The planes a view's FITS files (and an in-situ keeper) get: the weight,
 * or X, Y, Z. A population's Y (output.exr_population_layers) is the
 * EXR's alone. */
static inline int fits_nplanes(const view_state *v)
{
    return v->pass.nplanes < 3 ? v->pass.nplanes : 3;
}

static inline void charge(const view_state *v, orr_stage s)
{
    orr_splat_charge(&v->pass, s);
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
