/* SPH kernels on a HEALPix map (splat/healpix_kernel.h): the ring geometry
 * against chealpix's own pixel centres, mass conserved to round-off for
 * kernels from far below a pixel to most of the sky, a tiny kernel in its
 * pixel, and a kernel's weights symmetric under the pixelisation's own
 * symmetry (a kernel at the north pole and its mirror at the south). */
#include <chealpix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/vecmath.h"
#include "splat/healpix_kernel.h"

static orr_kernel g_kernel;

static void test_rings_match_chealpix(void)
{
    for (int64_t nside = 1; nside <= 32; nside *= 2) {
        int64_t next = 0;
        double worst = 0.0;
        for (int64_t i = 1; i <= 4 * nside - 1; i++) {
            orr_healpix_ring r = orr_healpix_ring_at(nside, i);
            CHECK(r.start == next);
            next = r.start + r.n;
            for (int64_t j = 0; j < r.n; j++) {
                double v[3], phi = r.phi0 + (double)j * 2.0 * ORR_PI / (double)r.n;
                pix2vec_ring64(nside, r.start + j, v);
                double mine[3] = {r.sin_theta * cos(phi), r.sin_theta * sin(phi), r.z};
                for (int k = 0; k < 3; k++)
                    worst = fmax(worst, fabs(mine[k] - v[k]));
            }
        }
        CHECK(next == 12 * nside * nside);
        CHECK(worst < 1e-13);
    }
}

/* A map of nside, zeroed, and its total in double. */
static float *new_map(int64_t nside)
{
    return calloc((size_t)(12 * nside * nside), sizeof(float));
}

static double map_sum(const float *m, int64_t nside)
{
    double s = 0.0;
    for (int64_t k = 0; k < 12 * nside * nside; k++)
        s += m[k];
    return s;
}

static void random_dir(unsigned *seed, double d[3])
{
    double z = 2.0 * rand_r(seed) / RAND_MAX - 1.0, phi = 2.0 * ORR_PI * rand_r(seed) / RAND_MAX;
    double s = sqrt(1.0 - z * z);
    d[0] = s * cos(phi), d[1] = s * sin(phi), d[2] = z;
}

static void test_mass_conserved(void)
{
    const int64_t nside = 16;
    orr_healpix_scratch scratch = {0};
    unsigned seed = 7;
    double worst = 0.0;
    for (int nested = 0; nested < 2; nested++)
        for (double theta = 1e-7; theta < 3.0; theta *= 3.0) {
            float *m = new_map(nside);
            orr_healpix_target t = {&g_kernel, nside, nested, m, NULL};
            double d[3];
            for (int p = 0; p < 20; p++) {
                random_dir(&seed, d);
                CHECK(orr_healpix_kernel_deposit(&t, d, theta, 1.0f, &scratch));
            }
            d[0] = d[1] = 0.0, d[2] = 1.0; /* a pole, where rings shrink to 4 pixels */
            CHECK(orr_healpix_kernel_deposit(&t, d, theta, 1.0f, &scratch));
            worst = fmax(worst, fabs(map_sum(m, nside) / 21.0 - 1.0));
            free(m);
        }
    fprintf(stderr, "  mass: worst relative error %.3g\n", worst);
    CHECK(worst < 1e-6);
    orr_healpix_scratch_free(&scratch);
}

static void test_tiny_kernel_stays_in_its_pixel(void)
{
    const int64_t nside = 8;
    float *m = new_map(nside);
    orr_healpix_scratch scratch = {0};
    orr_healpix_target t = {&g_kernel, nside, 0, m, NULL};
    double d[3];
    pix2vec_ring64(nside, 300, d); /* a pixel's centre: a kernel of 1e-4 rad is far from its edges */
    CHECK(orr_healpix_kernel_deposit(&t, d, 1e-4, 2.0f, &scratch));
    CHECK_NEAR(m[300], 2.0, 1e-6);
    CHECK_NEAR(map_sum(m, nside), 2.0, 1e-6);
    orr_healpix_scratch_free(&scratch);
    free(m);
}

/* HEALPix is symmetric under z -> -z (ring i <-> 4 nside - i) and under
 * phi -> phi + pi/2: mirrored kernels must get mirrored weights. */
