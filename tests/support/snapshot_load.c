#include "snapshot_load.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "source/source.h"

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "load_snapshot: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

void load_snapshot(const char *path, int need_h, loaded_snapshot *p)
{
    orr_error err = {0};
    const char *none[1] = {NULL};
    orr_source_options opt = {.format = "auto", .chunk_size = 1 << 20, .fields = none, .nfields = 0};
    orr_source *src = NULL;
    if (orr_source_open_file(path, &opt, &src, &err) != ORR_OK)
        fail(err.msg, NULL);
    if (src->info.count <= 0)
        fail(path, "the particle count is not in the header");
    if (need_h && !src->info.has_h)
        fail(path, "no smoothing lengths");
    size_t n = (size_t)src->info.count;
    /* The file's h to orrery's (support 2h), from its support radius in
     * units of its h. */
    double to_half_support = (src->info.h_support > 0 ? src->info.h_support : 2.0) / 2.0;
    *p = (loaded_snapshot){n, malloc(n * sizeof *p->x), malloc(n * sizeof *p->y), malloc(n * sizeof *p->z),
                           malloc(n * sizeof *p->mass), src->info.has_h ? malloc(n * sizeof *p->h) : NULL};
    if (!p->x || !p->y || !p->z || !p->mass || (src->info.has_h && !p->h))
        fail(path, "out of memory");
    size_t filled = 0;
    for (;;) {
        const orr_chunk *c;
        if (orr_source_next(src, &c, &err) != ORR_OK)
            fail(err.msg, NULL);
        if (c->n == 0)
            break;
        if (c->n > n - filled)
            fail(path, "more particles than the header says");
        memcpy(p->x + filled, c->x, c->n * sizeof *c->x);
        memcpy(p->y + filled, c->y, c->n * sizeof *c->y);
        memcpy(p->z + filled, c->z, c->n * sizeof *c->z);
        memcpy(p->mass + filled, c->mass, c->n * sizeof *c->mass);
        for (size_t i = 0; p->h && i < c->n; i++)
            p->h[filled + i] = (float)(c->h[i] * to_half_support);
        filled += c->n;
    }
    orr_source_close(src);
    if (filled != n)
        fail(path, "fewer particles than the header says");
}

void free_snapshot(loaded_snapshot *p)
{
    free(p->x);
    free(p->y);
    free(p->z);
    free(p->mass);
    free(p->h);
    memset(p, 0, sizeof *p);
}
