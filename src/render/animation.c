#include "render/animation.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "encode/atomic.h"
#include "render/sequence_open.h"
#include "source/partition.h"

/* Where frame markers live, inside each view's output folder. */
#define MARKER_DIR ".orrery-frames"
#define MARKER_MAGIC "orrery-frame 1"
#define MARKER_MAX_FILES 32

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

int orr_frame_digits(long nframes)
{
    int digits = 4;
    for (long top = 10000; nframes - 1 >= top && digits < 18; top *= 10)
        digits++;
    return digits;
}

orr_status orr_frame_name(const char *name, long frame, long nframes, char *out, size_t size, orr_error *err)
{
    int n = nframes <= 1 ? snprintf(out, size, "%s", name)
                         : snprintf(out, size, "%s_%0*ld", name, orr_frame_digits(nframes), frame);
    if (n < 0 || (size_t)n >= size)
        return orr_fail(err, ORR_ERR_USAGE, "output name %s with a frame number is too long", name);
    return ORR_OK;
}

/* ---- frame markers ---- */

typedef struct marker_entry {
    long long size;
    char name[256];
} marker_entry;

typedef struct marker {
    int n;
    marker_entry e[MARKER_MAX_FILES];
} marker;

static orr_status marker_path(const orr_scene *s, char *path, orr_error *err)
{
    int n = snprintf(path, ORR_PATH_MAX, "%s/" MARKER_DIR "/%s.done", s->out_dir, s->out_name);
    if (n < 0 || n >= ORR_PATH_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "frame marker path for %s/%s is too long", s->out_dir, s->out_name);
    return ORR_OK;
}

/* Reads a marker; 0 when there is none or it is not one (a partial write is
 * impossible: markers are renamed into place). */
static int read_marker(const char *path, marker *m)
{
    m->n = 0;
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    char line[512];
    int ok = fgets(line, sizeof line, f) && strncmp(line, MARKER_MAGIC, strlen(MARKER_MAGIC)) == 0;
    while (ok && m->n < MARKER_MAX_FILES && fgets(line, sizeof line, f)) {
        marker_entry *e = &m->e[m->n];
        if (sscanf(line, "%lld %255[^\n]", &e->size, e->name) == 2)
            m->n++;
    }
    fclose(f);
    return ok && m->n > 0;
}

/* Whether every file the marker lists is in dir with the size it had. */
static int marker_holds(const marker *m, const char *dir)
{
    for (int i = 0; i < m->n; i++) {
        char path[ORR_PATH_MAX];
        struct stat st;
        if (snprintf(path, sizeof path, "%s/%s", dir, m->e[i].name) >= (int)sizeof path ||
            stat(path, &st) != 0 || (long long)st.st_size != m->e[i].size)
            return 0;
    }
    return 1;
}

static int view_frame_complete(const orr_scene *s)
{
    char path[ORR_PATH_MAX];
    marker m;
    orr_error ignored;
    return !marker_path(s, path, &ignored) && read_marker(path, &m) && marker_holds(&m, s->out_dir);
}

/* Adds (or updates) the entry for output file `path`. */
static void marker_add(marker *m, const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    struct stat st;
    if (stat(path, &st) != 0 || strlen(name) >= sizeof m->e[0].name)
        return;
    int i = 0;
    while (i < m->n && strcmp(m->e[i].name, name) != 0)
        i++;
    if (i == MARKER_MAX_FILES)
        return;
    if (i == m->n)
        m->n++;
    m->e[i].size = (long long)st.st_size;
    snprintf(m->e[i].name, sizeof m->e[i].name, "%s", name);
}

/* Records the view's outputs of this frame. A compose keeps what the render
 * recorded and updates the pictures it rewrote. */
static orr_status write_marker(const orr_scene *s, const orr_render_report *rep, int keep_old, orr_error *err)
{
    char dir[ORR_PATH_MAX], path[ORR_PATH_MAX];
    if (snprintf(dir, sizeof dir, "%s/" MARKER_DIR, s->out_dir) >= (int)sizeof dir)
        return orr_fail(err, ORR_ERR_USAGE, "frame marker folder in %s: path too long", s->out_dir);
    orr_status st = marker_path(s, path, err);
    if (st)
        return st;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return orr_fail(err, ORR_ERR_IO, "%s: cannot create the frame marker folder: %s", dir, strerror(errno));
    marker m;
    if (!keep_old || !read_marker(path, &m))
        m.n = 0;
    for (int i = 0; i < rep->noutputs; i++)
        marker_add(&m, rep->outputs[i]);
    orr_atomic_file af;
    if ((st = orr_atomic_begin(&af, path, err)))
        return st;
    FILE *f = fopen(af.temp_path, "w");
    int ok = f != NULL && fprintf(f, "%s\n", MARKER_MAGIC) > 0;
    for (int i = 0; ok && i < m.n; i++)
        ok = fprintf(f, "%lld %s\n", m.e[i].size, m.e[i].name) > 0;
    if (f && fclose(f) != 0)
        ok = 0;
    if (!ok) {
        orr_atomic_abort(&af);
        return orr_fail(err, ORR_ERR_IO, "%s: cannot write the frame marker", path);
    }
    return orr_atomic_commit(&af, err);
}

