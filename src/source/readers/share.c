#include "source/readers/share.h"

#include <stdlib.h>

void orr_share_bounds(int64_t n, int part, int nparts, int64_t *first, int64_t *end)
{
    /* n / nparts each, the remainder one apiece to the first parts; written
     * without n * part, which could overflow for huge n. */
    int64_t base = n / nparts, extra = n % nparts;
    *first = base * part + (part < extra ? part : extra);
    *end = *first + base + (part < extra ? 1 : 0);
}

int64_t orr_share_runs(const int64_t *counts, size_t nruns, int part, int nparts, int64_t *lo, int64_t *hi)
{
    int64_t total = 0;
    for (size_t i = 0; i < nruns; i++)
        total += counts[i];
    int64_t first, end;
    orr_share_bounds(total, part, nparts, &first, &end);
    int64_t start = 0; /* index of run i's first row in the reading order */
    for (size_t i = 0; i < nruns; i++) {
        int64_t n = counts[i]; /* read before hi[i], which may be the same */
        int64_t a = first - start, b = end - start;
        a = a < 0 ? 0 : a > n ? n : a;
        b = b < a ? a : b > n ? n : b;
        lo[i] = a;
        hi[i] = b;
        start += n;
    }
    return first;
}

orr_status orr_share_alloc(orr_share *sh, size_t nruns, orr_error *err)
{
    sh->lo = orr_calloc(nruns ? nruns : 1, sizeof *sh->lo, "a share's runs", err);
    sh->hi = orr_calloc(nruns ? nruns : 1, sizeof *sh->hi, "a share's runs", err);
    sh->first = 0;
    if (sh->lo && sh->hi)
        return ORR_OK;
    orr_share_free(sh);
    return ORR_ERR_NOMEM;
}

orr_status orr_share_divide(orr_share *sh, size_t nruns, orr_source *src, const orr_source_options *opt,
                            orr_error *err)
{
    int part = 0, nparts = 1;
    if (opt && opt->nparts != 0) {
        if (opt->nparts < 0 || opt->part < 0 || opt->part >= opt->nparts)
            return orr_fail(err, ORR_ERR_USAGE, "%s: share %d of %d parts: out of range", src->info.path,
                            opt->part, opt->nparts);
        part = opt->part;
        nparts = opt->nparts;
    }
    sh->first = (uint64_t)orr_share_runs(sh->hi, nruns, part, nparts, sh->lo, sh->hi);
    int64_t count = 0;
    for (size_t i = 0; i < nruns; i++)
        count += sh->hi[i] - sh->lo[i];
    src->info.share_part = part;
    src->info.share_nparts = nparts;
    src->info.count = count;
    return ORR_OK;
}

void orr_share_free(orr_share *sh)
{
    free(sh->lo);
    free(sh->hi);
    sh->lo = sh->hi = NULL;
}
