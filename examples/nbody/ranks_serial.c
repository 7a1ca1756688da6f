/* orrery-nbody on one process: its slice is every particle, so there is
 * nothing to gather or to tell the renderer. */
#include "ranks.h"

void ranks_start(int *argc, char ***argv, int *rank, int *size)
{
    (void)argc;
    (void)argv;
    *rank = 0;
    *size = 1;
}

void ranks_finish(void) {}

int ranks_counts(size_t mine, size_t *counts)
{
    counts[0] = mine;
    return 0;
}

int ranks_gather(double *all, size_t per, const size_t *counts)
{
    (void)all;
    (void)per;
    (void)counts;
    return 0;
}

int ranks_allgather_u64(const uint64_t *mine, int n, uint64_t *all)
{
    for (int k = 0; k < n; k++)
        all[k] = mine[k];
    return 0;
}

int ranks_any(int failed)
{
    return failed != 0;
}

int ranks_render_together(orrery_renderer *r)
{
    (void)r;
    return ORRERY_OK;
}
