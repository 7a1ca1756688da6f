/* The splat pass: every chunk of particles into each view's planes. A
 * chunk's weights are found once (colour populations), then each view
 * gathers its blocks of particles into the camera frame and deposits
 * them (splat_block.h), in lanes or bands whose order never
 * depends on the threads (reduce/lanes.h), or a periodic box's copies on
 * one thread. What each block adds to the tally and a bad particle's
 * error are taken in block order, as one thread would meet them. */
#include "pass/splat_block.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "reduce/lanes.h"
#include "splat/healpix_kernel.h"
#include "post/view_psf.h"

/* The splat's reductions (reduce/lanes.h): lanes for most views, bands for
 * point deposits into large images. */
#define MAX_LANES ORR_MAX_LANES
_Static_assert(MAX_LANES <= ORR_SKY_PSF_LANES, "a sky PSF collects stars in every lane");

/* The weight array of a chunk, or an error listing the fields there are. */
static orr_status weight_field(const orr_splat_settings *set, const orr_source *src, const orr_chunk *c,
                               const float **w, orr_error *err)
{
    *w = orr_chunk_field(c, set->weight);
    if (*w)
        return ORR_OK;
    char have[512] = "mass";
    if (c->h)
        strncat(have, ", h", sizeof have - strlen(have) - 1);
    for (int i = 0; i < c->nextra; i++) {
        strncat(have, ", ", sizeof have - strlen(have) - 1);
        strncat(have, c->extra[i].name, sizeof have - strlen(have) - 1);
    }
    return orr_fail(err, ORR_ERR_USAGE, "%s: input.weight '%s' is not a field of %s (fields: %s)", set->path,
                    set->weight, src->info.path, have);
}

/* How many lanes the view splats in (reduce/lanes.h), for a source of
 * count particles (-1 when unknown). */
static int lanes_for(const orr_splat_view *v, int64_t count)
{
    int shares_per_particle = v->use_sph                                  ? 0
                              : v->splat.deposit.kind == ORR_DEPOSIT_NGP ? 1
                                                                     : ORR_MAX_SHARES_PER_POINT;
    return orr_lanes_for(v->proj.width, v->proj.height, v->nplanes, shares_per_particle, count);
}

static orr_status alloc_lanes(orr_splat_view *v, int64_t count, orr_error *err)
{
    return orr_lanes_alloc(&v->lanes, lanes_for(v, count), v->nplanes, v->proj.width, v->proj.height, err);
}

/* The bands of a point deposit: a window of blocks of a chunk of up to
 * capacity particles, each block's shares in a region of its own. */
static orr_status alloc_bands(orr_splat_view *v, size_t capacity, orr_error *err)
{
    v->lanes.n = 1;
    size_t nblocks = (capacity + BLOCK - 1) / BLOCK;
    size_t window = nblocks < ORR_BAND_WINDOW_BLOCKS ? nblocks : ORR_BAND_WINDOW_BLOCKS;
    size_t per_point = v->splat.deposit.kind == ORR_DEPOSIT_NGP ? 1 : ORR_MAX_SHARES_PER_POINT;
    size_t npix = (size_t)v->proj.width * (size_t)v->proj.height;
    return orr_bands_init(&v->bands, npix, v->nplanes, window ? window : 1, per_point * BLOCK, err);
}

void orr_splat_free_lanes(orr_splat_view *v)
{
    orr_lanes_free(&v->lanes);
}

/* The scratch of a chunk's splat: block buffers and an error per lane, and
 * per block where its smoothing lengths start and what it added. */
typedef struct splat_work {
    block_buffers *buffers; /* MAX_LANES */
    block_buffers *samples; /* MAX_LANES, with motion blur: buffers[k].samples */
    orr_error lane_err[MAX_LANES];
    size_t failed[MAX_LANES]; /* the block at which a lane stopped, or SIZE_MAX */
    size_t nblocks_cap;
    size_t *lengths_first; /* per block */
    block_tally *tally;    /* per block */
    /* Per worker, seconds spent gathering and projecting (0) and depositing
     * (1): the threads interleave the two, so the chunk's splat time is
     * shared between the stages in this proportion (--timings). */
    double split[MAX_LANES][2];
    /* output.exr_population_layers: the planes after X, Y, Z (X, Y, Z per
     * population), and each particle's population; 0 and NULL without. */
    int npop_planes;
    int32_t *pop_of;
} splat_work;

