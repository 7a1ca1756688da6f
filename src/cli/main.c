/* orrery: the command-line front end of the library. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    "  model -o FILE [--particles N] [--seed S] [--separation KPC] [--galaxies pair|mw|m31] ...\n"
    "                                                     write the built-in Milky Way-Andromeda model\n"
    "  ics --zeldovich -o FILE.hdf5 [--grid N] [--box MPC_H] [--z Z] [--seed S] ...\n"
    "                                                     write a ΛCDM box (Zel'dovich initial conditions)\n"
    "  path SCENE.yaml [--set KEY=VALUE ...] [--frames N] [-o FILE.png]\n"
    "                                                     print a camera path; draw it over the particles\n"
    "  video SCENE.yaml [--codec h264|h265|prores|png] [--fps F] [--frames N] [--out FILE] ...\n"
    "                                                     encode rendered frames into a video (ffmpeg)\n"
    "\n"
    "options:\n"
    "  -h, --help      this text (also 'orrery COMMAND --help')\n"
    "  -V, --version   the version\n"
    "\n"
    "exit status: 0 success, 1 runtime failure, 2 usage error.\n"
    "Scene files: docs/scenes.md. Command line: docs/cli.md.\n";

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage_text, stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    cli_clean_up_on_signals();
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
    if (strcmp(cmd, "ics") == 0)
        return cmd_ics(argc - 1, argv + 1);
    if (strcmp(cmd, "path") == 0)
        return cmd_path(argc - 1, argv + 1);
    if (strcmp(cmd, "video") == 0)
        return cmd_video(argc - 1, argv + 1);
    fprintf(stderr, "orrery: error: unknown command '%s' (see 'orrery --help')\n", cmd);
    return EXIT_USAGE;
}
