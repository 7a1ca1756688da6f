/* The in-situ API on MPI ranks: each rank hands over its share of the
 * particles, and the frame rank 0 writes equals (to float round-off) the
 * frame one process renders from all of them, the observer particle living
 * on the last rank; and the plane reduction's sums are exact. Run under
 * mpirun with any number of ranks. */
#include <math.h>
#include <mpi.h>
#include <stdlib.h>

#include "check.h"
#include "fits_image.h"
#include "mpi/mpi_parallel.h"
#include "mpi/orrery_mpi.h"

#define N 20000

static double pos[N][3];
static float mass[N];
static uint64_t ids[N];

static void make_particles(void)
{
    srand(5);
    for (int i = 0; i < N; i++) {
        for (int k = 0; k < 3; k++)
            pos[i][k] = 20.0 * rand() / RAND_MAX - 10.0;
        mass[i] = 1.0f + (float)(i % 7);
        ids[i] = (uint64_t)i + 100;
    }
    /* The observer (id 1) and the reference (id 2) among them. */
    ids[N - 1] = 1;
    pos[N - 1][0] = pos[N - 1][1] = pos[N - 1][2] = 0.5;
    ids[N - 2] = 2;
    pos[N - 2][0] = 8;
}

/* Particles first..last-1, as orrery reads them in place. */
static orr_particle_arrays share(int first, int last)
{
    orr_particle_arrays p = {0};
    p.n = (size_t)(last - first);
    p.x = (orr_array){&pos[first][0], ORR_F64, sizeof pos[0]};
    p.y = (orr_array){&pos[first][1], ORR_F64, sizeof pos[0]};
    p.z = (orr_array){&pos[first][2], ORR_F64, sizeof pos[0]};
    p.mass = (orr_array){&mass[first], ORR_F32, 0};
    p.id = &ids[first];
    p.time = 1.5;
    return p;
}

static const char *const scenes[2] = {
    "camera: {projection: orthographic, width: 24}\nimage: {width: 48, height: 40}\noutput: {png: false}\n",
    "observer: {id: 1, reference_id: 2}\ncamera: {projection: hammer-aitoff}\nimage: {width: 64, height: 32}\n"
    "output: {png: false}\n",
};

/* The plane reduction in groups smaller than the plane and than the
 * ranks, with a last group cut short: small integers, so the sums are
 * exact whatever the order. */
static void test_reduce_plane(int rank, int nranks)
{
    const size_t sizes[] = {1000, 7, 1};
    const size_t groups[] = {64, 2, 1000};
    for (int s = 0; s < 3; s++)
        for (int g = 0; g < 3; g++) {
            size_t n = sizes[s];
            float *v = malloc(n * sizeof *v);
            CHECK(v != NULL);
            if (!v)
                return;
            for (size_t i = 0; i < n; i++)
                v[i] = (float)(rank + 1 + (int)(i % 7));
            orr_error err;
            CHECK(orr_mpi_reduce_plane(MPI_COMM_WORLD, v, n, groups[g], &err) == ORR_OK);
            if (rank == 0) {
                size_t bad = 0;
                for (size_t i = 0; i < n; i++)
                    bad += v[i] != (float)(nranks * (nranks + 1) / 2 + nranks * (int)(i % 7));
                CHECK(bad == 0);
            }
            free(v);
        }
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, nranks;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &nranks);
    make_particles();
    test_reduce_plane(rank, nranks);
    for (int k = 0; k < 2; k++) {
        char dir_mpi[64], dir_one[64], msg[1024];
        snprintf(dir_mpi, sizeof dir_mpi, "output.dir=insitu-mpi-%d", k);
        snprintf(dir_one, sizeof dir_one, "output.dir=insitu-one-%d", k);
        const char *set_mpi[1] = {dir_mpi}, *set_one[1] = {dir_one};
        orrery_renderer *r = NULL;
        CHECK(orrery_open_yaml(&r, scenes[k], ".", set_mpi, 1, msg, sizeof msg) == ORRERY_OK);
        CHECK(r && orrery_use_mpi(r, MPI_COMM_WORLD) == ORRERY_OK);
        /* Rank j takes an uneven slice; the last rank holds the observer. */
        int first = (int)((long)N * rank / nranks), last = (int)((long)N * (rank + 1) / nranks);
        orr_particle_arrays mine = share(first, last);
        CHECK(orrery_render(r, &mine, 3) == ORRERY_OK);
        if (rank != 0)
            CHECK(orrery_output_count(r) == 0);
        orrery_close(r);
        if (rank == 0) {
            CHECK(orrery_open_yaml(&r, scenes[k], ".", set_one, 1, msg, sizeof msg) == ORRERY_OK);
            orr_particle_arrays all = share(0, N);
            CHECK(r && orrery_render(r, &all, 3) == ORRERY_OK);
            orrery_close(r);
            char a_path[128], b_path[128];
            snprintf(a_path, sizeof a_path, "insitu-mpi-%d/insitu_0003.fits", k);
            snprintf(b_path, sizeof b_path, "insitu-one-%d/insitu_0003.fits", k);
            long na = 0, nb = 0;
            float *a = read_fits_image(a_path, &na), *b = read_fits_image(b_path, &nb);
            CHECK(a && b && na == nb && na > 0);
            double max = 0, diff = 0, sum_a = 0, sum_b = 0;
            for (long i = 0; a && b && i < na; i++) {
                if (isnan(a[i]) || isnan(b[i])) { /* outside a sky map: blank in both */
                    CHECK(isnan(a[i]) && isnan(b[i]));
                    continue;
                }
                max = fmax(max, fabs(b[i]));
                diff = fmax(diff, fabs(a[i] - b[i]));
                sum_a += a[i];
                sum_b += b[i];
            }
            CHECK(max > 0);
            CHECK(diff <= 1e-5 * max);
            CHECK_NEAR(sum_a, sum_b, 1e-6 * sum_b);
            fprintf(stderr, "scene %d, %d ranks: max |difference| %.3g of max %.3g\n", k, nranks, diff, max);
            free(a);
            free(b);
        }
    }
    int failed = check_summary(), any = 0;
    MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return any;
}
