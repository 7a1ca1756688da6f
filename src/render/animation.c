#include "render/animation.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/digest.h"
#include "core/numbers.h"
#include "core/atomic.h"
#include "render/frame_markers.h"
#include "render/plan.h"
#include "render/sequence_open.h"
#include "scene/scene.h" /* the frame scenes it holds (copies it makes and frees; the plan reads them) */
#include "source/partition.h"

/* Where frame markers live, inside each view's output folder. */

orr_animation_options orr_animation_defaults(void)
{
    orr_animation_options o = {0};
    o.first = 0;
    o.last = -1;
    o.stride = 1;
    o.start = 0;
    return o;
}

/* The frames [first, last] of the run that opt asks for, clamped. */
static void frame_range(const orr_animation_options *opt, long nframes, long *first, long *last)
{
    *first = opt->first > 0 ? opt->first : 0;
    *last = opt->last < 0 || opt->last >= nframes ? nframes - 1 : opt->last;
}

long orr_animation_count(const orr_animation_options *opt, long nframes)
{
    long first, last;
    frame_range(opt, nframes, &first, &last);
    long stride = opt->stride > 0 ? opt->stride : 1;
    first += opt->start;
    return first > last ? 0 : (last - first) / stride + 1;
}

/* ---- the run ---- */

/* Each view's scene for one frame: the view with its frame's output name. */
static orr_status frame_scenes(const orr_scene *const *views, int n, long frame, orr_scene *out, orr_error *err)
{
    for (int k = 0; k < n; k++) {
        orr_status st = orr_plan_frame_scene(views[k], frame, &out[k], err); /* frees the last frame's */
        if (st)
            return st;
    }
    return ORR_OK;
}

/* Whether every view's frame is complete; else why (empty: never rendered). */
static int frame_complete(const orr_scene *scenes, const orr_view_identity *ids, int n, char *why, size_t size)
{
    for (int k = 0; k < n; k++) {
        const orr_output_place at = orr_plan_output_place(&scenes[k]);
        if (!orr_marker_frame_complete(&at, &ids[k], why, size))
            return 0;
    }
    return 1;
}

/* The run's snapshot sequence, when the scene has one: opened once, each
 * frame's particles interpolated from it at the frame's time. */
typedef struct run_input {
    orr_sequence *seq;
    double t0, t1; /* simulation time at the first and last frame */
} run_input;

static orr_status open_run_input(const orr_run_settings *run, const orr_source_request *req, int compose,
                                 run_input *ri, orr_error *err)
{
    memset(ri, 0, sizeof *ri);
    if (run->has_time) {
        ri->t0 = run->time[0];
        ri->t1 = run->time[1];
    }
    if (compose || !orr_input_has_sequence(req->input))
        return ORR_OK;
    orr_status st = orr_sequence_open_request(req, req->fields, req->nfields, &ri->seq, err);
    if (st)
        return st;
    double first, last;
    orr_sequence_time_range(ri->seq, &first, &last);
    if (!run->has_time) {
        ri->t0 = first;
        ri->t1 = last;
    } else if (!(fmin(ri->t0, ri->t1) >= first && fmax(ri->t0, ri->t1) <= last)) {
        /* Said before any frame is drawn, not at the first frame outside. */
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: animation.time [%g, %g] reaches outside the sequence's snapshots, times %g to %g",
                        run->scene_path, run->time[0], run->time[1], first, last);
    }
    return ORR_OK;
}

/* The frame's particles from the sequence (this process's share of them
 * when several render together), or NULL: the scene's own input. */
static orr_status frame_source(const run_input *ri, const orr_frame_time *when, const orr_parallel *par,
                               orr_source **out, orr_error *err)
{
    *out = NULL;
    if (!ri->seq)
        return ORR_OK;
    orr_source *src = NULL;
    orr_status st = orr_sequence_source_at(ri->seq, when->time, &src, err);
    if (!st && par && par->nranks > 1)
        return orr_source_partition(src, par->rank, par->nranks, out, err);
    *out = src;
    return st;
}

/* The run's plan (render/plan.h), made for the first frame that is drawn
 * (a resumed run whose frames are all complete plans nothing) and kept for
 * the others: the PSF, the kernels, a sky map's index are made once. */
static orr_status run_plan(orr_plan **plan, const orr_scene *const *views, int n, int compose, orr_error *err)
{
    return *plan ? ORR_OK : orr_plan_create(plan, views, n, compose ? ORR_PLAN_COMPOSE : ORR_PLAN_RENDER, err);
}

