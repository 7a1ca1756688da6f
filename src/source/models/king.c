/* The built-in "king" model: a King (1966) globular cluster.
 *
 * The distribution function is the lowered isothermal
 *   f(E) ~ exp(-E / sigma^2) - 1  for E < 0 (relative to the tidal radius),
 * whose density is (King 1966, AJ 71, 64, eq. 13; Binney & Tremaine 2008,
 * eq. 4.111)
 *   rho(W) ~ e^W erf(sqrt W) - sqrt(4W/pi) (1 + 2W/3),  W = -Phi / sigma^2.
 * With r in units of the King radius r0 = sqrt(9 sigma^2 / (4 pi G rho0)),
 * Poisson's equation is W'' + 2 W'/r = -9 rho(W) / rho(W0). We integrate it
 * outwards with RK4 in ln r from W(0) = W0 to W = 0 (the tidal radius rt),
 * tabulate W and the enclosed mass, and sample:
 * - radii by inverting the tabulated cumulative mass;
 * - speeds at radius r from p(v) ~ v^2 (exp(W - v^2 / 2 sigma^2) - 1),
 *   0 <= v <= sigma sqrt(2W), by rejection under a tabulated maximum;
 * - isotropic directions for both;
 * - V and B-V from the colour-magnitude diagram of gc_cmd.c.
 * Every particle uses only its own counter-based generator keyed by
 * (seed, index), so the output does not depend on chunking. */
#include "source/models/king.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/vecmath.h"
#include "source/models/gc_cmd.h"
#include "source/models/rng.h"

#define KING_PARTICLES_MIN 100
#define KING_PARTICLES_MAX 2000000000LL

/* The ODE: start at r = KING_R_START (series solution), steps of KING_DT in
 * ln r. At W0 = 9 about 14 000 steps; c = log10(rt/r0) is good to 1e-5. */
#define KING_R_START 1e-4
#define KING_DT 1e-3
#define KING_STEPS_MAX 200000

/* Below this W the density is evaluated from its series, avoiding the
 * cancellation between e^W erf(sqrt W) and the polynomial. */
#define KING_W_SERIES 1e-3

/* Table of the speed distribution's maximum against W (rejection envelope). */
#define KING_GMAX_N 512

#define KING_FIELDS 6

/* ---- the profile -------------------------------------------------------- */

double orr_king_rho_shape(double w)
{
    if (w <= 0.0)
        return 0.0;
    if (w < KING_W_SERIES) /* (8 / (15 sqrt pi)) W^(5/2) (1 + 2W/7 + O(W^2)) */
        return 8.0 / (15.0 * sqrt(ORR_PI)) * w * w * sqrt(w) * (1.0 + 2.0 * w / 7.0);
    return exp(w) * erf(sqrt(w)) - sqrt(4.0 * w / ORR_PI) * (1.0 + 2.0 * w / 3.0);
}

typedef struct king_ode {
    double rho0; /* rho_shape(W0): normalises the density to 1 at the centre */
} king_ode;

/* The state (W, P) with P = r^2 dW/dr; in t = ln r:
 * dW/dt = P / r, dP/dt = -9 r^3 rho(W)/rho0. */
static void king_derivs(const king_ode *o, double t, double w, double pp, double *dw, double *dp)
{
    double r = exp(t);
    *dw = pp / r;
    *dp = -9.0 * r * r * r * orr_king_rho_shape(w) / o->rho0;
}

static void rk4_step(const king_ode *o, double t, double h, double *w, double *pp)
{
    double k1w, k1p, k2w, k2p, k3w, k3p, k4w, k4p;
    king_derivs(o, t, *w, *pp, &k1w, &k1p);
    king_derivs(o, t + 0.5 * h, *w + 0.5 * h * k1w, *pp + 0.5 * h * k1p, &k2w, &k2p);
    king_derivs(o, t + 0.5 * h, *w + 0.5 * h * k2w, *pp + 0.5 * h * k2p, &k3w, &k3p);
    king_derivs(o, t + h, *w + h * k3w, *pp + h * k3p, &k4w, &k4p);
    *w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
    *pp += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
}