/* Where each block's neighbour smoothing lengths start: they are taken in
 * source order by the particles orr_lengths_counts counts, so each block's
 * start is the count before it (a serial pass, cheap beside the splat). */
static void lengths_starts(orr_splat_view *v, const orr_chunk *c, size_t nblocks, size_t *first)
{
    size_t next = v->lengths_next;
    for (size_t blk = 0; blk < nblocks; blk++) {
        first[blk] = next;
        if (!v->lengths)
            continue; /* the file's lengths, or none: nothing to count */
        size_t end = (blk + 1) * BLOCK < c->n ? (blk + 1) * BLOCK : c->n;
        for (size_t i = blk * BLOCK; i < end; i++)
            if (orr_lengths_counts(v->splat.type_mask, c, i) && next < v->lengths->n)
                next++;
    }
    v->lengths_next = next;
}

/* Gathers and projects block blk of the chunk into b for worker k (a lane,
 * or a thread of the bands), its report in *t, freshly zeroed. Returns the
 * particles gathered, or -1 on a bad particle, recorded in w->failed[k]
 * and w->lane_err[k]. */
static long take_block(const orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                       size_t blk, splat_work *w, int k, block_buffers *b, block_tally **t)
{
    size_t start = blk * BLOCK, end = start + BLOCK < c->n ? start + BLOCK : c->n;
    *t = &w->tally[blk];
    memset(*t, 0, sizeof **t);
    long n = orr_splat_project_block(v, src, c, wts, start, end, orr_v3(0, 0, 0), 0, w->lengths_first[blk], b, *t,
                           &w->lane_err[k]);
    if (n < 0)
        w->failed[k] = blk;
    return n;
}

/* One lane's blocks of the chunk, in order; stops at a bad particle,
 * recording the block in w->failed[lane] and the error in w->lane_err. */
static void splat_lane(orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                       size_t nblocks, int lane, splat_work *w)
{
    block_buffers *b = &w->buffers[lane];
    orr_plane *planes = orr_lane_planes(&v->lanes, v->planes, lane);
    double at = orr_thread_cpu_seconds();
    for (size_t blk = (size_t)lane; blk < nblocks; blk += (size_t)v->lanes.n) {
        block_tally *t;
        long n = take_block(v, src, c, wts, blk, w, lane, b, &t);
        if (n < 0)
            return;
        at = orr_splat_split_mark(w->split[lane], 0, at);
        orr_splat_deposit_block(v, planes, lane, (size_t)n, b, t);
        at = orr_splat_split_mark(w->split[lane], 1, at);
    }
}

/* The error of the first bad block, as a single thread would have met it:
 * each worker records the block it stopped at (or SIZE_MAX). */
static orr_status first_failure(const splat_work *w, int nworkers, orr_error *err)
{
    int bad = -1;
    for (int k = 0; k < nworkers; k++)
        if (w->failed[k] != SIZE_MAX && (bad < 0 || w->failed[k] < w->failed[bad]))
            bad = k;
    if (bad < 0)
        return ORR_OK;
    if (err)
        *err = w->lane_err[bad];
    return w->lane_err[bad].code ? w->lane_err[bad].code : ORR_ERR_DATA;
}

/* Adds the chunk's blocks to the view's tally, in block order. */
static void add_chunk_tally(orr_splat_view *v, const orr_chunk *c, const splat_work *w, size_t nblocks)
{
    for (size_t blk = 0; blk < nblocks; blk++)
        orr_splat_add_tally(&v->tally, &w->tally[blk]);
    if (v->drawing_stars)
        v->tally.n_stars += c->n;
    else
        v->tally.n_read += c->n;
}

/* Splats the chunk into one view, its lanes in parallel; the tally's sums
 * are taken in block order afterwards. On a bad particle the error is that
 * of the first bad block, as a single thread would have found it. */
