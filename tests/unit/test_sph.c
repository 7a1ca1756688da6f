/* SPH kernel deposits: single particles against brute-force pixel
 * integrals, mass conservation for h from 0.01 to 100 pixels inside and
 * across the image's edges, tiny kernels, the h = 0 fallback, perspective;
 * on the sky maps: large kernels, the l = +-180 seam, the poles and the
 * dome's rim, nothing off the map, shapes against a brute-force map of the
 * cap; and the inverse projection. */
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "splat/sph.h"
#include "test_random.h"

static const orr_kernel_kind kinds[] = {ORR_KERNEL_CUBIC, ORR_KERNEL_WENDLAND_C2, ORR_KERNEL_WENDLAND_C4};

static orr_kernel make_kernel(orr_kernel_kind kind)
{
    orr_kernel k;
    orr_error err = {0};
    CHECK(orr_kernel_init(&k, kind, &err) == ORR_OK);
    return k;
}

static orr_projection make_proj(orr_projection_kind kind, int w, int h)
{
    /* Orthographic with one unit per pixel, so h is in pixels. */
    return PLANNED(.kind = kind, .width = w, .height = h, .ortho_width = w, .fov_deg = 60, .dome_fov_deg = 180);
}

static orr_plane make_plane(const orr_projection *p)
{
    orr_plane pl;
    orr_error err = {0};
    CHECK(orr_plane_alloc(&pl, p->width, p->height, "mass", "", &err) == ORR_OK);
    return pl;
}

static orr_sph make_sph(const orr_kernel *k, const orr_projection *p)
{
    orr_sph s;
    orr_error err = {0};
    CHECK(orr_sph_init(&s, k, p, &err) == ORR_OK);
    return s;
}

static float at(const orr_plane *p, int i, int j)
{
    return p->data[(size_t)j * p->width + i];
}

/* Deposits particles at image positions with h in pixels (scale 1). */
static void deposit_flat(const orr_sph *s, orr_plane *pl, size_t n, const float *px, const float *py,
                         const float *h, const float *w, orr_deposit_stats *st)
{
    float *scale = malloc(n * sizeof *scale);
    uint8_t *vis = malloc(n);
    for (size_t i = 0; i < n; i++) {
        scale[i] = 1.0f;
        vis[i] = 1;
    }
    orr_sph_block b = {n, NULL, NULL, NULL, px, py, scale, vis, h, w};
    orr_sph_deposit(s, &b, pl, st);
    free(scale);
    free(vis);
}

static void deposit_one(const orr_sph *s, orr_plane *pl, float x, float y, float h, float w,
                        orr_deposit_stats *st)
{
    deposit_flat(s, pl, 1, &x, &y, &h, &w, st);
}

/* ---- a reference column kernel, independent of the library's tables ---- */

/* F tabulated finely in u = q^2 from the library's direct line-of-sight
 * integration (tested against a plain sum in test_kernel). */
#define REF_N 20000
typedef struct reference {
    double f[REF_N + 2];
} reference;

static reference *make_reference(const orr_kernel *k)
{
    reference *r = malloc(sizeof *r);
    for (int i = 0; i <= REF_N; i++)
        r->f[i] = orr_kernel_column_exact(k, sqrt(4.0 * i / REF_N));
    r->f[REF_N + 1] = 0.0;
    return r;
}

static double ref_column(const reference *r, double u)
{
    double t = u * (REF_N / 4.0);
    if (!(t < REF_N))
        return 0.0;
    int i = (int)t;
    return r->f[i] + (t - i) * (r->f[i + 1] - r->f[i]);
}

/* Gauss-Legendre nodes and weights on [0, 1]. */
static void gauss(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double z = cos(ORR_PI * (i + 0.75) / (n + 0.5)), dp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = z;
            for (int m = 2; m <= n; m++) {
                double p2 = ((2 * m - 1) * z * p1 - (m - 1) * p0) / m;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-15)
                break;
        }
        x[i] = 0.5 * (1 + z);
        w[i] = 1.0 / ((1 - z * z) * dp * dp);
    }
}

/* The integral of F over pixel [i, i+1) x [j, j+1) for a kernel of h
 * pixels at (cx, cy), by an n x n Gauss-Legendre rule. */
static double pixel_integral(const reference *r, double cx, double cy, double h, int i, int j, int n,
                             const double *x, const double *w)
{
    double s = 0.0;
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            double dx = (i + x[a] - cx) / h, dy = (j + x[b] - cy) / h;
            s += w[a] * w[b] * ref_column(r, dx * dx + dy * dy);
        }
    return s / (h * h);
}

/* ---- flat maps ---- */