static orr_status profile_push(orr_king_profile *p, int *cap, double r, double w, double mu, orr_error *err)
{
    if (p->n == *cap) {
        int nc = *cap ? *cap * 2 : 4096;
        double *nr = realloc(p->r, (size_t)nc * sizeof *nr);
        if (nr)
            p->r = nr;
        double *nw = nr ? realloc(p->w, (size_t)nc * sizeof *nw) : NULL;
        if (nw)
            p->w = nw;
        double *nm = nw ? realloc(p->mu, (size_t)nc * sizeof *nm) : NULL;
        if (!nm)
            return orr_fail(err, ORR_ERR_NOMEM, "king model: out of memory for the profile table");
        p->mu = nm;
        *cap = nc;
    }
    p->r[p->n] = r;
    p->w[p->n] = w;
    p->mu[p->n] = mu;
    p->n++;
    return ORR_OK;
}

orr_status orr_king_solve(double w0, orr_king_profile *out, orr_error *err)
{
    memset(out, 0, sizeof *out);
    if (!(w0 >= ORR_KING_W0_MIN && w0 <= ORR_KING_W0_MAX))
        return orr_fail(err, ORR_ERR_USAGE, "king model: W0 = %g is out of range (%g to %g)", w0,
                        ORR_KING_W0_MIN, ORR_KING_W0_MAX);
    out->w0 = w0;
    king_ode o = {orr_king_rho_shape(w0)};
    int cap = 0;
    /* Near the centre rho = rho0: W = W0 - 3/2 r^2, P = r^2 W' = -3 r^3. */
    double r = KING_R_START, w = w0 - 1.5 * r * r, pp = -3.0 * r * r * r;
    orr_status st = profile_push(out, &cap, 0.0, w0, 0.0, err);
    if (!st)
        st = profile_push(out, &cap, r, w, -pp / 9.0, err);
    double t = log(r);
    for (int step = 0; !st && step < KING_STEPS_MAX; step++) {
        double w_old = w, p_old = pp, t_old = t;
        rk4_step(&o, t, KING_DT, &w, &pp);
        t += KING_DT;
        if (w <= 0.0) {
            /* W falls through 0 linearly near rt: interpolate the crossing. */
            double f = w_old / (w_old - w);
            out->rt = exp(t_old + f * KING_DT);
            out->mu_total = -(p_old + f * (pp - p_old)) / 9.0;
            st = profile_push(out, &cap, out->rt, 0.0, out->mu_total, err);
            if (st)
                break;
            return ORR_OK;
        }
        st = profile_push(out, &cap, exp(t), w, -pp / 9.0, err);
    }
    orr_king_free(out);
    if (st)
        return st;
    return orr_fail(err, ORR_ERR_DATA, "king model: W0 = %g: the potential did not reach 0 (no tidal radius)", w0);
}

void orr_king_free(orr_king_profile *p)
{
    free(p->r);
    free(p->w);
    free(p->mu);
    p->r = p->w = p->mu = NULL;
    p->n = 0;
}

/* The index i with a[i] <= v < a[i + 1] in an increasing table (clamped). */
static int table_find(const double *a, int n, double v)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (a[mid] <= v)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static double table_interp(const double *x, const double *y, int n, double v)
{
    if (v <= x[0])
        return y[0];
    if (v >= x[n - 1])
        return y[n - 1];
    int i = table_find(x, n, v);
    double f = (v - x[i]) / (x[i + 1] - x[i]);
    return y[i] + f * (y[i + 1] - y[i]);
}

double orr_king_w_at(const orr_king_profile *p, double r) { return table_interp(p->r, p->w, p->n, r); }

double orr_king_mass_fraction(const orr_king_profile *p, double r)
{
    return table_interp(p->r, p->mu, p->n, r) / p->mu_total;
}

double orr_king_radius_of_mass(const orr_king_profile *p, double fraction)
{
    return table_interp(p->mu, p->r, p->n, fraction * p->mu_total);
}

void orr_king_scales(const orr_king_params *params, const orr_king_profile *p, double *sigma, double *rt_pc)
{
    /* M = 4 pi rho0 r0^3 mu_total and sigma^2 = 4 pi G rho0 r0^2 / 9, so
     * sigma^2 = G M / (9 r0 mu_total). */
    *sigma = sqrt(ORR_KING_G * params->mass / (9.0 * params->core_radius * p->mu_total));
    *rt_pc = p->rt * params->core_radius;
}

/* ---- speeds -------------------------------------------------------------- */

