/* Sky projections: known points of Hammer-Aitoff, the dome master and the
 * equirectangular map; equal areas; seams and rims lose and double nothing. */
#include <stdlib.h>

#include "check.h"
#include "planned.h"
#include "core/fastmath.h"
#include "splat/deposit.h"

/* A direction at galactic-like (l, b) in degrees, in the camera frame the
 * sky projections use: centre along +z, l = +90 along -x, b = +90 along -y. */
static orr_vec3 dir_lb(double l_deg, double b_deg)
{
    double l = l_deg * ORR_PI / 180, b = b_deg * ORR_PI / 180;
    return orr_v3(-cos(b) * sin(l), -sin(b), cos(b) * cos(l));
}

static orr_projection make(orr_projection_kind kind, int w, int h)
{
    return PLANNED(.kind = kind, .width = w, .height = h, .dome_fov_deg = 180);
}

static void expect_pixel(const orr_projection *p, orr_vec3 d, double x, double y, double tol)
{
    double px = -1, py = -1, s;
    CHECK(orr_project_point(p, orr_v3_scale(d, 3.7), &px, &py, &s) == 1);
    CHECK_NEAR(px, x, tol);
    CHECK_NEAR(py, y, tol);
}

static void test_hammer_aitoff_known_points(void)
{
    orr_projection p = make(ORR_PROJ_HAMMER_AITOFF, 800, 400);
    expect_pixel(&p, dir_lb(0, 0), 400, 200, 1e-9);   /* the centre */
    expect_pixel(&p, dir_lb(0, 90), 400, 0, 1e-9);    /* north pole: top */
    expect_pixel(&p, dir_lb(77, -90), 400, 400, 1e-9);/* south pole: bottom, whatever l */
    /* l = 90 on the equator: X = 2 sqrt2 sin45 / sqrt(1 + cos45), left of centre. */
    double x90 = 2 * sqrt(2) * sin(ORR_PI / 4) / sqrt(1 + cos(ORR_PI / 4));
    expect_pixel(&p, dir_lb(90, 0), 400 - x90 / (2 * sqrt(2)) * 400, 200, 1e-9);
    expect_pixel(&p, dir_lb(-90, 0), 400 + x90 / (2 * sqrt(2)) * 400, 200, 1e-9);
    /* The anti-centre sits on the seam: l -> +180 at the left edge, -180 at the right. */
    expect_pixel(&p, dir_lb(179.999999, 0), 0, 200, 1e-4);
    expect_pixel(&p, dir_lb(-179.999999, 0), 800, 200, 1e-4);
    /* b = 30 on the central meridian: Y = sqrt2 sin b / sqrt(1 + cos b). */
    double y30 = sqrt(2) * 0.5 / sqrt(1 + cos(ORR_PI / 6));
    expect_pixel(&p, dir_lb(0, 30), 400, 200 - y30 / sqrt(2) * 200, 1e-9);
    /* General point against the textbook formula with trigonometry. */
    double l = 123 * ORR_PI / 180, b = -41 * ORR_PI / 180;
    double den = sqrt(1 + cos(b) * cos(l / 2));
    double X = 2 * sqrt(2) * cos(b) * sin(l / 2) / den, Y = sqrt(2) * sin(b) / den;
    expect_pixel(&p, dir_lb(123, -41), 400 - X / (2 * sqrt(2)) * 400, 200 - Y / sqrt(2) * 200, 1e-9);
    /* Flipped: longitude grows to the right. */
    orr_projection f = PLANNED(.kind = ORR_PROJ_HAMMER_AITOFF, .width = 800, .height = 400, .lon_flip = 1);
    expect_pixel(&f, dir_lb(90, 0), 400 + x90 / (2 * sqrt(2)) * 400, 200, 1e-9);
    /* The observer's own position is not drawn. */
    double px, py, s;
    CHECK(orr_project_point(&p, orr_v3(0, 0, 0), &px, &py, &s) == 0);
}

