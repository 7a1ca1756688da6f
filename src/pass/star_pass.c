/* Stars from particles in the splat pass (stars/stars.h): each chunk's
 * stars spawned after its weights are found, splatted as points into every
 * view after the chunk's particles, and recorded in the frame's list, which
 * each sky map writes as NAME.stars.fits. */
#include "pass/splat_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/numbers.h"
#include "pass/camera_transform.h"

orr_status orr_frame_stars_prepare(frame_stars *fs, const orr_stars_settings *set, uint64_t observer_id,
                                   const char *scene_path, orr_error *err)
{
    memset(fs, 0, sizeof *fs);
    fs->observer_id = observer_id;
    return orr_stars_prepare(&fs->stage, set, scene_path, err);
}

static void free_list(frame_stars *fs)
{
    free(fs->l), free(fs->b), free(fs->v), free(fs->bv), free(fs->abs_v), free(fs->dist_pc);
    free(fs->px), free(fs->py), free(fs->pz), free(fs->parent), free(fs->index);
}

void orr_frame_stars_free(frame_stars *fs)
{
    orr_star_batch_free(&fs->batch);
    free(fs->glow_dimming);
    free_list(fs);
    memset(fs, 0, sizeof *fs);
}

void orr_frame_stars_begin(frame_stars *fs, const orr_sky_frame *sky)
{
    orr_stars_begin_frame(&fs->stage);
    fs->sky = *sky;
    fs->eye = sky->origin;
    fs->n = 0;
}

/* Room for the glow's dimming of n particles. */
static orr_status reserve_glow(frame_stars *fs, size_t n, orr_error *err)
{
    if (n <= fs->glow_cap)
        return ORR_OK;
    float *d = realloc(fs->glow_dimming, n * sizeof *d);
    if (!d)
        return orr_fail(err, ORR_ERR_NOMEM, "stars: out of memory for the glow's dimming of %zu particles", n);
    fs->glow_dimming = d;
    fs->glow_cap = n;
    return ORR_OK;
}

orr_status orr_frame_stars_spawn(frame_stars *fs, const orr_chunk *c, float *const *xyz, orr_error *err)
{
    orr_status st = reserve_glow(fs, c->n ? c->n : 1, err);
    if (st)
        return st;
    orr_stars_glow_dimming(&fs->stage, fs->eye, c, fs->glow_dimming);
    st = orr_stars_spawn(&fs->stage, fs->eye, fs->observer_id, c, xyz, &fs->batch, err);
    /* The dust keeps a chunk's optical depths by its first index: the
     * stars' are their chunk's own. */
    fs->batch.stars.first_index = c->first_index;
    return st;
}

/* realloc that keeps the old block when it fails, and says so in *fine. */
static void *realloc_or_keep(void *p, size_t size, int *fine)
{
    void *q = realloc(p, size);
    if (!q) {
        *fine = 0;
        return p;
    }
    return q;
}

/* Room for need stars in the list. */
static orr_status reserve_list(frame_stars *fs, size_t need, orr_error *err)
{
    if (need <= fs->cap)
        return ORR_OK;
    size_t cap = fs->cap ? fs->cap : 4096;
    while (cap < need)
        cap *= 2;
    int ok = 1;
#define GROW(a) (fs->a = realloc_or_keep(fs->a, cap * sizeof *fs->a, &ok))
    GROW(l), GROW(b), GROW(v), GROW(bv), GROW(abs_v), GROW(dist_pc), GROW(px), GROW(py), GROW(pz), GROW(parent),
        GROW(index);
#undef GROW
    if (!ok)
        return orr_fail(err, ORR_ERR_NOMEM, "stars: out of memory for a list of %zu stars", cap);
    fs->cap = cap;
    return ORR_OK;
}

