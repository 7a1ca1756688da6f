/* Snapshot sequences: interpolation in time against analytic trajectories,
 * matching by id, dropped and duplicate ids, the order of times, loads when
 * stepping forward, chunking, file patterns, and the input.sequence keys. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gadget_writer.h"
#include "render/plan.h"
#include "render/sequence_open.h"
#include "scene/scene.h"
#include "source/sequence.h"
#include "tmpdir.h"

#define MAXP 64

/* One snapshot to write: particle i has id[i], pos[i], vel[i], mass[i]. */
typedef struct snap_def {
    int n;
    uint64_t id[MAXP];
    double pos[MAXP][3], vel[MAXP][3], mass[MAXP];
} snap_def;

static const char *tmp_path(const char *name)
{
    static char path[8][512];
    static int next;
    char *p = path[next++ % 8];
    snprintf(p, sizeof path[0], "%s/%s", tmpdir, name);
    return p;
}

static void particle_of(void *user, uint64_t i, int type, gw_particle *p)
{
    const snap_def *d = user;
    (void)type;
    memset(p, 0, sizeof *p);
    memcpy(p->pos, d->pos[i], sizeof p->pos);
    memcpy(p->vel, d->vel[i], sizeof p->vel);
    p->id = d->id[i];
    p->mass = d->mass[i];
}

/* A Gadget-2 file of type-1 particles with ids, masses and (optionally)
 * velocities, at the given time. */
static const char *write_snap(const char *name, double time, const snap_def *d, int with_vel)
{
    gw_spec spec = {.snapformat = 2, .id64 = 1, .num_files = 1, .time = time};
    spec.blocks = GW_ID | (with_vel ? GW_VEL : 0);
    spec.npart[1] = d->n;
    spec.npart_total[1] = (uint32_t)d->n;
    const char *path = tmp_path(name);
    CHECK(gw_write(path, &spec, particle_of, (void *)d) == 0);
    return path;
}

/* Particle i on x = p(t) = c0 + c1 t + c2 t^2 + c3 t^3 (times i-dependent
 * offsets per axis); all coefficients are dyadic, so the values at integer
 * and half-integer times are exact in float. */
typedef struct cubic {
    double c[4];
} cubic;

static double cubic_x(const cubic *q, double t) { return q->c[0] + t * (q->c[1] + t * (q->c[2] + t * q->c[3])); }
static double cubic_v(const cubic *q, double t) { return q->c[1] + t * (2 * q->c[2] + t * 3 * q->c[3]); }

/* Axis d of particle i: a trajectory of the given degree (1 or 3). */
static cubic trajectory(int i, int d, int degree)
{
    cubic q = {{0.5 * i + d, 0.25 * (d + 1) - 0.125 * i, 0, 0}};
    if (degree == 3) {
        q.c[2] = -0.25 + 0.0625 * d;
        q.c[3] = 0.125 - 0.03125 * (i % 3);
    }
    return q;
}

/* n particles with ids 100 + i at time t on their trajectories; order
 * reversed when `reversed`. */
static void make_snap(snap_def *d, int n, double t, int degree, int reversed)
{
    memset(d, 0, sizeof *d);
    d->n = n;
    for (int k = 0; k < n; k++) {
        int i = reversed ? n - 1 - k : k;
        d->id[k] = 100 + (uint64_t)i;
        d->mass[k] = 1.0 + i;
        for (int ax = 0; ax < 3; ax++) {
            cubic q = trajectory(i, ax, degree);
            d->pos[k][ax] = cubic_x(&q, t);
            d->vel[k][ax] = cubic_v(&q, t);
        }
    }
}

static orr_sequence_options options(orr_interpolation interp, size_t chunk)
{
    orr_sequence_options o;
    memset(&o, 0, sizeof o);
    o.source.format = "auto";
    o.source.chunk_size = chunk;
    o.interpolation = interp;
    return o;
}

/* Every particle of a source, concatenated. */
typedef struct gathered {
    size_t n;
    float x[4 * MAXP], y[4 * MAXP], z[4 * MAXP], mass[4 * MAXP];
    uint64_t id[4 * MAXP];
    int chunks;
} gathered;

static orr_status gather(orr_sequence *seq, double t, gathered *g, orr_error *err)
{
    memset(g, 0, sizeof *g);
    orr_source *src = NULL;
    orr_status st = orr_sequence_source_at(seq, t, &src, err);
    while (!st) {
        const orr_chunk *c;
        st = orr_source_next(src, &c, err);
        if (st || c->n == 0)
            break;
        g->chunks++;
        for (size_t i = 0; i < c->n && g->n < 4 * MAXP; i++, g->n++) {
            g->x[g->n] = c->x[i];
            g->y[g->n] = c->y[i];
            g->z[g->n] = c->z[i];
            g->mass[g->n] = c->mass[i];
            g->id[g->n] = c->id[i];
        }
    }
    orr_source_close(src);
    return st;
}