static void test_dome_known_points(void)
{
    orr_projection p = make(ORR_PROJ_DOME, 1000, 1000); /* 180 degrees, radius 500 */
    /* The zenith is the view direction (+z); the front (+y) is at the bottom. */
    expect_pixel(&p, orr_v3(0, 0, 1), 500, 500, 1e-9);
    expect_pixel(&p, orr_v3(0, 1, 0), 500, 1000, 1e-9);   /* front on the rim */
    expect_pixel(&p, orr_v3(0, -1, 0), 500, 0, 1e-9);     /* back */
    expect_pixel(&p, orr_v3(1, 0, 0), 1000, 500, 1e-9);   /* right */
    /* 45 degrees from the zenith toward the front: half way out. */
    expect_pixel(&p, orr_v3(0, 1, 1), 500, 750, 1e-9);
    /* 30 degrees from the zenith, 60 degrees round from the front toward the right. */
    double t = ORR_PI / 6, a = ORR_PI / 3;
    orr_vec3 d = orr_v3(sin(t) * sin(a), sin(t) * cos(a), cos(t));
    expect_pixel(&p, d, 500 + 500 * (1.0 / 3) * sin(a), 500 + 500 * (1.0 / 3) * cos(a), 1e-9);
    /* Below the horizon is not on a 180 degree dome, but is on a 230 degree one. */
    double px, py, s;
    CHECK(orr_project_point(&p, orr_v3(0, 1, -0.2), &px, &py, &s) == 0);
    orr_projection w = PLANNED(.kind = ORR_PROJ_DOME, .width = 1000, .height = 1000, .dome_fov_deg = 230);
    orr_error err = {0};
    CHECK(orr_project_point(&w, orr_v3(0, 1, -0.2), &px, &py, &s) == 1);
    /* 115 degrees from the zenith is the rim of a 230 degree dome. */
    orr_vec3 rim = orr_v3(0, sin(115 * ORR_PI / 180), cos(115 * ORR_PI / 180));
    expect_pixel(&w, rim, 500, 1000, 1e-9);
    orr_projection_settings narrow = w.settings;
    narrow.dome_fov_deg = 80;
    CHECK(orr_projection_check(&narrow, &err) == ORR_ERR_USAGE);
    CHECK_CONTAINS(err.msg, "camera.dome_fov: 80 is out of range (90 to 360)");
}

static void test_equirectangular_known_points(void)
{
    orr_projection p = make(ORR_PROJ_EQUIRECTANGULAR, 720, 360);
    expect_pixel(&p, dir_lb(0, 0), 360, 180, 1e-9);
    expect_pixel(&p, dir_lb(90, 0), 180, 180, 1e-9);
    expect_pixel(&p, dir_lb(-45, 45), 450, 90, 1e-9);
    expect_pixel(&p, dir_lb(0, 90), 360, 0, 1e-9);
    expect_pixel(&p, dir_lb(179.999999, 0), 0, 180, 1e-4);
}

static void test_batch_matches_single(void)
{
    enum { N = 2000 };
    float x[N], y[N], z[N], px[N], py[N], sc[N];
    uint8_t vis[N];
    srand(3);
    for (int i = 0; i < N; i++) {
        x[i] = (float)(rand() / (double)RAND_MAX * 2 - 1);
        y[i] = (float)(rand() / (double)RAND_MAX * 2 - 1);
        z[i] = (float)(rand() / (double)RAND_MAX * 2 - 1);
    }
    orr_projection_kind kinds[] = {ORR_PROJ_HAMMER_AITOFF, ORR_PROJ_DOME, ORR_PROJ_EQUIRECTANGULAR};
    for (int k = 0; k < 3; k++) {
        orr_projection p = make(kinds[k], 600, 300);
        orr_project_batch(&p, N, x, y, z, px, py, sc, vis);
        for (int i = 0; i < N; i++) {
            double qx, qy, qs;
            int v = orr_project_point(&p, orr_v3(x[i], y[i], z[i]), &qx, &qy, &qs);
            CHECK(v == vis[i]);
            if (v && v == vis[i]) {
                /* The seam may put a float on the other edge: compare modulo it. */
                double dx = fabs(px[i] - qx);
                int same = dx < 2e-3 || fabs(dx - 2 * fabs(qx - p.cx)) < 2e-2;
                CHECK(same);
                if (!same)
                    fprintf(stderr, "kind %d point (%g %g %g): batch %g, single %g\n", (int)kinds[k], x[i], y[i],
                            z[i], px[i], qx);
                CHECK_NEAR(py[i], qy, 2e-3);
                CHECK_NEAR(sc[i], qs, 1e-3 * qs);
            }
        }
    }
}

