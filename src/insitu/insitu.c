/* The in-situ API of orrery.h: a scene loaded once, then one frame rendered
 * from a simulation's arrays at every call. */
#include "orrery.h"

#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/atomic.h"
#include "insitu/insitu_internal.h"
#include "insitu/kept_images.h"
#include "render/plan.h"
#include "render/render.h"
#include "scene/scene.h"
#include "source/arrays.h"

struct orrery_renderer {
    orr_scene_views views;
    orr_run_settings run;      /* what each frame reads of the run (view 0's animation.*; the plan's) */
    orr_source_request source; /* ... and of the input (its chunk size) */
    orr_render_report reports[ORR_SCENE_MAX_VIEWS];
    orr_error err;
    double seconds;
    orr_parallel parallel; /* set by orrery_use_mpi: the ranks that render each frame together */
    int has_parallel;
    _Alignas(max_align_t) unsigned char parallel_user[64]; /* what parallel.user points at (a communicator) */
    int noutputs;
    const char *outputs[ORR_SCENE_MAX_VIEWS * ORR_RENDER_MAX_OUTPUTS];
    orrery_progress_fn progress; /* orrery_set_progress */
    void *progress_user;
    atomic_int cancel;           /* orrery_cancel: the frame's source stops at its next chunk */
    int keep;             /* orrery_keep_images */
    orr_kept_images kept; /* ... the last frame's images */
    /* Made by orrery_open, executed by every orrery_render: the views'
     * projections, kernels, PSFs and sky indices are made once for the
     * simulation's run (render/plan.h). */
    orr_plan *plan;
};

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The caller's overrides after input.insitu=true, so the scene needs no input. */
static const char **with_insitu(const char *const *overrides, int n)
{
    const char **all = calloc((size_t)n + 1, sizeof *all);
    if (!all)
        return NULL;
    all[0] = "input.insitu=true";
    for (int i = 0; i < n; i++)
        all[i + 1] = overrides[i];
    return all;
}

static int finish_open(orrery_renderer *r, orr_status st, orrery_renderer **out, char *msg, size_t msg_size)
{
    if (msg && msg_size)
        snprintf(msg, msg_size, "%s", st ? r->err.msg : "");
    if (st) {
        orr_plan_destroy(r->plan);
        orr_scene_views_free(&r->views); /* after the plan, which points into them */
        free(r);
        return (int)st;
    }
    *out = r;
    return ORRERY_OK;
}

static int open_common(orrery_renderer **out, const char *path, const char *yaml, const char *base_dir,
                       const char *const *overrides, int noverrides, char *msg, size_t msg_size)
{
    *out = NULL;
    orrery_renderer *r = calloc(1, sizeof *r);
    const char **all = with_insitu(overrides, noverrides > 0 ? noverrides : 0);
    if (!r || !all) {
        free(r);
        free(all);
        if (msg && msg_size)
            snprintf(msg, msg_size, "out of memory creating the renderer");
        return ORRERY_ERR_NOMEM;
    }
    int n = (noverrides > 0 ? noverrides : 0) + 1;
    orr_status st = path ? orr_scene_load_views(&r->views, path, all, n, &r->err)
                         : orr_scene_load_views_string(&r->views, yaml, "insitu", base_dir ? base_dir : ".",
                                                       all, n, &r->err);
    for (int k = 0; k < r->views.n && !st; k++) {
        const char *dir = orr_plan_output_place(&r->views.view[k]).dir;
        st = orr_check_output_dir(dir, &r->err);
        orr_remove_stale_temporaries(dir); /* a killed simulation's last frame */
    }
    free(all);
    if (!st) {
        r->run = orr_plan_run_settings(&r->views.view[0]);
        orr_plan_source_request(&r->views.view[0], &r->source);
    }
    const orr_scene *list[ORR_SCENE_MAX_VIEWS];
    for (int k = 0; k < r->views.n; k++)
        list[k] = &r->views.view[k];
    if (!st)
        st = orr_plan_create(&r->plan, list, r->views.n, ORR_PLAN_RENDER, &r->err);
    return finish_open(r, st, out, msg, msg_size);
}

int orrery_open(orrery_renderer **out, const char *scene_path, const char *const *overrides, int noverrides,
                char *msg, size_t msg_size)
{
    if (!out || !scene_path) {
        if (msg && msg_size)
            snprintf(msg, msg_size, "orrery_open: no renderer pointer or scene path");
        return ORRERY_ERR_USAGE;
    }
    return open_common(out, scene_path, NULL, NULL, overrides, noverrides, msg, msg_size);
}

int orrery_open_yaml(orrery_renderer **out, const char *yaml, const char *base_dir,
                     const char *const *overrides, int noverrides, char *msg, size_t msg_size)
{
    if (!out || !yaml) {
        if (msg && msg_size)
            snprintf(msg, msg_size, "orrery_open_yaml: no renderer pointer or YAML text");
        return ORRERY_ERR_USAGE;
    }
    return open_common(out, NULL, yaml, base_dir, overrides, noverrides, msg, msg_size);
}

