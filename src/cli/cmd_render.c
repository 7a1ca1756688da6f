/* orrery render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--frames A:B] [--force] [--jobs N] [--timings]
 *               [--quiet]
 * orrery compose SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--frames A:B] [--quiet]
 * The two take the same arguments: compose is the second half of render. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/cli.h"
#include "render/animation.h"
#include "render/plan.h"
#include "scene/scene.h"

static const char render_help[] =
    "usage: orrery render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--frames A:B] [--force]\n"
    "                     [--jobs N] [--timings] [--quiet]\n"
    "\n"
    "Renders the scene's particles to a FITS file (linear float planes: the\n"
    "weight, or CIE X, Y, Z with colour.populations) and a PNG (stretched and\n"
    "colour-mapped, or the colour synthesis) named after the scene, in\n"
    "output.dir; with output.raw also NAME.raw.fits, the planes before any\n"
    "PSF, for `orrery compose`. A scene with views (e.g. a dome master and a\n"
    "panorama) renders all of them from one pass over the particles.\n"
    "\n"
    "A scene with animation.frames > 1 renders a run of frames, each named\n"
    "NAME_0000.png, NAME_0001.png, ...; frames an earlier run completed are\n"
    "skipped (a missing or truncated output is redone), so an interrupted run\n"
    "can simply be started again.\n"
    "\n"
    "  --set KEY=VALUE   override a scene key, e.g. --set camera.fov=60,\n"
    "                    --set camera.position=[0,0,100] (repeatable; applied in order);\n"
    "                    --set views.NAME.KEY=VALUE changes one view\n"
    "  -o, --output DIR  write the outputs into DIR (overrides output.dir; created if missing)\n"
    "  --frames A:B      render frames A to B of the run (0-based, inclusive; A: or :B\n"
    "                    leave an end open; a single number is one frame)\n"
    "  --force           render frames again even when their outputs are complete\n"
    "  --jobs N          render frames in N processes at once (each takes every N-th frame)\n"
    "  --timings         print where each frame's time went, wall and CPU seconds per stage\n"
    "                    (source, gather+project, deposit, PSF, colour/post, each encoder, ...),\n"
    "                    and for a run a line a frame and the total; printed even with --quiet\n"
    "  -q, --quiet       no progress or summary, only errors\n"
    "  -h, --help        this text\n"
    "\n"
    "Scene keys: docs/scenes.md. Exit status: 0 success, 1 runtime failure, 2 usage error.\n";

static const char compose_help[] =
    "usage: orrery compose SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--frames A:B] [--quiet]\n"
    "\n"
    "Re-grades a render without rendering again: reads the raw planes that\n"
    "`orrery render` wrote with output.raw: true (DIR/NAME.raw.fits), applies\n"
    "the scene's colour synthesis (colour.synthesis.*) or stretch and colour\n"
    "map (output.*) as they are now, and writes DIR/NAME.png. Change the\n"
    "grading with --set, e.g.\n"
    "  orrery compose futuresky.yaml --set colour.synthesis.stretch=asinh\n"
    "A flat view's raw planes are taken before its PSF, which compose applies\n"
    "as set now; a sky map's PSF, and a flat view's that draws its stars one\n"
    "by one (psf.fwhm with psf.kind hst or file), is drawn into its raw planes\n"
    "as it renders, so --set psf.* is refused there: render again to change it.\n"
    "\n"
    "  --set KEY=VALUE   override a scene key (repeatable; applied in order)\n"
    "  -o, --output DIR  the folder the render wrote to (overrides output.dir; created if missing)\n"
    "  --frames A:B      re-grade only these frames of a run (default: all)\n"
    "  -q, --quiet       nothing but errors\n"
    "  -h, --help        this text\n"
    "\n"
    "Exit status: 0 success, 1 runtime failure, 2 usage error.\n";

static void print_report(const orr_render_report *r, const char *view, double seconds)
{
    if (view[0])
        printf("view %s: ", view);
    printf("read %llu particles from %s in %.2f s (%.3g particles/s)\n", (unsigned long long)r->n_read,
           r->source, seconds, seconds > 0 ? r->n_read / seconds : 0.0);
    /* Sky maps cull what is outside their field (below a dome's horizon);
     * flat cameras what is behind them. */
    printf("  selected %llu; skipped %llu non-finite; %llu not drawn (%s)\n", (unsigned long long)r->n_selected,
           (unsigned long long)r->n_nonfinite, (unsigned long long)r->deposit.n_culled,
           r->has_sky_frame ? "outside the sky map" : "behind the camera");
    printf("  weight in the image %.9g, off the image %.9g, not drawn %.9g\n", r->deposit.deposited,
           r->deposit.outside, r->deposit.culled);
    if (r->n_lengths_bounded)
        printf("  the glow's lengths: %llu of %llu left at a bound, their own kernel the wider (no full neighbour "
               "search)\n", (unsigned long long)r->n_lengths_bounded, (unsigned long long)r->n_lengths);
    if (r->n_stars)
        printf("  drew %llu stars spawned from the particles (stars.*)\n", (unsigned long long)r->n_stars);
    if (r->n_stereo_skipped)
        printf("  of those not drawn, %llu inside the stereo eye circle (closer to the viewer than half the eye "
               "separation, horizontally)\n",
               (unsigned long long)r->n_stereo_skipped);
    if (r->n_replicas)
        printf("  periodic box drawn %d times; out of view or beyond the radius, skipped whole: %llu chunk copies; "
               "skipped: %llu of %llu blocks (%.1f %%, counted as not drawn)\n",
               r->n_replicas, (unsigned long long)r->n_replicas_culled, (unsigned long long)r->n_blocks_culled,
               (unsigned long long)r->n_blocks, r->n_blocks ? 100.0 * r->n_blocks_culled / r->n_blocks : 0.0);
    if (r->has_sky_frame)
        printf("  observer at (%.6g, %.6g, %.6g); north (b = 90) along (%.4f, %.4f, %.4f)\n", r->sky.origin.x,
               r->sky.origin.y, r->sky.origin.z, r->sky.z.x, r->sky.z.y, r->sky.z.z);
    for (int i = 0; i < r->noutputs; i++)
        printf("  wrote %s\n", r->outputs[i]);
}

