/* The renderer's plan, in the spirit of FFTW's: made once for a run of
 * frames (orr_plan_create), executed once per frame (orr_plan_execute),
 * destroyed at the end (orr_plan_destroy). Internal to the library: the
 * in-situ API (orrery_open makes the plan, orrery_render executes it) and
 * the animation driver use it; a still is a plan made, executed once and
 * destroyed (orr_render_frame).
 *
 * What the plan holds is what does not depend on the frame's particles, its
 * camera or its time: each view's projection (set up and checked), its
 * image planes (zeroed each frame, not allocated), the SPH kernel's tables,
 * a sky map's index and its PSF core stamps, the PSF (a Hubble or file
 * kernel made once for all the views that share it, the FFT convolvers with
 * their FFTW plans, the bright stars' PSF), and what each view's stages read
 * of its scene (the splat pass's settings, what its files are): the plan is
 * the renderer's reader of the scenes. What it redoes every frame is
 * what moves: the observer frame (found among the particles), the cameras
 * (a camera path, an observer's sky frame, a stereo eye's convergence),
 * motion blur's shutter cameras, a periodic box's copies around the camera,
 * the smoothing lengths and the dust (both from the particles), the splat's
 * lanes and bands (sized by the source's count and chunk capacity), the
 * files' names (the frame's number), the reports. docs/architecture.md has
 * the plan's lifetime. */
#ifndef ORR_RENDER_PLAN_H
#define ORR_RENDER_PLAN_H

#include "pass/progress.h"
#include "render/frame_markers.h"
#include "render/path_overview.h"
#include "render/report.h"
#include "render/run_settings.h"
#include "render/source_request.h"

typedef struct orr_plan orr_plan;

/* What the plan's frames do: render particles, or re-grade raw planes
 * already written (orrery compose: no particles; a stereo view is then one
 * view, not two eyes). */
typedef enum { ORR_PLAN_RENDER, ORR_PLAN_COMPOSE } orr_plan_purpose;

/* Plans views[0..n) of one scene (they share input.* and observer.*), for
 * a run of frames: checks each output folder and makes everything the
 * frames share. The plan keeps what it needs of the scenes as its own
 * copies: it points into none of them, and they may go once it is made. */
orr_status orr_plan_create(orr_plan **out, const orr_scene *const *views, int n, orr_plan_purpose purpose,
                           orr_error *err);

/* Renders one frame with the plan: gather, splat, reduce, post, encode.
 * in is what moves from frame to frame: the frame's number and time (its
 * camera, its output names: output.name with the frame's number, none in
 * a still; orr_frame_name), its particles, the processes, a keeper; NULL:
 * a still from the scene's input. reports[i] describes planned view i. */
orr_status orr_plan_execute(orr_plan *plan, const orr_frame_input *in, orr_render_report *reports,
                            orr_progress_fn progress, void *progress_user, orr_error *err);

/* One frame of a compose: its place in the run (its files' names carry
 * its number, none in a still; its camera and colour.tint's time), and the
 * white level to re-grade each view given with (animation.white_smoothing:
 * NAME.fits, after the PSF, re-graded with it), or none. */
typedef struct orr_compose_frame {
    orr_frame_time time;
    const double *white; /* [views given], NAN for a view graded as planned; NULL: every view as planned */
} orr_compose_frame;

/* Re-grades one frame's raw planes with a plan of purpose ORR_PLAN_COMPOSE
 * (orr_compose_views); frame NULL: a still. */
orr_status orr_plan_compose(orr_plan *plan, const orr_compose_frame *frame, orr_render_report *reports,
                            orr_error *err);

/* Seconds orr_plan_create took (for benchmarks and --timings). */
double orr_plan_seconds(const orr_plan *plan);

void orr_plan_destroy(orr_plan *plan);

/* ---- what the stages outside the plan read of a scene ----
 * The plan is the renderer's only reader of the scenes: what works before
 * a plan is made, or without one (a run of frames, its sequence and its
 * markers, the path overview, the commands and the in-situ API that load
 * the scenes), takes what these compile instead. */

/* What a render of scene s asks of its particle source (render/source_request.h);
 * it points into s, which must outlive it. */
void orr_plan_source_request(const orr_scene *s, orr_source_request *r);

/* Where view s (or a frame's scene: a view with its frame's output name)
 * writes its files and keeps its markers (render/frame_names.h); it points
 * into s. */
orr_output_place orr_plan_output_place(const orr_scene *s);

/* What view s's frames are made from, as their markers record it
 * (render/frame_markers.h); it points into s. */
orr_view_making orr_plan_view_making(const orr_scene *s);

/* What a run of frames of scene s reads of it (render/animation.h); it
 * points into s. */
orr_run_settings orr_plan_run_settings(const orr_scene *s);

/* The scene of one frame of view's run: a copy (out: zeroed or a scene,
 * whose strings are freed first) with the frame's output name (output.name
 * with its number, orr_frame_name). */
orr_status orr_plan_frame_scene(const orr_scene *view, long frame, orr_scene *out, orr_error *err);

/* Whether view s's PSF is drawn into its raw planes as it renders (a sky
 * map's; a flat view's that draws its stars one by one), so that orrery
 * compose cannot change it; *sky says whether s is a sky map. */
int orr_plan_psf_in_raw_planes(const orr_scene *s, int *sky);

/* What `orrery path` and its overview read of scene s
 * (render/path_overview.h); it points into s. */
void orr_plan_path_scene(const orr_scene *s, orr_path_scene *ps);

#endif