orr_status orr_frame_stars_record(frame_stars *fs, const float *dimmed_y, orr_error *err)
{
    const orr_star_batch *b = &fs->batch;
    orr_status st = reserve_list(fs, fs->n + b->stars.n, err);
    if (st)
        return st;
    const double pc = fs->stage.set.length_unit, deg = 180.0 / ORR_PI;
    for (size_t i = 0; i < b->stars.n; i++) {
        const size_t j = fs->n++;
        const orr_vec3 d = orr_v3_sub(orr_v3(b->stars.x[i], b->stars.y[i], b->stars.z[i]), fs->eye);
        const double r = orr_v3_norm(d);
        fs->l[j] = atan2(orr_v3_dot(d, fs->sky.y), orr_v3_dot(d, fs->sky.x)) * deg;
        fs->b[j] = r > 0 ? asin(fmax(-1.0, fmin(1.0, orr_v3_dot(d, fs->sky.z) / r))) * deg : 0.0;
        double extinction = 0;
        if (dimmed_y && b->xyz[1][i] > 0)
            extinction = dimmed_y[i] > 0 ? -2.5 * log10((double)dimmed_y[i] / b->xyz[1][i]) : 99.0;
        fs->v[j] = (float)(b->info[i].v + extinction);
        fs->bv[j] = b->info[i].bv;
        fs->abs_v[j] = (float)b->info[i].abs_v;
        fs->dist_pc[j] = (float)(r * pc);
        fs->px[j] = b->stars.x[i], fs->py[j] = b->stars.y[i], fs->pz[j] = b->stars.z[i];
        fs->parent[j] = (int64_t)b->info[i].parent;
        fs->index[j] = (int32_t)b->info[i].index;
    }
    return ORR_OK;
}

/* Which of the list's stars the view shows: keep[i] 1 for those its
 * projection draws. Returns how many. */
static size_t stars_in_view(const frame_stars *fs, const orr_splat_view *v, unsigned char *keep, float *buf)
{
    const size_t n = fs->n;
    float *x = buf, *y = buf + n, *z = buf + 2 * n, *ix = buf + 3 * n, *iy = buf + 4 * n, *scale = buf + 5 * n;
    const orr_camera_transform t = orr_camera_transform_at(v->camera_position, &v->world_to_camera, orr_v3(0, 0, 0));
    for (size_t i = 0; i < n; i++) {
        orr_camera_point p = orr_to_camera(&t, fs->px[i], fs->py[i], fs->pz[i]);
        x[i] = p.x, y[i] = p.y, z[i] = p.z;
    }
    orr_project_batch(&v->proj, n, x, y, z, ix, iy, scale, keep);
    size_t shown = 0;
    for (size_t i = 0; i < n; i++)
        shown += keep[i] != 0;
    return shown;
}

/* Copies the kept rows of column src (n elements of size bytes) to dst,
 * in order. */
static void kept_rows(void *dst, const void *src, size_t size, const unsigned char *keep, size_t n)
{
    size_t out = 0;
    for (size_t i = 0; i < n; i++)
        if (keep[i])
            memcpy((char *)dst + out++ * size, (const char *)src + i * size, size);
}

orr_status orr_frame_stars_view_table(const frame_stars *fs, const orr_splat_view *v, orr_star_table *t, void **scratch,
                                      orr_error *err)
{
    const size_t n = fs->n;
    unsigned char *keep = malloc(n ? n : 1);
    float *buf = malloc((n ? n : 1) * 6 * sizeof(float));
    /* The table's own columns: the list serves every view. */
    size_t rows = n ? n : 1;
    char *copy = malloc(rows * (2 * sizeof(double) + 4 * sizeof(float) + sizeof(int64_t) + sizeof(int32_t)));
    if (!keep || !buf || !copy) {
        free(keep), free(buf), free(copy);
        return orr_fail(err, ORR_ERR_NOMEM, "stars: out of memory for the list of %zu stars", n);
    }
    size_t shown = n ? stars_in_view(fs, v, keep, buf) : 0;
    double *l = (double *)copy, *b = l + rows;
    float *vv = (float *)(b + rows), *bv = vv + rows, *mv = bv + rows, *dist = mv + rows;
    int64_t *parent = (int64_t *)(dist + rows);
    int32_t *index = (int32_t *)(parent + rows);
    kept_rows(l, fs->l, sizeof *l, keep, n), kept_rows(b, fs->b, sizeof *b, keep, n);
    kept_rows(vv, fs->v, sizeof *vv, keep, n), kept_rows(bv, fs->bv, sizeof *bv, keep, n);
    kept_rows(mv, fs->abs_v, sizeof *mv, keep, n), kept_rows(dist, fs->dist_pc, sizeof *dist, keep, n);
    kept_rows(parent, fs->parent, sizeof *parent, keep, n), kept_rows(index, fs->index, sizeof *index, keep, n);
    free(keep), free(buf);
    *t = (orr_star_table){shown, l, b, vv, bv, mv, dist, parent, index};
    *scratch = copy;
    return ORR_OK;
}