static void test_single_particle_matches_pixel_integral(void)
{
    const double hs[] = {0.3, 0.45, 0.7, 1.0, 1.5, 2.2, 3.1, 3.99, 4.0, 5.5, 8.0, 9.99, 10.0, 16.0, 30.0, 50.0};
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 224, 224);
    uint64_t seed = 7;
    double worst_all = 0.0;
    for (int kk = 0; kk < 3; kk++) {
        orr_kernel k = make_kernel(kinds[kk]);
        reference *ref = make_reference(&k);
        orr_sph s = make_sph(&k, &p);
        for (size_t m = 0; m < sizeof hs / sizeof hs[0]; m++) {
            double h = hs[m], cx = 112 + test_uniform(&seed), cy = 112 + test_uniform(&seed);
            orr_plane pl = make_plane(&p);
            orr_deposit_stats st = {0};
            deposit_one(&s, &pl, (float)cx, (float)cy, (float)h, 1.0f, &st);
            int n = (int)ceil(24.0 / h) + 6;
            double *x = malloc(n * sizeof *x), *w = malloc(n * sizeof *w);
            gauss(n, x, w);
            /* The float position is what was deposited. */
            cx = (float)cx;
            cy = (float)cy;
            int r = (int)ceil(2 * h) + 1;
            double peak = 0.0, worst = 0.0, lowest = 0.0;
            for (int j = (int)cy - r; j <= (int)cy + r; j++)
                for (int i = (int)cx - r; i <= (int)cx + r; i++) {
                    double want = pixel_integral(ref, cx, cy, h, i, j, n, x, w);
                    peak = fmax(peak, want);
                    worst = fmax(worst, fabs(at(&pl, i, j) - want));
                    lowest = fmin(lowest, at(&pl, i, j));
                }
            worst /= peak;
            worst_all = fmax(worst_all, worst);
            if (!(worst < 1e-4))
                fprintf(stderr, "%s h = %g: error %.3g of the peak pixel\n", orr_kernel_name(kinds[kk]), h, worst);
            CHECK(worst < 1e-4);
            /* Nothing below zero beyond round-off (the table differences
             * give -1.5e-8 at most; the separable expansion, which dips to
             * -1e-5 of the peak near the support's edge, is clamped). */
            CHECK(lowest >= -1e-7 * peak);
            CHECK_NEAR(orr_plane_sum(&pl), 1.0, 1e-6);
            free(x);
            free(w);
            orr_plane_free(&pl);
        }
        orr_sph_free(&s);
        orr_kernel_free(&k);
        free(ref);
    }
    fprintf(stderr, "  largest single-particle error: %.2g of the peak pixel\n", worst_all);
}

/* Particles wholly inside: the image holds exactly their mass, whatever h. */
static void test_mass_conserved_inside(void)
{
    const double hs[] = {0.01, 0.03, 0.1, 0.3, 1, 2, 3.9, 4, 7, 9.9, 10, 30, 100};
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 512, 512);
    uint64_t seed = 11;
    enum { N = 60 };
    for (int kk = 0; kk < 3; kk++) {
        orr_kernel k = make_kernel(kinds[kk]);
        orr_sph s = make_sph(&k, &p);
        for (size_t m = 0; m < sizeof hs / sizeof hs[0]; m++) {
            float px[N], py[N], h[N], w[N];
            double total = 0.0;
            for (int i = 0; i < N; i++) {
                px[i] = (float)(256 + 100 * (test_uniform(&seed) - 0.5));
                py[i] = (float)(256 + 100 * (test_uniform(&seed) - 0.5));
                h[i] = (float)(hs[m] * (0.8 + 0.2 * test_uniform(&seed)));
                w[i] = (float)(0.5 + test_uniform(&seed));
                total += w[i];
            }
            orr_plane pl = make_plane(&p);
            orr_deposit_stats st = {0};
            deposit_flat(&s, &pl, N, px, py, h, w, &st);
            CHECK_NEAR(orr_plane_sum(&pl) / total, 1.0, 1e-6);
            CHECK_NEAR(st.deposited / total, 1.0, 1e-6);
            CHECK_NEAR(st.outside / total, 0.0, 1e-6);
            CHECK(st.n_particles == N);
            orr_plane_free(&pl);
        }
        orr_sph_free(&s);
        orr_kernel_free(&k);
    }
}

/* Particles straddling the edges: what lands plus what falls off is their
 * mass, and what landed is what the image holds. */
