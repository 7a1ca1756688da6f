/* orrery render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--quiet]
 * orrery compose SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--quiet]
 * The two take the same arguments: compose is the second half of render. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "render/render.h"

static const char render_help[] =
    "usage: orrery render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--quiet]\n"
    "\n"
    "Renders the scene's particles to a FITS file (linear float planes: the\n"
    "weight, or CIE X, Y, Z with colour.populations) and a PNG (stretched and\n"
    "colour-mapped, or the colour synthesis) named after the scene, in\n"
    "output.dir; with output.raw also NAME.raw.fits, the planes before any\n"
    "PSF, for `orrery compose`. A scene with views (e.g. a dome master and a\n"
    "panorama) renders all of them from one pass over the particles.\n"
    "\n"
    "  --set KEY=VALUE   override a scene key, e.g. --set camera.fov=60,\n"
    "                    --set camera.position=[0,0,100] (repeatable; applied in order);\n"
    "                    --set views.NAME.KEY=VALUE changes one view\n"
    "  -o, --output DIR  write the outputs into DIR (overrides output.dir; created if missing)\n"
    "  -q, --quiet       no progress or summary, only errors\n"
    "  -h, --help        this text\n"
    "\n"
    "Scene keys: docs/scenes.md. Exit status: 0 success, 1 runtime failure, 2 usage error.\n";

static const char compose_help[] =
    "usage: orrery compose SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--quiet]\n"
    "\n"
    "Re-grades a render without rendering again: reads the raw planes that\n"
    "`orrery render` wrote with output.raw: true (DIR/NAME.raw.fits, before\n"
    "any PSF), applies the scene's PSF, colour synthesis (colour.synthesis.*)\n"
    "or stretch and colour map (output.*) as they are now, and writes\n"
    "DIR/NAME.png. Change the grading with --set, e.g.\n"
    "  orrery compose futuresky.yaml --set colour.synthesis.stretch=asinh\n"
    "\n"
    "  --set KEY=VALUE   override a scene key (repeatable; applied in order)\n"
    "  -o, --output DIR  the folder the render wrote to (overrides output.dir)\n"
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
    if (r->n_stereo_skipped)
        printf("  of those not drawn, %llu inside the stereo eye circle (closer to the viewer than half the eye "
               "separation, horizontally)\n",
               (unsigned long long)r->n_stereo_skipped);
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

static int run_scene_command(int argc, char **argv, int compose)
{
    const char *cmd = compose ? "compose" : "render";
    const char *scene_path = NULL, *out_dir = NULL;
    int quiet = 0;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    int nsets = 0;
    if (!sets) {
        fprintf(stderr, "orrery %s: out of memory\n", cmd);
        return EXIT_RUNTIME;
    }
    int code = EXIT_OK;
    for (int i = 1; i < argc && code == EXIT_OK; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(compose ? compose_help : render_help, stdout);
            free(sets);
            return EXIT_OK;
        } else if (strcmp(a, "--set") == 0 || strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (i + 1 >= argc)
                code = cli_usage_error(cmd, "%s needs a value", a);
            else if (strcmp(a, "--set") == 0)
                sets[nsets++] = argv[++i];
            else
                out_dir = argv[++i];
        } else if (strncmp(a, "--set=", 6) == 0) {
            sets[nsets++] = a + 6;
        } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            code = cli_usage_error(cmd, "unknown option '%s'", a);
        } else if (scene_path) {
            code = cli_usage_error(cmd, "one scene file at a time (got '%s' and '%s')", scene_path, a);
        } else {
            scene_path = a;
        }
    }
    if (code == EXIT_OK && !scene_path)
        code = cli_usage_error(cmd, "no scene file given");
    if (code != EXIT_OK) {
        free(sets);
        return code;
    }

    orr_error err = {0};
    orr_scene_views *views = calloc(1, sizeof *views);
    orr_render_report *reports = calloc(ORR_SCENE_MAX_VIEWS, sizeof *reports);
    const orr_scene *list[ORR_SCENE_MAX_VIEWS];
    orr_status st = views && reports ? ORR_OK : orr_fail(&err, ORR_ERR_NOMEM, "out of memory");
    if (!st)
        st = orr_scene_load_views(views, scene_path, sets, nsets, &err);
    for (int k = 0; !st && k < views->n; k++) {
        if (out_dir && strlen(out_dir) >= sizeof views->view[k].out_dir)
            st = orr_fail(&err, ORR_ERR_USAGE, "output directory name is too long");
        else if (out_dir)
            snprintf(views->view[k].out_dir, sizeof views->view[k].out_dir, "%s", out_dir);
        list[k] = &views->view[k];
    }
    if (!st && compose) {
        st = orr_compose_views(list, views->n, reports, &err);
        for (int k = 0; !st && !quiet && k < views->n; k++)
            print_compose_report(&reports[k], views->name[k]);
    } else if (!st) {
        cli_progress progress;
        cli_progress_init(&progress, !quiet);
        double t0 = cli_now();
        st = orr_render_views(list, views->n, reports, cli_progress_update, &progress, &err);
        cli_progress_finish(&progress);
        for (int k = 0; !st && !quiet && k < views->n; k++)
            print_report(&reports[k], views->name[k], cli_now() - t0);
    }
    code = st ? cli_report_error(&err) : EXIT_OK;
    free(views);
    free(reports);
    free(sets);
    return code;
}

int cmd_render(int argc, char **argv) { return run_scene_command(argc, argv, 0); }
int cmd_compose(int argc, char **argv) { return run_scene_command(argc, argv, 1); }
