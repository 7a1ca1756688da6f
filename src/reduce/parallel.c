/* The sums over processes of reduce/parallel.h, on the back end's
 * reductions. */
#include "reduce/parallel.h"

orr_status orr_parallel_sum_planes(const orr_parallel *par, orr_plane *planes, int n, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int j = 0; j < n && !st; j++)
        st = par->reduce_sum(par->user, planes[j].data, (size_t)planes[j].width * (size_t)planes[j].height, err);
    return st;
}

static void add_entry(orr_sums *s, uint64_t *count, double *weight)
{
    if (s->n >= ORR_SUMS_MAX)
        return;
    s->count[s->n] = count;
    s->weight[s->n] = weight;
    s->n++;
}

void orr_sums_count(orr_sums *s, uint64_t *count)
{
    add_entry(s, count, NULL);
}

void orr_sums_weight(orr_sums *s, double *weight)
{
    add_entry(s, NULL, weight);
}

void orr_sums_deposit(orr_sums *s, orr_deposit_stats *d)
{
    orr_sums_weight(s, &d->deposited);
    orr_sums_weight(s, &d->outside);
    orr_sums_weight(s, &d->culled);
    orr_sums_count(s, &d->n_particles);
    orr_sums_count(s, &d->n_culled);
}

orr_status orr_parallel_sum(const orr_parallel *par, orr_sums *s, orr_error *err)
{
    double v[ORR_SUMS_MAX];
    for (int i = 0; i < s->n; i++)
        v[i] = s->count[i] ? (double)*s->count[i] : *s->weight[i];
    orr_status st = par->allreduce_sum(par->user, v, (size_t)s->n, err);
    if (st)
        return st;
    for (int i = 0; i < s->n; i++) {
        if (s->count[i])
            *s->count[i] = (uint64_t)v[i];
        else
            *s->weight[i] = v[i];
    }
    return ORR_OK;
}