static void test_symmetric(void)
{
    const int64_t nside = 8;
    float *m = new_map(nside), *n = new_map(nside);
    orr_healpix_scratch scratch = {0};
    orr_healpix_target a = {&g_kernel, nside, 0, m, NULL}, b = {&g_kernel, nside, 0, n, NULL};
    double d[3] = {0.3, 0.2, 0.0};
    d[2] = sqrt(1.0 - d[0] * d[0] - d[1] * d[1]);
    double mirror[3] = {-d[1], d[0], -d[2]}; /* rotated by pi/2 and mirrored */
    CHECK(orr_healpix_kernel_deposit(&a, d, 0.15, 1.0f, &scratch));
    CHECK(orr_healpix_kernel_deposit(&b, mirror, 0.15, 1.0f, &scratch));
    double worst = 0.0, peak = 0.0;
    for (int64_t i = 1; i <= 4 * nside - 1; i++) {
        orr_healpix_ring r = orr_healpix_ring_at(nside, i), s = orr_healpix_ring_at(nside, 4 * nside - i);
        for (int64_t j = 0; j < r.n; j++) {
            int64_t jm = (j + r.n / 4) % r.n; /* phi + pi/2 */
            worst = fmax(worst, fabs(m[r.start + j] - n[s.start + jm]));
            peak = fmax(peak, m[r.start + j]);
        }
    }
    CHECK(peak > 0.01);
    CHECK(worst < 1e-6 * peak);
    orr_healpix_scratch_free(&scratch);
    free(m);
    free(n);
}

static int progress_calls;
static uint64_t progress_done;
static int64_t progress_total;

static void count_progress(void *user, uint64_t done, int64_t total)
{
    (void)user;
    progress_calls++;
    progress_done = done;
    progress_total = total;
}

/* A frame's work limit: a kernel's estimated samples (a whole-sky one's
 * are the map's pixels, a small one's the 200 to 800 sub-pixel centres of
 * healpix_kernel.h); a kernel beyond the limit is refused with nothing
 * added, and a frame foreseen far beyond it is refused at once. */
static void test_work_budget(void)
{
    const int64_t nside = 8;
    CHECK(orr_healpix_kernel_cost(nside, 2.0) == 12 * nside * nside + 1);
    uint64_t small = orr_healpix_kernel_cost(nside, 1e-3);
    CHECK(small >= 150 && small <= 1000);
    float *m = calloc((size_t)(12 * nside * nside), sizeof *m);
    orr_healpix_budget budget;
    orr_healpix_budget_start(&budget, 1000, 0);
    orr_healpix_target t = {&g_kernel, nside, 0, m, &budget};
    orr_healpix_scratch scratch = {0};
    const double dir[3] = {0, 0, 1};
    CHECK(orr_healpix_kernel_deposit(&t, dir, 2.0, 1.0f, &scratch) == 1);
    CHECK(orr_healpix_kernel_deposit(&t, dir, 2.0, 1.0f, &scratch) == -1);
    double sum = 0;
    for (int64_t p = 0; p < 12 * nside * nside; p++)
        sum += m[p];
    CHECK_NEAR(sum, 1.0, 1e-5); /* the second kernel added nothing */
    CHECK(atomic_load(&budget.exceeded) == 1 && atomic_load(&budget.particles) == 1);
    /* 100 particles at 769 samples each: 76900, far beyond 4 x 1000. */
    orr_healpix_budget_start(&budget, 1000, 100);
    CHECK(orr_healpix_budget_foresee(&budget, 769, 1) == 0 && atomic_load(&budget.exceeded) == 1);
    /* Within four times the limit: left to the limit itself. */
    orr_healpix_budget_start(&budget, 100000, 100);
    CHECK(orr_healpix_budget_foresee(&budget, 769, 1) == 1 && atomic_load(&budget.exceeded) == 0);
    /* Progress: reported at most once a second, with the kernels done so
     * far and the frame's particles (a long frame is one chunk, between
     * whose ends the render reports nothing). */
    progress_calls = 0;
    orr_healpix_budget_start(&budget, UINT64_MAX, 40);
    budget.progress = count_progress;
    atomic_store(&budget.next_report, 0); /* the second has passed */
    for (int i = 0; i < 32; i++)
        CHECK(orr_healpix_kernel_deposit(&t, dir, 1e-2, 1.0f, &scratch) == 1);
    CHECK(progress_calls == 1 && progress_done == 16 && progress_total == 40);
    orr_healpix_scratch_free(&scratch);
    free(m);
}

int main(void)
{
    orr_error err = {0};
    if (orr_kernel_init(&g_kernel, ORR_KERNEL_CUBIC, &err) != ORR_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    RUN(test_rings_match_chealpix);
    RUN(test_mass_conserved);
    RUN(test_tiny_kernel_stays_in_its_pixel);
    RUN(test_symmetric);
    RUN(test_work_budget);
    orr_kernel_free(&g_kernel);
    return check_summary();
}
