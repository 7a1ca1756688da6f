/* Motion blur (animation.shutter): every particle is drawn as a streak, the
 * path it takes across the image while the shutter is open, so fast stars
 * and a fast camera smear the way a film camera's do instead of strobing.
 *
 * The shutter is open for `shutter` of the frame interval, centred on the
 * frame's time. Over it a particle moves by its velocity (vx, vy, vz) times
 * the simulation time that passes (animation.frame_interval, or the span of
 * animation.time over the frames; zero for a still snapshot, when only the
 * camera moves), and the camera moves along its path (or, from an
 * observer, with the observer particle's velocity). In the camera frame the
 * streak runs from where the camera sees the particle when the shutter
 * opens to where it sees it when the shutter closes; the renderer draws
 * it as m equal samples at the midpoints of m equal steps along that chord,
 * each with 1/m of the particle's weight, so a streak holds exactly the
 * particle's flux and its samples lie at most ORR_BLUR_STEP_PX apart on the
 * image (no gaps for any deposit: even NGP fills every pixel of the
 * streak), up to ORR_BLUR_MAX_SAMPLES samples. A particle that moves less
 * than a pixel stays one sample: the cost grows with the motion, not with
 * the particle count. docs/animation.md#motion-blur. */
#ifndef ORR_PASS_MOTION_BLUR_H
#define ORR_PASS_MOTION_BLUR_H

#include "core/vecmath.h"
#include "frame/camera.h"
#include "frame/project_point.h"
#include "frame/projection.h"
#include "pass/camera_transform.h"

/* Samples a streak gets: one per ORR_BLUR_STEP_PX of its length on the
 * image, at most ORR_BLUR_MAX_SAMPLES (streaks longer than 256 pixels a
 * frame are sampled more sparsely). */
#define ORR_BLUR_STEP_PX 1.0f
#define ORR_BLUR_MAX_SAMPLES 256

typedef struct orr_motion_blur {
    int active;                 /* animation.shutter > 0 */
    double half_time;           /* half the simulation time the shutter is open: a particle moves by
                                 * -v half_time to +v half_time (0: particles held still) */
    orr_camera open, close;     /* the camera when the shutter opens and closes */
    orr_mat3 open_rot, close_rot; /* their world-to-camera rotations */
    orr_projection_kind kind;   /* the view's projection, to measure streaks in pixels */
    orr_proj_consts k;
    float px_per_radian;        /* sky and perspective: pixels per radian at the centre */
} orr_motion_blur;

/* The plan of a view: cameras at shutter open and close, and the
 * particles' half shutter time. proj must be set up. */
void orr_motion_blur_plan(orr_motion_blur *b, double half_time, const orr_camera *open, const orr_camera *close,
                          const orr_projection *proj);

/* The streak's two camera transforms for a periodic copy moved by shift
 * (orr_vec3 0 for the box itself). */
void orr_motion_blur_transforms(const orr_motion_blur *b, orr_vec3 shift, orr_camera_transform *open,
                                orr_camera_transform *close);

/* A particle's streak in the camera frame: where it starts (q0) and the
 * vector to where it ends (s), from its world position p and velocity v
 * (v ignored when the blur's half_time is 0). */
void orr_motion_blur_streak(const orr_motion_blur *b, const orr_camera_transform *open,
                            const orr_camera_transform *close, const float p[3], const float v[3], float q0[3],
                            float s[3]);

/* How many samples a streak from q0 along s is drawn with: its length on
 * the image over ORR_BLUR_STEP_PX, rounded up, 1 to ORR_BLUR_MAX_SAMPLES. */
int orr_motion_blur_samples(const orr_motion_blur *b, const float q0[3], const float s[3]);

#endif
