#include "dust/dust.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/owned.h"
#include "particles/smoothing.h"

const orr_named orr_dust_curve_names[] = {
    {"ccm89", ORR_DUST_CCM89}, {"f99", ORR_DUST_F99}, {"file", ORR_DUST_CURVE_FILE}, {NULL, 0}};

#define MAG_PER_TAU 1.0857362047581294 /* 2.5 log10(e): A_V = 1.0857 tau_V */

void orr_dust_settings_defaults(orr_dust_settings *d)
{
    memset(d, 0, sizeof *d);
    d->dust_to_gas = 0.01;
    d->z_sun = 0.0134;
    d->curve = ORR_DUST_CCM89;
    d->r_v = ORR_DUST_RV_DEFAULT;
}

int orr_dust_settings_strings(orr_dust_settings *d, char **fields[])
{
    fields[0] = &d->curve_file;
    return ORR_DUST_STRINGS;
}

void orr_dust_settings_free(orr_dust_settings *d)
{
    char **fields[ORR_DUST_STRINGS];
    orr_owned_free_all(fields, orr_dust_settings_strings(d, fields));
}

orr_status orr_dust_settings_copy(orr_dust_settings *dst, const orr_dust_settings *src, orr_error *err)
{
    char **fields[ORR_DUST_STRINGS];
    return orr_owned_copy(dst, src, sizeof *dst, fields, orr_dust_settings_strings(dst, fields), err);
}

static void types_text(unsigned mask, char *buf, size_t size)
{
    size_t n = (size_t)snprintf(buf, size, "[");
    for (int t = 0; t < 32 && n < size; t++)
        if (mask >> t & 1u)
            n += (size_t)snprintf(buf + n, size - n, "%s%d", n > 1 ? ", " : "", t);
    if (n < size)
        snprintf(buf + n, size - n, "]");
}

orr_status orr_dust_settings_check(const orr_dust_settings *d, const char *path, unsigned drawn_types,
                                   orr_error *err)
{
    if (!d->types)
        return ORR_OK;
    char both[64];
    types_text(d->types & drawn_types, both, sizeof both);
    if (d->types & drawn_types)
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.types: type(s) %s are also drawn as light (input.types); "
                        "dust is not light: list only the star types in input.types", path, both);
    if (!(d->kappa_v > 0))
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.kappa_v is required with dust.types: the V-band opacity per "
                        "unit dust mass, in the scene's area per mass (docs/dust.md#units)", path);
    if (d->curve == ORR_DUST_CURVE_FILE && !d->curve_file)
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.curve: file needs dust.curve_file", path);
    if (d->curve != ORR_DUST_CURVE_FILE && d->curve_file)
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.curve_file is given but dust.curve is not file", path);
    /* The opacities are floats: a product beyond them would make every
     * column infinite and its shadow's edge NaN. */
    if (!(d->kappa_v * d->dust_to_gas <= FLT_MAX))
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.kappa_v * dust.dust_to_gas = %g * %g is beyond single "
                        "precision (%g): the opacities would be infinite; dust.kappa_v is in the scene's area per "
                        "mass (docs/dust.md#units)", path, d->kappa_v, d->dust_to_gas, (double)FLT_MAX);
    /* Read now even where only colour renders use it, so a missing or
     * malformed file is an error in a single-band render too. */
    if (d->curve == ORR_DUST_CURVE_FILE) {
        orr_dust_curve curve;
        if (orr_dust_curve_load(&curve, d->curve_file, err))
            return orr_fail_prefix(err, "%s: ", path);
    }
    return ORR_OK;
}

/* ---- reading the dust ---- */

static orr_status bad_particle(const orr_dust_context *ctx, const orr_source *src, const orr_chunk *c, size_t i,
                               const char *what, double v, orr_error *err)
{
    return orr_fail(err, ORR_ERR_DATA, "%s: %s: dust particle %llu (id %llu, type %d): %s = %g is not usable (%s)",
                    ctx->scene_path, src->info.path, (unsigned long long)(c->first_index + i),
                    (unsigned long long)c->id[i], (int)c->type[i], what, v,
                    strcmp(what, "position") == 0 ? "not finite" : "must be finite and >= 0, h > 0");
}

