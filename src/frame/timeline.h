/* Where a frame sits in an animation. A scene renders animation.frames
 * frames (one by default); everything that moves (a camera path, the
 * snapshot time of a sequence, a tint along a run) is a function of this. */
#ifndef ORR_FRAME_TIMELINE_H
#define ORR_FRAME_TIMELINE_H

typedef struct orr_frame_time {
    long frame;     /* 0-based frame number */
    long nframes;   /* frames in the whole run (>= 1) */
    double u;       /* position in the run: frame / (nframes - 1), 0 when nframes == 1 */
    double seconds; /* frame / fps: time in the film */
    double time;    /* simulation time drawn in this frame (a sequence's interpolated time;
                     * otherwise the snapshot's own) */
    double interval; /* simulation time from one frame to the next (0 for a single frame, or
                      * when the run's time stands still) */
} orr_frame_time;

/* The frame time of frame `frame` of `nframes` at `fps` frames per second,
 * simulation time running linearly from t0 at the first frame to t1 at the
 * last. */
static inline orr_frame_time orr_frame_at(long frame, long nframes, double fps, double t0, double t1)
{
    orr_frame_time f;
    f.frame = frame;
    f.nframes = nframes;
    f.u = nframes > 1 ? (double)frame / (double)(nframes - 1) : 0.0;
    f.seconds = fps > 0 ? (double)frame / fps : 0.0;
    f.time = t0 + (t1 - t0) * f.u;
    f.interval = nframes > 1 ? (t1 - t0) / (double)(nframes - 1) : 0.0;
    return f;
}

#endif