static void print_compose_report(const orr_render_report *r, const char *view)
{
    if (view[0])
        printf("view %s: ", view);
    printf("composed from %s (white %g)\n", r->source, r->white);
    for (int i = 0; i < r->noutputs; i++)
        printf("  wrote %s\n", r->outputs[i]);
}

/* --frames: "A:B", "A:", ":B" or "A". */
static int parse_frames(const char *text, long *first, long *last)
{
    long long a = 0, b = -1;
    const char *colon = strchr(text, ':');
    char head[32];
    size_t len = colon ? (size_t)(colon - text) : strlen(text);
    if (len >= sizeof head)
        return 0;
    memcpy(head, text, len);
    head[len] = '\0';
    if (len > 0 && !cli_parse_count(head, 0, 100000000, &a))
        return 0;
    if (!colon)
        b = a;
    else if (colon[1] != '\0' && !cli_parse_count(colon + 1, 0, 100000000, &b))
        return 0;
    if (!colon && len == 0)
        return 0;
    if (b >= 0 && b < a)
        return 0;
    *first = (long)a;
    *last = (long)b;
    return 1;
}

/* Frames done, on stderr: a line rewritten in place on a terminal, a plain
 * line per frame otherwise. */
typedef struct frame_progress {
    int enabled, tty;
    long total, rendered, skipped, redone;
    double start;
} frame_progress;

/* Says why an earlier run's frame was rendered again: the first few of a
 * run, so that a changed setting redoing thousands of frames is one note,
 * not thousands. */
#define REDONE_NOTES 3

static void note_redone(frame_progress *p, long frame, const char *why)
{
    if (++p->redone > REDONE_NOTES || !p->enabled)
        return;
    fprintf(stderr, "%sorrery: frame %ld of an earlier run rendered again: %s%s\n", p->tty ? "\r" : "", frame, why,
            p->redone == REDONE_NOTES ? " (further such frames are not listed)" : "");
}