static orr_status do_frame(orr_plan *plan, const orr_scene *scenes, const orr_view_identity *ids, int n,
                           long frame, const orr_run_settings *run, const run_input *ri,
                           const orr_animation_options *opt, orr_render_report *reports, orr_error *err)
{
    int writer = !opt->parallel || opt->parallel->rank == 0; /* rank 0 of several processes writes */
    for (int k = 0; k < n; k++) {
        const orr_output_place at = orr_plan_output_place(&scenes[k]);
        if (writer && !opt->compose && run->frames > 1)
            orr_marker_remove(&at);
    }
    orr_frame_input in = {.time = orr_frame_at(frame, run->frames, run->fps, ri->t0, ri->t1),
                          .parallel = opt->parallel};
    const orr_compose_frame recompose = {.time = in.time, .white = NULL};
    orr_status st = opt->compose ? ORR_OK : frame_source(ri, &in.time, opt->parallel, &in.source, err);
    if (!st)
        st = opt->compose ? orr_plan_compose(plan, &recompose, reports, err)
                          : orr_plan_execute(plan, &in, reports, opt->progress, opt->progress_user, err);
    orr_source_close(in.source);
    if (st && run->frames > 1)
        return orr_fail_prefix(err, "frame %ld: ", frame);
    for (int k = 0; k < n && !st && run->frames > 1 && writer; k++) {
        const orr_output_place at = orr_plan_output_place(&scenes[k]);
        st = orr_marker_write(&at, &ids[k], &reports[k], opt->compose, err);
    }
    return st;
}

/* Whether every process found the frame complete: they must agree, since
 * they render it together. */
static orr_status agree_complete(const orr_parallel *par, int *complete, orr_error *err)
{
    if (!par || par->nranks <= 1)
        return ORR_OK;
    double votes = *complete;
    orr_status st = par->allreduce_sum(par->user, &votes, 1, err);
    *complete = votes == par->nranks;
    return st;
}

/* What determines each view's frames in this run; and, once per run, the
 * removal of the temporary files a killed earlier run left in its folders. */
static orr_status run_identities(const orr_scene *const *views, int n, const run_input *ri, int compose,
                                 orr_view_identity *ids, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) {
        char markers[ORR_PATH_MAX];
        const char *dir = orr_plan_output_place(views[k]).dir;
        orr_remove_stale_temporaries(dir);
        if (snprintf(markers, sizeof markers, "%s/" MARKER_DIR, dir) < (int)sizeof markers)
            orr_remove_stale_temporaries(markers);
        const orr_view_making making = orr_plan_view_making(views[k]);
        st = compose ? ORR_OK : orr_view_identity_make(&making, ri->seq, &ids[k], err);
    }
    return st;
}

static void free_identities(orr_view_identity *ids, int n)
{
    for (int k = 0; k < n; k++)
        free(ids[k].head);
}

orr_status orr_render_animation(const orr_scene *const *views, int n, const orr_animation_options *opt,
                                orr_render_report *reports, orr_error *err)
{
    if (n < 1 || n > ORR_SCENE_MAX_VIEWS)
        return orr_fail(err, ORR_ERR_USAGE, "%d views: expected 1 to %d", n, ORR_SCENE_MAX_VIEWS);
    const orr_run_settings run = orr_plan_run_settings(views[0]);
    const long nframes = run.frames;
    long first, last;
    frame_range(opt, nframes, &first, &last);
    if (opt->first >= nframes)
        return orr_fail(err, ORR_ERR_USAGE, "%s: frame %ld asked for, but the run has %ld frames (0 to %ld)",
                        run.scene_path, opt->first, nframes, nframes - 1);
    const long stride = opt->stride > 0 ? opt->stride : 1;
    orr_scene *scenes = orr_calloc((size_t)n, sizeof *scenes, "frame scenes", err);
    if (!scenes)
        return ORR_ERR_NOMEM;
    orr_view_identity ids[ORR_SCENE_MAX_VIEWS] = {{0}};
    orr_plan *plan = NULL;
    run_input ri;
    orr_source_request source;
    orr_plan_source_request(views[0], &source);
    orr_status st = open_run_input(&run, &source, opt->compose, &ri, err);
    if (!st)
        st = run_identities(views, n, &ri, opt->compose, ids, err);
    /* A still is always rendered; a compose always re-grades. */
    const int resumable = nframes > 1 && !opt->force && !opt->compose;
    long capped[ORR_SCENE_MAX_VIEWS] = {0}, capped_first[ORR_SCENE_MAX_VIEWS];
    for (int k = 0; k < n; k++)
        capped_first[k] = -1;
    for (long f = first + opt->start; f <= last && !st; f += stride) {
        if ((st = frame_scenes(views, n, f, scenes, err)))
            break;
        char why[512] = "";
        int skip = resumable && frame_complete(scenes, ids, n, why, sizeof why);
        if (resumable && (st = agree_complete(opt->parallel, &skip, err)))
            break;
        if (!skip && (st = run_plan(&plan, views, n, opt->compose, err)) && nframes > 1)
            orr_fail_prefix(err, "frame %ld: ", f);
        if (!skip && !st)
            st = do_frame(plan, scenes, ids, n, f, &run, &ri, opt, reports, err);
        for (int k = 0; k < n && !skip && !st; k++)
            if (reports[k].stars_capped && capped[k]++ == 0)
                capped_first[k] = f;
        if (!st && !skip && !opt->compose && opt->timed)
            opt->timed(opt->timed_user, f, &reports[0].times);
        if (!st && opt->done)
            opt->done(opt->done_user, f, skip, skip || !why[0] ? NULL : why);
    }
    for (int k = 0; k < n; k++) {
        reports[k].stars_capped_frames = capped[k];
        reports[k].stars_capped_first = capped_first[k];
    }
    orr_plan_destroy(plan);
    free_identities(ids, n);
    orr_sequence_close(ri.seq);
    for (int k = 0; k < n; k++)
        orr_scene_free(&scenes[k]);
    free(scenes);
    return st;
}

