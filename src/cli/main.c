/* orrery: the command-line front end of the library. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"

static const char usage_text[] =
    "usage: orrery <command> [options]\n"
    "\n"
    "Renders gravitational N-body simulations to images.\n"
    "\n"
    "commands:\n"
    "  render SCENE.yaml [--set KEY=VALUE ...] [-o DIR]   render a scene to FITS and PNG\n"
    "  compose SCENE.yaml [--set KEY=VALUE ...] [-o DIR]  re-grade a render from its raw planes\n"
    "  info FILE [--format FORMAT]                        particle count, fields, bounds, mass\n"
    "  model -o FILE [--particles N] [--seed S] [--separation KPC]\n"
    "                                                     write the built-in Milky Way-Andromeda model\n"
    "  video SCENE.yaml [--codec h264|h265|prores|png] [--fps F] [--frames N] [--out FILE] ...\n"
    "                                                     encode rendered frames into a video (ffmpeg)\n"
    "\n"
    "options:\n"
    "  -h, --help      this text (also 'orrery COMMAND --help')\n"
    "  -V, --version   the version\n"
    "\n"
    "exit status: 0 success, 1 runtime failure, 2 usage error.\n"
    "Scene files: docs/scenes.md. Command line: docs/cli.md.\n";

int cli_report_error(const orr_error *err)
{
    fprintf(stderr, "orrery: error: %s\n", err->msg[0] ? err->msg : "unknown error");
    return err->code == ORR_ERR_USAGE ? EXIT_USAGE : EXIT_RUNTIME;
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "orrery %s: ", command);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(see 'orrery %s --help')\n", command);
    va_end(ap);
    return EXIT_USAGE;
}

int cli_parse_count(const char *text, long long min, long long max, long long *out)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !(v >= (double)min && v <= (double)max) || v != (double)(long long)v)
        return 0;
    *out = (long long)v;
    return 1;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_init(cli_progress *p, int enabled)
{
    p->enabled = enabled;
    p->tty = isatty(STDERR_FILENO);
    p->start = p->last = cli_now();
    p->last_decile = 0;
}

void cli_progress_update(void *user, uint64_t done, int64_t total)
{
    cli_progress *p = user;
    if (!p->enabled)
        return;
    double now = cli_now();
    double rate = done / (now - p->start > 1e-9 ? now - p->start : 1e-9);
    if (p->tty) {
        if (now - p->last < 0.2)
            return;
        p->last = now;
        if (total > 0)
            fprintf(stderr, "\r  %llu / %lld particles (%.0f%%), %.3g particles/s, %.0f s left   ",
                    (unsigned long long)done, (long long)total, 100.0 * done / total, rate,
                    (total - (double)done) / (rate > 0 ? rate : 1));
        else
            fprintf(stderr, "\r  %llu particles, %.3g particles/s   ", (unsigned long long)done, rate);
        return;
    }
    if (total > 0) {
        int decile = (int)(10.0 * done / total);
        if (decile > p->last_decile && decile < 10) {
            p->last_decile = decile;
            fprintf(stderr, "  %d%%: %llu of %lld particles, %.3g particles/s\n", 10 * decile,
                    (unsigned long long)done, (long long)total, rate);
        }
    }
}

void cli_progress_finish(cli_progress *p)
{
    if (p->enabled && p->tty && cli_now() - p->start >= 0.2)
        fprintf(stderr, "\r%80s\r", "");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage_text, stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
        fputs(usage_text, stdout);
        return EXIT_OK;
    }
    if (strcmp(cmd, "-V") == 0 || strcmp(cmd, "--version") == 0) {
        printf("orrery %s\n", ORRERY_VERSION);
        return EXIT_OK;
    }
    if (strcmp(cmd, "render") == 0)
        return cmd_render(argc - 1, argv + 1);
    if (strcmp(cmd, "compose") == 0)
        return cmd_compose(argc - 1, argv + 1);
    if (strcmp(cmd, "info") == 0)
        return cmd_info(argc - 1, argv + 1);
    if (strcmp(cmd, "model") == 0)
        return cmd_model(argc - 1, argv + 1);
    if (strcmp(cmd, "video") == 0)
        return cmd_video(argc - 1, argv + 1);
    fprintf(stderr, "orrery: unknown command '%s'\n\n%s", cmd, usage_text);
    return EXIT_USAGE;
}
