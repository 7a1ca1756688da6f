#include "pass/lengths.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "particles/smoothing.h"

orr_status orr_lengths_needed(const orr_splat_settings *set, const orr_source *src, int *needed, orr_error *err)
{
    *needed = 0;
    if (set->has_glow) {
        *needed = 1;
        return ORR_OK;
    }
    if (set->deposit.kind != ORR_DEPOSIT_SPH)
        return ORR_OK;
    if (set->deposit.lengths == ORR_LENGTHS_FILE && !src->info.has_h)
        return orr_fail(err, ORR_ERR_DATA,
                        "%s: smoothing.lengths is file, but %s has no smoothing lengths; use smoothing.lengths: "
                        "neighbours (or auto) to compute them",
                        set->path, src->info.path);
    *needed = set->deposit.lengths == ORR_LENGTHS_NEIGHBOURS || (set->deposit.lengths == ORR_LENGTHS_AUTO && !src->info.has_h);
    return ORR_OK;
}

/* Positions of the particles that take a length, in source order, and
 * with a bound each one's limit (orr_lengths_bound; NULL without). */
typedef struct positions {
    float *x, *y, *z, *enough;
    size_t n, cap;
} positions;

static orr_status grow(positions *p, int with_enough, orr_error *err)
{
    size_t cap = p->cap ? 2 * p->cap : (size_t)1 << 16;
    float **a[4] = {&p->x, &p->y, &p->z, &p->enough};
    for (int k = 0; k < 3 + (with_enough != 0); k++) {
        float *g = realloc(*a[k], cap * sizeof *g);
        if (!g)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for the positions of %zu particles (smoothing "
                            "lengths from the neighbours need them all at once)", cap);
        *a[k] = g;
    }
    p->cap = cap;
    return ORR_OK;
}

static void positions_free(positions *p)
{
    free(p->x), free(p->y), free(p->z), free(p->enough);
}

/* The largest angular length of particle i that leaves its glow as wide as
 * its own kernel (orr_lengths_bound), or 0 when its length must be exact. */
static float glow_enough(const orr_lengths_bound *b, const orr_vec3 *centre, const orr_chunk *c, size_t i)
{
    if (!orr_stars_spawns(b->stars, c->type[i]))
        return 0.0f;
    const double own = (float)orr_stars_kernel_length(b->stars, c->mass[i]); /* (rounded as the splat does) */
    const double dx = c->x[i] - centre->x, dy = c->y[i] - centre->y, dz = c->z[i] - centre->z;
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (!(r2 < 0.25 * FLT_MAX))
        return 0.0f; /* (the splat's float r^2 could overflow: exact) */
    const double limit = own / (sqrt(r2) * b->h_scale) * (1.0 - 1e-5);
    return limit > 0 ? (float)limit : 0.0f; /* (the observer, at r = 0: any) */
}

/* The direction of (x, y, z) from centre, or 0 for a particle at the centre
 * (the observer itself, which is not drawn). */
static void direction_from(const orr_vec3 *centre, float *x, float *y, float *z)
{
    double dx = *x - centre->x, dy = *y - centre->y, dz = *z - centre->z, r = sqrt(dx * dx + dy * dy + dz * dz);
    double k = r > 0 ? 1.0 / r : 0.0;
    *x = (float)(dx * k), *y = (float)(dy * k), *z = (float)(dz * k);
}

