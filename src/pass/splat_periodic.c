/* A periodic box's copies in the splat (pass/periodic_view.h): each
 * block summarised once, then every copy of the chunk drawn on one thread
 * in block order, skipping whole copies and blocks out of view or beyond
 * the sphere of images before their particles are touched. */
#include "pass/splat_block.h"

#include <stdlib.h>
#include <string.h>

#include "pass/periodic_view.h"

/* Gathers, projects and deposits particles [start, end) of c, moved by
 * shift (fading: across the copies' sphere), into the view's own planes,
 * starting at smoothing length lengths_next; what the block added goes
 * into the tally. */
static orr_status draw_block(orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *w,
                             size_t start, size_t end, orr_vec3 shift, int fading, size_t lengths_next,
                             block_buffers *b, double *split, orr_error *err)
{
    block_tally t;
    memset(&t, 0, sizeof t);
    double at = orr_thread_cpu_seconds();
    long n = orr_splat_project_block(v, src, c, w, start, end, shift, fading, lengths_next, b, &t, err);
    if (n < 0)
        return err ? err->code : ORR_ERR_DATA;
    at = orr_splat_split_mark(split, 0, at);
    orr_splat_deposit_block(v, v->planes, 0, (size_t)n, b, &t);
    orr_splat_split_mark(split, 1, at);
    orr_splat_add_tally(&v->tally, &t);
    return ORR_OK;
}

/* A copy of a block (or of a whole chunk) skipped out of view: its weight
 * counts as not drawn, as the projection would have counted it. */
static void count_culled(orr_splat_view *v, const orr_block_summary *sum)
{
    orr_deposit_stats *d[2] = {&v->tally.deposit, &v->tally.deposit_y};
    v->tally.n_selected += sum->n;
    for (int k = 0; k < v->nplanes && k < 2; k++) {
        d[k]->culled += sum->w[k];
        d[k]->n_culled += sum->n;
        d[k]->n_particles += sum->n;
    }
}

/* Whether a copy (by shift) of the particles summarised in sum is skipped
 * whole: beyond the periodic sphere, or out of view. (Never with a
 * particle the gather must see, nor with culling off.) */
static int copy_skipped(const orr_periodic_view *pv, const orr_block_summary *sum, orr_vec3 shift)
{
    if (sum->must_gather)
        return 0;
    if (pv->cull_sphere && orr_replica_sphere_box(&pv->sphere, sum->lo, sum->hi, shift) == ORR_SPHERE_BEYOND)
        return 1;
    return pv->cull && orr_view_cull_box(&pv->view, sum->lo, sum->hi, shift, sum->radius);
}

/* Whether a drawn copy of a block has particles in the sphere's taper or
 * beyond it, so that each is weighed by its distance (else it is drawn
 * whole, on the fast path). */
static int copy_fades(const orr_periodic_view *pv, const orr_block_summary *sum, orr_vec3 shift)
{
    return pv->sphere.radius > 0 && (sum->must_gather || sum->n == 0 ||
                                     orr_replica_sphere_box(&pv->sphere, sum->lo, sum->hi, shift) != ORR_SPHERE_INSIDE);
}

/* A periodic box: the chunk drawn once per copy of the box. Each block is
 * summarised once (bounds, largest kernel, weights); then a copy of the
 * chunk wholly out of view is skipped, and within the others each copy of
 * a block out of view, before their particles are touched. Drawn on one
 * thread into the view's own planes, in block order (in a fly-through the
 * culling, not threads, is what saves the time). */
orr_status orr_splat_chunk_periodic(orr_splat_view *v, const orr_source *src, const orr_chunk *c, const float *const *w,
                                    block_buffers *b, double *split, orr_error *err)
{
    const orr_periodic_view *pv = &v->periodic;
    const size_t nblocks = (c->n + BLOCK - 1) / BLOCK, first_length = v->lengths_next;
    orr_block_summary *sum = orr_malloc((nblocks ? nblocks : 1) * sizeof *sum, "block summaries", err), whole;
    if (!sum)
        return ORR_ERR_NOMEM;
    orr_block_lengths bl = {v->lengths, first_length, v->h_scale, v->use_sph};
    memset(&whole, 0, sizeof whole);
    for (size_t q = 0; q < nblocks; q++) {
        size_t end = (q + 1) * BLOCK < c->n ? (q + 1) * BLOCK : c->n;
        orr_block_summarise(&v->splat, c, q * BLOCK, end, &bl, w, v->nplanes, &sum[q]);
        bl.next += sum[q].lengths_used;
        orr_block_summary_merge(&whole, &sum[q]);
    }
    orr_status st = ORR_OK;
    for (int r = 0; r < pv->replicas.n && !st; r++) {
        const orr_vec3 shift = pv->replicas.offset[r];
        v->tally.n_blocks += nblocks;
        if (copy_skipped(pv, &whole, shift)) {
            count_culled(v, &whole);
            v->tally.n_replicas_culled++;
            v->tally.n_blocks_culled += nblocks;
            continue;
        }
        size_t next = first_length; /* every copy takes the same lengths */
        for (size_t q = 0; q < nblocks && !st; q++) {
            size_t end = (q + 1) * BLOCK < c->n ? (q + 1) * BLOCK : c->n;
            if (copy_skipped(pv, &sum[q], shift)) {
                count_culled(v, &sum[q]);
                v->tally.n_blocks_culled++;
            } else {
                st = draw_block(v, src, c, w, q * BLOCK, end, shift, copy_fades(pv, &sum[q], shift), next, b, split,
                                err);
            }
            next += sum[q].lengths_used;
        }
    }
    v->lengths_next = first_length + whole.lengths_used;
    v->tally.n_read += c->n;
    free(sum);
    return st;
}
