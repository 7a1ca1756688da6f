/* orrery path SCENE.yaml [--set KEY=VALUE ...] [--frames N] [--every K] [-o FILE.png] [--size WxH]
 * [--fit all|path]: the scene's camera path as a table, and as a picture. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "frame/path.h"
#include "render/plan.h"
#include "scene/scene.h"

static const char path_help[] =
    "usage: orrery path SCENE.yaml [--set KEY=VALUE ...] [--frames N] [--every K]\n"
    "                   [-o FILE.png] [--size WxH] [--fit all|path]\n"
    "\n"
    "Prints the scene's camera path (camera.path.*) frame by frame: the\n"
    "camera's position and view direction. With -o, also draws it over the\n"
    "scene's particles seen from above (down the path's axis) as a PNG.\n"
    "\n"
    "  --set KEY=VALUE   override a scene key (repeatable; applied in order)\n"
    "  --frames N        frames in the run (default: the scene's animation.frames, or 100 for a still)\n"
    "  --every K         print every K-th frame (default: about 50 rows; the last frame always)\n"
    "  -o, --output FILE write the overview picture (PNG)\n"
    "  --size WxH        its size in pixels (default 800x800; --size N for N x N)\n"
    "  --fit all|path    frame the path and every particle (all, default) or the path alone\n"
    "  -h, --help        this text\n"
    "\n"
    "Paths: docs/paths.md. Exit status: 0 success, 1 runtime failure, 2 usage error.\n";

typedef struct path_args {
    const char *scene, *png;
    const char **sets;
    int nsets;
    long long frames, every;
    int width, height, fit_path;
} path_args;

static int parse_size(const char *text, int *w, int *h)
{
    char *end;
    long a = strtol(text, &end, 10), b = a;
    if (end == text)
        return 0;
    if (*end == 'x' || *end == 'X') {
        const char *second = end + 1;
        b = strtol(second, &end, 10);
        if (end == second)
            return 0;
    }
    if (*end != '\0' || a < 16 || b < 16 || a > 65536 || b > 65536)
        return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

enum { OPT_SET = 256, OPT_FRAMES, OPT_EVERY, OPT_SIZE, OPT_FIT };

static const struct option path_options[] = {
    {"set", required_argument, NULL, OPT_SET},     {"output", required_argument, NULL, 'o'},
    {"frames", required_argument, NULL, OPT_FRAMES}, {"every", required_argument, NULL, OPT_EVERY},
    {"size", required_argument, NULL, OPT_SIZE},   {"fit", required_argument, NULL, OPT_FIT},
    {"help", no_argument, NULL, 'h'},              {NULL, 0, NULL, 0},
};

/* One option; returns EXIT_OK, or a usage error. */
static int take_option(path_args *pa, int code, const char *value, int *help)
{
    switch (code) {
    case 'h':
        *help = 1;
        return EXIT_OK;
    case OPT_SET:
        pa->sets[pa->nsets++] = value;
        return EXIT_OK;
    case 'o':
        pa->png = value;
        return EXIT_OK;
    case OPT_FRAMES:
        return cli_count_option("path", "--frames", value, 1, 1000000, &pa->frames);
    case OPT_EVERY:
        return cli_count_option("path", "--every", value, 1, 1000000, &pa->every);
    case OPT_SIZE:
        if (!parse_size(value, &pa->width, &pa->height))
            return cli_usage_error("path", "--size: expected WxH or N, 16 to 65536 pixels a side, got '%s'", value);
        return EXIT_OK;
    case OPT_FIT:
        if (strcmp(value, "all") != 0 && strcmp(value, "path") != 0)
            return cli_usage_error("path", "--fit: expected all or path, got '%s'", value);
        pa->fit_path = value[0] == 'p';
        return EXIT_OK;
    case CLI_OPERAND:
        if (pa->scene)
            return cli_usage_error("path", "one scene file at a time (got '%s' and '%s')", pa->scene, value);
        pa->scene = value;
        return EXIT_OK;
    default:
        return EXIT_USAGE; /* CLI_BAD: already told */
    }
}