static orr_status splat_view_lanes(orr_splat_view *v, const orr_source *src, const orr_chunk *c,
                                   const float *const *wts, splat_work *w, orr_error *err)
{
    size_t nblocks = (c->n + BLOCK - 1) / BLOCK;
    lengths_starts(v, c, nblocks, w->lengths_first);
    for (int lane = 0; lane < MAX_LANES; lane++)
        w->failed[lane] = SIZE_MAX;
    const int nlanes = v->lanes.n;
#pragma omp parallel for schedule(dynamic, 1)
    for (int lane = 0; lane < nlanes; lane++)
        splat_lane(v, src, c, wts, nblocks, lane, w);
    orr_status st = first_failure(w, nlanes, err);
    if (!st)
        add_chunk_tally(v, c, w, nblocks);
    return st;
}

/* Threads of the splat: the machine's, at most MAX_LANES (the work's
 * buffers). */
static int splat_threads(void)
{
    int n = omp_get_max_threads();
    return n < MAX_LANES ? n : MAX_LANES;
}

/* The shares of blocks [first, first + count) of the chunk, sorted by band
 * into regions 0 .. count-1, the blocks shared out among the threads. A
 * thread stops at a bad particle (w->failed); its later blocks are all
 * after it, so the first failure is the one a single thread would meet. */
static void window_shares(orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                          size_t first, size_t count, splat_work *w, int nthreads)
{
    const int W = v->proj.width, H = v->proj.height;
#pragma omp parallel num_threads(nthreads)
    {
        const int me = omp_get_thread_num();
        block_buffers *b = &w->buffers[me];
#pragma omp for schedule(dynamic, 1)
        for (size_t q = 0; q < count; q++) {
            if (w->failed[me] != SIZE_MAX)
                continue;
            block_tally *t;
            long n = take_block(v, src, c, wts, first + q, w, me, b, &t);
            if (n < 0)
                continue;
            orr_shares shares = {b->share_pixel, {NULL}, 0};
            for (int k = 0; k < v->nplanes; k++)
                shares.w[k] = b->share_w[k];
            if (b->indexed) {
                orr_ngp_batch nb = orr_splat_place_indexed(v, (size_t)n, b, t);
                orr_ngp_shares(&nb, &shares);
            } else {
                orr_deposit_stats st[ORR_PLANES_MAX];
                memset(st, 0, sizeof st);
                orr_point_batch pb = {(size_t)n, b->px, b->py, b->visible, {NULL}, v->nplanes};
                for (int k = 0; k < v->nplanes; k++)
                    pb.w[k] = b->wp[k];
                orr_deposit_shares(v->splat.deposit.kind, &pb, &v->proj, W, H, &shares, st);
                t->deposit[0] = st[0];
                t->deposit[1] = st[1];
            }
            orr_bands_put(&v->bands, q, &shares, b->band_cursor);
        }
    }
}

/* Splats the chunk into a view of point deposits: window by window, the
 * blocks' shares in parallel, then the bands in parallel (splat/bands.h:
 * the same sums in the same order whatever the threads). */
static orr_status splat_view_banded(orr_splat_view *v, const orr_source *src, const orr_chunk *c,
                                    const float *const *wts, splat_work *w, orr_error *err)
{
    const size_t nblocks = (c->n + BLOCK - 1) / BLOCK, window = v->bands.nregions;
    const int nthreads = splat_threads(), nbands = v->bands.nbands;
    lengths_starts(v, c, nblocks, w->lengths_first);
    for (int k = 0; k < MAX_LANES; k++)
        w->failed[k] = SIZE_MAX;
    for (size_t first = 0; first < nblocks; first += window) {
        size_t count = nblocks - first < window ? nblocks - first : window;
        orr_clock at = orr_clock_now();
        window_shares(v, src, c, wts, first, count, w, nthreads);
        orr_status st = first_failure(w, nthreads, err);
        if (st)
            return st;
        orr_clock mid = orr_clock_now();
        /* Runs of eight consecutive bands: each band prefetches the next. */
#pragma omp parallel for schedule(dynamic, 8) num_threads(nthreads)
        for (int band = 0; band < nbands; band++)
            orr_bands_apply(&v->bands, band, count, v->planes);
        /* The two phases follow each other: their wall times split the splat. */
        w->split[0][0] += mid.wall - at.wall;
        w->split[0][1] += orr_clock_now().wall - mid.wall;
    }
    add_chunk_tally(v, c, w, nblocks);
    return ORR_OK;
}

