#include "pass/periodic_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/numbers.h"

/* Deposits reach a pixel or so past a particle's centre (cloud-in-cell, the
 * smallest kernel disc); the view is widened by this many pixels, plenty. */
#define CULL_MARGIN_PIXELS 4.0
/* A kernel's support is 2h; a little more covers round-off. */
#define SUPPORT_PER_H 2.02

orr_status orr_periodic_box_side(const orr_periodic_settings *ps, const char *scene_path, const orr_source_info *info,
                                 double *box, orr_error *err)
{
    if (ps->box > 0) {
        *box = ps->box;
        return ORR_OK;
    }
    for (int k = 0; k < info->nheader; k++) {
        if (strcmp(info->header[k].key, "BoxSize") != 0)
            continue;
        const char *text = info->header[k].value;
        char *end;
        double first = orr_strtod(text, &end);
        if (end == text || !(first > 0) || !isfinite(first))
            return orr_fail(err, ORR_ERR_DATA,
                            "%s: input.periodic.replicas %d needs the box side, but the file's BoxSize is '%s'; "
                            "set input.periodic.box",
                            info->path, ps->replicas, text);
        for (const char *p = end; *p;) {
            double next = orr_strtod(p, &end);
            if (end == p)
                break;
            if (next != first)
                return orr_fail(err, ORR_ERR_DATA,
                                "%s: BoxSize is '%s', not a cube; orrery replicates cubes only: set "
                                "input.periodic.box",
                                info->path, text);
            p = end;
        }
        *box = first;
        return ORR_OK;
    }
    return orr_fail(err, ORR_ERR_USAGE,
                    "%s: input.periodic.replicas %d needs the box side: %s has no BoxSize in its header; set "
                    "input.periodic.box",
                    scene_path, ps->replicas, info->path);
}

/* The copies: n^3 around the box itself, or around the camera's copy,
 * and then only those reaching into the camera's sphere. */
static orr_status place_copies(orr_periodic_view *pv, const orr_periodic_settings *ps, orr_vec3 camera,
                               orr_error *err)
{
    orr_status st = orr_replicas_place(&pv->replicas, pv->box, ps->replicas, ps->around_camera, camera, err);
    if (st || !ps->around_camera)
        return st;
    st = orr_replica_sphere_resolve(&pv->sphere, pv->box, ps->replicas, ps->radius, ps->has_fade ? ps->fade : -1,
                                    err);
    if (st)
        return st;
    pv->sphere.camera = camera;
    orr_replicas_keep_sphere(&pv->replicas, pv->box, &pv->sphere);
    return ORR_OK;
}

orr_status orr_periodic_view_setup(orr_periodic_view *pv, const orr_splat_settings *set, const orr_source_info *info,
                                   const orr_projection *p, const orr_camera *cam, int can_cull, orr_error *err)
{
    memset(pv, 0, sizeof *pv);
    if (set->periodic.replicas <= 1)
        return ORR_OK;
    orr_status st = orr_periodic_box_side(&set->periodic, set->path, info, &pv->box, err);
    if (!st && (st = place_copies(pv, &set->periodic, cam->position, err)))
        orr_fail_prefix(err, "%s: ", set->path);
    if (st)
        return st;
    const char *off = getenv("ORRERY_NO_CULL");
    pv->active = 1;
    /* A copy or block beyond the sphere draws nothing however particles are
     * drawn (their weights are 0 there), so it is skipped unless told not. */
    pv->cull_sphere = pv->sphere.radius > 0 && !(off && strcmp(off, "1") == 0);
    pv->cull = can_cull && !(off && strcmp(off, "1") == 0);
    orr_view_cull_setup(&pv->view, p, cam, CULL_MARGIN_PIXELS);
    pv->cull = pv->cull && pv->view.active;
    return ORR_OK;
}

static int finite3(const orr_chunk *c, size_t i)
{
    return isfinite(c->x[i]) && isfinite(c->y[i]) && isfinite(c->z[i]);
}

/* Mirrors the splat pass's gather (splat_gather.c): which particles are drawn,
 * which smoothing length each takes. */
void orr_block_summarise(const orr_splat_settings *set, const orr_chunk *c, size_t start, size_t end,
                         const orr_block_lengths *bl, const float *const *w, int nw, orr_block_summary *out)
{
    memset(out, 0, sizeof *out);
    out->lo = orr_v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    out->hi = orr_v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    size_t next = bl->next;
    float hmax = 0.0f;
    for (size_t i = start; i < end; i++) {
        float h = 0.0f;
        if (bl->lengths) {
            if (orr_lengths_counts(set->type_mask, c, i) && next < bl->lengths->n)
                h = bl->lengths->h[next++] * bl->h_scale;
        } else if (c->h) {
            h = c->h[i] * bl->h_scale;
        }
        if (!(set->type_mask & (1u << c->type[i])) || (set->skip_observer && c->id[i] == set->observer_id))
            continue;
        int finite = finite3(c, i);
        for (int k = 0; k < nw; k++)
            finite = finite && isfinite(w[k][i]);
        if (!finite || !isfinite(h)) {
            out->must_gather = 1; /* the gather fails or counts it */
            continue;
        }
        out->n++;
        for (int k = 0; k < nw; k++)
            out->w[k] += w[k][i];
        hmax = h > hmax ? h : hmax;
        double x = c->x[i], y = c->y[i], z = c->z[i];
        out->lo = orr_v3(x < out->lo.x ? x : out->lo.x, y < out->lo.y ? y : out->lo.y, z < out->lo.z ? z : out->lo.z);
        out->hi = orr_v3(x > out->hi.x ? x : out->hi.x, y > out->hi.y ? y : out->hi.y, z > out->hi.z ? z : out->hi.z);
    }
    out->lengths_used = next - bl->next;
    out->radius = bl->use_kernel ? SUPPORT_PER_H * hmax : 0.0;
    if (out->n == 0) /* nothing to draw: an empty box, culled by any plane */
        out->lo = out->hi = orr_v3(0, 0, 0);
}

void orr_block_summary_merge(orr_block_summary *a, const orr_block_summary *b)
{
    if (b->n > 0 && a->n > 0) {
        a->lo = orr_v3(fmin(a->lo.x, b->lo.x), fmin(a->lo.y, b->lo.y), fmin(a->lo.z, b->lo.z));
        a->hi = orr_v3(fmax(a->hi.x, b->hi.x), fmax(a->hi.y, b->hi.y), fmax(a->hi.z, b->hi.z));
    } else if (b->n > 0) {
        a->lo = b->lo;
        a->hi = b->hi;
    }
    a->radius = fmax(a->radius, b->radius);
    for (int k = 0; k < ORR_PLANES_MAX; k++)
        a->w[k] += b->w[k];
    a->n += b->n;
    a->lengths_used += b->lengths_used;
    a->must_gather = a->must_gather || b->must_gather;
}
