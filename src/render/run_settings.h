/* What a run of frames reads of its scene, as the plan compiles it: in a
 * header of its own, so that the plan (plan.h) names it without including
 * the run's driver (animation.h), which calls the plan. */
#ifndef ORR_RENDER_RUN_SETTINGS_H
#define ORR_RENDER_RUN_SETTINGS_H

/* What a run of frames reads of a view's scene (animation.*: a run takes
 * its length, rate and times from its first view), compiled by the plan
 * (orr_plan_run_settings, render/plan.h); it points into the scene. */
typedef struct orr_run_settings {
    const char *scene_path; /* for messages */
    long long frames;       /* animation.frames: frames in the run (1: a still) */
    double fps;             /* animation.fps */
    int has_time;
    double time[2];         /* animation.time: the simulation time at the first and the last frame */
    int white_smoothing;    /* animation.white_smoothing: frames the white level is averaged over */
} orr_run_settings;

#endif