/* Deposits N directions uniform on the sphere (NGP) and returns the plane. */
static orr_plane uniform_sky(const orr_projection *p, int n, orr_deposit_kind kind, double *deposited)
{
    orr_plane plane;
    orr_error err = {0};
    CHECK(orr_plane_alloc(&plane, p->width, p->height, "n", "", &err) == ORR_OK);
    enum { B = 4096 };
    static float x[B], y[B], z[B], w[B], px[B], py[B], sc[B];
    static uint8_t vis[B];
    orr_deposit_stats st = {0};
    srand(17);
    for (int done = 0; done < n; done += B) {
        int m = n - done < B ? n - done : B;
        for (int i = 0; i < m; i++) {
            double c = 2 * (rand() / (double)RAND_MAX) - 1, a = 2 * ORR_PI * (rand() / (double)RAND_MAX);
            double s = sqrt(fmax(0, 1 - c * c));
            x[i] = (float)(s * cos(a));
            y[i] = (float)(s * sin(a));
            z[i] = (float)c;
            w[i] = 1.0f;
        }
        orr_project_batch(p, (size_t)m, x, y, z, px, py, sc, vis);
        orr_deposit(kind, &plane, (size_t)m, px, py, w, vis, p, &st);
    }
    *deposited = st.deposited;
    CHECK(st.outside == 0);
    return plane;
}

static void test_hammer_aitoff_equal_area(void)
{
    /* Directions uniform on the sphere give a flat Hammer-Aitoff image: the
     * mean count per pixel is the same near the centre, near the edge and at
     * high latitude, and the scatter is Poisson. */
    orr_projection p = make(ORR_PROJ_HAMMER_AITOFF, 200, 100);
    int n = 4000000;
    double dep;
    orr_plane plane = uniform_sky(&p, n, ORR_DEPOSIT_NGP, &dep);
    CHECK_NEAR(dep, n, 0);
    double expected = n / (ORR_PI * 100 * 50); /* pixels in the ellipse: pi a b */
    double sum[3] = {0}, sum2 = 0;
    int count[3] = {0}, all = 0;
    for (int j = 0; j < 100; j++)
        for (int i = 0; i < 200; i++) {
            double u = (i + 0.5 - 100) / 100, v = (j + 0.5 - 50) / 50, r2 = u * u + v * v;
            double c = plane.data[j * 200 + i];
            if (!orr_projection_pixel_in_map(&p, i, j)) {
                CHECK(c == 0); /* nothing outside the ellipse */
                continue;
            }
            /* Skip the rim: its pixels are only partly inside the ellipse. */
            if (r2 > 0.9)
                continue;
            int region = r2 < 0.1 ? 0 : fabs(v) > 0.6 ? 2 : u * u > 0.5 ? 1 : -1;
            if (region >= 0) {
                sum[region] += c;
                count[region]++;
            }
            sum2 += (c - expected) * (c - expected);
            all++;
        }
    for (int r = 0; r < 3; r++)
        CHECK_NEAR(sum[r] / count[r], expected, 0.02 * expected);
    double rms = sqrt(sum2 / all);
    CHECK(rms < 1.15 * sqrt(expected)); /* Poisson: sqrt(mean) */
    orr_plane_free(&plane);
}