static void test_mass_across_edges(void)
{
    const double hs[] = {0.01, 0.3, 1, 3, 5, 12, 40, 100, 1000};
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 300, 200);
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_sph s = make_sph(&k, &p);
    uint64_t seed = 5;
    enum { N = 40 };
    for (size_t m = 0; m < sizeof hs / sizeof hs[0]; m++) {
        float px[N], py[N], h[N], w[N];
        double total = 0.0;
        for (int i = 0; i < N; i++) {
            /* Within a support radius of one of the four edges. */
            double r = 2 * hs[m] * (2 * test_uniform(&seed) - 1), along = test_uniform(&seed);
            int edge = i % 4;
            px[i] = (float)(edge == 0 ? r : edge == 1 ? 300 + r : 300 * along);
            py[i] = (float)(edge == 2 ? r : edge == 3 ? 200 + r : 200 * along);
            h[i] = (float)hs[m];
            w[i] = 1.0f;
            total += 1.0;
        }
        orr_plane pl = make_plane(&p);
        orr_deposit_stats st = {0};
        deposit_flat(&s, &pl, N, px, py, h, w, &st);
        CHECK_NEAR((st.deposited + st.outside) / total, 1.0, 1e-9);
        CHECK_NEAR(orr_plane_sum(&pl) / total, st.deposited / total, 1e-6);
        CHECK(st.outside > 0.01 * total);
        orr_plane_free(&pl);
    }
    /* A kernel centred on an edge puts half of itself in the image (up to
     * the table's accuracy), by every method: the table's corners, the
     * midpoint rule summed, and (h = 400, in a bigger image) the midpoint
     * rule with the analytic sum. */
    const double half_h[] = {0.7, 2, 6, 50, 400};
    orr_projection big = make_proj(ORR_PROJ_ORTHOGRAPHIC, 1000, 1800);
    for (size_t m = 0; m < sizeof half_h / sizeof half_h[0]; m++) {
        const orr_projection *q = half_h[m] > 50 ? &big : &p;
        orr_sph sq = make_sph(&k, q);
        orr_plane pl = make_plane(q);
        orr_deposit_stats st = {0};
        deposit_one(&sq, &pl, 0.0f, (float)(0.5 * q->height), (float)half_h[m], 2.0f, &st);
        CHECK_NEAR(st.deposited, 1.0, 2e-4);
        CHECK_NEAR(st.outside, 1.0, 2e-4);
        CHECK_NEAR(orr_plane_sum(&pl), st.deposited, 1e-6);
        orr_plane_free(&pl);
        orr_sph_free(&sq);
    }
    /* Far off the image, even absurdly far: all outside, no overflow. */
    orr_plane pl = make_plane(&p);
    orr_deposit_stats st = {0};
    deposit_one(&s, &pl, 1e30f, -1e30f, 3.0f, 1.0f, &st);
    deposit_one(&s, &pl, -5000.0f, 100.0f, 1e6f, 1.0f, &st); /* huge, covering the image */
    CHECK_NEAR(st.outside + st.deposited, 2.0, 1e-9);
    CHECK(st.deposited > 0);
    CHECK_NEAR(orr_plane_sum(&pl), st.deposited, 1e-9);
    orr_plane_free(&pl);
    orr_sph_free(&s);
    orr_kernel_free(&k);
}

/* A block deposits what its particles deposit one at a time: the block
 * draws its large kernels band by band after the small ones, so a piece
 * drawn twice or missed would show here, pixel by pixel. Kernels of 0.2 to
 * 60 pixels per h, some across the image's edges, on an image of many
 * bands. */
static void test_block_matches_single_deposits(void)
{
    enum { N = 300 };
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 320, 700);
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_sph s = make_sph(&k, &p);
    uint64_t seed = 23;
    float px[N], py[N], h[N], w[N];
    for (int i = 0; i < N; i++) {
        px[i] = (float)(-40 + 400 * test_uniform(&seed));
        py[i] = (float)(-40 + 780 * test_uniform(&seed));
        h[i] = (float)(0.2 * pow(300.0, test_uniform(&seed)));
        w[i] = (float)(0.5 + test_uniform(&seed));
    }
    orr_plane block = make_plane(&p), single = make_plane(&p);
    orr_deposit_stats st_block = {0}, st_single = {0};
    deposit_flat(&s, &block, N, px, py, h, w, &st_block);
    for (int i = 0; i < N; i++)
        deposit_one(&s, &single, px[i], py[i], h[i], w[i], &st_single);
    double peak = 0.0, worst = 0.0;
    for (size_t m = 0; m < (size_t)p.width * p.height; m++) {
        peak = fmax(peak, single.data[m]);
        worst = fmax(worst, fabs(block.data[m] - single.data[m]));
    }
    CHECK(peak > 0 && worst <= 1e-5 * peak);
    CHECK_NEAR(st_block.deposited, st_single.deposited, 1e-9 * st_single.deposited);
    CHECK_NEAR(st_block.outside, st_single.outside, 1e-6 * st_single.deposited);
    CHECK(st_block.outside > 0);
    CHECK_NEAR(orr_plane_sum(&block), st_block.deposited, 1e-6 * st_block.deposited);
    orr_plane_free(&block);
    orr_plane_free(&single);
    orr_sph_free(&s);
    orr_kernel_free(&k);
}

