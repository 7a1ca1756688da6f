/* orrery-nbody on one process: its slice is every particle, so there is
 * nothing to gather or to tell the renderer. */
#include <stdlib.h>
#include <string.h>

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

int ranks_exchange(const void *send, const size_t *send_bytes, void **recv, size_t *recv_bytes)
{
    recv_bytes[0] = send_bytes[0];
    *recv = malloc(send_bytes[0] + 1);
    if (!*recv)
        return -1;
    memcpy(*recv, send, send_bytes[0]);
    return 0;
}

int ranks_sum_u64(uint64_t *v, int n)
{
    (void)v;
    (void)n;
    return 0;
}

int ranks_extreme(double *v, int n, int take_max)
{
    (void)v;
    (void)n;
    (void)take_max;
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