static void frame_progress_done(void *user, long frame, int skipped, const char *redone)
{
    frame_progress *p = user;
    if (skipped)
        p->skipped++;
    else
        p->rendered++;
    if (redone)
        note_redone(p, frame, redone);
    if (!p->enabled)
        return;
    long done = p->rendered + p->skipped;
    double elapsed = cli_now() - p->start;
    double rate = p->rendered / (elapsed > 1e-9 ? elapsed : 1e-9);
    double left = rate > 0 ? (p->total - done) / rate : 0;
    if (p->tty) {
        int width = 30, filled = p->total > 0 ? (int)(width * done / p->total) : width;
        char bar[32];
        for (int i = 0; i < width; i++)
            bar[i] = i < filled ? '#' : '.';
        bar[width] = '\0';
        fprintf(stderr, "\r  [%s] %ld/%ld frames, %.2f frames/s, %.0f s left   ", bar, done, p->total, rate, left);
        if (done == p->total)
            fputc('\n', stderr);
    } else {
        fprintf(stderr, "  frame %ld %s (%ld of %ld, %.2f frames/s, %.0f s left)\n", frame,
                skipped ? "already complete, skipped" : "done", done, p->total, rate, left);
    }
}

/* With --jobs: each child tells the parent of every frame it finishes with
 * one record on a pipe (smaller than PIPE_BUF, so records never interleave). */
typedef struct frame_record {
    long frame;
    int skipped, redone;
    char why[256];
} frame_record;

static void frame_done_to_pipe(void *user, long frame, int skipped, const char *redone)
{
    int fd = *(int *)user;
    frame_record r = {frame, skipped, redone != NULL, ""};
    if (redone)
        snprintf(r.why, sizeof r.why, "%s", redone);
    ssize_t w;
    do
        w = write(fd, &r, sizeof r);
    while (w < 0 && errno == EINTR);
}

/* Renders the run in `jobs` processes, frame-parallel; the parent shows the
 * progress. Returns the first failing child's exit code. */
static int render_jobs(const orr_scene *const *list, int n, orr_animation_options opt, int jobs,
                       frame_progress *fp)
{
    int fds[2];
    if (pipe(fds) != 0) {
        fprintf(stderr, "orrery: error: cannot create a pipe for --jobs: %s\n", strerror(errno));
        return EXIT_RUNTIME;
    }
    fflush(NULL);
    pid_t pids[64];
    int started = 0;
    for (; started < jobs; started++) {
        pid_t pid = fork();
        if (pid < 0) {
            fprintf(stderr, "orrery: error: cannot start job %d: %s\n", started + 1, strerror(errno));
            break;
        }
        if (pid == 0) {
            close(fds[0]);
            orr_animation_options mine = opt;
            mine.start = started;
            mine.stride = jobs;
            mine.done = frame_done_to_pipe;
            mine.done_user = &fds[1];
            mine.progress = NULL;
            orr_render_report *reports = calloc(ORR_SCENE_MAX_VIEWS, sizeof *reports);
            orr_error err = {0};
            orr_status st = reports ? orr_render_animation(list, n, &mine, reports, &err)
                                    : orr_fail(&err, ORR_ERR_NOMEM, "out of memory");
            int code = st ? cli_report_error(&err) : EXIT_OK;
            free(reports);
            _exit(code);
        }
        pids[started] = pid;
    }
    close(fds[1]);
    frame_record r;
    ssize_t got;
    while ((got = read(fds[0], &r, sizeof r)) != 0) {
        if (got < 0 && errno == EINTR)
            continue;
        if (got != (ssize_t)sizeof r)
            break;
        frame_progress_done(fp, r.frame, r.skipped, r.redone ? r.why : NULL);
    }
    close(fds[0]);
    int code = started == jobs ? EXIT_OK : EXIT_RUNTIME;
    for (int i = 0; i < started; i++) {
        int status;
        while (waitpid(pids[i], &status, 0) < 0 && errno == EINTR)
            ;
        int child = WIFEXITED(status) ? WEXITSTATUS(status) : EXIT_RUNTIME;
        if (code == EXIT_OK && child != EXIT_OK)
            code = child;
    }
    return code;
}

typedef struct run_args {
    const char *scene_path, *out_dir;
    const char **sets;
    int nsets, quiet, force, jobs, timings;
    int frame_parallel; /* orrery-mpi: each rank renders whole frames of its own */
    long first, last;
} run_args;

