/* The render driver: scene -> frame -> particle chunks -> splat -> outputs.
 * Several views of one scene (a dome master and a panorama, say) are
 * rendered from one pass over the particles: each chunk is splatted into
 * every view's plane before the next is read. Particles are gathered,
 * moved into the camera frame and projected in blocks small enough to stay
 * in cache. */
#ifndef ORR_RENDER_RENDER_H
#define ORR_RENDER_RENDER_H

#include <stdint.h>

#include "frame/camera.h"
#include "frame/observer.h"
#include "scene/scene.h"
#include "splat/deposit.h"
#include "splat/plane.h"

#define ORR_RENDER_MAX_OUTPUTS 10 /* stereo.mode: separate writes each format twice */

typedef struct orr_render_report {
    char source[ORR_PATH_MAX];   /* what was read */
    uint64_t n_read;             /* particles read from the source */
    uint64_t n_selected;         /* of those, of a selected type (the observer excluded) */
    uint64_t n_nonfinite;        /* skipped for a non-finite position or weight */
    uint64_t n_stereo_skipped;   /* omni-directional stereo: not drawn, inside the eye circle
                                  * (counted in deposit.n_culled too) */
    orr_deposit_stats deposit;   /* weights deposited, off the image, culled (with colour: of X) */
    orr_deposit_stats deposit_y; /* with colour: the same for Y, the luminance */
    double sim_time;
    double white;                /* the PNG stretch's white level (with colour: Y0) */
    int has_sky_frame;           /* an observer frame was built */
    orr_sky_frame sky;           /* ... this one */
    orr_camera camera;           /* the camera used (a stereo eye's, for an eye) */
    double stereo_convergence;   /* perspective stereo: the zero-parallax distance used */
    int noutputs;
    char outputs[ORR_RENDER_MAX_OUTPUTS][ORR_PATH_MAX];
} orr_render_report;

/* Called after each chunk with the particles read so far and the total
 * (-1 when the source does not know it). */
typedef void (*orr_progress_fn)(void *user, uint64_t done, int64_t total);

/* Opens the scene's particle source (file or built-in model), asking for
 * the given extra fields only (NULL: all). */
orr_status orr_scene_open_source(const orr_scene *scene, const char *const *fields, int nfields,
                                 orr_source **out, orr_error *err);

/* Renders views[0..n) of one scene (they share input.* and observer.*) and
 * writes their outputs; reports[i] describes view i. */
orr_status orr_render_views(const orr_scene *const *views, int n, orr_render_report *reports,
                            orr_progress_fn progress, void *progress_user, orr_error *err);

/* Re-grades views[0..n) from the raw planes a render with output.raw wrote
 * (DIR/NAME.raw.fits): applies the scene's PSF, colour synthesis or stretch
 * and colour map as they are now, and writes DIR/NAME.png. Nothing is read
 * from the particles. */
orr_status orr_compose_views(const orr_scene *const *views, int n, orr_render_report *reports, orr_error *err);

/* Renders one scene: orr_render_views with one view. */
orr_status orr_render_scene(const orr_scene *scene, orr_render_report *report, orr_progress_fn progress,
                            void *progress_user, orr_error *err);

#endif