static int parse_args(int argc, char **argv, path_args *pa, int *help)
{
    const char *value;
    int code;
    cli_options_begin();
    while (!*help && (code = cli_next_option("path", argc, argv, "ho:", path_options, &value)) != -1) {
        int st = take_option(pa, code, value, help);
        if (st != EXIT_OK)
            return st;
    }
    if (!*help && !pa->scene)
        return cli_usage_error("path", "no scene file given");
    return EXIT_OK;
}

static orr_status eval_frames(const orr_path_scene *ps, long n, orr_camera *cams, orr_error *err)
{
    for (long f = 0; f < n; f++) {
        orr_frame_time t = orr_frame_at(f, n, 30, 0, 0);
        orr_status st = orr_path_camera(ps->camera_path, &t, &cams[f], err);
        if (st)
            return st;
    }
    return ORR_OK;
}

static void print_table(const orr_path_scene *ps, const orr_camera *cams, long n, long every)
{
    printf("camera path of %s: %s, %ld frames\n", ps->scene_path, orr_path_kind_name(ps->camera_path->kind), n);
    printf("%7s %8s  %12s %12s %12s  %9s %9s %9s\n", "frame", "u", "x", "y", "z", "dir_x", "dir_y", "dir_z");
    for (long f = 0; f < n; f++) {
        if (f % every != 0 && f != n - 1)
            continue;
        const orr_camera *c = &cams[f];
        orr_vec3 d = orr_quat_rotate(c->orientation, orr_v3(0, 0, 1));
        double u = n > 1 ? (double)f / (double)(n - 1) : 0.0;
        printf("%7ld %8.5f  %12.6g %12.6g %12.6g  %9.5f %9.5f %9.5f\n", f, u, c->position.x, c->position.y,
               c->position.z, d.x, d.y, d.z);
    }
}

int cmd_path(int argc, char **argv)
{
    path_args pa = {.frames = 0, .width = 800, .height = 800};
    pa.sets = calloc((size_t)argc, sizeof *pa.sets);
    if (!pa.sets) {
        fprintf(stderr, "orrery: error: out of memory\n");
        return EXIT_RUNTIME;
    }
    int help = 0, code = parse_args(argc, argv, &pa, &help);
    if (help)
        fputs(path_help, stdout);
    if (help || code != EXIT_OK) {
        free(pa.sets);
        return code;
    }
    orr_error err = {0};
    orr_scene *s = calloc(1, sizeof *s);
    orr_camera *cams = NULL;
    orr_path_scene ps;
    orr_status st = s ? ORR_OK : orr_fail(&err, ORR_ERR_NOMEM, "out of memory");
    if (!st)
        st = orr_scene_load(s, pa.scene, pa.sets, pa.nsets, &err);
    if (!st)
        orr_plan_path_scene(s, &ps);
    /* The run's length: --frames, or the scene's animation.frames, or 100. */
    if (!st && pa.frames == 0)
        pa.frames = ps.frames > 1 ? ps.frames : 100;
    if (!st && !(cams = calloc((size_t)pa.frames, sizeof *cams)))
        st = orr_fail(&err, ORR_ERR_NOMEM, "out of memory for %lld cameras", pa.frames);
    if (!st && !ps.has_camera_path)
        st = orr_fail(&err, ORR_ERR_USAGE, "%s: no camera path: set camera.path.kind (docs/paths.md)",
                      ps.scene_path);
    if (!st)
        st = eval_frames(&ps, (long)pa.frames, cams, &err);
    if (!st) {
        long every = pa.every ? (long)pa.every : (long)((pa.frames + 49) / 50);
        print_table(&ps, cams, (long)pa.frames, every);
    }
    if (!st && pa.png) {
        orr_path_overview ov = {.width = pa.width, .height = pa.height, .fit_path = pa.fit_path};
        st = orr_path_overview_write(&ps, cams, (long)pa.frames, &ov, pa.png, &err);
        if (!st)
            printf("wrote %s: %dx%d, %.6g units across, seen down (%.4f, %.4f, %.4f), %llu particles\n", pa.png,
                   ov.width, ov.height, ov.view_width, ov.normal.x, ov.normal.y, ov.normal.z, ov.n_particles);
    }
    code = st ? cli_report_error(&err) : EXIT_OK;
    free(cams);
    if (s)
        orr_scene_free(s);
    free(s);
    free(pa.sets);
    return code;
}