/* In x = v / sigma the speed density is g(x) = x^2 (e^(W - x^2/2) - 1).
 * With y = x^2 / 2, g = 2y (e^(W - y) - 1), whose maximum is where
 * e^(W - y) (1 - y) = 1, y in (0, min(W, 1)): found by bisection. */
static double speed_density_max(double w)
{
    if (w <= 0.0)
        return 0.0;
    double lo = 0.0, hi = w < 1.0 ? w : 1.0;
    for (int i = 0; i < 100; i++) {
        double mid = 0.5 * (lo + hi);
        if (exp(w - mid) * (1.0 - mid) > 1.0)
            lo = mid;
        else
            hi = mid;
    }
    double y = 0.5 * (lo + hi);
    return 2.0 * y * (exp(w - y) - 1.0);
}

typedef struct king_state {
    orr_king_params params;
    orr_king_profile prof;
    double sigma, rt_pc;
    double gmax[KING_GMAX_N]; /* speed_density_max at W = W0 k / (N - 1) */
    uint64_t total, next_index;
} king_state;

/* g's maximum grows with W, so the value at the next node up bounds it.
 * Below the first node it falls as W^2 towards the tidal radius, and the
 * node's value would make the rejection loop arbitrarily long: there (a
 * rare star near the tidal radius) the maximum is found for this W. */
static double envelope(const king_state *k, double w)
{
    double t = w / k->params.w0 * (KING_GMAX_N - 1);
    if (t < 1.0)
        return speed_density_max(w) * 1.000001;
    int j = (int)ceil(t);
    if (j > KING_GMAX_N - 1)
        j = KING_GMAX_N - 1;
    return k->gmax[j] * 1.000001;
}

static double draw_speed(const king_state *k, double w, orr_rng *r)
{
    if (w <= 0.0)
        return 0.0;
    double xe = sqrt(2.0 * w), gm = envelope(k, w);
    for (;;) {
        double x = xe * orr_rng_uniform(r);
        double g = x * x * (exp(w - 0.5 * x * x) - 1.0);
        if (orr_rng_uniform(r) * gm <= g)
            return x * k->sigma;
    }
}

static orr_vec3 isotropic(orr_rng *r)
{
    double cost = 2.0 * orr_rng_uniform(r) - 1.0, sint = sqrt(fmax(0.0, 1.0 - cost * cost));
    double phi = 2.0 * ORR_PI * orr_rng_uniform(r);
    return orr_v3(sint * cos(phi), sint * sin(phi), cost);
}

/* ---- the source ------------------------------------------------------------ */

typedef struct king_star {
    orr_vec3 pos, vel;
    double rad;
    orr_gc_star cmd;
} king_star;

static void make_star(const king_state *k, uint64_t index, king_star *s)
{
    orr_rng r = orr_rng_seed(k->params.seed, index, 0);
    double rad = orr_king_radius_of_mass(&k->prof, orr_rng_uniform(&r));
    s->rad = rad * k->params.core_radius;
    s->pos = orr_v3_scale(isotropic(&r), s->rad);
    double v = draw_speed(k, orr_king_w_at(&k->prof, rad), &r);
    s->vel = orr_v3_scale(isotropic(&r), v);
    s->cmd = orr_gc_draw(&r);
}

static orr_status king_next(orr_source *src, orr_error *err)
{
    (void)err;
    king_state *k = src->state;
    orr_chunk *c = &src->chunk;
    uint64_t left = k->total - k->next_index;
    size_t n = left < c->capacity ? (size_t)left : c->capacity;
    float mass = (float)(k->params.mass / (double)k->total);
    c->first_index = k->next_index;
    for (size_t i = 0; i < n; i++) {
        uint64_t index = k->next_index + i;
        king_star s;
        make_star(k, index, &s);
        c->x[i] = (float)s.pos.x;
        c->y[i] = (float)s.pos.y;
        c->z[i] = (float)s.pos.z;
        c->mass[i] = mass;
        c->id[i] = index + 1;
        c->type[i] = (uint8_t)s.cmd.phase;
        c->extra[0].data[i] = (float)s.vel.x;
        c->extra[1].data[i] = (float)s.vel.y;
        c->extra[2].data[i] = (float)s.vel.z;
        c->extra[3].data[i] = (float)s.rad;
        c->extra[4].data[i] = (float)s.cmd.mv;
        c->extra[5].data[i] = (float)s.cmd.bv;
    }
    c->n = n;
    k->next_index += n;
    return ORR_OK;
}

