#include "splat/healpix_kernel.h"

#include <chealpix.h>
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "core/vecmath.h"

/* chealpix's 64-bit interface takes nside up to 2^29. */
#define NSIDE_LIMIT ((int64_t)1 << 29)

orr_healpix_ring orr_healpix_ring_at(int64_t nside, int64_t i)
{
    orr_healpix_ring r;
    const double three_n2 = 3.0 * (double)nside * (double)nside;
    if (i < nside || i > 3 * nside) { /* a polar cap: 4 k pixels on the k-th ring from the pole */
        const int64_t k = i < nside ? i : 4 * nside - i;
        const double from_pole = (double)k * (double)k / three_n2; /* 1 - |z|, exactly as the rings are defined */
        r.z = i < nside ? 1.0 - from_pole : from_pole - 1.0;
        r.sin_theta = sqrt(from_pole * (2.0 - from_pole));
        r.n = 4 * k;
        r.start = i < nside ? 2 * k * (k - 1) : 12 * nside * nside - 2 * k * (k + 1);
        r.phi0 = ORR_PI / (4.0 * (double)k);
        return r;
    }
    /* The equatorial belt: 4 nside pixels a ring, every other ring shifted by half a pixel. */
    r.z = 4.0 / 3.0 - 2.0 * (double)i / (3.0 * (double)nside);
    r.sin_theta = sqrt((1.0 - r.z) * (1.0 + r.z));
    r.n = 4 * nside;
    r.start = 2 * nside * (nside - 1) + 4 * nside * (i - nside);
    r.phi0 = (i - nside) % 2 == 0 ? 0.5 * ORR_PI / (2.0 * (double)nside) : 0.0;
    return r;
}

/* The ring number (continuous) at z: rings grow from the north pole. */
static double ring_of_z(int64_t nside, double z)
{
    if (z > 2.0 / 3.0)
        return (double)nside * sqrt(3.0 * (1.0 - z));
    if (z < -2.0 / 3.0)
        return 4.0 * (double)nside - (double)nside * sqrt(3.0 * (1.0 + z));
    return (double)nside * (2.0 - 1.5 * z);
}

void orr_healpix_scratch_free(orr_healpix_scratch *s)
{
    free(s->share);
    s->share = NULL;
    s->n = s->room = 0;
}

/* Adds wt to pixel: to the last share when it is the same pixel (a
 * kernel's sub-pixels come in runs along a ring). 0 when out of memory. */
static int scratch_add(orr_healpix_scratch *s, int64_t pixel, double wt)
{
    if (s->n && s->share[s->n - 1].pixel == pixel) {
        s->share[s->n - 1].weight += wt;
        return 1;
    }
    if (s->n == s->room) {
        size_t room = s->room ? 2 * s->room : 256;
        orr_healpix_share *grown = realloc(s->share, room * sizeof *grown);
        if (!grown)
            return 0;
        s->share = grown;
        s->room = room;
    }
    s->share[s->n++] = (orr_healpix_share){pixel, wt};
    return 1;
}

/* One particle's sampling: the sub-pixel level, the kernel and where it is. */
typedef struct kernel_cap {
    const orr_healpix_target *t;
    int64_t nside_f; /* the sub-pixels' nside, nside << level */
    int level;
    double dir[3], theta, inv_theta2;
    double laplacian_term; /* a sub-pixel's solid angle / (24 theta^2): its size's correction */
    double cos_r;          /* of the support's angular radius 2 theta (-1: the whole sphere) */
    double z, sin_t, phi;  /* dir's */
} kernel_cap;

/* The map pixel (in its order) that holds ring pixel p of the sub-pixels. */
static int64_t map_pixel(const kernel_cap *c, int64_t p)
{
    const orr_healpix_target *t = c->t;
    if (c->level == 0) {
        int64_t nest = p;
        if (t->nested)
            ring2nest64(t->nside, p, &nest);
        return nest;
    }
    int64_t nest_f = 0, out = 0;
    ring2nest64(c->nside_f, p, &nest_f);
    out = nest_f >> (2 * c->level); /* a NESTED pixel's 4^level children are numbered after it */
    if (!t->nested)
        nest2ring64(t->nside, out, &out);
    return out;
}