static orr_status splat_view(orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *wts,
                             splat_work *w, orr_error *err)
{
    return v->banded ? splat_view_banded(v, src, c, wts, w, err) : splat_view_lanes(v, src, c, wts, w, err);
}

/* Each particle's X, Y, Z into its population's planes (xyz[3 + 3p + c])
 * and 0 into the others', particles [start, start + count). A particle of
 * no population (pop < 0) has X = Y = Z = 0 and is in none. So the
 * populations' planes sum, pixel by pixel, to the X, Y, Z planes. */
static void split_xyz_by_population(float *const *xyz, int npop_planes, const int32_t *pop, size_t start,
                                    size_t count)
{
    for (int k = 0; k < npop_planes; k++) {
        const int p = k / 3;
        const float *restrict in = xyz[k % 3] + start;
        float *restrict out = xyz[3 + k] + start;
        for (size_t i = 0; i < count; i++)
            out[i] = pop[i] == p ? in[i] : 0.0f;
    }
}

/* The per-particle weights of a chunk: input.weight's field, or with
 * colour the X, Y, Z of each particle's population (into xyz, room for the
 * chunk's capacity), assigned in MAX_LANES parallel stretches; an error is
 * the first stretch's that failed, as one thread would have met it. */
static orr_status chunk_weights(const orr_splat_settings *set, const orr_source *src, const orr_chunk *c, float *const *xyz,
                                const float **w, splat_work *work, orr_error *err)
{
    if (!set->has_populations)
        return weight_field(set, src, c, &w[0], err);
    orr_status st_part[MAX_LANES];
    const size_t n = c->n, per = (n + MAX_LANES - 1) / MAX_LANES;
#pragma omp parallel for schedule(static, 1)
    for (int part = 0; part < MAX_LANES; part++) {
        size_t start = (size_t)part * per < n ? (size_t)part * per : n;
        size_t count = start + per < n ? per : n - start;
        int32_t *pop = work->pop_of ? work->pop_of + start : NULL;
        st_part[part] = orr_population_assign_at(&set->populations, src->info.time, c, start, count, set->only_index, pop,
                                                 xyz[0] + start, xyz[1] + start, xyz[2] + start,
                                                 &work->lane_err[part]);
        if (pop && !st_part[part])
            split_xyz_by_population(xyz, work->npop_planes, pop, start, count);
    }
    for (int part = 0; part < MAX_LANES; part++)
        if (st_part[part]) {
            if (err)
                *err = work->lane_err[part];
            orr_fail_prefix(err, "%s: colour.populations: ", set->path);
            return st_part[part];
        }
    for (int k = 0; k < 3 + work->npop_planes; k++)
        w[k] = xyz[k];
    return ORR_OK;
}

/* Room for the per-block records of a chunk of n particles. */
static orr_status reserve_blocks(splat_work *w, size_t n, orr_error *err)
{
    size_t nblocks = (n + BLOCK - 1) / BLOCK;
    if (nblocks <= w->nblocks_cap && w->tally)
        return ORR_OK;
    nblocks = nblocks ? nblocks : 1;
    free(w->lengths_first);
    free(w->tally);
    w->lengths_first = orr_malloc(nblocks * sizeof *w->lengths_first, "splat blocks", err);
    w->tally = w->lengths_first ? orr_malloc(nblocks * sizeof *w->tally, "splat blocks", err) : NULL;
    w->nblocks_cap = w->tally ? nblocks : 0;
    return w->tally ? ORR_OK : ORR_ERR_NOMEM;
}

/* The eye of view v, for its dust. */
static orr_dust_eye dust_eye(const orr_splat_view *v)
{
    const orr_mat3 *r = &v->world_to_camera; /* its third row: the view axis */
    return (orr_dust_eye){v->camera_position, orr_projection_traits_of(v->proj.settings.kind).parallel,
                          orr_v3(r->m[2][0], r->m[2][1], r->m[2][2])};
}