/* Kernels much smaller than a pixel land in the pixel(s) they overlap. */
static void test_tiny_kernels(void)
{
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 8, 8);
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_sph s = make_sph(&k, &p);
    orr_plane pl = make_plane(&p);
    orr_deposit_stats st = {0};
    deposit_one(&s, &pl, 3.3f, 4.6f, 0.01f, 2.5f, &st);
    CHECK_NEAR(at(&pl, 3, 4), 2.5, 1e-6);
    CHECK_NEAR(orr_plane_sum(&pl), 2.5, 1e-6);
    /* h = 0.2 at a pixel centre: support 0.4 < 0.5, all in the pixel. */
    memset(pl.data, 0, sizeof(float) * 64);
    deposit_one(&s, &pl, 5.5f, 1.5f, 0.2f, 1.0f, &st);
    CHECK_NEAR(at(&pl, 5, 1), 1.0, 1e-6);
    /* Straddling a pixel edge: split by symmetry. */
    memset(pl.data, 0, sizeof(float) * 64);
    deposit_one(&s, &pl, 4.0f, 2.5f, 0.05f, 1.0f, &st);
    CHECK_NEAR(at(&pl, 3, 2), 0.5, 1e-6);
    CHECK_NEAR(at(&pl, 4, 2), 0.5, 1e-6);
    /* At a pixel corner: a quarter each. */
    memset(pl.data, 0, sizeof(float) * 64);
    deposit_one(&s, &pl, 2.0f, 6.0f, 0.003f, 1.0f, &st);
    CHECK_NEAR(at(&pl, 1, 5), 0.25, 1e-6);
    CHECK_NEAR(at(&pl, 2, 5), 0.25, 1e-6);
    CHECK_NEAR(at(&pl, 1, 6), 0.25, 1e-6);
    CHECK_NEAR(at(&pl, 2, 6), 0.25, 1e-6);
    CHECK_NEAR(orr_plane_sum(&pl), 1.0, 1e-6);
    /* Just inside a pixel edge, overlapping the next pixel a little. */
    memset(pl.data, 0, sizeof(float) * 64);
    deposit_one(&s, &pl, 3.99f, 3.5f, 0.01f, 1.0f, &st);
    CHECK(at(&pl, 3, 3) > 0.9f && at(&pl, 4, 3) > 0.0f);
    CHECK_NEAR(at(&pl, 3, 3) + at(&pl, 4, 3), 1.0, 1e-6);
    orr_plane_free(&pl);
    orr_sph_free(&s);
    orr_kernel_free(&k);
}

/* No smoothing length: cloud-in-cell, exactly as orr_deposit. */
static void test_no_h_is_cic(void)
{
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 16, 12);
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_sph s = make_sph(&k, &p);
    enum { N = 5 };
    float px[N] = {3.3f, 7.9f, 0.2f, 15.8f, 8.0f}, py[N] = {2.2f, 5.5f, 11.9f, 0.1f, 6.0f};
    float w[N] = {1, 2, 3, 4, 5}, h[N] = {0.0f, -1.0f, NAN, INFINITY, 0.0f}, sc[N] = {1, 1, 1, 1, 1};
    uint8_t vis[N] = {1, 1, 1, 1, 1};
    for (int variant = 0; variant < 2; variant++) {
        orr_plane a = make_plane(&p), b = make_plane(&p);
        orr_deposit_stats sa = {0}, sb = {0};
        orr_sph_block blk = {N, NULL, NULL, NULL, px, py, sc, vis, variant ? NULL : h, w};
        orr_sph_deposit(&s, &blk, &a, &sa);
        orr_deposit(ORR_DEPOSIT_CIC, &b, N, px, py, w, vis, &p, &sb);
        CHECK(memcmp(a.data, b.data, sizeof(float) * 16 * 12) == 0);
        CHECK_NEAR(sa.deposited, sb.deposited, 1e-6);
        CHECK_NEAR(sa.outside, sb.outside, 1e-6);
        CHECK(sa.n_particles == N);
        orr_plane_free(&a);
        orr_plane_free(&b);
    }
    orr_sph_free(&s);
    orr_kernel_free(&k);
}