static void test_sky_deposits_lose_nothing(void)
{
    orr_projection_kind kinds[] = {ORR_PROJ_HAMMER_AITOFF, ORR_PROJ_DOME, ORR_PROJ_EQUIRECTANGULAR};
    for (int k = 0; k < 3; k++)
        for (int d = 0; d < 2; d++) {
            orr_projection p = make(kinds[k], 101, 51); /* odd sizes: no pixel centre on an axis */
            double dep;
            int n = 100000;
            orr_plane plane = uniform_sky(&p, n, d ? ORR_DEPOSIT_CIC : ORR_DEPOSIT_NGP, &dep);
            double in_map = 0, off_map = 0;
            for (int j = 0; j < p.height; j++)
                for (int i = 0; i < p.width; i++)
                    *(orr_projection_pixel_in_map(&p, i, j) ? &in_map : &off_map) += plane.data[j * p.width + i];
            CHECK(off_map == 0);
            /* The dome shows half the sky; the others all of it. */
            double want = kinds[k] == ORR_PROJ_DOME ? dep : n;
            CHECK_NEAR(in_map, want, 1e-3);
            if (kinds[k] == ORR_PROJ_DOME)
                CHECK_NEAR(dep, n / 2.0, 5 * sqrt(n / 4.0));
            orr_plane_free(&plane);
        }
}

static void test_seam_shares_both_sides(void)
{
    /* A particle exactly on the anti-centre, deposited by CIC, shares its
     * weight between the left and right ends of the equator. */
    orr_projection p = make(ORR_PROJ_HAMMER_AITOFF, 200, 100);
    float x = 0, y = 0, z = -1, w = 1, px, py, sc;
    uint8_t vis;
    orr_project_batch(&p, 1, &x, &y, &z, &px, &py, &sc, &vis);
    orr_plane plane;
    orr_error err = {0};
    CHECK(orr_plane_alloc(&plane, 200, 100, "m", "", &err) == ORR_OK);
    orr_deposit_stats st = {0};
    orr_deposit(ORR_DEPOSIT_CIC, &plane, 1, &px, &py, &w, &vis, &p, &st);
    double left = 0, right = 0;
    for (int j = 48; j < 52; j++) {
        left += plane.data[j * 200 + 0] + plane.data[j * 200 + 1];
        right += plane.data[j * 200 + 198] + plane.data[j * 200 + 199];
    }
    CHECK_NEAR(left + right, 1.0, 1e-6);
    CHECK_NEAR(orr_plane_sum(&plane), 1.0, 1e-6);
    CHECK(left > 0.2 && right > 0.2);
    /* The same in the equirectangular map, which wraps exactly. */
    orr_projection e = make(ORR_PROJ_EQUIRECTANGULAR, 200, 100);
    orr_project_batch(&e, 1, &x, &y, &z, &px, &py, &sc, &vis);
    memset(plane.data, 0, sizeof(float) * 200 * 100);
    orr_deposit(ORR_DEPOSIT_CIC, &plane, 1, &px, &py, &w, &vis, &e, &st);
    CHECK_NEAR(plane.data[49 * 200 + 0] + plane.data[50 * 200 + 0], 0.5, 1e-3);
    CHECK_NEAR(plane.data[49 * 200 + 199] + plane.data[50 * 200 + 199], 0.5, 1e-3);
    orr_plane_free(&plane);
}

static void test_fast_atan2(void)
{
    /* The projection loops' arctangent against libm's over every quadrant. */
    double worst = 0;
    for (int i = -2000; i <= 2000; i++)
        for (int j = -50; j <= 50; j++) {
            float y = (float)(i * 0.0137), x = (float)(j * 0.731);
            worst = fmax(worst, fabs(orr_atan2f(y, x) - atan2((double)y, (double)x)));
        }
    CHECK(worst < 3.5e-7); /* measured 3.05e-7, near +-pi (core/fastmath.h) */
    CHECK(orr_atan2f(0.0f, 0.0f) == 0.0f);
    CHECK_NEAR(orr_atan2f(0.0f, -1.0f), ORR_PI, 1e-6);
    CHECK_NEAR(orr_atan2f(-1.0f, 0.0f), -ORR_PI / 2, 1e-6);
}

int main(void)
{
    RUN(test_fast_atan2);
    RUN(test_hammer_aitoff_known_points);
    RUN(test_dome_known_points);
    RUN(test_equirectangular_known_points);
    RUN(test_batch_matches_single);
    RUN(test_hammer_aitoff_equal_area);
    RUN(test_sky_deposits_lose_nothing);
    RUN(test_seam_shares_both_sides);
    return check_summary();
}