int orrery_render(orrery_renderer *r, const orr_particle_arrays *p, long frame)
{
    if (!r)
        return ORRERY_ERR_USAGE;
    double t0 = now_seconds();
    r->noutputs = 0;
    orr_kept_clear(&r->kept);
    orr_error_clear(&r->err);
    atomic_store(&r->cancel, 0);
    if (!p || frame < 0)
        return (int)orr_fail(&r->err, ORR_ERR_USAGE, "orrery_render: %s", p ? "negative frame number" : "no particles");
    const orr_run_settings *run = &r->run;
    /* A run at least as long as this frame, and never a still: every frame
     * gets its own name (the plan's: output.name with the frame number). */
    long nframes = run->frames > frame + 1 ? run->frames : frame + 1;
    if (nframes < 2)
        nframes = 2;
    orr_source *src = NULL;
    /* All types: the observer and reference particles may be of types the
     * scene does not draw (the renderer selects input.types). */
    orr_status st =
        orr_arrays_source_open(p, "in-situ particles", (size_t)r->source.input->chunk_size, 0, &src, &r->err);
    if (!st) {
        src->cancel = &r->cancel;
        double t_first = run->has_time ? run->time[0] : p->time;
        double t_last = run->has_time ? run->time[1] : p->time;
        orr_frame_input in = {orr_frame_at(frame, nframes, run->fps, t_first, t_last), src,
                              r->has_parallel ? &r->parallel : NULL, r->keep ? orr_kept_add : NULL, &r->kept};
        st = orr_plan_execute(r->plan, &in, r->reports, r->progress, r->progress_user, &r->err);
    }
    orr_source_close(src);
    if (st) /* a failed frame keeps nothing, not half of its views */
        orr_kept_clear(&r->kept);
    for (int k = 0; k < r->views.n && !st; k++)
        for (int i = 0; i < r->reports[k].noutputs; i++)
            r->outputs[r->noutputs++] = r->reports[k].outputs[i];
    r->seconds = now_seconds() - t0;
    return (int)st;
}

int orr_insitu_set_parallel(orrery_renderer *r, const orr_parallel *par, const void *user, size_t user_size)
{
    if (user_size > sizeof r->parallel_user)
        return (int)orr_fail(&r->err, ORR_ERR_INTERNAL, "parallel context of %zu bytes: at most %zu", user_size,
                             sizeof r->parallel_user);
    memcpy(r->parallel_user, user, user_size);
    r->parallel = *par;
    r->parallel.user = r->parallel_user;
    r->has_parallel = 1;
    return ORRERY_OK;
}

const char *orrery_error(const orrery_renderer *r) { return r ? r->err.msg : "no renderer"; }

int orrery_output_count(const orrery_renderer *r) { return r ? r->noutputs : 0; }

const char *orrery_output(const orrery_renderer *r, int i)
{
    return r && i >= 0 && i < r->noutputs ? r->outputs[i] : NULL;
}

double orrery_render_seconds(const orrery_renderer *r) { return r ? r->seconds : 0; }

int orrery_cancel(orrery_renderer *r)
{
    if (!r)
        return ORRERY_ERR_USAGE;
    atomic_store(&r->cancel, 1);
    return ORRERY_OK;
}

int orrery_set_progress(orrery_renderer *r, orrery_progress_fn fn, void *user)
{
    if (!r)
        return ORRERY_ERR_USAGE;
    r->progress = fn;
    r->progress_user = user;
    return ORRERY_OK;
}

void orrery_close(orrery_renderer *r)
{
    if (r) {
        orr_kept_clear(&r->kept);
        orr_plan_destroy(r->plan);
        orr_scene_views_free(&r->views); /* after the plan, which points into them */
    }
    free(r);
}

size_t orrery_particle_arrays_size(void) { return sizeof(orr_particle_arrays); }

int orrery_keep_images(orrery_renderer *r, int keep)
{
    if (!r)
        return ORRERY_ERR_USAGE;
    r->keep = keep != 0;
    return ORRERY_OK;
}

int orrery_image_count(const orrery_renderer *r) { return r ? r->kept.n : 0; }

static const orr_kept_image *kept_image(const orrery_renderer *r, int i)
{
    return r && i >= 0 && i < r->kept.n ? &r->kept.image[i] : NULL;
}

int orrery_image_size(const orrery_renderer *r, int i, int *width, int *height, int *nplanes)
{
    const orr_kept_image *im = kept_image(r, i);
    if (!im)
        return ORRERY_ERR_USAGE;
    if (width)
        *width = im->width;
    if (height)
        *height = im->height;
    if (nplanes)
        *nplanes = im->nplanes;
    return ORRERY_OK;
}

const float *orrery_image_plane(const orrery_renderer *r, int i, int j, const char **name, const char **unit)
{
    const orr_kept_image *im = kept_image(r, i);
    if (!im || j < 0 || j >= im->nplanes)
        return NULL;
    if (name)
        *name = im->planes[j].name;
    if (unit)
        *unit = im->planes[j].unit;
    return im->planes[j].data;
}

const float *orrery_image_rgb(const orrery_renderer *r, int i)
{
    const orr_kept_image *im = kept_image(r, i);
    return im ? im->rgb : NULL;
}

const char *orrery_image_header(const orrery_renderer *r, int i)
{
    const orr_kept_image *im = kept_image(r, i);
    return im ? im->header : NULL;
}
