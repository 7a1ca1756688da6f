/* Runs of frames: a scene with animation.frames > 1 renders one frame after
 * another, each with its own output names (NAME_0007.png), skipping frames
 * an earlier run finished. docs/animation.md. */
#ifndef ORR_RENDER_ANIMATION_H
#define ORR_RENDER_ANIMATION_H

#include "pass/progress.h"
#include "render/frame_names.h"
#include "render/report.h"
#include "render/run_settings.h"

/* Told after each frame of the run: rendered (skipped = 0) or found complete
 * from an earlier run (skipped = 1). redone is NULL, or why an earlier
 * run's frame was not taken: its scene settings, an input or an output
 * changed since ("image.width changed from 320 to 640"). */
typedef void (*orr_frame_done_fn)(void *user, long frame, int skipped, const char *redone);

typedef struct orr_animation_options {
    long first, last;   /* frames to do, inclusive; clamped to the run (last < 0: to the end) */
    long stride, start; /* of those, every stride-th from first + start: how frame-parallel
                         * jobs share a run (stride 1, start 0: all) */
    int force;          /* redo frames that are already complete */
    int compose;        /* re-grade the frames from their raw planes (orrery compose) */
    orr_frame_done_fn done;
    void *done_user;
    orr_progress_fn progress; /* particles read within a frame */
    void *progress_user;
    const orr_parallel *parallel; /* several processes render each frame together (MPI); NULL: one */
    /* Told after each frame rendered (not skipped, not composed) where its
     * time went (core/timings.h); NULL: not told. */
    void (*timed)(void *user, long frame, const orr_stage_times *times);
    void *timed_user;
} orr_animation_options;

/* Options for every frame of the run, one job. */
orr_animation_options orr_animation_defaults(void);

/* The frames opt selects of a run of nframes: how many, and the first. */
long orr_animation_count(const orr_animation_options *opt, long nframes);

/* Renders (or composes) the frames of views[0..n) that opt selects. After
 * a frame's outputs are all written, a marker in DIR/.orrery-frames/
 * records what made them (orrery's version, the scene's effective
 * settings, the identity of each input file) and each output's size and
 * checksum; a later run skips a frame whose marker says what this run
 * would write and whose outputs are all as written, and redoes it
 * otherwise, so an interrupted run loses at most the frame in progress and
 * a run with other settings never keeps an old frame. reports[k]
 * describes view k's last frame. */
orr_status orr_render_animation(const orr_scene *const *views, int n, const orr_animation_options *opt,
                                orr_render_report *reports, orr_error *err);

/* animation.white_smoothing: once a run's frames are rendered (each graded
 * with its own automatic white level, which its marker records), re-grades
 * every frame's picture from its FITS planes with the geometric mean of the
 * white levels of the white_smoothing frames around it, so the exposure
 * follows the scene without flickering, and updates the markers. Views
 * without smoothing, and stills, are left as they are. Run it after the
 * whole run (all jobs) is rendered: each frame's level needs its
 * neighbours'. */
orr_status orr_animation_smooth_whites(const orr_scene *const *views, int n, orr_render_report *reports,
                                       orr_error *err);

#endif