static orr_status gather_positions(const orr_splat_settings *set, orr_source *src, const orr_vec3 *centre,
                                   const orr_lengths_bound *bound, positions *p, orr_error *err)
{
    for (;;) {
        const orr_chunk *c;
        orr_status st = orr_source_next(src, &c, err);
        if (st || c->n == 0)
            return st;
        for (size_t i = 0; i < c->n; i++) {
            if (!orr_lengths_counts(set->type_mask, c, i))
                continue;
            if (p->n == p->cap && (st = grow(p, bound != NULL, err)))
                return st;
            if (bound)
                p->enough[p->n] = glow_enough(bound, centre, c, i);
            p->x[p->n] = c->x[i];
            p->y[p->n] = c->y[i];
            p->z[p->n] = c->z[i];
            if (centre)
                direction_from(centre, &p->x[p->n], &p->y[p->n], &p->z[p->n]);
            p->n++;
        }
    }
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void orr_lengths_free(orr_lengths *l)
{
    free(l->h);
    *l = (orr_lengths){0};
}

/* Every process's directions, in rank order, into all (3 arrays of
 * *n_all), and where this process's start (*first). */
static orr_status share_directions(const orr_parallel *par, const positions *mine, positions *all, size_t *first,
                                   orr_error *err)
{
    double *counts = calloc((size_t)par->nranks, sizeof *counts);
    if (!counts)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for %d processes' counts", par->nranks);
    counts[par->rank] = (double)mine->n;
    orr_status st = par->allreduce_sum(par->user, counts, (size_t)par->nranks, err);
    size_t n = 0;
    *first = 0;
    for (int r = 0; r < par->nranks && !st; r++) {
        if (r == par->rank)
            *first = n;
        n += (size_t)counts[r];
    }
    free(counts);
    double *xyz = st ? NULL : calloc(3 * n + 1, sizeof *xyz);
    if (!st && !xyz)
        st = orr_fail(err, ORR_ERR_NOMEM, "out of memory for the directions of %zu particles (the glow's lengths)", n);
    for (size_t i = 0; i < mine->n && !st; i++) {
        xyz[3 * (*first + i)] = mine->x[i];
        xyz[3 * (*first + i) + 1] = mine->y[i];
        xyz[3 * (*first + i) + 2] = mine->z[i];
    }
    if (!st)
        st = par->allreduce_sum(par->user, xyz, 3 * n, err); /* each slot is one process's, the others add 0 */
    while (!st && all->cap < n)
        st = grow(all, 0, err);
    for (size_t i = 0; i < n && !st; i++) {
        all->x[i] = (float)xyz[3 * i];
        all->y[i] = (float)xyz[3 * i + 1];
        all->z[i] = (float)xyz[3 * i + 2];
    }
    all->n = st ? 0 : n;
    free(xyz);
    return st;
}

/* The k-th neighbour's lengths of the points p, those with enough[i] > 0
 * possibly at a bound (orr_smoothing_lengths_bounded; enough NULL: every
 * one exact). */
static orr_status search(const positions *p, const float *enough, int k, float *h, size_t *skipped, orr_error *err)
{
    orr_kdtree tree;
    orr_status st = orr_kdtree_build(&tree, p->n, p->x, p->y, p->z, err);
    if (!st)
        st = orr_smoothing_lengths_bounded(&tree, k, ORR_SMOOTHING_FACTOR_DEFAULT, enough, h, skipped, err);
    orr_kdtree_free(&tree);
    return st;
}

/* The lengths of this process's particles, mine (rewinds src): with
 * several processes, found among every process's (share_directions). */
static orr_status find_lengths(const orr_splat_settings *set, const orr_parallel *par, const positions *mine,
                               float *h_mine, size_t *skipped, orr_error *err)
{
    positions shared = {0};
    const positions *all = mine;
    size_t first = 0;
    float *h_all = h_mine;
    orr_status st = ORR_OK;
    if (par) {
        st = share_directions(par, mine, &shared, &first, err);
        all = &shared;
        if (!st && shared.n && !(h_all = malloc(shared.n * sizeof *h_all)))
            st = orr_fail(err, ORR_ERR_NOMEM, "out of memory for %zu smoothing lengths", shared.n);
    }
    /* Only the search's own errors get the step's name: a reader's error
     * (a bad row of a table) already names its file and line, and is the
     * same whichever pass over the particles meets it first. */
    if (!st && all->n && (st = search(all, par ? NULL : mine->enough, set->deposit.neighbours, h_all, skipped, err)))
        orr_fail_prefix(err, "%s: smoothing lengths from the neighbours: ", set->path);
    if (par) {
        for (size_t i = 0; i < mine->n && !st; i++)
            h_mine[i] = h_all[first + i];
        free(h_all);
        positions_free(&shared);
    }
    return st;
}

orr_status orr_lengths_compute_bounded(const orr_splat_settings *set, orr_source *src, const orr_vec3 *centre,
                                       const orr_parallel *par, const orr_lengths_bound *bound, orr_lengths *out,
                                       orr_error *err)
{
    *out = (orr_lengths){0};
    positions mine = {0};
    double t0 = seconds_now();
    size_t skipped = 0;
    if (!centre || par || (bound && !bound->stars))
        bound = NULL; /* (its limits are angles seen from centre, for this process's particles alone) */
    orr_source_only_types(src, set->type_mask); /* (a model then makes no gas the lengths do not count) */
    orr_status st = gather_positions(set, src, centre, bound, &mine, err);
    /* Collective from here: every process takes part even if its own pass failed. */
    if (par)
        st = par->any_failed(par->user, st, err);
    if (!st && mine.n && !(out->h = malloc(mine.n * sizeof *out->h)))
        st = orr_fail(err, ORR_ERR_NOMEM, "out of memory for %zu smoothing lengths", mine.n);
    if (!st && (mine.n || par))
        st = find_lengths(set, par, &mine, out->h, &skipped, err);
    positions_free(&mine);
    if (!st)
        st = orr_source_rewind(src, err);
    if (st) {
        orr_source_only_types(src, 0); /* (the next pass takes every type, whatever happened to this one) */
        orr_lengths_free(out);
        return st;
    }
    out->n = mine.n;
    out->skipped = skipped;
    out->seconds = seconds_now() - t0;
    out->angular = centre != NULL;
    out->centre = centre ? *centre : orr_v3(0, 0, 0);
    return ORR_OK;
}