/* ---- the run ---- */

/* Each view's scene for one frame: the view with its frame's output name. */
static orr_status frame_scenes(const orr_scene *const *views, int n, long frame, orr_scene *out, orr_error *err)
{
    for (int k = 0; k < n; k++) {
        out[k] = *views[k];
        orr_status st = orr_frame_name(views[k]->out_name, frame, views[k]->anim_frames, out[k].out_name,
                                       sizeof out[k].out_name, err);
        if (st)
            return st;
    }
    return ORR_OK;
}

static int frame_complete(const orr_scene *scenes, int n)
{
    for (int k = 0; k < n; k++)
        if (!view_frame_complete(&scenes[k]))
            return 0;
    return 1;
}

/* The run's snapshot sequence, when the scene has one: opened once, each
 * frame's particles interpolated from it at the frame's time. */
typedef struct run_input {
    orr_sequence *seq;
    double t0, t1; /* simulation time at the first and last frame */
} run_input;

static orr_status open_run_input(const orr_scene *s, int compose, run_input *ri, orr_error *err)
{
    memset(ri, 0, sizeof *ri);
    if (s->has_anim_time) {
        ri->t0 = s->anim_time[0];
        ri->t1 = s->anim_time[1];
    }
    if (compose || !orr_scene_has_sequence(s))
        return ORR_OK;
    const char *fields[4];
    int nfields = orr_render_fields(s, fields);
    orr_status st = orr_sequence_open_scene(s, fields, nfields, &ri->seq, err);
    if (st)
        return st;
    double first, last;
    orr_sequence_time_range(ri->seq, &first, &last);
    if (!s->has_anim_time) {
        ri->t0 = first;
        ri->t1 = last;
    } else if (!(fmin(ri->t0, ri->t1) >= first && fmax(ri->t0, ri->t1) <= last)) {
        /* Said before any frame is drawn, not at the first frame outside. */
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: animation.time [%g, %g] reaches outside the sequence's snapshots, times %g to %g",
                        s->path, s->anim_time[0], s->anim_time[1], first, last);
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

static orr_status do_frame(const orr_scene *scenes, int n, long frame, const run_input *ri,
                           const orr_animation_options *opt, orr_render_report *reports, orr_error *err)
{
    const orr_scene *s0 = &scenes[0];
    const orr_scene *list[ORR_SCENE_MAX_VIEWS];
    for (int k = 0; k < n; k++)
        list[k] = &scenes[k];
    orr_frame_input in = {orr_frame_at(frame, s0->anim_frames, s0->anim_fps, ri->t0, ri->t1), NULL, opt->parallel};
    orr_status st = opt->compose ? ORR_OK : frame_source(ri, &in.time, opt->parallel, &in.source, err);
    if (!st)
        st = opt->compose ? orr_compose_views(list, n, reports, err)
                          : orr_render_frame(list, n, &in, reports, opt->progress, opt->progress_user, err);
    orr_source_close(in.source);
    if (st && s0->anim_frames > 1)
        return orr_fail_prefix(err, "frame %ld: ", frame);
    /* The writer (rank 0 of several processes) records the frame. */
    int writer = !opt->parallel || opt->parallel->rank == 0;
    for (int k = 0; k < n && !st && s0->anim_frames > 1 && writer; k++)
        st = write_marker(&scenes[k], &reports[k], opt->compose, err);
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

orr_status orr_render_animation(const orr_scene *const *views, int n, const orr_animation_options *opt,
                                orr_render_report *reports, orr_error *err)
{
    if (n < 1 || n > ORR_SCENE_MAX_VIEWS)
        return orr_fail(err, ORR_ERR_USAGE, "%d views: expected 1 to %d", n, ORR_SCENE_MAX_VIEWS);
    const long nframes = views[0]->anim_frames;
    long first, last;
    frame_range(opt, nframes, &first, &last);
    if (opt->first >= nframes)
        return orr_fail(err, ORR_ERR_USAGE, "%s: frame %ld asked for, but the run has %ld frames (0 to %ld)",
                        views[0]->path, opt->first, nframes, nframes - 1);
    const long stride = opt->stride > 0 ? opt->stride : 1;
    orr_scene *scenes = orr_calloc((size_t)n, sizeof *scenes, "frame scenes", err);
    if (!scenes)
        return ORR_ERR_NOMEM;
    run_input ri;
    orr_status st = open_run_input(views[0], opt->compose, &ri, err);
    for (long f = first + opt->start; f <= last && !st; f += stride) {
        if ((st = frame_scenes(views, n, f, scenes, err)))
            break;
        /* A still is always rendered; a compose always re-grades. */
        int skip = nframes > 1 && !opt->force && !opt->compose && frame_complete(scenes, n);
        if (nframes > 1 && !opt->force && !opt->compose && (st = agree_complete(opt->parallel, &skip, err)))
            break;
        if (!skip)
            st = do_frame(scenes, n, f, &ri, opt, reports, err);
        if (!st && opt->done)
            opt->done(opt->done_user, f, skip);
    }
    orr_sequence_close(ri.seq);
    free(scenes);
    return st;
}
