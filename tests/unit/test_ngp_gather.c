/* The fused NGP gather (pass/ngp_gather.h) against the general passes
 * and against the projections in double: the same pixel for every
 * particle, on every projection, with and without dimming; and a
 * non-finite position or weight anywhere in a block is caught. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "frame/project_point.h"
#include "pass/ngp_gather.h"
#include "splat/deposit.h"
#include "test_random.h"

#define N 1999 /* not a multiple of any vector width: the loops' tails run */

static uint64_t rng_state = 12345;
static double uniform(void)
{
    return test_uniform(&rng_state);
}

typedef struct particles {
    float x[N], y[N], z[N], w[N];
} particles;

/* Particles around the camera at (ox, oy, oz): a cube of side 40 centred
 * there, so some are behind it, off the image and near every edge. */
static void make_particles(particles *p, const orr_camera_transform *t)
{
    for (int i = 0; i < N; i++) {
        p->x[i] = (float)(t->ox + 40 * (uniform() - 0.5));
        p->y[i] = (float)(t->oy + 40 * (uniform() - 0.5));
        p->z[i] = (float)(t->oz + 40 * (uniform() - 0.5));
        p->w[i] = (float)(0.5 + uniform());
    }
}

/* A rotation about an oblique axis, and the camera off the origin. */
static orr_camera_transform make_transform(int dim)
{
    orr_camera_transform t = {.ox = 100.25, .oy = -3.5, .oz = 7.0, .dim = dim, .near2 = 0.01f};
    double a = 0.7, c = cos(a), s = sin(a), u[3] = {0.48, 0.6, 0.64}; /* unit axis */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double cross = 0;
            if (i != j) {
                int k = 3 - i - j;
                double sign = ((i + 1) % 3 == j) ? -1 : 1;
                cross = sign * u[k];
            }
            t.r[i][j] = (float)((i == j ? c : 0) + (1 - c) * u[i] * u[j] + s * cross);
        }
    return t;
}

static orr_projection make_projection(orr_projection_kind kind)
{
    const int two_to_one = kind == ORR_PROJ_HAMMER_AITOFF || kind == ORR_PROJ_EQUIRECTANGULAR;
    return PLANNED(.kind = kind, .width = two_to_one ? 160 : 97, .height = two_to_one ? 80 : 83, .ortho_width = 30,
                   .fov_deg = 70, .near = 0.5, .dome_fov_deg = 200);
}

/* The general path: camera frame, projection batch, then the deposit's
 * own indices (via orr_deposit into a plane of the weights). */
static void general_plane(const orr_projection *p, const orr_camera_transform *t, const particles *q,
                          orr_plane *plane, orr_deposit_stats *st)
{
    static float x[N], y[N], z[N], w[N], px[N], py[N], scale[N];
    static uint8_t vis[N];
    for (int i = 0; i < N; i++) {
        orr_camera_point c = orr_to_camera(t, q->x[i], q->y[i], q->z[i]);
        x[i] = c.x;
        y[i] = c.y;
        z[i] = c.z;
        w[i] = q->w[i] * (t->dim ? orr_camera_dimming(t, c.r2) : 1.0f);
    }
    orr_project_batch(p, N, x, y, z, px, py, scale, vis);
    orr_deposit(ORR_DEPOSIT_NGP, plane, N, px, py, w, vis, p, st);
}

static void fused_plane(const orr_projection *p, const orr_camera_transform *t, const particles *q,
                        orr_plane *plane, orr_deposit_stats *st, int32_t *index)
{
    static float px[N], py[N], dimming[N], w[N];
    const orr_map_outline m = orr_map_outline_of(p, p->width, p->height);
    orr_ngp_gather_out out = {index, px, py, dimming};
    CHECK(orr_ngp_gather(p, &m, t, N, q->x, q->y, q->z, q->w, &out) == 1);
    for (int i = 0; i < N; i++)
        w[i] = t->dim ? q->w[i] * dimming[i] : q->w[i];
    orr_ngp_batch b = {N, index, px, py, {w}, 1, 0};
    orr_ngp_place(p, &m, &b, st);
    orr_ngp_add(&b, plane);
}

static int same_plane(const orr_plane *a, const orr_plane *b)
{
    return memcmp(a->data, b->data, (size_t)a->width * a->height * sizeof(float)) == 0;
}

/* The pixel each particle went to agrees with the projection in double,
 * except within 1e-3 pixel of a pixel's edge (float rounding may go
 * either way there) and on a sky map's rim (folded). */
