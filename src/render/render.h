/* The render driver: scene -> frame -> particle chunks -> splat -> outputs.
 * Several views of one scene (a dome master and a panorama, say) are
 * rendered from one pass over the particles: each chunk is splatted into
 * every view's plane before the next is read. Particles are gathered,
 * moved into the camera frame and projected in blocks small enough to stay
 * in cache. */
#ifndef ORR_RENDER_RENDER_H
#define ORR_RENDER_RENDER_H

#include "pass/progress.h" /* orr_progress_fn */
#include "render/report.h"

/* Renders views[0..n) of one scene (they share input.* and observer.*) and
 * writes their outputs; reports[i] describes view i. A still: the scene's
 * input as it is, frame 0 of 1. */
orr_status orr_render_views(const orr_scene *const *views, int n, orr_render_report *reports,
                            orr_progress_fn progress, void *progress_user, orr_error *err);

/* orr_render_views for one frame of a run: the views' output names get the
 * frame's number (in->time: output.name as it is in a still). */
orr_status orr_render_frame(const orr_scene *const *views, int n, const orr_frame_input *in,
                            orr_render_report *reports, orr_progress_fn progress, void *progress_user,
                            orr_error *err);

/* Re-grades views[0..n) from the raw planes a render with output.raw wrote
 * (DIR/NAME.raw.fits): applies the scene's PSF, colour synthesis or stretch
 * and colour map as they are now, and writes DIR/NAME.png. Nothing is read
 * from the particles. */
orr_status orr_compose_views(const orr_scene *const *views, int n, orr_render_report *reports, orr_error *err);

/* Renders one scene: orr_render_views with one view. */
orr_status orr_render_scene(const orr_scene *scene, orr_render_report *report, orr_progress_fn progress,
                            void *progress_user, orr_error *err);

#endif
