/* The render driver: scene -> frame -> particle chunks -> splat -> outputs.
 * It holds the hot loop's shape: particles are gathered, transformed into
 * the camera frame and projected in blocks small enough to stay in cache. */
#ifndef ORR_RENDER_RENDER_H
#define ORR_RENDER_RENDER_H

#include <stdint.h>

#include "frame/camera.h"
#include "scene/scene.h"
#include "splat/deposit.h"
#include "splat/plane.h"

#define ORR_RENDER_MAX_OUTPUTS 4

typedef struct orr_render_report {
    char source[ORR_PATH_MAX];   /* what was read */
    uint64_t n_read;             /* particles read from the source */
    uint64_t n_selected;         /* of those, of a selected type */
    uint64_t n_nonfinite;        /* skipped for a non-finite position or weight */
    orr_deposit_stats deposit;   /* weights deposited, off the image, culled */
    double sim_time;
    double white;                /* the PNG stretch's white level */
    int noutputs;
    char outputs[ORR_RENDER_MAX_OUTPUTS][ORR_PATH_MAX];
} orr_render_report;

/* Called after each chunk with the particles read so far and the total
 * (-1 when the source does not know it). */
typedef void (*orr_progress_fn)(void *user, uint64_t done, int64_t total);

/* The camera a scene describes. */
orr_status orr_scene_camera(const orr_scene *scene, orr_camera *cam, orr_error *err);

/* Opens the scene's particle source (file or built-in model). */
orr_status orr_scene_open_source(const orr_scene *scene, orr_source **out, orr_error *err);

/* Splats every selected particle of src into plane (already allocated at the
 * projection's size) and accumulates the counts into report. */
orr_status orr_splat_source(const orr_scene *scene, const orr_camera *cam, const orr_projection *proj,
                            orr_source *src, orr_plane *plane, orr_render_report *report,
                            orr_progress_fn progress, void *progress_user, orr_error *err);

/* Renders the scene and writes its outputs (FITS and/or PNG in out_dir). */
orr_status orr_render_scene(const orr_scene *scene, orr_render_report *report, orr_progress_fn progress,
                            void *progress_user, orr_error *err);

#endif