static orr_status king_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    ((king_state *)src->state)->next_index = 0;
    return ORR_OK;
}

static orr_status king_skip_chunk(orr_source *src, orr_error *err)
{
    (void)err;
    king_state *k = src->state;
    uint64_t left = k->total - k->next_index;
    k->next_index += left < src->chunk.capacity ? left : src->chunk.capacity;
    return ORR_OK;
}

static void king_close(orr_source *src)
{
    king_state *k = src->state;
    if (k)
        orr_king_free(&k->prof);
    free(src->state);
    src->state = NULL;
}

static const orr_source_ops KING_OPS = {
    .next = king_next, .rewind = king_rewind, .close = king_close, .skip_chunk = king_skip_chunk};

static orr_status check_params(const orr_king_params *p, size_t chunk_size, orr_error *err)
{
    if (!p)
        return orr_fail(err, ORR_ERR_USAGE, "king model: no parameters given");
    if (p->particles < KING_PARTICLES_MIN || p->particles > KING_PARTICLES_MAX)
        return orr_fail(err, ORR_ERR_USAGE, "king model: %lld particles requested; it needs %d to %lld",
                        p->particles, KING_PARTICLES_MIN, (long long)KING_PARTICLES_MAX);
    if (!(p->w0 >= ORR_KING_W0_MIN && p->w0 <= ORR_KING_W0_MAX))
        return orr_fail(err, ORR_ERR_USAGE, "king model: w0 = %g is out of range (%g to %g)", p->w0,
                        ORR_KING_W0_MIN, ORR_KING_W0_MAX);
    if (!(p->core_radius > 0.0 && isfinite(p->core_radius)))
        return orr_fail(err, ORR_ERR_USAGE, "king model: core radius %g pc must be a positive number",
                        p->core_radius);
    if (!(p->mass > 0.0 && isfinite(p->mass)))
        return orr_fail(err, ORR_ERR_USAGE, "king model: mass %g Msun must be a positive number", p->mass);
    if (chunk_size == 0)
        return orr_fail(err, ORR_ERR_USAGE, "king model: chunk size must be at least 1 particle");
    return ORR_OK;
}

static const char *const KING_FIELD_NAMES[KING_FIELDS] = {"vx", "vy", "vz", "r", "V", "BV"};

static void fill_info(orr_source_info *info, const orr_king_params *p)
{
    snprintf(info->format, sizeof info->format, "model:king");
    snprintf(info->path, sizeof info->path, "built-in model king (N=%lld, seed=%llu, W0=%g, r0=%g pc, M=%g Msun)",
             p->particles, (unsigned long long)p->seed, p->w0, p->core_radius, p->mass);
    info->count = p->particles;
    info->time = 0.0;
    info->has_h = 0;
    info->has_id = 1;
    info->has_type = 1;
    info->nextra = KING_FIELDS;
    for (int i = 0; i < KING_FIELDS; i++)
        snprintf(info->extra_names[i], sizeof info->extra_names[i], "%s", KING_FIELD_NAMES[i]);
}

orr_status orr_king_source_open(const orr_king_params *params, size_t chunk_size, orr_source **out,
                                orr_error *err)
{
    *out = NULL;
    orr_status st = check_params(params, chunk_size, err);
    if (st != ORR_OK)
        return st;
    orr_source *src = orr_source_new("model", "", &KING_OPS, sizeof(king_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    king_state *k = src->state;
    k->params = *params;
    k->total = (uint64_t)params->particles;
    st = orr_king_solve(params->w0, &k->prof, err);
    if (st != ORR_OK) {
        orr_source_close(src);
        return st;
    }
    orr_king_scales(params, &k->prof, &k->sigma, &k->rt_pc);
    for (int j = 0; j < KING_GMAX_N; j++)
        k->gmax[j] = speed_density_max(params->w0 * j / (KING_GMAX_N - 1));
    fill_info(&src->info, params);
    size_t cap = (uint64_t)chunk_size < k->total ? chunk_size : (size_t)k->total;
    st = orr_chunk_alloc(&src->chunk, cap, 0, KING_FIELD_NAMES, KING_FIELDS, err);
    if (st != ORR_OK) {
        orr_source_close(src);
        return st;
    }
    *out = src;
    return ORR_OK;
}
