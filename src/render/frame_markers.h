/* Frame markers: what made each finished frame of a run, so a resumed run
 * skips a frame only when the same settings and inputs made it and its
 * outputs are intact (docs/animation.md). Used by the run driver
 * (animation.c). */
#ifndef ORR_RENDER_FRAME_MARKERS_H
#define ORR_RENDER_FRAME_MARKERS_H

#include <stddef.h>

#include "core/error.h"
#include "render/frame_names.h"
#include "render/report.h"
#include "source/sequence.h"

/* Markers live in DIR/.orrery-frames/NAME.done and begin with the magic. */
#define MARKER_DIR ".orrery-frames"
#define MARKER_MAGIC "orrery-frame"

/* What a view's frames are made from, as its markers record it: compiled
 * by the plan from the view's scene (orr_plan_view_making, render/plan.h),
 * into which it points. */
typedef struct orr_view_making {
    const char *settings;         /* the scene's effective settings text, one "key=value" a line */
    uint64_t settings_digest;     /* ... the digest of the whole text */
    const char *input_file;       /* input.file; NULL when none (a model or a sequence) */
    const char *psf_file;         /* psf.file when the PSF is read from it; else NULL */
    const char *camera_path_file; /* camera.path.file; NULL when none */
} orr_view_making;

/* What determines a view's frames, as the marker's head lines. */
typedef struct orr_view_identity {
    char *head;               /* "version ...\nsettings ...\ninput ...\n", allocated */
    const char *settings;     /* the scene's settings text */
} orr_view_identity;

/* DIR/.orrery-frames/NAME.done for the frame's output folder and name. */
orr_status orr_marker_path(const orr_output_place *at, char *path, orr_error *err);
/* The marker's text (allocated; at most 1 MiB), or NULL when it cannot be read whole. */
char *orr_marker_read(const char *path);
/* The line of text starting with prefix (its length in *len), or NULL. */
const char *orr_marker_find_line(const char *text, const char *prefix, size_t *len);
/* The head lines that say what makes the view's frames (id->head, allocated). */
orr_status orr_view_identity_make(const orr_view_making *m, const orr_sequence *seq, orr_view_identity *id,
                                  orr_error *err);
/* 1 when the view's frame is complete (marker agrees and outputs intact);
 * else 0 and why (empty: never rendered). */
int orr_marker_frame_complete(const orr_output_place *at, const orr_view_identity *id, char *why, size_t size);
/* Records the view's outputs of this frame (compose: orrery compose updates the render's marker with its outputs). */
orr_status orr_marker_write(const orr_output_place *at, const orr_view_identity *id, const orr_render_report *rep,
                            int compose, orr_error *err);
/* Removes the frame's marker before its outputs are redone. */
void orr_marker_remove(const orr_output_place *at);

/* Checks that the frames 0..count-1 of DIR/NAME (named as f says, with
 * exactly f->digits digits) were all made alike, by their markers: the same orrery, scene
 * settings and inputs. Fails naming the first frame made otherwise and
 * how, so that a video never mixes two runs (frames rendered in pieces
 * with --frames and other settings). Frames without a marker are not
 * compared. */
orr_status orr_frames_agree(const char *dir, const char *name, const orr_frame_naming *f, long count,
                            orr_error *err);

#endif