/* The sub-pixels of ring i inside the support, added to the scratch list;
 * returns 0 when out of memory. */
static int sample_ring(const kernel_cap *c, int64_t i, orr_healpix_scratch *s)
{
    const orr_healpix_ring r = orr_healpix_ring_at(c->nside_f, i);
    const double denom = r.sin_theta * c->sin_t;
    int64_t j0 = 0, j1 = r.n - 1;
    if (c->cos_r > -1.0 && denom > 1e-300) {
        /* The longitudes within the support: cos R = z zc + sin t sin tc cos dphi. */
        const double cos_dphi = (c->cos_r - r.z * c->z) / denom;
        if (cos_dphi >= 1.0)
            return 1;
        if (cos_dphi > -1.0) {
            const double dphi = acos(cos_dphi), step = 2.0 * ORR_PI / (double)r.n;
            const int64_t lo = (int64_t)ceil((c->phi - dphi - r.phi0) / step);
            const int64_t hi = (int64_t)floor((c->phi + dphi - r.phi0) / step);
            if (hi - lo + 1 < r.n)
                j0 = lo, j1 = hi;
        }
    } else if (c->cos_r > -1.0 && r.z * c->z < c->cos_r) {
        return 1; /* the kernel at a pole, this ring beyond it */
    }
    for (int64_t j = j0; j <= j1; j++) {
        const int64_t jj = ((j % r.n) + r.n) % r.n;
        const double phi = r.phi0 + (double)jj * 2.0 * ORR_PI / (double)r.n;
        const double d[3] = {r.sin_theta * cos(phi) - c->dir[0], r.sin_theta * sin(phi) - c->dir[1],
                             r.z - c->dir[2]};
        /* The chord, from the differences: 2 - 2 cos would lose a small kernel's digits. */
        const double u = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * c->inv_theta2;
        if (!(u < ORR_KERNEL_SUPPORT * ORR_KERNEL_SUPPORT))
            continue;
        float lf;
        const double f = orr_kernel_column_u(c->t->kernel, (float)u, &lf);
        const double wt = f + c->laplacian_term * lf;
        if (wt != 0.0 && !scratch_add(s, map_pixel(c, r.start + jj), wt))
            return 0;
    }
    return 1;
}

/* The level of sub-pixels at most theta / 4 across (a pixel of nside n is
 * about sqrt(pi / 3) / n radians across), within chealpix's limit. */
static int sub_level(int64_t nside, double theta)
{
    const double across = sqrt(ORR_PI / 3.0) / (double)nside;
    int level = 0;
    while (across / (double)((int64_t)1 << level) > 0.25 * theta && (nside << (level + 1)) <= NSIDE_LIMIT)
        level++;
    return level;
}

static void point_deposit(const orr_healpix_target *t, const double dir[3], float w)
{
    int64_t pix = 0;
    if (t->nested)
        vec2pix_nest64(t->nside, dir, &pix);
    else
        vec2pix_ring64(t->nside, dir, &pix);
    t->data[pix] += w;
}

static int64_t now_ms(void);

void orr_healpix_budget_start(orr_healpix_budget *b, uint64_t limit, int64_t expected)
{
    b->limit = limit;
    b->expected = expected > 0 ? expected : 0;
    atomic_store(&b->samples, 0);
    atomic_store(&b->particles, 0);
    atomic_store(&b->foreseen, 0);
    atomic_store(&b->foreseen_particles, 0);
    atomic_store(&b->exceeded, 0);
    atomic_store(&b->reporting, 0);
    atomic_store(&b->next_report, now_ms() + 1000);
}

/* The sub-pixel centres a support of angular radius `radius` holds, about:
 * its cap's solid angle over a sub-pixel's (4 pi / (12 nside_f^2)). */
static uint64_t kernel_samples(int64_t nside_f, double radius)
{
    const double cap = radius >= ORR_PI ? 2.0 : 1.0 - cos(radius); /* solid angle / 2 pi */
    return (uint64_t)(6.0 * cap * (double)nside_f * (double)nside_f) + 1;
}

/* The support's angular radius: a chord of 2 theta (u < 4), an angle of
 * 2 asin(theta); the whole sphere from theta = 1. */