static void test_culled_particles(void)
{
    orr_projection p = make_proj(ORR_PROJ_ORTHOGRAPHIC, 16, 16);
    orr_kernel k = make_kernel(ORR_KERNEL_WENDLAND_C2);
    orr_sph s = make_sph(&k, &p);
    orr_plane pl = make_plane(&p);
    float px[2] = {5, 9}, py[2] = {5, 9}, h[2] = {1, 1}, w[2] = {3, 4}, sc[2] = {1, 1};
    uint8_t vis[2] = {0, 1};
    orr_deposit_stats st = {0};
    orr_sph_block b = {2, NULL, NULL, NULL, px, py, sc, vis, h, w};
    orr_sph_deposit(&s, &b, &pl, &st);
    CHECK_NEAR(st.culled, 3.0, 0);
    CHECK(st.n_culled == 1 && st.n_particles == 2);
    CHECK_NEAR(st.deposited, 4.0, 1e-6);
    CHECK_NEAR(orr_plane_sum(&pl), 4.0, 1e-5);
    orr_plane_free(&pl);
    orr_sph_free(&s);
    orr_kernel_free(&k);
}

/* Perspective: h_pix = h f / z; the image is the flat deposit of that. */
static void test_perspective(void)
{
    orr_projection persp = make_proj(ORR_PROJ_PERSPECTIVE, 200, 150);
    orr_projection flat = make_proj(ORR_PROJ_ORTHOGRAPHIC, 200, 150);
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_sph sp = make_sph(&k, &persp), sf = make_sph(&k, &flat);
    enum { N = 3 };
    float x[N] = {0.1f, -0.3f, 0.0f}, y[N] = {-0.05f, 0.2f, 0.0f}, z[N] = {2.0f, 5.0f, 0.5f};
    float h[N] = {0.01f, 0.05f, 0.02f}, w[N] = {1, 2, 3}, px[N], py[N], sc[N], hp[N];
    uint8_t vis[N];
    orr_project_batch(&persp, N, x, y, z, px, py, sc, vis);
    for (int i = 0; i < N; i++) {
        CHECK(vis[i]);
        hp[i] = h[i] * sc[i];
    }
    CHECK_NEAR(hp[2], 0.02 * persp.focal / 0.5, 1e-4);
    orr_plane a = make_plane(&persp), b = make_plane(&flat);
    orr_deposit_stats sa = {0}, sb = {0};
    orr_sph_block blk = {N, x, y, z, px, py, sc, vis, h, w};
    orr_sph_deposit(&sp, &blk, &a, &sa);
    deposit_flat(&sf, &b, N, px, py, hp, w, &sb);
    double diff = 0.0;
    for (int i = 0; i < 200 * 150; i++)
        diff = fmax(diff, fabs(a.data[i] - b.data[i]));
    CHECK(diff < 1e-6);
    CHECK_NEAR(sa.deposited, 6.0, 1e-5);
    orr_plane_free(&a);
    orr_plane_free(&b);
    orr_sph_free(&sp);
    orr_sph_free(&sf);
    orr_kernel_free(&k);
}

/* ---- the inverse projection ---- */

static void test_unproject(void)
{
    orr_projection ps[6];
    ps[0] = make_proj(ORR_PROJ_HAMMER_AITOFF, 720, 360);
    ps[1] = make_proj(ORR_PROJ_DOME, 400, 400);
    ps[2] = make_proj(ORR_PROJ_EQUIRECTANGULAR, 720, 360);
    ps[3] = make_proj(ORR_PROJ_PERSPECTIVE, 320, 200);
    ps[4] = PLANNED(.kind = ORR_PROJ_DOME, .width = 300, .height = 320, .dome_fov_deg = 230);
    ps[5] = PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 500, .height = 250, .lon_flip = 1);
    uint64_t seed = 3;
    for (int k = 0; k < 6; k++) {
        const orr_projection *p = &ps[k];
        int bad = 0;
        for (int t = 0; t < 2000; t++) {
            double x = test_uniform(&seed) * p->width, y = test_uniform(&seed) * p->height;
            orr_vec3 d;
            if (!orr_unproject(p, x, y, &d))
                continue;
            double qx, qy, s;
            CHECK_NEAR(orr_v3_norm(d), 1.0, 1e-12);
            if (!orr_project_point(p, orr_v3_scale(d, 2.5), &qx, &qy, &s) || fabs(qx - x) > 1e-6 ||
                fabs(qy - y) > 1e-6) {
                if (bad++ < 3)
                    fprintf(stderr, "%s: (%g, %g) -> (%g, %g)\n", orr_projection_name(p->settings.kind), x, y, qx, qy);
            }
        }
        CHECK(bad == 0);
        /* Pixel centres are on the map exactly when pixel_in_map says so. */
        int disagree = 0;
        for (int j = 0; j < p->height; j += 3)
            for (int i = 0; i < p->width; i += 3) {
                orr_vec3 d;
                disagree += orr_unproject(p, i + 0.5, j + 0.5, &d) != orr_projection_pixel_in_map(p, i, j);
            }
        CHECK(disagree == 0);
    }
    orr_vec3 d;
    CHECK(orr_unproject(&ps[0], 2, 2, &d) == 0);       /* a corner outside the ellipse */
    CHECK(orr_unproject(&ps[1], 5, 395, &d) == 0);     /* outside the dome's circle */
    CHECK(orr_unproject(&ps[2], -1, 100, &d) == 0);    /* off the equirectangular image */
    CHECK(orr_unproject(&ps[0], 360, 180, &d) == 1);   /* the centre looks along +z */
    CHECK_NEAR(d.z, 1.0, 1e-12);
    orr_projection o = make_proj(ORR_PROJ_ORTHOGRAPHIC, 10, 10);
    CHECK(orr_unproject(&o, -50, 3, &d) == 1 && d.z == 1.0);
}