/* Particle i's opacity kappa * dust_to_gas (* Z / Z_sun) * mass, checked. */
static orr_status particle_opacity(const orr_dust_settings *d, const orr_dust_context *ctx, const orr_source *src,
                                   const orr_chunk *c, const float *z, size_t i, float *k, orr_error *err)
{
    double m = c->mass[i];
    if (!(m >= 0) || isinf(m))
        return bad_particle(ctx, src, c, i, "mass", m, err);
    double scale = d->kappa_v * d->dust_to_gas;
    if (z) {
        if (!(z[i] >= 0) || isinf(z[i]))
            return bad_particle(ctx, src, c, i, d->metallicity, z[i], err);
        scale *= z[i] / d->z_sun;
    }
    *k = (float)(scale * m);
    if (isinf(*k))
        return orr_fail(err, ORR_ERR_DATA, "%s: %s: dust particle %llu (id %llu, type %d): its opacity dust.kappa_v "
                        "* dust.dust_to_gas * mass = %g is beyond single precision; give kappa_v in the scene's "
                        "area per mass (docs/dust.md#units)", ctx->scene_path, src->info.path,
                        (unsigned long long)(c->first_index + i), (unsigned long long)c->id[i], (int)c->type[i],
                        scale * m);
    return ORR_OK;
}

static orr_status take_chunk(orr_dust_frame *f, const orr_dust_settings *d, const orr_dust_context *ctx,
                             const orr_source *src, const orr_chunk *c, int *with_h, orr_error *err)
{
    const float *z = NULL;
    if (d->metallicity[0] && !(z = orr_chunk_field(c, d->metallicity)))
        return orr_fail(err, ORR_ERR_USAGE, "%s: dust.metallicity: %s has no field '%s'", ctx->scene_path,
                        src->info.path, d->metallicity);
    for (size_t i = 0; i < c->n; i++) {
        if (c->type[i] >= 32 || !(d->types >> c->type[i] & 1u))
            continue;
        if (!isfinite(c->x[i]) || !isfinite(c->y[i]) || !isfinite(c->z[i]))
            return bad_particle(ctx, src, c, i, "position", NAN, err);
        float k = 0, h = 0;
        orr_status st = particle_opacity(d, ctx, src, c, z, i, &k, err);
        if (st)
            return st;
        if (*with_h) {
            h = (float)(c->h[i] * ctx->h_scale);
            if (!(h > 0) || isinf(h))
                return bad_particle(ctx, src, c, i, "smoothing length h", c->h[i], err);
        }
        if ((st = orr_dust_set_add(&f->set, c->x[i], c->y[i], c->z[i], h, k, err)))
            return st;
    }
    return ORR_OK;
}

/* Lengths for dust read without: from the dust's own neighbours, as SPH
 * does (particles/smoothing.h), times smoothing.h_scale. */
static orr_status neighbour_lengths(orr_dust_frame *f, const orr_dust_context *ctx, double h_scale,
                                    orr_error *err)
{
    orr_dust_set *s = &f->set;
    if (s->n < 2)
        return orr_fail(err, ORR_ERR_DATA, "%s: dust.types: %zu dust particle(s) without smoothing lengths: at "
                        "least 2 are needed to take lengths from the neighbours", ctx->scene_path, s->n);
    orr_status st = orr_smoothing_lengths(s->n, s->x, s->y, s->z, ctx->neighbours, ORR_SMOOTHING_FACTOR_DEFAULT,
                                          s->h, err);
    if (st)
        return orr_fail_prefix(err, "%s: dust: ", ctx->scene_path);
    for (size_t i = 0; i < s->n; i++) {
        s->h[i] = (float)(s->h[i] * h_scale);
        if (!(s->h[i] > 0))
            return orr_fail(err, ORR_ERR_DATA, "%s: dust: %zu-th dust particle at (%g, %g, %g) has smoothing "
                            "length 0 from its neighbours (more than smoothing.neighbours = %d particles at one "
                            "point)", ctx->scene_path, i, s->x[i], s->y[i], s->z[i], ctx->neighbours);
    }
    return ORR_OK;
}

static orr_status read_dust(orr_dust_frame *f, const orr_dust_settings *d, const orr_dust_context *ctx,
                            orr_source *src, orr_error *err)
{
    orr_status st = orr_source_rewind(src, err);
    int with_h = -1;
    while (!st) {
        const orr_chunk *c;
        if ((st = orr_source_next(src, &c, err)) || c->n == 0)
            break;
        if (with_h < 0)
            with_h = c->h != NULL;
        st = take_chunk(f, d, ctx, src, c, &with_h, err);
    }
    if (!st)
        st = orr_source_rewind(src, err);
    /* (No dust at all is no error: a frame may have none.) */
    if (!st && with_h <= 0 && f->set.n > 0)
        st = neighbour_lengths(f, ctx, ctx->h_scale, err);
    return st;
}