static void check_against_double(const orr_projection *p, const orr_camera_transform *t, const particles *q,
                                 const int32_t *index)
{
    int checked = 0, bad = 0;
    for (int i = 0; i < N; i++) {
        orr_vec3 d = {q->x[i] - t->ox, q->y[i] - t->oy, q->z[i] - t->oz}, c;
        c.x = t->r[0][0] * d.x + t->r[0][1] * d.y + t->r[0][2] * d.z;
        c.y = t->r[1][0] * d.x + t->r[1][1] * d.y + t->r[1][2] * d.z;
        c.z = t->r[2][0] * d.x + t->r[2][1] * d.y + t->r[2][2] * d.z;
        double px, py, scale;
        int vis = orr_project_point(p, c, &px, &py, &scale);
        if (!vis) {
            bad += index[i] != ORR_NGP_CULLED;
            continue;
        }
        double fx = px - floor(px), fy = py - floor(py);
        if (fx < 1e-3 || fx > 1 - 1e-3 || fy < 1e-3 || fy > 1 - 1e-3)
            continue;
        int ix = (int)floor(px), iy = (int)floor(py);
        if (!orr_projection_pixel_in_map(p, ix, iy))
            continue; /* off a flat image: lost; off a sky map: folded */
        bad += index[i] != iy * p->width + ix;
        checked++;
    }
    CHECK(bad == 0);
    CHECK(checked > N / 10);
}

static void test_matches_general_path(void)
{
    const orr_projection_kind kinds[] = {ORR_PROJ_ORTHOGRAPHIC, ORR_PROJ_PERSPECTIVE, ORR_PROJ_HAMMER_AITOFF,
                                         ORR_PROJ_EQUIRECTANGULAR, ORR_PROJ_DOME};
    static particles q;
    static int32_t index[N];
    for (int k = 0; k < 5; k++)
        for (int dim = 0; dim < 2; dim++) {
            orr_projection p = make_projection(kinds[k]);
            orr_camera_transform t = make_transform(dim);
            make_particles(&q, &t);
            orr_plane a, b;
            orr_error err;
            CHECK(orr_plane_alloc(&a, p.width, p.height, "w", "", &err) == ORR_OK);
            CHECK(orr_plane_alloc(&b, p.width, p.height, "w", "", &err) == ORR_OK);
            orr_deposit_stats sa = {0}, sb = {0};
            general_plane(&p, &t, &q, &a, &sa);
            fused_plane(&p, &t, &q, &b, &sb, index);
            if (!same_plane(&a, &b))
                fprintf(stderr, "%s, dim %d: the fused gather's image differs\n", orr_projection_name(kinds[k]),
                        dim);
            CHECK(same_plane(&a, &b));
            CHECK(sa.deposited == sb.deposited && sa.outside == sb.outside && sa.culled == sb.culled);
            CHECK(sa.n_culled == sb.n_culled && sa.n_particles == sb.n_particles && sb.n_particles == N);
            CHECK(sb.deposited > 0);
            if (kinds[k] == ORR_PROJ_PERSPECTIVE || kinds[k] == ORR_PROJ_DOME)
                CHECK(sb.n_culled > 0); /* the cube reaches behind the camera */
            check_against_double(&p, &t, &q, index);
            orr_plane_free(&a);
            orr_plane_free(&b);
        }
}

static void test_catches_nonfinite(void)
{
    static particles q;
    static int32_t index[N];
    static float px[N], py[N], dimming[N];
    const float bad_values[] = {NAN, INFINITY, -INFINITY};
    const int where[] = {0, 7, 8, 1000, N - 1};
    orr_projection p = make_projection(ORR_PROJ_DOME);
    const orr_map_outline m = orr_map_outline_of(&p, p.width, p.height);
    orr_camera_transform t = make_transform(1);
    make_particles(&q, &t);
    orr_ngp_gather_out out = {index, px, py, dimming};
    CHECK(orr_ngp_gather(&p, &m, &t, N, q.x, q.y, q.z, q.w, &out) == 1);
    float *arrays[4] = {q.x, q.y, q.z, q.w};
    for (int a = 0; a < 4; a++)
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 5; k++) {
                float keep = arrays[a][where[k]];
                arrays[a][where[k]] = bad_values[v];
                int ok = orr_ngp_gather(&p, &m, &t, N, q.x, q.y, q.z, q.w, &out);
                if (ok)
                    fprintf(stderr, "array %d, value %g at %d: not caught\n", a, (double)bad_values[v], where[k]);
                CHECK(ok == 0);
                arrays[a][where[k]] = keep;
            }
    /* A huge but finite position is fine. */
    q.x[5] = 3e38f;
    CHECK(orr_ngp_gather(&p, &m, &t, N, q.x, q.y, q.z, q.w, &out) == 1);
}

int main(void)
{
    RUN(test_matches_general_path);
    RUN(test_catches_nonfinite);
    return check_summary();
}
