/* Writes the inputs of bench/bench_scale.sh: a Gadget-1 snapshot that both
 * orrery and SPLASH read, every particle as gas (type 0) with its own mass
 * and a smoothing length from its k-th nearest neighbour.
 *
 *   bench_snapshot pair|plummer N OUT [--k K] [--seed S]
 *
 * pair     the built-in MW-M31 model (docs/model.md; kpc, 1e10 Msun), all
 *          its components and markers, at separation 780 kpc.
 * plummer  a Plummer sphere of scale radius 1 cut at r = 10, total mass 1.
 *
 * h = 0.5 r_k (r_k: distance to the k-th neighbour, k = 32 by default), the
 * definition of orrery's `smoothing: {lengths: neighbours}` (orr_smoothing_lengths);
 * the file holds Gadget's HSML = 2h, which both programs halve back to h.
 * RHO = m (1.2 / h)^3, the SPH relation h = 1.2 (m / rho)^(1/3): SPLASH needs
 * a positive density, and its column density does not depend on it (its
 * weight m / (rho h^3) times rho; docs/splash.md). Velocities are written as
 * zero, U as one.
 *
 * Memory: positions, masses and h as float plus the k-d tree, about 45 bytes
 * a particle (450 MB at 1e7); the file is written from them in one streaming
 * pass, to OUT.tmp and renamed. Prints N, the total mass and h's range. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gadget_writer.h"
#include "particles/smoothing.h"
#include "plummer.h"
#include "source/models/model.h"

#define PLUMMER_RMAX 10.0

typedef struct particles {
    size_t n;
    float *x, *y, *z, *mass, *h;
} particles;

static void fail(const char *what)
{
    fprintf(stderr, "bench_snapshot: %s\n", what);
    exit(1);
}

static int particles_alloc(particles *p, size_t n)
{
    p->n = n;
    p->x = malloc(n * sizeof *p->x);
    p->y = malloc(n * sizeof *p->y);
    p->z = malloc(n * sizeof *p->z);
    p->mass = malloc(n * sizeof *p->mass);
    p->h = malloc(n * sizeof *p->h);
    return p->x && p->y && p->z && p->mass && p->h;
}

static void particles_free(particles *p)
{
    free(p->x);
    free(p->y);
    free(p->z);
    free(p->mass);
    free(p->h);
}

/* The built-in model, chunk by chunk, into the arrays. */
static void make_pair(particles *p, uint64_t seed)
{
    orr_model_params params = {(long long)p->n, seed, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    orr_error err = {0};
    orr_source *src = NULL;
    if (orr_model_source_open(&params, 1 << 20, &src, &err) != ORR_OK)
        fail(err.msg);
    size_t filled = 0;
    for (;;) {
        const orr_chunk *c;
        if (orr_source_next(src, &c, &err) != ORR_OK)
            fail(err.msg);
        if (c->n == 0)
            break;
        if (c->n > p->n - filled)
            fail("the model gave more particles than asked for");
        memcpy(p->x + filled, c->x, c->n * sizeof *c->x);
        memcpy(p->y + filled, c->y, c->n * sizeof *c->y);
        memcpy(p->z + filled, c->z, c->n * sizeof *c->z);
        memcpy(p->mass + filled, c->mass, c->n * sizeof *c->mass);
        filled += c->n;
    }
    orr_source_close(src);
    if (filled != p->n)
        fail("the model gave fewer particles than asked for");
}

static void make_plummer(particles *p, uint64_t seed)
{
    plummer_positions(p->n, seed, PLUMMER_RMAX, p->x, p->y, p->z);
    for (size_t i = 0; i < p->n; i++)
        p->mass[i] = (float)(1.0 / (double)p->n);
}

static void particle_at(void *user, uint64_t i, int type, gw_particle *out)
{
    const particles *p = user;
    (void)type;
    double h = p->h[i], m = p->mass[i];
    memset(out, 0, sizeof *out);
    out->pos[0] = p->x[i];
    out->pos[1] = p->y[i];
    out->pos[2] = p->z[i];
    out->id = i + 1;
    out->mass = m;
    out->u = 1.0;
    out->rho = m * pow(1.2 / h, 3.0);
    out->hsml = 2.0 * h;
}

static void write_snapshot(const char *path, particles *p)
{
    gw_spec spec = {.snapformat = 1, .blocks = GW_VEL | GW_ID | GW_U | GW_RHO | GW_HSML, .num_files = 1};
    spec.npart[0] = (int32_t)p->n;
    spec.npart_total[0] = (uint32_t)p->n;
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        fail("output path too long");
    if (gw_write(tmp, &spec, particle_at, p) != 0 || rename(tmp, path) != 0) {
        fprintf(stderr, "bench_snapshot: %s: %s\n", path, strerror(errno));
        remove(tmp);
        exit(1);
    }
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Total mass and h's minimum, median and maximum; fails if any h is not
 * positive (SPLASH divides by it, and RHO would be infinite). */
static void report(const char *path, const particles *p)
{
    double mass = 0;
    for (size_t i = 0; i < p->n; i++)
        mass += p->mass[i];
    float *sorted = malloc(p->n * sizeof *sorted);
    if (!sorted)
        fail("out of memory");
    memcpy(sorted, p->h, p->n * sizeof *sorted);
    qsort(sorted, p->n, sizeof *sorted, compare_float);
    if (!(sorted[0] > 0))
        fail("a smoothing length is zero (particles at the same position)");
    printf("wrote %zu particles to %s: total mass %.9g, h from %.4g to %.4g (median %.4g)\n", p->n, path, mass,
           (double)sorted[0], (double)sorted[p->n - 1], (double)sorted[p->n / 2]);
    free(sorted);
}

static void usage(void)
{
    fputs("usage: bench_snapshot pair|plummer N OUT [--k K] [--seed S]\n", stderr);
    exit(2);
}

int main(int argc, char **argv)
{
    if (argc < 4 || argc % 2)
        usage();
    const char *model = argv[1], *path = argv[3];
    char *end;
    double nd = strtod(argv[2], &end);
    if (*end || !(nd >= 100 && nd <= 2e9 && nd == floor(nd))) {
        fprintf(stderr, "bench_snapshot: N '%s': expected a whole number from 100 to 2e9\n", argv[2]);
        return 2;
    }
    int k = ORR_SMOOTHING_K_DEFAULT;
    uint64_t seed = 1;
    for (int i = 4; i + 1 < argc; i += 2) {
        long v = strtol(argv[i + 1], &end, 10);
        if (*end || v < 0) {
            fprintf(stderr, "bench_snapshot: %s '%s': expected a whole number >= 0\n", argv[i], argv[i + 1]);
            return 2;
        }
        if (strcmp(argv[i], "--k") == 0 && v >= 1 && v <= 1000)
            k = (int)v;
        else if (strcmp(argv[i], "--seed") == 0)
            seed = (uint64_t)v;
        else
            usage();
    }
    particles p;
    if (!particles_alloc(&p, (size_t)nd))
        fail("out of memory");
    if (strcmp(model, "pair") == 0)
        make_pair(&p, seed);
    else if (strcmp(model, "plummer") == 0)
        make_plummer(&p, seed);
    else
        usage();
    orr_error err = {0};
    if (orr_smoothing_lengths(p.n, p.x, p.y, p.z, k, ORR_SMOOTHING_FACTOR_DEFAULT, p.h, &err) != ORR_OK)
        fail(err.msg);
    report(path, &p);
    write_snapshot(path, &p);
    particles_free(&p);
    return 0;
}