/* ---- sky maps ---- */

/* A direction at (l, b) degrees in the sky maps' camera frame. */
static orr_vec3 dir_lb(double l_deg, double b_deg)
{
    double l = l_deg * ORR_PI / 180, b = b_deg * ORR_PI / 180;
    return orr_v3(-cos(b) * sin(l), -sin(b), cos(b) * cos(l));
}

/* Deposits particles at directions d[i], distance r[i], smoothing length
 * h[i], through the projection, as the renderer does. */
static void deposit_sky(const orr_sph *s, const orr_projection *p, orr_plane *pl, size_t n, const orr_vec3 *d,
                        const double *r, const double *h, const float *w, int with_positions,
                        orr_deposit_stats *st)
{
    float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *z = malloc(n * sizeof *z);
    float *px = malloc(n * sizeof *px), *py = malloc(n * sizeof *py), *sc = malloc(n * sizeof *sc);
    float *hf = malloc(n * sizeof *hf);
    uint8_t *vis = malloc(n);
    for (size_t i = 0; i < n; i++) {
        x[i] = (float)(r[i] * d[i].x);
        y[i] = (float)(r[i] * d[i].y);
        z[i] = (float)(r[i] * d[i].z);
        hf[i] = (float)h[i];
    }
    orr_project_batch(p, n, x, y, z, px, py, sc, vis);
    orr_sph_block b = {n, with_positions ? x : NULL, with_positions ? y : NULL, with_positions ? z : NULL,
                       px, py, sc, vis, hf, w};
    orr_sph_deposit(s, &b, pl, st);
    free(x);
    free(y);
    free(z);
    free(px);
    free(py);
    free(sc);
    free(hf);
    free(vis);
}

/* Sum of the plane over pixels off the map (must be zero). */
static double off_map(const orr_projection *p, const orr_plane *pl)
{
    double s = 0.0;
    for (int j = 0; j < p->height; j++)
        for (int i = 0; i < p->width; i++)
            if (!orr_projection_pixel_in_map(p, i, j))
                s += fabs(at(pl, i, j));
    return s;
}

static void test_sky_mass_conserved(void)
{
    orr_projection ps[3] = {make_proj(ORR_PROJ_HAMMER_AITOFF, 360, 180), make_proj(ORR_PROJ_DOME, 240, 240),
                            make_proj(ORR_PROJ_EQUIRECTANGULAR, 360, 180)};
    /* Angular h from a fraction of a pixel to 20 degrees. */
    const double thetas[] = {0.001, 0.01, 0.03, 0.1, 20 * ORR_PI / 180};
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    uint64_t seed = 21;
    enum { N = 24 };
    for (int m = 0; m < 3; m++) {
        const orr_projection *p = &ps[m];
        orr_sph s = make_sph(&k, p);
        for (size_t t = 0; t < sizeof thetas / sizeof thetas[0]; t++) {
            orr_vec3 d[N];
            double r[N], h[N];
            float w[N];
            double total = 0.0;
            for (int i = 0; i < N; i++) {
                /* Random directions, and some at the awkward places: the
                 * seam, the poles, near the dome's rim. */
                double l = 360 * test_uniform(&seed) - 180, b = asin(2 * test_uniform(&seed) - 1) * 180 / ORR_PI;
                if (i == 0)
                    l = 179.5, b = 3;
                if (i == 1)
                    l = -178, b = -40;
                if (i == 2)
                    b = 88.5;
                if (i == 3)
                    b = -89.9;
                d[i] = dir_lb(l, b);
                if (p->settings.kind == ORR_PROJ_DOME) {
                    /* Visible: within 90 degrees of +z; two at the rim. */
                    if (d[i].z < 0)
                        d[i].z = -d[i].z;
                    if (i < 2)
                        d[i] = orr_v3_normalize(orr_v3(d[i].x, d[i].y, 0.01));
                }
                r[i] = 1 + 9 * test_uniform(&seed);
                h[i] = thetas[t] * r[i];
                w[i] = (float)(0.5 + test_uniform(&seed));
                total += w[i];
            }
            orr_plane pl = make_plane(p);
            orr_deposit_stats st = {0};
            deposit_sky(&s, p, &pl, N, d, r, h, w, 1, &st);
            CHECK_NEAR(orr_plane_sum(&pl) / total, 1.0, 1e-5);
            CHECK_NEAR(st.deposited / total, 1.0, 1e-9);
            CHECK(st.outside == 0 && st.culled == 0);
            CHECK(off_map(p, &pl) == 0.0);
            orr_plane_free(&pl);
            /* Without camera-frame positions the local scale is used:
             * still exact. */
            pl = make_plane(p);
            orr_deposit_stats st2 = {0};
            if (thetas[t] < 0.05) {
                deposit_sky(&s, p, &pl, N, d, r, h, w, 0, &st2);
                CHECK_NEAR(orr_plane_sum(&pl) / total, 1.0, 1e-5);
                CHECK(off_map(p, &pl) == 0.0);
            }
            orr_plane_free(&pl);
        }
        orr_sph_free(&s);
    }
    orr_kernel_free(&k);
}