static double support_radius(double theta) { return theta >= 1.0 ? ORR_PI : 2.0 * asin(theta); }

static int sub_level(int64_t nside, double theta);

uint64_t orr_healpix_kernel_cost(int64_t nside, double theta)
{
    return kernel_samples(nside << sub_level(nside, theta), support_radius(theta));
}

int orr_healpix_budget_foresee(orr_healpix_budget *b, uint64_t samples, size_t n)
{
    double seen = (double)(atomic_fetch_add(&b->foreseen_particles, n) + n);
    double cost = (double)(atomic_fetch_add(&b->foreseen, samples) + samples);
    if (b->expected > 0 && cost / seen * (double)b->expected > 4.0 * (double)b->limit)
        atomic_store(&b->exceeded, 1);
    return !atomic_load(&b->exceeded);
}

static int64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* Calls the progress function when a second has passed since the last
 * call, from whichever thread gets there first (the others go on). */
static void report_progress(orr_healpix_budget *b, uint64_t done)
{
    int idle = 0;
    if (!b->progress || now_ms() < atomic_load(&b->next_report) ||
        !atomic_compare_exchange_strong(&b->reporting, &idle, 1))
        return;
    atomic_store(&b->next_report, now_ms() + 1000);
    b->progress(b->progress_user, done, b->expected > 0 ? b->expected : -1);
    atomic_store(&b->reporting, 0);
}

/* Takes the kernel's samples from the budget: 0 when they go beyond it. */
static int take_budget(orr_healpix_budget *b, uint64_t samples)
{
    if (!b)
        return 1;
    if (atomic_load(&b->exceeded) || atomic_fetch_add(&b->samples, samples) + samples > b->limit) {
        atomic_store(&b->exceeded, 1);
        return 0;
    }
    uint64_t done = atomic_fetch_add(&b->particles, 1) + 1;
    if (done % 16 == 0)
        report_progress(b, done);
    return 1;
}

int orr_healpix_kernel_deposit(const orr_healpix_target *t, const double dir[3], double theta, float w,
                               orr_healpix_scratch *scratch)
{
    kernel_cap c = {.t = t, .theta = theta, .inv_theta2 = 1.0 / (theta * theta)};
    c.level = sub_level(t->nside, theta);
    c.nside_f = t->nside << c.level;
    c.laplacian_term = 4.0 * ORR_PI / (12.0 * (double)c.nside_f * (double)c.nside_f) / (24.0 * theta * theta);
    for (int k = 0; k < 3; k++)
        c.dir[k] = dir[k];
    c.z = fmax(-1.0, fmin(1.0, dir[2]));
    c.sin_t = hypot(dir[0], dir[1]);
    c.phi = atan2(dir[1], dir[0]);
    const double radius = support_radius(theta);
    c.cos_r = theta >= 1.0 ? -1.0 : cos(radius);
    if (!take_budget(t->budget, kernel_samples(c.nside_f, radius)))
        return -1;
    /* The rings the support can reach, from its colatitude range. */
    const double colat = acos(c.z);
    const double z_top = cos(fmax(0.0, colat - radius)), z_bottom = cos(fmin(ORR_PI, colat + radius));
    const int64_t last_ring = 4 * c.nside_f - 1;
    int64_t i0 = (int64_t)floor(ring_of_z(c.nside_f, z_top)), i1 = (int64_t)ceil(ring_of_z(c.nside_f, z_bottom));
    i0 = i0 < 1 ? 1 : i0;
    i1 = i1 > last_ring ? last_ring : i1;
    scratch->n = 0;
    for (int64_t i = i0; i <= i1; i++)
        if (!sample_ring(&c, i, scratch))
            return 0;
    double sum = 0.0;
    for (size_t k = 0; k < scratch->n; k++)
        sum += scratch->share[k].weight;
    if (!(sum > 0)) {
        point_deposit(t, dir, w);
        return 1;
    }
    const double scale = (double)w / sum;
    for (size_t k = 0; k < scratch->n; k++)
        t->data[scratch->share[k].pixel] += (float)(scale * scratch->share[k].weight);
    return 1;
}