static int same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* A float that is not a short dyadic number, so rounding would show. */
static double awkward(int i, int d) { return 1.0 / 3.0 + 0.7071067811865476 * i - 0.1 * d; }

/* ---- interpolation ---- */

static void test_snapshot_times_bit_for_bit(void)
{
    static snap_def a, b;
    make_snap(&a, 20, 0, 1, 0);
    make_snap(&b, 20, 1, 1, 1); /* listed in the opposite order */
    for (int k = 0; k < 20; k++)
        for (int d = 0; d < 3; d++) {
            a.pos[k][d] = awkward(k, d);
            b.pos[k][d] = awkward(k, d) * 1.37 + 1e-3;
        }
    const char *paths[] = {write_snap("exact0", 0.25, &a, 1), write_snap("exact1", 0.75, &b, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    static gathered g;
    const snap_def *defs[2] = {&a, &b};
    const double times[2] = {0.25, 0.75};
    for (int s = 0; s < 2; s++) {
        CHECK(gather(seq, times[s], &g, &err) == ORR_OK);
        CHECK(g.n == 20);
        for (size_t i = 0; i < g.n; i++) {
            /* Find the particle of this id in the file as written. */
            int k = 0;
            while (k < 20 && defs[s]->id[k] != g.id[i])
                k++;
            CHECK(k < 20);
            if (k == 20)
                continue;
            CHECK(same_bits(g.x[i], (float)defs[s]->pos[k][0]));
            CHECK(same_bits(g.y[i], (float)defs[s]->pos[k][1]));
            CHECK(same_bits(g.z[i], (float)defs[s]->pos[k][2]));
        }
    }
    double t0, t1;
    orr_sequence_time_range(seq, &t0, &t1);
    CHECK(t0 == 0.25 && t1 == 0.75);
    orr_sequence_close(seq);
}

/* Checks the gathered positions against trajectory(degree) at time t. */
static void check_on_trajectory(const gathered *g, double t, int degree, double tol)
{
    for (size_t k = 0; k < g->n; k++) {
        int i = (int)(g->id[k] - 100);
        const float *axes[3] = {g->x, g->y, g->z};
        for (int d = 0; d < 3; d++) {
            cubic q = trajectory(i, d, degree);
            CHECK_NEAR(axes[d][k], cubic_x(&q, t), tol);
        }
    }
}

static void test_constant_velocity_exact(void)
{
    static snap_def a, b;
    make_snap(&a, 16, 1.0, 1, 0);
    make_snap(&b, 16, 3.0, 1, 1);
    const char *paths[] = {write_snap("cv0", 1.0, &a, 1), write_snap("cv1", 3.0, &b, 1)};
    const orr_interpolation kinds[] = {ORR_INTERP_LINEAR, ORR_INTERP_HERMITE};
    static gathered g;
    for (int k = 0; k < 2; k++) {
        orr_sequence *seq = NULL;
        orr_error err;
        orr_sequence_options o = options(kinds[k], 1000);
        CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
        if (!seq)
            return;
        const double times[] = {1.25, 2.0, 2.5, 2.875};
        for (int t = 0; t < 4; t++) {
            CHECK(gather(seq, times[t], &g, &err) == ORR_OK);
            CHECK(g.n == 16);
            CHECK(orr_sequence_get_stats(seq).hermite == (kinds[k] == ORR_INTERP_HERMITE));
            check_on_trajectory(&g, times[t], 1, 1e-6);
        }
        orr_sequence_close(seq);
    }
}

/* A cubic trajectory with its true velocities: Hermite reproduces it (to
 * float rounding); linear interpolation does not, which shows the check
 * can fail. */
static void test_hermite_cubic_exact(void)
{
    static snap_def a, b;
    make_snap(&a, 12, 1.0, 3, 0);
    make_snap(&b, 12, 3.0, 3, 0);
    const char *paths[] = {write_snap("cub0", 1.0, &a, 1), write_snap("cub1", 3.0, &b, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 5);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    static gathered g;
    const double times[] = {1.5, 2.0, 2.75};
    for (int t = 0; t < 3; t++) {
        CHECK(gather(seq, times[t], &g, &err) == ORR_OK);
        CHECK(g.n == 12);
        CHECK(orr_sequence_get_stats(seq).hermite == 1);
        check_on_trajectory(&g, times[t], 3, 2e-6);
    }
    orr_sequence_close(seq);

    o = options(ORR_INTERP_LINEAR, 5);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    CHECK(gather(seq, 2.0, &g, &err) == ORR_OK);
    /* Particle 0's x (c = 0, 0.25, -0.25, 0.125): the chord from x(1) =
     * 0.125 to x(3) = 1.875 has its midpoint at 1, the curve x(2) = 0.5. */
    cubic q = trajectory((int)(g.id[0] - 100), 0, 3);
    CHECK(g.id[0] == 100);
    CHECK_NEAR(g.x[0], 1.0, 1e-6);
    CHECK_NEAR(cubic_x(&q, 2.0), 0.5, 1e-12);
    orr_sequence_close(seq);
}

static void test_matched_by_id_and_extras_from_earlier(void)
{
    static snap_def a, b;
    make_snap(&a, 30, 0.0, 1, 0);
    make_snap(&b, 30, 2.0, 1, 0);
    /* Shuffle b (a fixed permutation) and give it other masses. */
    for (int k = 0; k < 30; k++) {
        int j = (k * 7 + 3) % 30;
        if (j > k) {
            uint64_t id = b.id[k];
            b.id[k] = b.id[j];
            b.id[j] = id;
            for (int d = 0; d < 3; d++) {
                double p = b.pos[k][d], v = b.vel[k][d];
                b.pos[k][d] = b.pos[j][d];
                b.pos[j][d] = p;
                b.vel[k][d] = b.vel[j][d];
                b.vel[j][d] = v;
            }
        }
        b.mass[k] = 1000;
    }
    const char *paths[] = {write_snap("sh0", 0.0, &a, 0), write_snap("sh1", 2.0, &b, 0)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    static gathered g;
    CHECK(gather(seq, 0.5, &g, &err) == ORR_OK);
    CHECK(g.n == 30);
    CHECK(orr_sequence_get_stats(seq).hermite == 0); /* auto without velocities */
    check_on_trajectory(&g, 0.5, 1, 1e-6);
    for (size_t k = 0; k < g.n; k++) {
        CHECK(g.mass[k] == (float)(1.0 + (double)(g.id[k] - 100))); /* the earlier snapshot's */
        CHECK(k == 0 || g.id[k] > g.id[k - 1]);                      /* in id order */
    }
    orr_sequence_close(seq);
}

static void test_missing_ids_dropped_and_counted(void)
{
    static snap_def a, b;
    make_snap(&a, 10, 0.0, 1, 0); /* ids 100..109 */
    make_snap(&b, 13, 1.0, 1, 0); /* ids 100..112 */
    for (int k = 0; k < 3; k++) { /* b loses 100..102 */
        b.id[k] = b.id[10 + k];
        memcpy(b.pos[k], b.pos[10 + k], sizeof b.pos[k]);
    }
    b.n = 10; /* b: 110..112 then 103..109 */
    const char *paths[] = {write_snap("miss0", 0.0, &a, 1), write_snap("miss1", 1.0, &b, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    static gathered g;
    CHECK(gather(seq, 0.5, &g, &err) == ORR_OK);
    orr_sequence_stats st = orr_sequence_get_stats(seq);
    CHECK(g.n == 7);
    CHECK(st.matched == 7);
    CHECK(st.only_earlier == 3);
    CHECK(st.only_later == 3);
    for (size_t k = 0; k < g.n; k++)
        CHECK(g.id[k] == 103 + k);
    check_on_trajectory(&g, 0.5, 1, 1e-6);
    /* At a snapshot's own time, the whole snapshot. */
    CHECK(gather(seq, 1.0, &g, &err) == ORR_OK);
    CHECK(g.n == 10);
    orr_sequence_close(seq);
}

/* Ids spread over all 64 bits (hashed ids, as some codes write): every
 * digit of the sort varies. Particle i has id mix(i). */
static uint64_t mix(uint64_t i)
{
    uint64_t z = (i + 1) * 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    return z ^ (z >> 31);
}

static void test_large_ids(void)
{
    static snap_def a, b;
    make_snap(&a, MAXP, 0.0, 1, 0);
    make_snap(&b, MAXP, 1.0, 1, 1);
    for (int k = 0; k < MAXP; k++) {
        a.id[k] = mix(a.id[k] - 100);
        b.id[k] = mix(b.id[k] - 100);
    }
    const char *paths[] = {write_snap("big0", 0.0, &a, 1), write_snap("big1", 1.0, &b, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    static gathered g;
    CHECK(gather(seq, 0.25, &g, &err) == ORR_OK);
    CHECK(g.n == MAXP);
    CHECK(orr_sequence_get_stats(seq).only_earlier == 0);
    for (size_t k = 0; k < g.n; k++) {
        CHECK(k == 0 || g.id[k] > g.id[k - 1]);
        int i = 0;
        while (i < MAXP && mix((uint64_t)i) != g.id[k])
            i++;
        CHECK(i < MAXP);
        cubic q = trajectory(i, 1, 1);
        CHECK_NEAR(g.y[k], cubic_x(&q, 0.25), 1e-6);
    }
    orr_sequence_close(seq);
    /* Two ids equal only once the high digits are sorted too. */
    b.id[5] = b.id[40];
    paths[1] = write_snap("big1", 1.0, &b, 1);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    orr_source *src = NULL;
    CHECK(seq && orr_sequence_source_at(seq, 0.5, &src, &err) == ORR_ERR_DATA);
    char want[64];
    snprintf(want, sizeof want, "id %llu appears more than once", (unsigned long long)b.id[40]);
    CHECK_CONTAINS(err.msg, want);
    orr_sequence_close(seq);
}

static void test_duplicate_ids(void)
{
    static snap_def a, b;
    make_snap(&a, 8, 0.0, 1, 0);
    make_snap(&b, 8, 1.0, 1, 0);
    b.id[6] = 105;
    const char *paths[] = {write_snap("dup0", 0.0, &a, 1), write_snap("dup1", 1.0, &b, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    orr_source *src = NULL;
    CHECK(orr_sequence_source_at(seq, 0.5, &src, &err) == ORR_ERR_DATA);
    CHECK(src == NULL);
    CHECK_CONTAINS(err.msg, "dup1");
    CHECK_CONTAINS(err.msg, "id 105 appears more than once");
    /* The sequence is still usable at the earlier snapshot's time. */
    CHECK(orr_sequence_source_at(seq, 0.0, &src, &err) == ORR_OK);
    orr_source_close(src);
    orr_sequence_close(seq);
}

static void test_times_must_increase(void)
{
    static snap_def a;
    make_snap(&a, 4, 0.0, 1, 0);
    const char *paths[] = {write_snap("ord0", 2.0, &a, 1), write_snap("ord1", 3.0, &a, 1),
                           write_snap("ord2", 3.0, &a, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 3, &o, &seq, &err) == ORR_ERR_USAGE);
    CHECK(seq == NULL);
    CHECK_CONTAINS(err.msg, "strictly increase");
    CHECK_CONTAINS(err.msg, "ord1 has time 3");
    CHECK_CONTAINS(err.msg, "ord2, has time 3");
    const char *backwards[] = {paths[1], paths[0]};
    CHECK(orr_sequence_open(backwards, 2, &o, &seq, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "ord1 has time 3");
    CHECK_CONTAINS(err.msg, "ord0, has time 2");
    CHECK(orr_sequence_open(paths, 1, &o, &seq, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "at least 2");
}

static void test_time_outside_range(void)
{
    static snap_def a;
    make_snap(&a, 4, 0.0, 1, 0);
    const char *paths[] = {write_snap("rng0", 1.0, &a, 1), write_snap("rng1", 2.0, &a, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    orr_source *src = NULL;
    const double bad[] = {0.999, 2.0000001, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        CHECK(orr_sequence_source_at(seq, bad[i], &src, &err) == ORR_ERR_USAGE);
        CHECK(src == NULL);
        CHECK_CONTAINS(err.msg, "outside the snapshots' times");
    }
    CHECK(orr_sequence_source_at(seq, 2.0, &src, &err) == ORR_OK); /* the end itself is held */
    orr_source_close(src);
    orr_sequence_close(seq);
}

/* Stepping forward through a 3-snapshot sequence reads each file once;
 * a source from an earlier time is refused once the sequence has moved. */
static void test_each_snapshot_loaded_once(void)
{
    static snap_def a, b, c;
    make_snap(&a, 10, 0.0, 1, 0);
    make_snap(&b, 10, 1.0, 1, 1);
    make_snap(&c, 10, 2.0, 1, 0);
    const char *paths[] = {write_snap("mono0", 0.0, &a, 1), write_snap("mono1", 1.0, &b, 1),
                           write_snap("mono2", 2.0, &c, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open(paths, 3, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    CHECK(orr_sequence_get_stats(seq).loads == 0); /* opening reads headers only */
    static gathered g;
    for (int f = 0; f <= 24; f++) {
        double t = 2.0 * f / 24.0;
        CHECK(gather(seq, t, &g, &err) == ORR_OK);
        CHECK(g.n == 10);
        check_on_trajectory(&g, t, 1, 1e-6);
    }
    CHECK(orr_sequence_get_stats(seq).loads == 3);
    orr_source *old = NULL, *now = NULL;
    CHECK(orr_sequence_source_at(seq, 1.5, &old, &err) == ORR_OK);
    CHECK(orr_sequence_source_at(seq, 1.75, &now, &err) == ORR_OK);
    const orr_chunk *ch;
    CHECK(orr_source_next(old, &ch, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "stale");
    CHECK(orr_source_next(now, &ch, &err) == ORR_OK && ch->n == 10);
    orr_source_close(old);
    orr_source_close(now);
    CHECK(orr_sequence_get_stats(seq).loads == 3);
    orr_sequence_close(seq);
}

static void test_chunk_sizes_agree(void)
{
    static snap_def a, b;
    make_snap(&a, 50, 0.0, 3, 0);
    make_snap(&b, 50, 1.0, 3, 1);
    b.n = 45; /* some dropped, so the walk skips while filling chunks */
    const char *paths[] = {write_snap("chk0", 0.0, &a, 1), write_snap("chk1", 1.0, &b, 1)};
    static gathered g[3];
    const size_t sizes[] = {1, 7, 1000000};
    for (int s = 0; s < 3; s++) {
        orr_sequence *seq = NULL;
        orr_error err;
        orr_sequence_options o = options(ORR_INTERP_AUTO, sizes[s]);
        CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
        if (!seq)
            return;
        CHECK(gather(seq, 0.3, &g[s], &err) == ORR_OK);
        orr_sequence_close(seq);
    }
    CHECK(g[0].n == 45 && g[0].chunks == 45);
    CHECK(g[1].chunks == 7);
    CHECK(g[2].chunks == 1);
    for (int s = 1; s < 3; s++) {
        CHECK(g[s].n == g[0].n);
        CHECK(memcmp(g[s].x, g[0].x, sizeof g[0].x) == 0);
        CHECK(memcmp(g[s].y, g[0].y, sizeof g[0].y) == 0);
        CHECK(memcmp(g[s].z, g[0].z, sizeof g[0].z) == 0);
        CHECK(memcmp(g[s].id, g[0].id, sizeof g[0].id) == 0);
    }
}

static void test_hermite_needs_velocities(void)
{
    static snap_def a;
    make_snap(&a, 4, 0.0, 1, 0);
    const char *paths[] = {write_snap("nv0", 0.0, &a, 1), write_snap("nv1", 1.0, &a, 0)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_HERMITE, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    if (!seq)
        return;
    orr_source *src = NULL;
    CHECK(orr_sequence_source_at(seq, 0.5, &src, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "nv1: has no velocities");
    orr_sequence_close(seq);
}

static void test_memory_limit(void)
{
    static snap_def a;
    make_snap(&a, 40, 0.0, 1, 0);
    const char *paths[] = {write_snap("mem0", 0.0, &a, 1), write_snap("mem1", 1.0, &a, 1)};
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    o.max_memory = 1000; /* bytes: 80 particles of 37 bytes do not fit */
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_ERR_USAGE);
    CHECK(seq == NULL);
    CHECK_CONTAINS(err.msg, "input.sequence.max_memory");
    CHECK_CONTAINS(err.msg, "mem0 and ");
    o.max_memory = 0; /* the default */
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    /* x y z mass (16) + id (8) + type (1) + vx vy vz (12). */
    CHECK(seq && orr_sequence_bytes_per_particle(seq) == 37);
    orr_sequence_close(seq);
}

/* ---- patterns ---- */

static void test_patterns(void)
{
    char out[256];
    orr_error err;
    CHECK(orr_sequence_pattern_path("snap_%03d.hdf5", 7, out, sizeof out, &err) == ORR_OK);
    CHECK(strcmp(out, "snap_007.hdf5") == 0);
    CHECK(orr_sequence_pattern_path("100%%/s%d", 12345, out, sizeof out, &err) == ORR_OK);
    CHECK(strcmp(out, "100%/s12345") == 0);
    CHECK(orr_sequence_pattern_path("x%4x", 255, out, sizeof out, &err) == ORR_OK);
    CHECK(strcmp(out, "x  ff") == 0);
    static const char *const bad[][2] = {
        {"snap.hdf5", "no integer conversion"},
        {"snap_%d_%d", "more than one"},
        {"snap_%s", "'%s' is not an integer conversion"},
        {"snap_%ld", "'%l' is not an integer conversion"},
        {"snap_%", "is not an integer conversion"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK(orr_sequence_pattern_check(bad[i][0], &err) == ORR_ERR_USAGE);
        CHECK_CONTAINS(err.msg, bad[i][1]);
        CHECK_CONTAINS(err.msg, bad[i][0]);
    }
    CHECK(orr_sequence_pattern_path("a%d", 1, out, 2, &err) == ORR_ERR_USAGE);

    /* Files 0, 2, 4 of a pattern; then a range with a missing file. */
    static snap_def a;
    make_snap(&a, 4, 0.0, 1, 0);
    write_snap("pat_000", 0.0, &a, 1);
    write_snap("pat_002", 1.0, &a, 1);
    write_snap("pat_004", 2.0, &a, 1);
    char pattern[600];
    snprintf(pattern, sizeof pattern, "%s/pat_%%03d", tmpdir);
    orr_sequence *seq = NULL;
    orr_sequence_options o = options(ORR_INTERP_AUTO, 1000);
    CHECK(orr_sequence_open_pattern(pattern, 0, 4, 2, &o, &seq, &err) == ORR_OK);
    CHECK(seq && orr_sequence_count(seq) == 3);
    CHECK(seq && strcmp(orr_sequence_path(seq, 2), tmp_path("pat_004")) == 0);
    CHECK(seq && orr_sequence_time(seq, 1) == 1.0);
    orr_sequence_close(seq);
    CHECK(orr_sequence_open_pattern(pattern, 0, 4, 1, &o, &seq, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "pat_001: cannot open");
    CHECK(orr_sequence_open_pattern(pattern, 4, 0, 1, &o, &seq, &err) == ORR_ERR_USAGE);
}

/* ---- scene keys ---- */

static orr_scene g_scene;

static orr_status load(const char *yaml, orr_error *err)
{
    orr_scene_free(&g_scene);
    return orr_scene_load_string(&g_scene, yaml, "scene.yaml", "/base", NULL, 0, err);
}

static void test_scene_keys(void)
{
    orr_error err;
    CHECK(load("input:\n  sequence:\n    pattern: snaps/snap_%03d.hdf5\n    first: 2\n    last: 40\n"
               "    step: 2\n    interpolation: hermite\n    max_memory: 2.5\n",
               &err) == ORR_OK);
    CHECK(strcmp(g_scene.input.sequence.pattern, "/base/snaps/snap_%03d.hdf5") == 0);
    CHECK(g_scene.input.sequence.first == 2 && g_scene.input.sequence.last == 40 && g_scene.input.sequence.step == 2);
    CHECK(g_scene.input.sequence.interpolation == ORR_INTERP_HERMITE);
    CHECK(g_scene.input.sequence.max_memory == 2.5);
    CHECK(g_scene.input.file == NULL);

    CHECK(load("input: {sequence: {files: [a.dat, /abs/b.dat, c.dat]}}", &err) == ORR_OK);
    CHECK(g_scene.input.sequence.nfiles == 3);
    CHECK(strcmp(orr_scene_sequence_file(&g_scene, 0), "/base/a.dat") == 0);
    CHECK(strcmp(orr_scene_sequence_file(&g_scene, 1), "/abs/b.dat") == 0);
    CHECK(strcmp(orr_scene_sequence_file(&g_scene, 2), "/base/c.dat") == 0);
    CHECK(g_scene.input.sequence.interpolation == ORR_INTERP_AUTO);
    CHECK(g_scene.input.sequence.step == 1);

    static const char *const bad[][2] = {
        {"input: {file: a.dat, sequence: {files: [a, b]}}", "input.file"},
        {"input: {model: {name: mw-m31}, sequence: {pattern: s%d, last: 3}}", "input.model.name"},
        {"input: {sequence: {pattern: s%d, last: 3, files: [a, b]}}", "input.sequence.files"},
        {"input: {sequence: {pattern: snap.hdf5, last: 3}}", "input.sequence.pattern"},
        {"input: {sequence: {pattern: s%d%d, last: 3}}", "more than one"},
        {"input: {sequence: {pattern: s%d}}", "input.sequence.last"},
        {"input: {sequence: {pattern: s%d, first: 5, last: 3}}", "input.sequence.last"},
        {"input: {sequence: {pattern: s%d, last: 3, step: 0}}", "input.sequence.step"},
        {"input: {file: a.dat, sequence: {first: 1}}", "input.sequence.first"},
        {"input: {sequence: {files: [a]}}", "input.sequence.files"},
        {"input: {sequence: {files: a}}", "input.sequence.files"},
        {"input: {sequence: {files: [a, [b]]}}", "input.sequence.files[1]"},
        {"input: {sequence: {files: [a, b], interpolation: cubic}}", "input.sequence.interpolation"},
        {"input: {sequence: {files: [a, b], max_memory: 0}}", "input.sequence.max_memory"},
        {"input: {file: a.dat, sequence: {interpolation: linear}}", "input.sequence.interpolation"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK(load(bad[i][0], &err) == ORR_ERR_USAGE);
        CHECK_CONTAINS(err.msg, bad[i][1]);
    }
}

/* A scene's sequence, by pattern and by files, relative to the scene's folder. */
/* The scene's sequence, as a run opens it: through the request the plan
 * compiles (every field). */
static orr_status open_scene_sequence(const orr_scene *s, orr_sequence **seq, orr_error *err)
{
    orr_source_request req;
    orr_plan_source_request(s, &req);
    return orr_sequence_open_request(&req, NULL, 0, seq, err);
}

static void test_open_from_scene(void)
{
    static snap_def a;
    make_snap(&a, 6, 0.0, 1, 0);
    write_snap("scn_010.g2", 0.5, &a, 1);
    write_snap("scn_020.g2", 1.5, &a, 1);
    write_snap("scn_030.g2", 4.0, &a, 1);
    orr_error err;
    orr_sequence *seq = NULL;
    orr_scene_free(&g_scene);
    CHECK(orr_scene_load_string(&g_scene,
                                "input: {sequence: {pattern: scn_%03d.g2, first: 10, last: 30, step: 10}, "
                                "types: [1]}",
                                "seq.yaml", tmpdir, NULL, 0, &err) == ORR_OK);
    CHECK(open_scene_sequence(&g_scene, &seq, &err) == ORR_OK);
    CHECK(seq && orr_sequence_count(seq) == 3);
    double t0 = 0, t1 = 0;
    if (seq)
        orr_sequence_time_range(seq, &t0, &t1);
    CHECK(t0 == 0.5 && t1 == 4.0);
    orr_sequence_close(seq);

    orr_scene_free(&g_scene);

    CHECK(orr_scene_load_string(&g_scene, "input: {sequence: {files: [scn_030.g2, scn_010.g2]}}", "seq.yaml",
                                tmpdir, NULL, 0, &err) == ORR_OK);
    CHECK(open_scene_sequence(&g_scene, &seq, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "seq.yaml: sequence: snapshot times must strictly increase");
    CHECK_CONTAINS(err.msg, "scn_030.g2 has time 4");

    orr_scene_free(&g_scene);

    CHECK(orr_scene_load_string(&g_scene, "input: {sequence: {pattern: scn_%03d.g2, first: 10, last: 40, step: 10}}",
                                "seq.yaml", tmpdir, NULL, 0, &err) == ORR_OK);
    CHECK(open_scene_sequence(&g_scene, &seq, &err) == ORR_ERR_IO);
    CHECK_CONTAINS(err.msg, "scn_040.g2: cannot open");

    orr_scene_free(&g_scene);

    CHECK(orr_scene_load_string(&g_scene, "input: {file: x}", "seq.yaml", tmpdir, NULL, 0, &err) == ORR_OK);
    CHECK(open_scene_sequence(&g_scene, &seq, &err) == ORR_ERR_USAGE);
}

/* ---- a periodic box ---- */

/* Three particles in a box of side 10 between t = 0 and 1: id 100 leaves
 * through x = 10 and comes back at x = 0.4 (+0.8), id 101 moves within the
 * box (+0.5), id 102 leaves through x = 0 (-0.8); y and z stay. */
static const char *write_wrap(const char *name, double t)
{
    static snap_def d;
    memset(&d, 0, sizeof d);
    const double x0[3] = {9.6, 5.0, 0.3}, v[3] = {0.8, 0.5, -0.8};
    d.n = 3;
    for (int i = 0; i < 3; i++) {
        d.id[i] = 100 + (uint64_t)i;
        d.mass[i] = 1;
        double x = x0[i] + v[i] * t;
        d.pos[i][0] = x - 10 * floor(x / 10);
        d.pos[i][1] = 2 + i;
        d.pos[i][2] = 7;
        d.vel[i][0] = v[i];
    }
    gw_spec spec = {.snapformat = 2, .id64 = 1, .num_files = 1, .time = t, .box_size = 10};
    spec.blocks = GW_ID | GW_VEL;
    spec.npart[1] = d.n;
    spec.npart_total[1] = (uint32_t)d.n;
    const char *path = tmp_path(name);
    CHECK(gw_write(path, &spec, particle_of, &d) == 0);
    return path;
}

/* x of the three particles at t through seq. */
static void wrap_xs(orr_sequence *seq, double t, double x[3])
{
    static gathered g;
    orr_error err;
    CHECK(gather(seq, t, &g, &err) == ORR_OK);
    CHECK(g.n == 3);
    for (int i = 0; i < 3; i++)
        x[i] = g.n == 3 ? g.x[i] : NAN;
}

/* With the box's side known, a particle that wraps moves through the face
 * (x from 9.6 to 10.4, taken back into [0, 10)), by linear and Hermite
 * interpolation alike; without it, it is dragged back across the box. */
static void test_periodic_wrap(void)
{
    const char *paths[] = {write_wrap("wrap_0.g2", 0), write_wrap("wrap_1.g2", 1)};
    const orr_interpolation kinds[] = {ORR_INTERP_LINEAR, ORR_INTERP_HERMITE};
    for (int k = 0; k < 2; k++) {
        orr_sequence *seq = NULL;
        orr_error err;
        orr_sequence_options o = options(kinds[k], 1000);
        o.box = 10;
        CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
        if (!seq)
            return;
        const double t[] = {0.25, 0.5, 0.75};
        const double expect[3][3] = {{9.8, 5.125, 0.1}, {0.0, 5.25, 9.9}, {0.2, 5.375, 9.7}};
        for (int q = 0; q < 3; q++) {
            double x[3];
            wrap_xs(seq, t[q], x);
            for (int i = 0; i < 3; i++)
                CHECK_NEAR(x[i], expect[q][i], 2e-6);
        }
        orr_source *src = NULL;
        CHECK(orr_sequence_source_at(seq, 0.5, &src, &err) == ORR_OK);
        int has_box = 0;
        for (int h = 0; src && h < src->info.nheader; h++)
            has_box |= strcmp(src->info.header[h].key, "BoxSize") == 0 && strcmp(src->info.header[h].value, "10") == 0;
        CHECK(has_box);
        orr_source_close(src);
        orr_sequence_close(seq);
    }
    /* Not periodic: dragged through the middle of the box. */
    orr_sequence *seq = NULL;
    orr_error err;
    orr_sequence_options o = options(ORR_INTERP_LINEAR, 1000);
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_OK);
    double x[3];
    if (seq)
        wrap_xs(seq, 0.5, x);
    CHECK(seq && fabs(x[0] - 5.0) < 1e-5 && fabs(x[2] - 4.9) < 1e-5);
    orr_sequence_close(seq);
    o.box = -1;
    CHECK(orr_sequence_open(paths, 2, &o, &seq, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "periodic box");
}

/* A scene says the box is periodic with input.periodic.box, or with
 * copies (input.periodic.replicas) and box auto, the first file's BoxSize;
 * without input.periodic the sequence is not wrapped. */
static void test_periodic_wrap_from_scene(void)
{
    write_wrap("wrapscn_0.g2", 0);
    write_wrap("wrapscn_1.g2", 1);
    static const struct {
        const char *periodic;
        double x0;
    } cases[] = {{"periodic: {replicas: 3}, ", 0.0}, {"periodic: {box: 10}, ", 0.0}, {"", 5.0}};
    for (int k = 0; k < 3; k++) {
        char yaml[256];
        snprintf(yaml, sizeof yaml, "input: {%ssequence: {pattern: wrapscn_%%d.g2, first: 0, last: 1}}",
                 cases[k].periodic);
        orr_error err;
        orr_sequence *seq = NULL;
        orr_scene_free(&g_scene);
        CHECK(orr_scene_load_string(&g_scene, yaml, "wrap.yaml", tmpdir, NULL, 0, &err) == ORR_OK);
        CHECK(open_scene_sequence(&g_scene, &seq, &err) == ORR_OK);
        double x[3] = {NAN, NAN, NAN};
        if (seq)
            wrap_xs(seq, 0.5, x);
        CHECK_NEAR(x[0], cases[k].x0, 1e-5);
        orr_sequence_close(seq);
    }
}

int main(void)
{
    make_tmpdir();
    RUN(test_snapshot_times_bit_for_bit);
    RUN(test_constant_velocity_exact);
    RUN(test_hermite_cubic_exact);
    RUN(test_matched_by_id_and_extras_from_earlier);
    RUN(test_missing_ids_dropped_and_counted);
    RUN(test_large_ids);
    RUN(test_duplicate_ids);
    RUN(test_times_must_increase);
    RUN(test_time_outside_range);
    RUN(test_each_snapshot_loaded_once);
    RUN(test_chunk_sizes_agree);
    RUN(test_hermite_needs_velocities);
    RUN(test_memory_limit);
    RUN(test_patterns);
    RUN(test_scene_keys);
    RUN(test_open_from_scene);
    RUN(test_periodic_wrap);
    RUN(test_periodic_wrap_from_scene);
    remove_tmpdir();
    return check_summary();
}