/* ---- a white level that follows the scene ---- */

/* The white level frame f's render graded its picture with, from its
 * marker; NaN when there is none (a frame not rendered). */
static double rendered_white(const orr_scene *frame)
{
    char path[ORR_PATH_MAX];
    orr_error ignored;
    const orr_output_place at = orr_plan_output_place(frame);
    char *marker = orr_marker_path(&at, path, &ignored) ? NULL : orr_marker_read(path);
    size_t len;
    const char *line = marker ? orr_marker_find_line(marker, "white ", &len) : NULL;
    double white = line ? orr_strtod(line + 6, NULL) : NAN;
    free(marker);
    return white > 0 ? white : NAN;
}

/* The geometric mean of the whites of the frames within half a window of
 * f that have one: in log space, so a white twice as high and one half as
 * high cancel. */
static double smoothed_white(const double *whites, long nframes, long f, int window)
{
    double sum = 0;
    int n = 0;
    for (long g = f - window / 2; g <= f + window / 2; g++)
        if (g >= 0 && g < nframes && isfinite(whites[g])) {
            sum += log(whites[g]);
            n++;
        }
    return n ? exp(sum / n) : NAN;
}

/* Re-grades frame f of view s with white level `white`, from its FITS
 * planes, and records the new picture in the frame's marker. */
static orr_status regrade_frame(orr_plan *plan, const orr_scene *s, long f, double white, orr_render_report *rep,
                                orr_error *err)
{
    orr_scene *frame = calloc(1, sizeof *frame); /* zeroed: frame_scenes frees what it holds */
    if (!frame)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a frame's scene");
    orr_status st = frame_scenes(&s, 1, f, frame, err); /* where its marker is */
    const orr_run_settings run = orr_plan_run_settings(s);
    const orr_compose_frame regrade = {.time = orr_frame_at(f, run.frames, run.fps, 0, 0), .white = &white};
    if (!st)
        st = orr_plan_compose(plan, &regrade, rep, err);
    orr_view_identity unused = {NULL, NULL};
    const orr_output_place at = orr_plan_output_place(frame);
    if (!st)
        st = orr_marker_write(&at, &unused, rep, 1, err);
    orr_scene_free(frame);
    free(frame);
    return st ? orr_fail_prefix(err, "frame %ld: smoothing the white level: ", f) : ORR_OK;
}

orr_status orr_animation_smooth_whites(const orr_scene *const *views, int n, orr_render_report *reports,
                                       orr_error *err)
{
    orr_status st = ORR_OK;
    for (int k = 0; k < n && !st; k++) {
        const orr_scene *s = views[k];
        const orr_run_settings run = orr_plan_run_settings(s);
        const long nframes = run.frames;
        if (run.white_smoothing <= 1 || nframes <= 1)
            continue;
        double *whites = orr_calloc((size_t)nframes, sizeof *whites, "white levels", err);
        orr_scene *frame = calloc(1, sizeof *frame); /* zeroed: frame_scenes frees what it holds */
        if (!whites || !frame)
            st = ORR_ERR_NOMEM;
        for (long f = 0; f < nframes && !st; f++)
            if (!(st = frame_scenes(&s, 1, f, frame, err)))
                whites[f] = rendered_white(frame);
        /* One plan re-grades every frame: the white level is a grading key,
         * which the plan does not hold. */
        orr_plan *plan = NULL;
        for (long f = 0; f < nframes && !st; f++)
            if (isfinite(whites[f]) && !(st = run_plan(&plan, &s, 1, 1, err)))
                st = regrade_frame(plan, s, f, smoothed_white(whites, nframes, f, run.white_smoothing), &reports[k],
                                   err);
        orr_plan_destroy(plan);
        if (frame)
            orr_scene_free(frame);
        free(frame);
        free(whites);
    }
    return st;
}
