/* orrery render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--quiet] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "render/render.h"

static const char render_help[] =
    "usage: orrery render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--quiet]\n"
    "\n"
    "Renders the scene's particles to a FITS file (linear float planes) and a\n"
    "PNG (stretched, colour-mapped) named after the scene, in output.dir.\n"
    "\n"
    "  --set KEY=VALUE   override a scene key, e.g. --set camera.fov=60,\n"
    "                    --set camera.position=[0,0,100] (repeatable; applied in order)\n"
    "  -o, --output DIR  write the outputs into DIR (overrides output.dir; created if missing)\n"
    "  -q, --quiet       no progress or summary, only errors\n"
    "  -h, --help        this text\n"
    "\n"
    "Scene keys: docs/scenes.md. Exit status: 0 success, 1 runtime failure, 2 usage error.\n";

static void print_report(const orr_render_report *r, double seconds)
{
    printf("read %llu particles from %s in %.2f s (%.3g particles/s)\n", (unsigned long long)r->n_read,
           r->source, seconds, seconds > 0 ? r->n_read / seconds : 0.0);
    printf("  selected %llu; skipped %llu non-finite; %llu not drawn (behind the camera)\n",
           (unsigned long long)r->n_selected, (unsigned long long)r->n_nonfinite,
           (unsigned long long)r->deposit.n_culled);
    printf("  weight in the image %.9g, off the image %.9g, not drawn %.9g\n", r->deposit.deposited,
           r->deposit.outside, r->deposit.culled);
    for (int i = 0; i < r->noutputs; i++)
        printf("  wrote %s\n", r->outputs[i]);
}

int cmd_render(int argc, char **argv)
{
    const char *scene_path = NULL, *out_dir = NULL;
    int quiet = 0;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    int nsets = 0;
    if (!sets) {
        fprintf(stderr, "orrery render: out of memory\n");
        return EXIT_RUNTIME;
    }
    int code = EXIT_OK;
    for (int i = 1; i < argc && code == EXIT_OK; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(render_help, stdout);
            free(sets);
            return EXIT_OK;
        } else if (strcmp(a, "--set") == 0 || strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (i + 1 >= argc)
                code = cli_usage_error("render", "%s needs a value", a);
            else if (strcmp(a, "--set") == 0)
                sets[nsets++] = argv[++i];
            else
                out_dir = argv[++i];
        } else if (strncmp(a, "--set=", 6) == 0) {
            sets[nsets++] = a + 6;
        } else if (strcmp(a, "-q") == 0 || strcmp(a, "--quiet") == 0) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            code = cli_usage_error("render", "unknown option '%s'", a);
        } else if (scene_path) {
            code = cli_usage_error("render", "one scene file at a time (got '%s' and '%s')", scene_path, a);
        } else {
            scene_path = a;
        }
    }
    if (code == EXIT_OK && !scene_path)
        code = cli_usage_error("render", "no scene file given");
    if (code != EXIT_OK) {
        free(sets);
        return code;
    }

    orr_error err = {0};
    orr_scene *scene = calloc(1, sizeof *scene);
    if (!scene) {
        free(sets);
        fprintf(stderr, "orrery render: out of memory\n");
        return EXIT_RUNTIME;
    }
    orr_status st = orr_scene_load(scene, scene_path, sets, nsets, &err);
    if (!st && out_dir) {
        if (strlen(out_dir) >= sizeof scene->out_dir)
            st = orr_fail(&err, ORR_ERR_USAGE, "output directory name is too long");
        else
            snprintf(scene->out_dir, sizeof scene->out_dir, "%s", out_dir);
    }
    if (!st) {
        cli_progress progress;
        cli_progress_init(&progress, !quiet);
        orr_render_report report;
        double t0 = cli_now();
        st = orr_render_scene(scene, &report, cli_progress_update, &progress, &err);
        cli_progress_finish(&progress);
        if (!st && !quiet)
            print_report(&report, cli_now() - t0);
    }
    code = st ? cli_report_error(&err) : EXIT_OK;
    free(scene);
    free(sets);
    return code;
}
