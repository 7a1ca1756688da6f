/* orrery-mpi: `orrery render` and `orrery compose` on MPI ranks.
 *
 *   mpirun -np 4 orrery-mpi render SCENE.yaml [options of orrery render] [--frame-parallel]
 *
 * By default the ranks render every frame together: each takes a share of
 * the particles (the source's chunks dealt out in turn), splats it into its
 * own planes, and the planes are summed onto rank 0, which post-processes
 * and writes. With --frame-parallel each rank renders whole frames of a run
 * (every nranks-th), for runs of many small frames. docs/scale.md. */
#include <mpi.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "mpi/mpi_parallel.h"

static const char usage_text[] =
    "usage: mpirun -np N orrery-mpi render SCENE.yaml [--set KEY=VALUE ...] [-o DIR] [--frames A:B]\n"
    "                               [--force] [--frame-parallel] [--quiet]\n"
    "       mpirun -np N orrery-mpi compose SCENE.yaml [...]\n"
    "\n"
    "orrery render on MPI ranks: every rank reads a share of the particles and\n"
    "the image planes are summed onto rank 0, which writes the outputs; with\n"
    "--frame-parallel each rank renders whole frames of a run instead. compose\n"
    "is always frame-parallel. Options as for 'orrery render --help'.\n";

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm comm = MPI_COMM_WORLD;
    MPI_Comm_set_errhandler(comm, MPI_ERRORS_RETURN);
    orr_parallel par = orr_mpi_parallel(&comm);
    cli_clean_up_on_signals();
    int code;
    if (argc < 2 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0) {
        if (par.rank == 0)
            fputs(usage_text, argc < 2 ? stderr : stdout);
        code = argc < 2 ? EXIT_USAGE : EXIT_OK;
    } else if (strcmp(argv[1], "render") == 0 || strcmp(argv[1], "compose") == 0) {
        cli_parallel = &par;
        code = strcmp(argv[1], "render") == 0 ? cmd_render(argc - 1, argv + 1) : cmd_compose(argc - 1, argv + 1);
    } else {
        if (par.rank == 0)
            fprintf(stderr, "orrery-mpi: unknown command '%s' (render or compose)\n", argv[1]);
        code = EXIT_USAGE;
    }
    /* The worst exit code of any rank is the program's. */
    int worst = code;
    MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, comm);
    MPI_Finalize();
    return worst;
}