/* The chunk's spawned stars into every view, as points dimmed from their
 * own distance (and by the dust in front of them), after the chunk's
 * particles, so the dust's optical depths of the particles serve every
 * view before the stars' are found. The first view's dimmed weights give
 * the list's apparent V. */
static orr_status splat_stars(orr_splat_view *const *views, int nviews, const orr_source *src, splat_work *work,
                              orr_error *err)
{
    frame_stars *fs = views[0]->stars;
    const orr_chunk *sc = &fs->batch.stars;
    orr_status st = reserve_blocks(work, sc->n, err);
    for (int k = 0; k < nviews && !st; k++) {
        const float *wv[ORR_PLANES_MAX] = {fs->batch.xyz[0], fs->batch.xyz[1], fs->batch.xyz[2]};
        if (views[k]->dust) {
            orr_dust_eye eye = dust_eye(views[k]);
            st = orr_dust_weights(views[k]->dust, &eye, sc, wv, views[k]->nplanes, err);
        }
        if (!st && k == 0)
            st = orr_frame_stars_record(fs, views[k]->dust ? wv[1] : NULL, err);
        if (st)
            break;
        /* Points: no lengths from the neighbours (the stars were not among
         * them), so no glow. */
        const orr_lengths *lengths = views[k]->lengths;
        views[k]->lengths = NULL;
        views[k]->drawing_stars = 1;
        st = splat_view(views[k], src, sc, wv, work, err);
        views[k]->lengths = lengths;
        views[k]->drawing_stars = 0;
    }
    return st;
}

/* Splats a chunk into every view; its time goes to the
 * gather and deposit stages (the weights to the gather; the splat shared
 * as the workers' own clocks say). */
static orr_status splat_chunk(orr_splat_view *const *views, int nviews, const orr_source *src, const orr_chunk *c,
                              splat_work *work, float *const *xyz, orr_error *err)
{
    const float *w[ORR_PLANES_MAX] = {NULL};
    orr_status st = chunk_weights(&views[0]->splat, src, c, xyz, w, work, err);
    if (!st && views[0]->stars) /* the stars take their light from the weights */
        st = orr_frame_stars_spawn(views[0]->stars, c, xyz, err);
    orr_splat_charge(views[0], ORR_STAGE_GATHER);
    memset(work->split, 0, sizeof work->split);
    for (int k = 0; k < nviews && !st; k++) {
        const float *wv[ORR_PLANES_MAX];
        memcpy(wv, w, sizeof wv);
        if (views[k]->dust) { /* dimmed by the dust between the view's eye and each star (dust/dust.h) */
            orr_dust_eye eye = dust_eye(views[k]);
            st = orr_dust_weights(views[k]->dust, &eye, c, wv, views[k]->nplanes, err);
        }
        if (!st)
            st = views[k]->periodic.active
                     ? orr_splat_chunk_periodic(views[k], src, c, wv, &work->buffers[0], work->split[0], err)
                     : splat_view(views[k], src, c, wv, work, err);
    }
    if (!st && views[0]->stars && views[0]->stars->batch.stars.n)
        st = splat_stars(views, nviews, src, work, err);
    double part[2] = {0.0, 0.0};
    for (int k = 0; k < MAX_LANES; k++)
        part[0] += work->split[k][0], part[1] += work->split[k][1];
    if (views[0]->timer)
        orr_stage_charge_split(&views[0]->timer->times, ORR_STAGE_GATHER, ORR_STAGE_DEPOSIT,
                               part[0] / (part[0] + part[1]), &views[0]->timer->at);
    return st;
}

static orr_status alloc_work(splat_work *w, size_t capacity, int blur, orr_error *err)
{
    memset(w, 0, sizeof *w);
    w->buffers = orr_malloc(MAX_LANES * sizeof *w->buffers, "splat block buffers", err);
    if (!w->buffers)
        return ORR_ERR_NOMEM;
    if (blur) {
        if (!(w->samples = orr_malloc(MAX_LANES * sizeof *w->samples, "motion blur samples", err)))
            return ORR_ERR_NOMEM;
        for (int k = 0; k < MAX_LANES; k++)
            w->buffers[k].samples = &w->samples[k];
    }
    return reserve_blocks(w, capacity, err);
}