/* Mass in the columns [i0, i1). */
static double columns(const orr_plane *pl, int i0, int i1)
{
    double s = 0.0;
    for (int j = 0; j < pl->height; j++)
        for (int i = i0; i < i1; i++)
            s += at(pl, i, j);
    return s;
}

static void test_seam_drawn_on_both_sides(void)
{
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_projection ps[2] = {make_proj(ORR_PROJ_HAMMER_AITOFF, 720, 360),
                            make_proj(ORR_PROJ_EQUIRECTANGULAR, 720, 360)};
    /* Kernels centred a little left of l = 180 (near the left edge): a
     * small one (local path with folding), a mid one, a large one. */
    const double thetas[] = {0.02, 0.06, 0.3};
    for (int m = 0; m < 2; m++) {
        orr_sph s = make_sph(&k, &ps[m]);
        for (int t = 0; t < 3; t++) {
            orr_vec3 d = dir_lb(179.0, 15.0);
            double r = 3.0, h = thetas[t] * r;
            float w = 1.0f;
            orr_plane pl = make_plane(&ps[m]);
            orr_deposit_stats st = {0};
            deposit_sky(&s, &ps[m], &pl, 1, &d, &r, &h, &w, 1, &st);
            double left = columns(&pl, 0, 180), right = columns(&pl, 540, 720);
            CHECK(left > 0.5);
            CHECK(right > 0.05);
            CHECK_NEAR(left + right, 1.0, 1e-5);
            CHECK_NEAR(orr_plane_sum(&pl), 1.0, 1e-5);
            CHECK(off_map(&ps[m], &pl) == 0.0);
            orr_plane_free(&pl);
        }
        orr_sph_free(&s);
    }
    orr_kernel_free(&k);
}

/* Over a pole of the equirectangular map the cap spreads along the top
 * rows; on the dome, a cap past the rim is drawn inside it. */
static void test_poles_and_rim(void)
{
    orr_kernel k = make_kernel(ORR_KERNEL_WENDLAND_C4);
    orr_projection eq = make_proj(ORR_PROJ_EQUIRECTANGULAR, 360, 180);
    orr_sph s = make_sph(&k, &eq);
    orr_vec3 d = dir_lb(40, 87);
    double r = 1, h = 0.05;
    float w = 2.0f;
    orr_plane pl = make_plane(&eq);
    orr_deposit_stats st = {0};
    deposit_sky(&s, &eq, &pl, 1, &d, &r, &h, &w, 1, &st);
    int lit = 0;
    for (int i = 0; i < 360; i++)
        lit += at(&pl, i, 0) > 0;
    CHECK(lit == 360); /* the pole row is one point: all of it */
    CHECK_NEAR(orr_plane_sum(&pl), 2.0, 2e-5);
    orr_plane_free(&pl);
    orr_sph_free(&s);

    orr_projection dome = make_proj(ORR_PROJ_DOME, 300, 300);
    s = make_sph(&k, &dome);
    d = orr_v3_normalize(orr_v3(0.3, 1.0, 0.02)); /* 89 degrees from the zenith */
    h = 0.1;
    pl = make_plane(&dome);
    st = (orr_deposit_stats){0};
    deposit_sky(&s, &dome, &pl, 1, &d, &r, &h, &w, 1, &st);
    CHECK_NEAR(orr_plane_sum(&pl), 2.0, 2e-5);
    CHECK(off_map(&dome, &pl) == 0.0);
    orr_plane_free(&pl);
    orr_sph_free(&s);
    orr_kernel_free(&k);
}

