/* A view of the renderer's plan (render/plan.h), as plan.c makes and runs
 * it: planned once from its scene (an eye's copy for a stereo view),
 * begun every frame, freed with the plan. Private to render/.
 *
 * What orr_plan_view makes depends on the view's scene alone: the
 * projection (checked and set up), the planes (zeroed each frame: the
 * image size does not change), the SPH kernel's tables (milliseconds), the
 * PSF (the Hubble PSF takes 0.3-2 s; a convolver plans its FFTs; the
 * bright stars' PSF), a sky map's index (0.1 s for a 3600^2 dome) and PSF
 * core stamps (made as stars land, and kept: a cell's stamps depend on the
 * cell alone), and the view's own copies of what its stages read of the
 * scene (view_state.h), so that the plan keeps no scene. */
#ifndef ORR_RENDER_PLAN_VIEW_H
#define ORR_RENDER_PLAN_VIEW_H

#include "post/view_psf.h"
#include "render/view_state.h"

/* Plans view v from scene s; the Hubble PSFs it makes go into kernels,
 * shared by the views that ask for the same one. v is zeroed before. */
orr_status orr_plan_view(view_state *v, const orr_scene *s, orr_psf_kernels *kernels, orr_error *err);

/* The frame's part of planned view v: its report rep, the camera (a path,
 * the observer's sky frame or none, a stereo eye's camera and principal
 * point), motion blur's shutter cameras, the grading as planned. */
orr_status orr_view_begin_frame(view_state *v, const orr_sky_frame *observer, orr_vec3 observer_velocity,
                                const orr_frame_time *when, orr_render_report *rep, orr_error *err);

/* Re-grades view f's final planes (NAME.fits, after the PSF) with the
 * white level white, as animation.white_smoothing does. */
void orr_view_regrade_final(view_files *f, double white);

/* Frees what orr_plan_view made (a view zeroed or partly planned too). */
void orr_view_free(view_state *v);

#endif