/* Room for a chunk's colour weights: X, Y, Z, and with population planes
 * (nplanes > 3) each population's X, Y, Z and each particle's population. */
static orr_status alloc_colour_weights(splat_work *w, int nplanes, size_t cap, float **xyz, orr_error *err)
{
    for (int k = 0; k < nplanes; k++)
        if (!(xyz[k] = orr_malloc(cap * sizeof(float), "colour weights", err)))
            return ORR_ERR_NOMEM;
    w->npop_planes = nplanes - 3;
    if (w->npop_planes > 0 && !(w->pop_of = orr_malloc(cap * sizeof *w->pop_of, "colour populations", err)))
        return ORR_ERR_NOMEM;
    return ORR_OK;
}

static void free_work(splat_work *w)
{
    free(w->buffers);
    free(w->samples);
    free(w->lengths_first);
    free(w->tally);
    free(w->pop_of);
}

/* A HEALPix view's SPH work limit for this frame: so many kernel samples
 * per thread (splat/healpix_kernel.h). */
static void start_healpix_budgets(orr_splat_view *const *views, int nviews, const orr_source *src,
                                  orr_progress_fn progress, void *progress_user)
{
    const uint64_t limit = ORR_HEALPIX_SAMPLE_LIMIT_PER_THREAD * (uint64_t)omp_get_max_threads();
    for (int k = 0; k < nviews; k++) {
        orr_healpix_budget *b = views[k]->use_sph ? views[k]->sph.healpix_budget : NULL;
        if (!b)
            continue;
        orr_healpix_budget_start(b, limit, src->info.count);
        /* A map's kernels can take minutes within one chunk: their own
         * progress, from the first HEALPix view (one line is enough). */
        b->progress = progress;
        b->progress_user = progress_user;
        progress = NULL;
    }
}

/* The frame has at least the particles read so far (a count the source
 * does not know beforehand, a text table's, is then foreseen from them). */
static void expect_at_least(orr_splat_view *const *views, int nviews, int64_t read)
{
    for (int k = 0; k < nviews; k++) {
        orr_healpix_budget *b = views[k]->use_sph ? views[k]->sph.healpix_budget : NULL;
        if (b && b->expected < read)
            b->expected = read;
    }
}

/* A HEALPix view whose kernels went beyond the limit: refused, with the
 * figures and the ways to a frame that can be made. */
static orr_status check_healpix_budgets(orr_splat_view *const *views, int nviews, orr_error *err)
{
    for (int k = 0; k < nviews; k++) {
        orr_healpix_budget *b = views[k]->use_sph ? views[k]->sph.healpix_budget : NULL;
        if (!b || !atomic_load(&b->exceeded))
            continue;
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: camera.healpix_nside %lld with deposit: sph: the frame's kernels need more than "
                        "the limit of %.3g kernel samples (%.2g per thread, about a minute each; %.3g foreseen "
                        "from the first %llu of %lld particles): kernels near the camera cover much of the sky, "
                        "at up to 12 nside^2 samples each. Use a smaller camera.healpix_nside (the work goes as "
                        "its square), deposit: ngp, or a camera farther from the particles",
                        views[k]->splat.path, (long long)views[k]->proj.settings.healpix_nside, (double)b->limit,
                        (double)ORR_HEALPIX_SAMPLE_LIMIT_PER_THREAD,
                        (double)atomic_load(&b->foreseen) / (double)atomic_load(&b->foreseen_particles) *
                            (double)b->expected,
                        (unsigned long long)atomic_load(&b->foreseen_particles), (long long)b->expected);
    }
    return ORR_OK;
}

/* The types the splat takes anything from: those its views draw and those
 * that spawn stars; a source may leave out the others (a model its gas,
 * which the dust took in a pass of its own), counted as read. */
static unsigned pass_types(orr_splat_view *const *views, int nviews)
{
    unsigned types = views[0]->stars ? views[0]->stars->stage.set.types : 0;
    for (int k = 0; k < nviews; k++) {
        if (!views[k]->splat.type_mask)
            return 0; /* (every type) */
        types |= views[k]->splat.type_mask;
    }
    return types;
}

