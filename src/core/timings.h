/* Where a frame's time goes: wall and CPU seconds per stage of the render
 * (orrery render --timings; docs/performance.md, "A production frame").
 * The library only measures; the command line prints. */
#ifndef ORR_CORE_TIMINGS_H
#define ORR_CORE_TIMINGS_H

typedef enum orr_stage {
    ORR_STAGE_SETUP,   /* the plan (projections, PSF generation, the sky maps' index: in the first frame a plan
                        * draws) and each frame's views (cameras, the sky frame) */
    ORR_STAGE_SOURCE,  /* opening the input and reading (or generating) its chunks */
    ORR_STAGE_LENGTHS, /* smoothing lengths from the neighbours */
    ORR_STAGE_GATHER,  /* per-particle weights (colour populations), gather into the camera frame, projection */
    ORR_STAGE_DEPOSIT, /* the deposit: points, kernels, a sky map's PSF cores */
    ORR_STAGE_REDUCE,  /* lanes added, MPI reductions, the bright stars chosen */
    ORR_STAGE_PSF,     /* a sky map's spike stars, a flat view's convolution */
    ORR_STAGE_POST,    /* surface brightness, masks, colour synthesis, stretch, colour map, sRGB */
    ORR_STAGE_FITS,    /* encoders: FITS (NAME.fits, NAME.raw.fits) */
    ORR_STAGE_EXR,     /* OpenEXR planes */
    ORR_STAGE_PNG,     /* PNG */
    ORR_STAGE_IMAGE,   /* output.image (OpenImageIO) */
    ORR_STAGE_STEREO,  /* a stereo pair's files, written together */
    ORR_STAGE_COMMIT,  /* the frame's files renamed into place */
    ORR_NSTAGES
} orr_stage;

typedef struct orr_stage_times {
    double wall[ORR_NSTAGES], cpu[ORR_NSTAGES]; /* seconds; cpu: all of the process's threads */
    double total_wall, total_cpu;               /* the whole frame (or run), measured on its own */
    long frames;                                /* frames these are the sum of */
} orr_stage_times;

/* A reading of the clocks: wall (monotonic) and the process's CPU time. */
typedef struct orr_clock {
    double wall, cpu;
} orr_clock;

orr_clock orr_clock_now(void);
/* The calling thread's CPU time. */
double orr_thread_cpu_seconds(void);

/* The stage's short name ("deposit"), or "?" for a bad one. */
const char *orr_stage_name(orr_stage s);

/* Adds the time since *since to stage s (when t is not NULL) and moves
 * *since to now. */
void orr_stage_charge(orr_stage_times *t, orr_stage s, orr_clock *since);
/* The same, shared between stages a and b in the proportion share_a : 1 -
 * share_a (threaded work whose parts interleave: see render.c). */
void orr_stage_charge_split(orr_stage_times *t, orr_stage a, orr_stage b, double share_a, orr_clock *since);

/* Work done on a thread of its own, beside the stages charged since before
 * (a copy of *t taken when the thread started), and charged to stage s
 * while the caller waited for it: of the other stages charged meanwhile,
 * to which the process's clock gave the rest of the thread's CPU seconds,
 * each hands s that share of its CPU and wall seconds, so s has the
 * thread's CPU time in all and the stages still sum to the totals (as
 * orr_stage_charge_split shares interleaved work). */
void orr_stage_charge_beside(orr_stage_times *t, const orr_stage_times *before, orr_stage s, double cpu);

/* Closes a frame measured from start: its totals, frames = 1. */
void orr_stage_times_finish(orr_stage_times *t, orr_clock start);
/* to += from, stage by stage (a run's total). */
void orr_stage_times_add(orr_stage_times *to, const orr_stage_times *from);
/* The stages' sums, to compare with the totals. */
void orr_stage_times_sum(const orr_stage_times *t, double *wall, double *cpu);

/* A frame's stage timings and the clock reading the last stage ended at:
 * each stage is charged the time since then. */
typedef struct orr_frame_timer {
    orr_stage_times times;
    orr_clock at;
} orr_frame_timer;

/* Charges stage s the time since the last stage ended (orr_stage_charge);
 * nothing when t is NULL (not measured). */
static inline void orr_frame_timer_charge(orr_frame_timer *t, orr_stage s)
{
    if (t)
        orr_stage_charge(&t->times, s, &t->at);
}

#endif