orr_status orr_dust_frame_prepare(orr_dust_frame *f, const orr_dust_settings *d, const orr_dust_context *ctx,
                                  orr_source *src, orr_error *err)
{
    memset(f, 0, sizeof *f);
    f->colour = ctx->colour;
    f->drawn_types = ctx->drawn_types;
    orr_status st = orr_dust_set_init(&f->set, ctx->kernel, err);
    if (!st)
        st = read_dust(f, d, ctx, src, err);
    if (!st)
        st = orr_dust_set_build(&f->set, err);
    orr_dust_curve curve;
    if (!st && ctx->colour)
        st = d->curve == ORR_DUST_CURVE_FILE ? orr_dust_curve_load(&curve, d->curve_file, err)
             : d->curve == ORR_DUST_F99      ? orr_dust_curve_f99(&curve, d->r_v, err)
                                             : orr_dust_curve_ccm89(&curve, d->r_v, err);
    if (!st && ctx->colour)
        st = orr_dust_redden_build(&f->red, &curve, err);
    if (st && !strstr(err ? err->msg : "", ctx->scene_path))
        orr_fail_prefix(err, "%s: ", ctx->scene_path);
    return st;
}

void orr_dust_frame_free(orr_dust_frame *f)
{
    orr_dust_set_free(&f->set);
    orr_dust_redden_free(&f->red);
    for (int k = 0; k < ORR_PLANES_MAX; k++)
        free(f->out[k]);
    free(f->tau);
    free(f->want);
    memset(f, 0, sizeof *f);
}

/* ---- a chunk's weights ---- */

static orr_status reserve(orr_dust_frame *f, size_t n, int nplanes, orr_error *err)
{
    int planes = nplanes > 3 ? nplanes : 3;
    if (n <= f->out_cap && planes <= f->out_planes)
        return ORR_OK;
    n = n > f->out_cap ? n : f->out_cap;
    for (int k = 0; k < planes; k++) {
        free(f->out[k]);
        if (!(f->out[k] = orr_malloc(n * sizeof(float), "dust weights", err)))
            return ORR_ERR_NOMEM;
    }
    free(f->tau);
    free(f->want);
    f->want = NULL;
    if (!(f->tau = orr_malloc(n * sizeof(double), "dust optical depths", err)) ||
        !(f->want = orr_malloc(n, "dust optical depths", err)))
        return ORR_ERR_NOMEM;
    f->out_cap = n;
    f->out_planes = planes;
    return ORR_OK;
}

static int drawn(const orr_dust_frame *f, const orr_chunk *c, size_t i)
{
    return c->type[i] < 32 && (f->drawn_types >> c->type[i] & 1u);
}

/* tau_V of each drawn particle of c from eye (0 for the others). From a
 * point the stars share the tree's traversal by direction (column_group.c);
 * an orthographic view sees each star from its own foot on the camera plane,
 * so each walks alone. Either way each star's value is its own walk's, the
 * same on any number of threads. */
static orr_status chunk_tau(orr_dust_frame *f, const orr_dust_eye *eye, const orr_chunk *c, orr_error *err)
{
    const orr_dust_set *s = &f->set;
    const orr_dust_eye view = *eye;
    double *tau = f->tau;
    const long n = (long)c->n;
    if (!view.parallel) {
        for (long i = 0; i < n; i++)
            f->want[i] = (unsigned char)drawn(f, c, (size_t)i);
        const double e[3] = {view.eye.x, view.eye.y, view.eye.z};
        return orr_dust_tau_many(s, e, c->n, c->x, c->y, c->z, f->want, tau, err);
    }
#pragma omp parallel for schedule(dynamic, 1024)
    for (long i = 0; i < n; i++) {
        const double p[3] = {c->x[i], c->y[i], c->z[i]};
        if (!drawn(f, c, (size_t)i) || !isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            tau[i] = 0.0;
            continue;
        }
        /* the star's foot on the camera plane */
        const double depth = (p[0] - view.eye.x) * view.axis.x + (p[1] - view.eye.y) * view.axis.y +
                             (p[2] - view.eye.z) * view.axis.z;
        const double e[3] = {p[0] - depth * view.axis.x, p[1] - depth * view.axis.y, p[2] - depth * view.axis.z};
        tau[i] = orr_dust_tau(s, e, p);
    }
    return ORR_OK;
}