orr_status orr_splat_views(orr_splat_view *const *views, int nviews, orr_source *src, orr_progress_fn progress,
                               void *progress_user, orr_error *err)
{
    start_healpix_budgets(views, nviews, src, progress, progress_user);
    int64_t read = 0;
    splat_work *work = orr_malloc(sizeof *work, "splat work", err);
    if (!work)
        return ORR_ERR_NOMEM;
    int blur = 0;
    for (int k = 0; k < nviews; k++)
        blur |= views[k]->blur.active;
    orr_status st = alloc_work(work, src->chunk.capacity, blur, err);
    /* With colour, a chunk's X, Y, Z weights (and each population's). */
    float *xyz[ORR_PLANES_MAX] = {NULL};
    size_t cap = views[0]->splat.has_populations ? src->chunk.capacity : 0;
    if (!st && cap)
        st = alloc_colour_weights(work, views[0]->nplanes, cap, xyz, err);
    for (int k = 0; k < nviews && !st; k++)
        st = views[k]->banded && !views[k]->periodic.active ? alloc_bands(views[k], src->chunk.capacity, err)
                             : alloc_lanes(views[k], src->info.count, err);
    for (int k = 0; k < nviews && !st; k++)
        if (views[k]->coarse && views[k]->lanes.n > views[k]->coarse->nlanes)
            st = orr_fail(err, ORR_ERR_INTERNAL, "%s: %d lanes, but the coarse glow was planned for %d",
                          views[k]->splat.path, views[k]->lanes.n, views[k]->coarse->nlanes);
    orr_splat_charge(views[0], ORR_STAGE_SETUP); /* the lanes' planes, zeroed */
    orr_source_only_types(src, pass_types(views, nviews));
    while (!st) {
        const orr_chunk *c;
        st = orr_source_next(src, &c, err);
        orr_splat_charge(views[0], ORR_STAGE_SOURCE);
        if (st || c->n == 0)
            break;
        read += (int64_t)c->n;
        expect_at_least(views, nviews, read);
        if ((st = reserve_blocks(work, c->n, err)) || (st = splat_chunk(views, nviews, src, c, work, xyz, err)) ||
            (st = check_healpix_budgets(views, nviews, err)))
            break;
        /* From this thread alone, between chunks. */
        if (progress)
            progress(progress_user, views[0]->tally.n_read, src->info.count);
    }
    for (int k = 0; k < nviews; k++) {
        views[k]->tally.n_read += src->left_out; /* (read as far as the count goes: NPART) */
        orr_bands_free(&views[k]->bands);
        if (!st)
            orr_lanes_merge(&views[k]->lanes, views[k]->planes,
                            (size_t)views[k]->proj.width * (size_t)views[k]->proj.height);
    }
    for (int k = 0; k < nviews && !st; k++) {
        st = orr_coarse_glow_finish(views[k], err);
        views[k]->tally.stars_capped = views[0]->stars && views[0]->stars->stage.capped;
    }
    for (int k = 0; k < nviews && !st; k++)
        if (views[k]->psf.sky)
            st = orr_sky_psf_select(views[k]->psf.sky, err);
    orr_splat_charge(views[0], ORR_STAGE_REDUCE);
    for (int k = 0; k < ORR_PLANES_MAX; k++)
        free(xyz[k]);
    free_work(work);
    free(work);
    return st;
}

/* How the view is splatted: in bands or lanes, and whether NGP blocks take
 * the fused gather. (A sky PSF collects its stars per lane: it keeps
 * lanes; streaks are drawn as their samples are made: in lanes.) */
void orr_splat_choose_path(orr_splat_view *v)
{
    const orr_splat_settings *set = &v->splat;
    v->banded = !v->use_sph && !v->psf.sky && !v->blur.active &&
                orr_lanes_use_bands((size_t)v->proj.width * (size_t)v->proj.height);
    v->ngp_fused = set->deposit.kind == ORR_DEPOSIT_NGP && !v->use_sph && !v->psf.sky && !v->use_ods && !v->blur.active;
}