/* The sky kernel against a brute-force map of the cap: F of each
 * sub-pixel's angular distance (as a chord) over h / r, times its solid
 * angle, normalised over the map. A pixel is on the map when its centre
 * is; its sub-pixels off the map count as the centre. Returns the largest
 * difference over the peak pixel. */
static double sky_shape_error(const orr_kernel *k, const orr_projection *p, orr_vec3 d, double theta)
{
    orr_sph s = make_sph(k, p);
    orr_plane pl = make_plane(p);
    orr_deposit_stats st = {0};
    double r = 2.0, h = theta * r;
    float w = 1.0f;
    deposit_sky(&s, p, &pl, 1, &d, &r, &h, &w, 1, &st);
    reference *ref = make_reference(k);
    double *want = calloc((size_t)p->width * p->height, sizeof *want), total = 0.0;
    const int n = 6;
    for (int j = 0; j < p->height; j++)
        for (int i = 0; i < p->width; i++) {
            if (!orr_projection_pixel_in_map(p, i, j))
                continue;
            double sum = 0.0;
            for (int a = 0; a < n; a++)
                for (int b = 0; b < n; b++) {
                    orr_vec3 e;
                    double qx, qy, sc;
                    if (!orr_unproject(p, i + (a + 0.5) / n, j + (b + 0.5) / n, &e))
                        orr_unproject(p, i + 0.5, j + 0.5, &e);
                    if (!orr_project_point(p, e, &qx, &qy, &sc))
                        continue;
                    orr_vec3 c = orr_v3_sub(e, d);
                    sum += ref_column(ref, orr_v3_dot(c, c) / (theta * theta)) / (sc * sc);
                }
            want[(size_t)j * p->width + i] = sum;
            total += sum;
        }
    double peak = 0.0, worst = 0.0;
    for (size_t i = 0; i < (size_t)p->width * p->height; i++) {
        want[i] /= total;
        peak = fmax(peak, want[i]);
        worst = fmax(worst, fabs(pl.data[i] - want[i]));
    }
    free(want);
    free(ref);
    orr_plane_free(&pl);
    orr_sph_free(&s);
    return worst / peak;
}

static void test_sky_shapes(void)
{
    orr_kernel k = make_kernel(ORR_KERNEL_CUBIC);
    orr_projection dome = make_proj(ORR_PROJ_DOME, 240, 240);
    orr_projection ait = make_proj(ORR_PROJ_HAMMER_AITOFF, 360, 180);
    orr_projection eq = make_proj(ORR_PROJ_EQUIRECTANGULAR, 360, 180);
    struct {
        const orr_projection *p;
        orr_vec3 d;
        double theta, tol;
    } cases[] = {
        /* Mid-size kernels (4 to 8 pixels per h): the local affine model. */
        {&dome, {0.5, 0.5, 0.7071067811865476}, 0.05, 0.02},
        {&ait, {-0.6, -0.3, 0.7416198487095663}, 0.07, 0.02},
        {&eq, {0.2, -0.5, 0.8426149773176359}, 0.07, 0.02},
        /* Small ones (2.1 pixels per h at the dome's 45 degrees and near its
         * zenith), one sample a pixel. */
        {&dome, {0.5, 0.5, 0.7071067811865476}, 0.027, 0.01},
        {&dome, {0.1, 0.2, 0.97}, 0.027, 0.01},
        /* Large ones (20 degrees), mapped pixel by pixel. */
        {&dome, {0.6, 0.0, 0.8}, 0.35, 0.01},
        {&ait, {0.3, -0.2, -0.9327379053088815}, 0.35, 0.01},
        {&eq, {0.0, -0.8, 0.6}, 0.35, 0.01},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double e = sky_shape_error(&k, cases[c].p, orr_v3_normalize(cases[c].d), cases[c].theta);
        fprintf(stderr, "  %s, h/r = %g: largest difference %.2g of the peak pixel\n",
                orr_projection_name(cases[c].p->settings.kind), cases[c].theta, e);
        CHECK(e < cases[c].tol);
    }
    orr_kernel_free(&k);
}

int main(void)
{
    RUN(test_single_particle_matches_pixel_integral);
    RUN(test_mass_conserved_inside);
    RUN(test_mass_across_edges);
    RUN(test_block_matches_single_deposits);
    RUN(test_tiny_kernels);
    RUN(test_no_h_is_cic);
    RUN(test_culled_particles);
    RUN(test_perspective);
    RUN(test_unproject);
    RUN(test_sky_mass_conserved);
    RUN(test_seam_drawn_on_both_sides);
    RUN(test_poles_and_rim);
    RUN(test_sky_shapes);
    return check_summary();
}