static int same_eye(const orr_dust_eye *a, const orr_dust_eye *b)
{
    return a->parallel == b->parallel && a->eye.x == b->eye.x && a->eye.y == b->eye.y && a->eye.z == b->eye.z &&
           (!a->parallel || (a->axis.x == b->axis.x && a->axis.y == b->axis.y && a->axis.z == b->axis.z));
}

orr_status orr_dust_weights(orr_dust_frame *f, const orr_dust_eye *eye, const orr_chunk *c, const float **w,
                            int nplanes, orr_error *err)
{
    orr_status st = reserve(f, c->n ? c->n : 1, nplanes, err);
    if (st)
        return st;
    /* Views from the same eye (a dome master and a panorama) share a chunk's
     * optical depths. */
    if (f->last_chunk != c || f->last_first != c->first_index || !same_eye(&f->last_eye, eye)) {
        f->last_chunk = NULL;
        if ((st = chunk_tau(f, eye, c, err)))
            return st;
        f->last_chunk = c;
        f->last_first = c->first_index;
        f->last_eye = *eye;
    }
    const long n = (long)c->n;
    if (f->colour && nplanes >= 3) {
#pragma omp parallel for schedule(static, 4096)
        for (long i = 0; i < n; i++) {
            float xyz[3] = {w[0][i], w[1][i], w[2][i]};
            orr_dust_redden_apply(&f->red, f->tau[i], xyz);
            f->out[0][i] = xyz[0];
            f->out[1][i] = xyz[1];
            f->out[2][i] = xyz[2];
        }
        /* A population's X, Y, Z (output.exr_population_layers) are the
         * particle's or 0: its reddened X, Y, Z or 0. */
        for (int k = 3; k < nplanes; k++) {
            const float *const *mine = w + 3 + (k - 3) / 3 * 3; /* the population's three */
            for (long i = 0; i < n; i++) {
                int member = mine[0][i] != 0.0f || mine[1][i] != 0.0f || mine[2][i] != 0.0f;
                f->out[k][i] = member ? f->out[(k - 3) % 3][i] : 0.0f;
            }
        }
    } else {
        for (int k = 0; k < nplanes; k++)
            for (long i = 0; i < n; i++)
                f->out[k][i] = (float)(w[k][i] * exp(-f->tau[i]));
    }
    for (int k = 0; k < nplanes; k++)
        w[k] = f->out[k];
    return ORR_OK;
}

double orr_dust_av_ray(const orr_dust_frame *f, orr_vec3 eye, orr_vec3 dir)
{
    const double e[3] = {eye.x, eye.y, eye.z}, d[3] = {dir.x, dir.y, dir.z};
    return MAG_PER_TAU * orr_dust_tau_ray(&f->set, e, d);
}

/* Pixel (i, j)'s ray in the world: its origin and unit direction; 0 off the map. */
static int pixel_ray(const orr_dust_eye *eye, const orr_projection *p, const orr_mat3 *to_world, int i, int j,
                     orr_vec3 *origin, orr_vec3 *dir)
{
    const double px = i + 0.5, py = j + 0.5;
    orr_vec3 d;
    if (!orr_unproject(p, px, py, &d))
        return 0;
    *dir = orr_mat3_apply(*to_world, d);
    *origin = eye->eye;
    if (p->settings.kind == ORR_PROJ_ORTHOGRAPHIC)
        *origin = orr_v3_add(eye->eye, orr_mat3_apply(*to_world, orr_v3((px - p->cx) / p->focal,
                                                                          (py - p->cy) / p->focal, 0)));
    return 1;
}

orr_status orr_dust_av_plane(const orr_dust_frame *f, const orr_dust_eye *eye, const orr_projection *p,
                             const orr_mat3 *world_to_camera, orr_plane *out, orr_error *err)
{
    orr_status st = orr_plane_alloc(out, p->width, p->height, "A_V", "mag", err);
    if (st)
        return st;
    const orr_mat3 to_world = orr_mat3_transpose(*world_to_camera);
    const long n = (long)p->width * p->height;
#pragma omp parallel for schedule(dynamic, 256)
    for (long k = 0; k < n; k++) {
        orr_vec3 o, d;
        const int i = (int)(k % p->width), j = (int)(k / p->width);
        out->data[k] = pixel_ray(eye, p, &to_world, i, j, &o, &d) ? (float)orr_dust_av_ray(f, o, d) : NAN;
    }
    return ORR_OK;
}