enum { OPT_SET = 256, OPT_FRAMES, OPT_FORCE, OPT_JOBS, OPT_FRAME_PARALLEL, OPT_TIMINGS };

static const struct option render_options[] = {
    {"set", required_argument, NULL, OPT_SET},       {"output", required_argument, NULL, 'o'},
    {"frames", required_argument, NULL, OPT_FRAMES}, {"force", no_argument, NULL, OPT_FORCE},
    {"jobs", required_argument, NULL, OPT_JOBS},     {"frame-parallel", no_argument, NULL, OPT_FRAME_PARALLEL},
    {"timings", no_argument, NULL, OPT_TIMINGS},     {"quiet", no_argument, NULL, 'q'},
    {"help", no_argument, NULL, 'h'},                {NULL, 0, NULL, 0},
};

/* compose has no --force and no --jobs: it never skips frames, and is quick. */
static const struct option compose_options[] = {
    {"set", required_argument, NULL, OPT_SET},       {"output", required_argument, NULL, 'o'},
    {"frames", required_argument, NULL, OPT_FRAMES}, {"frame-parallel", no_argument, NULL, OPT_FRAME_PARALLEL},
    {"quiet", no_argument, NULL, 'q'},               {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

/* One option of render or compose; returns EXIT_OK, -1 after --help, or a
 * usage error. */
static int take_option(int code, const char *value, const char *cmd, int compose, run_args *a)
{
    long long jobs;
    switch (code) {
    case 'h':
        fputs(compose ? compose_help : render_help, stdout);
        return -1;
    case OPT_SET:
        a->sets[a->nsets++] = value;
        return EXIT_OK;
    case 'o':
        a->out_dir = value;
        return EXIT_OK;
    case OPT_FRAMES:
        if (!parse_frames(value, &a->first, &a->last))
            return cli_usage_error(cmd, "--frames %s: expected A:B, A:, :B or A (frame numbers from 0, A <= B)",
                                   value);
        return EXIT_OK;
    case OPT_JOBS:
        if (cli_count_option(cmd, "--jobs", value, 1, 64, &jobs) != EXIT_OK)
            return EXIT_USAGE;
        a->jobs = (int)jobs;
        return EXIT_OK;
    case OPT_FORCE:
        a->force = 1;
        return EXIT_OK;
    case OPT_TIMINGS:
        a->timings = 1;
        return EXIT_OK;
    case OPT_FRAME_PARALLEL: /* orrery-mpi's only */
        if (!cli_parallel)
            return cli_usage_error(cmd, "--frame-parallel is an option of orrery-mpi, for MPI ranks");
        a->frame_parallel = 1;
        return EXIT_OK;
    case 'q':
        a->quiet = 1;
        return EXIT_OK;
    case CLI_OPERAND:
        if (a->scene_path)
            return cli_usage_error(cmd, "one scene file at a time (got '%s' and '%s')", a->scene_path, value);
        a->scene_path = value;
        return EXIT_OK;
    default:
        return EXIT_USAGE; /* CLI_BAD: already told */
    }
}

static int parse_args(int argc, char **argv, const char *cmd, int compose, run_args *a)
{
    const char *value;
    int code;
    cli_options_begin();
    while ((code = cli_next_option(cmd, argc, argv, "ho:q", compose ? compose_options : render_options, &value)) !=
           -1) {
        int st = take_option(code, value, cmd, compose, a);
        if (st != EXIT_OK)
            return st;
    }
    if (!a->scene_path)
        return cli_usage_error(cmd, "no scene file given");
    if (cli_parallel && cli_parallel->rank != 0)
        a->quiet = 1; /* rank 0 speaks for all; every rank reports its own errors */
    return EXIT_OK;
}

/* The view's part of a --set key: the key itself, or what follows
 * "views.NAME." when it names this view; NULL when it names another. */
static const char *key_for_view(const char *key, const char *view)
{
    if (strncmp(key, "views.", 6) != 0)
        return key;
    size_t len = strlen(view);
    if (len == 0 || strncmp(key + 6, view, len) != 0 || key[6 + len] != '.')
        return NULL;
    return key + 6 + len + 1;
}

/* compose re-grades a view's raw planes. A flat view's raw planes are
 * taken before its PSF, so compose convolves them with the PSF as set now;
 * a sky map's PSF, and a flat view's that draws its stars one by one, is
 * drawn star by star into the raw planes as it renders (docs/psf.md), so a
 * psf key set for compose would change nothing: it is refused, with the
 * way to get it. */
static int check_compose_sets(const run_args *a, const orr_scene_views *views)
{
    for (int i = 0; i < a->nsets; i++)
        for (int k = 0; k < views->n; k++) {
            const char *key = key_for_view(a->sets[i], views->name[k]);
            int sky;
            const int psf_in_raw_planes = orr_plan_psf_in_raw_planes(&views->view[k], &sky);
            if (!key || strncmp(key, "psf", 3) != 0 || (key[3] != '.' && key[3] != '=') || !psf_in_raw_planes)
                continue;
            return cli_usage_error("compose",
                                   "--set %.*s: %s%s%s%s, whose PSF is drawn into the raw planes as it "
                                   "renders, so compose cannot change it: render again with this --set",
                                   (int)strcspn(a->sets[i], "="), a->sets[i], views->name[k][0] ? "view " : "",
                                   views->name[k], views->name[k][0] ? " " : "the scene ",
                                   sky ? "is a sky map" : "draws its stars one by one (psf.fwhm with hst or file)");
        }
    return EXIT_OK;
}

static void print_run_summary(const frame_progress *fp, long nframes, double seconds)
{
    printf("run of %ld frames: rendered %ld, skipped %ld already complete, in %.1f s", nframes, fp->rendered,
           fp->skipped, seconds);
    if (fp->rendered > 0)
        printf(" (%.2f frames/s)", fp->rendered / (seconds > 0 ? seconds : 1e-9));
    if (fp->redone > 0)
        printf("; %ld of them were an earlier run's, made with other settings or inputs, or changed since",
               fp->redone);
    printf("\n");
}

/* A view whose frames reached stars.max, said even with --quiet: the
 * picture lacks stars the scene asked for. */
static void warn_stars_capped(const orr_scene_views *views, const orr_render_report *reports, long nframes)
{
    for (int k = 0; k < views->n; k++) {
        const orr_render_report *r = &reports[k];
        if (!r->stars_capped_frames)
            continue;
        fprintf(stderr, "orrery: warning: %s%s%s", views->name[k][0] ? "view " : "", views->name[k],
                views->name[k][0] ? ": " : "");
        if (nframes > 1)
            fprintf(stderr, "%ld of the frames rendered (the first: frame %ld) reached", r->stars_capped_frames,
                    r->stars_capped_first);
        else
            fprintf(stderr, "the frame reached");
        fprintf(stderr, " stars.max: the stars past it were left in the glow (the sky's light is kept, but not "
                        "all its brightest points are drawn); raise stars.max to draw them\n");
    }
}

/* What was rendered: the run's summary and each view's report. */
static void print_summary(const run_args *a, const orr_scene_views *views, const orr_render_report *reports,
                          const frame_progress *fp, long nframes, int compose)
{
    double seconds = cli_now() - fp->start;
    if (nframes > 1)
        print_run_summary(fp, nframes, seconds);
    if (a->jobs > 1 && nframes > 1)
        return;
    for (int k = 0; k < views->n && fp->rendered > 0; k++) {
        if (compose)
            print_compose_report(&reports[k], views->name[k]);
        else
            print_report(&reports[k], views->name[k], nframes > 1 ? seconds / fp->rendered : seconds);
    }
}

static int run_loaded(const run_args *a, orr_scene_views *views, orr_render_report *reports, int compose)
{
    const orr_scene *list[ORR_SCENE_MAX_VIEWS];
    orr_error err = {0};
    for (int k = 0; k < views->n; k++) {
        if (a->out_dir && strlen(a->out_dir) >= ORR_PATH_MAX)
            return cli_report_error(&(orr_error){ORR_ERR_USAGE, "output directory name is too long"});
        /* -o "" is the current directory, as orr_check_output_dir takes it
         * (an owned string is never "", core/owned.h). */
        if (a->out_dir && orr_scene_set_output_dir(&views->view[k], a->out_dir[0] ? a->out_dir : ".", &err))
            return cli_report_error(&err);
        list[k] = &views->view[k];
    }
    const long nframes = orr_plan_run_settings(&views->view[0]).frames;
    orr_animation_options opt = orr_animation_defaults();
    opt.first = a->first;
    opt.last = a->last;
    opt.force = a->force;
    opt.compose = compose;
    /* Under orrery-mpi the ranks share each frame's particles, or (with
     * --frame-parallel) take every nranks-th frame each. */
    if (cli_parallel && (a->frame_parallel || compose)) {
        opt.start = cli_parallel->rank;
        opt.stride = cli_parallel->nranks;
    } else if (!compose) {
        opt.parallel = cli_parallel;
    }
    if (a->first >= nframes) {
        return cli_usage_error(compose ? "compose" : "render", "--frames: frame %ld asked for, but %s has %ld frame%s",
                               a->first, a->scene_path, nframes, nframes == 1 ? "" : "s");
    }
    frame_progress fp = {!a->quiet && nframes > 1, isatty(STDERR_FILENO), orr_animation_count(&opt, nframes), 0, 0,
                         0, cli_now()};
    cli_progress particles;
    cli_progress_init(&particles, !a->quiet && nframes == 1 && !compose);
    opt.done = frame_progress_done;
    opt.done_user = &fp;
    opt.progress = cli_progress_update;
    opt.progress_user = &particles;
    /* Under orrery-mpi, rank 0's: it alone finishes and writes the frames. */
    cli_timings timings;
    memset(&timings, 0, sizeof timings);
    timings.per_frame_lines = nframes > 1;
    if (a->timings && !(cli_parallel && cli_parallel->rank != 0)) {
        opt.timed = cli_timings_frame;
        opt.timed_user = &timings;
    }
    int code;
    if (a->jobs > 1 && nframes > 1) {
        code = render_jobs(list, views->n, opt, a->jobs, &fp);
    } else {
        orr_status st = orr_render_animation(list, views->n, &opt, reports, &err);
        cli_progress_finish(&particles);
        code = st ? cli_report_error(&err) : EXIT_OK;
    }
    /* animation.white_smoothing: once every frame is there (all jobs done),
     * the writer re-grades them with white levels averaged over time. */
    int writer = !cli_parallel || cli_parallel->rank == 0;
    if (code == EXIT_OK && !compose && writer && nframes > 1) {
        orr_status st = orr_animation_smooth_whites(list, views->n, reports, &err);
        code = st ? cli_report_error(&err) : EXIT_OK;
    }
    if (code != EXIT_OK)
        return code;
    if (!compose)
        warn_stars_capped(views, reports, nframes);
    if (!a->quiet)
        print_summary(a, views, reports, &fp, nframes, compose);
    /* With --jobs the frames' lines came from the jobs, which keep their sums. */
    if (opt.timed && !(a->jobs > 1 && nframes > 1))
        cli_timings_print(&timings);
    return code;
}

const orr_parallel *cli_parallel = NULL;

static int run_scene_command(int argc, char **argv, int compose)
{
    const char *cmd = compose ? "compose" : "render";
    run_args a = {.first = 0, .last = -1, .jobs = 1};
    a.sets = calloc((size_t)argc, sizeof *a.sets);
    orr_scene_views *views = calloc(1, sizeof *views);
    orr_render_report *reports = calloc(ORR_SCENE_MAX_VIEWS, sizeof *reports);
    int code = a.sets && views && reports ? parse_args(argc, argv, cmd, compose, &a) : EXIT_RUNTIME;
    if (code == EXIT_RUNTIME)
        fprintf(stderr, "orrery: error: out of memory\n");
    if (code == EXIT_OK) {
        orr_error err = {0};
        if (orr_scene_load_views(views, a.scene_path, a.sets, a.nsets, &err))
            code = cli_report_error(&err);
        else if (!compose || (code = check_compose_sets(&a, views)) == EXIT_OK)
            code = run_loaded(&a, views, reports, compose);
    }
    if (views)
        orr_scene_views_free(views);
    free(views);
    free(reports);
    free(a.sets);
    return code < 0 ? EXIT_OK : code;
}

int cmd_render(int argc, char **argv) { return run_scene_command(argc, argv, 0); }
int cmd_compose(int argc, char **argv) { return run_scene_command(argc, argv, 1); }
