/* orrery-nbody: an example N-body code that renders itself in-situ.
 *
 * A Barnes-Hut tree code (monopole, Plummer softening, kick-drift-kick
 * leapfrog, OpenMP) evolving the built-in Milky Way-Andromeda model or a
 * Gadget snapshot (e.g. GADGET-2's galaxy-merger initial conditions), which
 * hands its particles to orrery (orrery.h) every few steps, so a scene's
 * dome master, panorama or flat views are rendered while it runs, with no
 * snapshot written: the method of Dubinski's paper. It reports the cost of
 * rendering as a fraction of the cost of gravity. docs/insitu.md.
 *
 * Built as orrery-nbody-mpi (ranks_mpi.c), it runs on MPI ranks: each rank
 * reads and owns a contiguous slice of the particles, every rank builds the
 * tree over all positions (gathered from every rank each step) and computes
 * the forces on its own slice, and the ranks render together, each handing
 * over only its own particles (orrery_use_mpi). The replicated tree is for
 * demonstration: every rank holds every position, so it does not scale to
 * billions of particles.
 *
 * Units are those of the model and of GADGET-2's examples: kpc, 1e10 solar
 * masses, km/s, so G = 43007.1 and the time unit is 0.978 Gyr. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "orrery.h"
#include "ranks.h"
#include "source/model.h"
#include "source/partition.h"
#include "source/source.h"
#include "tree.h"

#define G_KPC_KMS 43007.1

/* The particles this process owns, n of them from number first on, and the
 * positions and masses of all n_all of them, which every process holds for
 * the tree (with one process, its slice is all of them). */
typedef struct bodies {
    size_t n, first, n_all;
    double *pos_all, *mass_all; /* x, y, z of particle i at 3i */
    double *pos, *mass;         /* this process's: pos_all + 3 first, mass_all + first */
    size_t *counts;             /* every process's n, in rank order */
    double *vel, *acc;
    uint64_t *id;
    uint8_t *type;
    /* The initial conditions' other per-particle fields (the model's "r" and
     * "E0", a snapshot's potential, ...), handed to orrery unchanged every
     * frame so colours chosen by them stay with each particle for the run. */
    int nfields;
    char field_name[ORR_ARRAYS_MAX_FIELDS][ORR_FIELD_NAME_MAX];
    float *field[ORR_ARRAYS_MAX_FIELDS];
    double time;
} bodies;

typedef struct options {
    const char *ic;        /* "model" or a snapshot file */
    long long particles;   /* model particles */
    double separation;     /* model separation, kpc */
    const char *scene;     /* rendered in-situ; NULL: no rendering */
    const char *sets[32];
    int nsets;
    long steps;
    double dt, eps, theta;
    long render_every;
    int quiet;
} options;

static const char usage[] =
    "usage: orrery-nbody [--ic model|SNAPSHOT] [--particles N] [--separation KPC]\n"
    "                    [--steps N] [--dt DT] [--eps EPS] [--theta THETA]\n"
    "                    [--scene SCENE.yaml [--set KEY=VALUE ...] [--render-every K]] [--quiet]\n"
    "\n"
    "Evolves N bodies with a Barnes-Hut tree code and renders SCENE in-situ every\n"
    "K steps (frame = step / K), reporting rendering time against gravity time.\n"
    "Units: kpc, 1e10 Msun, km/s (time unit 0.978 Gyr).\n"
    "\n"
    "  --ic model|FILE    initial conditions: the built-in MW-M31 model (default) or any\n"
    "                     snapshot orrery reads (e.g. GADGET-2's galaxy_littleendian.dat)\n"
    "  --particles N      model particles (default 100000)\n"
    "  --separation KPC   model separation (default 780)\n"
    "  --steps N          leapfrog steps (default 100)\n"
    "  --dt DT            time step (default 0.002, about 2 Myr)\n"
    "  --eps EPS          Plummer softening, kpc (default 0.2)\n"
    "  --theta THETA      opening angle (default 0.6)\n"
    "  --scene FILE       the scene rendered in-situ (its input.* keys are not used)\n"
    "  --set KEY=VALUE    override a scene key (repeatable)\n"
    "  --render-every K   render every K-th step (default 1)\n";

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int parse_args(int argc, char **argv, options *o)
{
    *o = (options){.ic = "model", .particles = 100000, .separation = 780, .steps = 100, .dt = 0.002,
                   .eps = 0.2, .theta = 0.6, .render_every = 1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int has_value = 1;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(usage, stdout);
            exit(0);
        } else if (strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
            has_value = 0;
        } else if (!v) {
            fprintf(stderr, "orrery-nbody: %s needs a value\n", a);
            return 0;
        } else if (strcmp(a, "--ic") == 0) {
            o->ic = v;
        } else if (strcmp(a, "--particles") == 0) {
            o->particles = atoll(v);
        } else if (strcmp(a, "--separation") == 0) {
            o->separation = atof(v);
        } else if (strcmp(a, "--steps") == 0) {
            o->steps = atol(v);
        } else if (strcmp(a, "--dt") == 0) {
            o->dt = atof(v);
        } else if (strcmp(a, "--eps") == 0) {
            o->eps = atof(v);
        } else if (strcmp(a, "--theta") == 0) {
            o->theta = atof(v);
        } else if (strcmp(a, "--scene") == 0) {
            o->scene = v;
        } else if (strcmp(a, "--set") == 0 && o->nsets < 32) {
            o->sets[o->nsets++] = v;
        } else if (strcmp(a, "--render-every") == 0) {
            o->render_every = atol(v);
        } else {
            fprintf(stderr, "orrery-nbody: unknown option '%s'\n%s", a, usage);
            return 0;
        }
        i += has_value;
    }
    if (o->steps < 0 || !(o->dt > 0) || !(o->eps > 0) || !(o->theta > 0 && o->theta < 2) ||
        o->render_every < 1 || o->particles < 100) {
        fprintf(stderr, "orrery-nbody: --steps >= 0, --dt > 0, --eps > 0, 0 < --theta < 2, --render-every >= 1 "
                        "and --particles >= 100 are required\n");
        return 0;
    }
    return 1;
}

static int alloc_bodies(bodies *b, size_t n)
{
    b->n = n;
    b->pos = malloc(3 * n * sizeof *b->pos);
    b->vel = malloc(3 * n * sizeof *b->vel);
    b->acc = calloc(3 * n, sizeof *b->acc);
    b->mass = malloc(n * sizeof *b->mass);
    b->id = malloc(n * sizeof *b->id);
    b->type = malloc(n * sizeof *b->type);
    return b->pos && b->vel && b->acc && b->mass && b->id && b->type;
}

static void free_bodies(bodies *b)
{
    if (b->pos_all) { /* pos and mass point into them */
        b->pos = b->mass = NULL;
        free(b->pos_all);
        free(b->mass_all);
    }
    free(b->counts);
    free(b->pos);
    free(b->vel);
    free(b->acc);
    free(b->mass);
    free(b->id);
    free(b->type);
    for (int f = 0; f < b->nfields; f++)
        free(b->field[f]);
}

static int is_velocity(const char *name)
{
    return strcmp(name, "vx") == 0 || strcmp(name, "vy") == 0 || strcmp(name, "vz") == 0;
}

/* Room for every extra field of the source but the velocities, as many as
 * orr_particle_arrays can carry (the rest are dropped). */
static int alloc_fields(bodies *b, const orr_source_info *info, size_t n)
{
    for (int i = 0; i < info->nextra && b->nfields < ORR_ARRAYS_MAX_FIELDS; i++) {
        if (is_velocity(info->extra_names[i]))
            continue;
        snprintf(b->field_name[b->nfields], ORR_FIELD_NAME_MAX, "%s", info->extra_names[i]);
        if (!(b->field[b->nfields++] = malloc(n * sizeof(float))))
            return 0;
    }
    return 1;
}

/* This process's share of the initial conditions, in the order of the
 * whole: a file reader that can reads only it (source/share.h); the model
 * is made in chunks of one share each, so chunk r is rank r's. */
static orr_status open_share(const options *o, int rank, int size, orr_source **out, orr_error *err)
{
    orr_source *src = NULL;
    orr_status st;
    if (strcmp(o->ic, "model") == 0) {
        orr_model_params mp = {o->particles, 1, o->separation, ORR_MODEL_PAIR, 0};
        size_t chunk = size > 1 ? (size_t)((o->particles + size - 1) / size) : (size_t)1 << 20;
        st = orr_model_source_open(&mp, chunk, &src, err);
    } else {
        /* every field the file has */
        orr_source_options so = {.format = "auto", .chunk_size = 1 << 20, .part = rank, .nparts = size};
        st = orr_source_open_file(o->ic, &so, &src, err);
    }
    /* Passed through when the reader read only its share already. */
    return st ? st : orr_source_partition(src, rank, size, out, err);
}

/* Reads this process's particles of the initial conditions (velocities
 * required). */
static orr_status load_bodies(const options *o, int rank, int size, bodies *b, orr_error *err)
{
    orr_source *src = NULL;
    orr_status st = open_share(o, rank, size, &src, err);
    if (st)
        return st;
    if (src->info.count < 0) {
        orr_source_close(src);
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: its particle count is not known before reading it (a text table); orrery-nbody needs "
                        "initial conditions whose header gives it (Gadget, HDF5, Tipsy) or the model",
                        o->ic);
    }
    /* A rank's share may be empty; an empty snapshot is found once the
     * shares are counted. */
    size_t cap = src->info.count > 0 ? (size_t)src->info.count : 1;
    if (!alloc_bodies(b, cap) || !alloc_fields(b, &src->info, cap)) {
        orr_source_close(src);
        return orr_fail(err, ORR_ERR_NOMEM, "%s: cannot hold %zu particles", o->ic, cap);
    }
    size_t n = 0;
    for (;;) {
        const orr_chunk *c;
        if ((st = orr_source_next(src, &c, err)) || c->n == 0)
            break;
        const float *v[3] = {orr_chunk_field(c, "vx"), orr_chunk_field(c, "vy"), orr_chunk_field(c, "vz")};
        const float *field[ORR_ARRAYS_MAX_FIELDS];
        for (int f = 0; f < b->nfields; f++)
            field[f] = orr_chunk_field(c, b->field_name[f]);
        if (!v[0] || !v[1] || !v[2]) {
            st = orr_fail(err, ORR_ERR_FORMAT, "%s: no velocities (vx, vy, vz): cannot evolve it", src->info.path);
            break;
        }
        for (size_t i = 0; i < c->n && n < cap; i++, n++) {
            const float p[3] = {c->x[i], c->y[i], c->z[i]};
            for (int k = 0; k < 3; k++) {
                b->pos[3 * n + k] = p[k];
                b->vel[3 * n + k] = v[k][i];
            }
            b->mass[n] = c->mass[i];
            b->id[n] = c->id[i];
            b->type[n] = c->type[i];
            for (int f = 0; f < b->nfields; f++)
                b->field[f][n] = field[f] ? field[f][i] : 0.0f;
        }
    }
    b->n = n;
    b->time = src->info.time;
    orr_source_close(src);
    return st;
}

/* Gives every process every position and mass: the slices in rank order,
 * this process's at b->first. */
static int share_bodies(bodies *b, int rank, int size)
{
    b->counts = calloc((size_t)size, sizeof *b->counts);
    if (!b->counts || ranks_counts(b->n, b->counts) != 0)
        return 0;
    b->n_all = b->first = 0;
    for (int r = 0; r < size; r++) {
        b->first += r < rank ? b->counts[r] : 0;
        b->n_all += b->counts[r];
    }
    double *pos_all = malloc((3 * b->n_all + 1) * sizeof *pos_all);
    double *mass_all = malloc((b->n_all + 1) * sizeof *mass_all);
    int failed = !pos_all || !mass_all;
    if (failed)
        fprintf(stderr, "orrery-nbody: out of memory for %zu positions\n", b->n_all);
    if (ranks_any(failed)) { /* before the gathers, which every process must join */
        free(pos_all);
        free(mass_all);
        return 0;
    }
    memcpy(pos_all + 3 * b->first, b->pos, 3 * b->n * sizeof *b->pos);
    memcpy(mass_all + b->first, b->mass, b->n * sizeof *b->mass);
    free(b->pos);
    free(b->mass);
    b->pos_all = pos_all;
    b->mass_all = mass_all;
    b->pos = pos_all + 3 * b->first;
    b->mass = mass_all + b->first;
    return ranks_gather(b->pos_all, 3, b->counts) == 0 && ranks_gather(b->mass_all, 1, b->counts) == 0;
}

/* The particles as orrery reads them, in place: positions and velocities
 * are arrays of [x, y, z] doubles. */
static orr_particle_arrays as_arrays(const bodies *b)
{
    orr_particle_arrays p = {0};
    p.n = b->n;
    p.x = (orr_array){&b->pos[0], ORR_F64, 3 * sizeof(double)};
    p.y = (orr_array){&b->pos[1], ORR_F64, 3 * sizeof(double)};
    p.z = (orr_array){&b->pos[2], ORR_F64, 3 * sizeof(double)};
    p.vx = (orr_array){&b->vel[0], ORR_F64, 3 * sizeof(double)};
    p.vy = (orr_array){&b->vel[1], ORR_F64, 3 * sizeof(double)};
    p.vz = (orr_array){&b->vel[2], ORR_F64, 3 * sizeof(double)};
    p.mass = (orr_array){b->mass, ORR_F64, 0};
    p.id = b->id;
    p.type = b->type;
    p.time = b->time;
    p.nfields = b->nfields;
    for (int f = 0; f < b->nfields; f++) {
        p.field_names[f] = b->field_name[f];
        p.fields[f] = (orr_array){b->field[f], ORR_F32, 0};
    }
    return p;
}

/* The accelerations of this process's particles, from a tree over all. */
static double gravity(bh_tree *t, bodies *b, const options *o, double *interactions)
{
    double t0 = now();
    if (bh_build(t, b->pos_all, b->mass_all, b->n_all) != 0) {
        fprintf(stderr, "orrery-nbody: out of memory building the tree\n");
        exit(1);
    }
    *interactions =
        bh_accelerations_of(t, b->pos_all, b->mass_all, G_KPC_KMS, o->eps, o->theta, b->first, b->n, b->acc);
    return now() - t0;
}

static void kick(bodies *b, double dt)
{
    for (size_t i = 0; i < 3 * b->n; i++)
        b->vel[i] += b->acc[i] * dt;
}

/* Moves this process's particles, then gathers every process's. */
static int drift(bodies *b, double dt)
{
    for (size_t i = 0; i < 3 * b->n; i++)
        b->pos[i] += b->vel[i] * dt;
    b->time += dt;
    return ranks_gather(b->pos_all, 3, b->counts);
}

static int render(orrery_renderer *r, const bodies *b, long frame, double *seconds)
{
    orr_particle_arrays p = as_arrays(b);
    int st = orrery_render(r, &p, frame);
    *seconds = orrery_render_seconds(r);
    if (st != ORRERY_OK)
        fprintf(stderr, "orrery-nbody: rendering frame %ld: %s\n", frame, orrery_error(r));
    return st;
}

/* Loads this process's particles and shares the positions; whether every
 * process succeeded (each prints its own error). */
static int start_bodies(const options *o, int rank, int size, bodies *b)
{
    orr_error err = {0};
    int ok = load_bodies(o, rank, size, b, &err) == ORR_OK;
    if (!ok)
        fprintf(stderr, "orrery-nbody: %s\n", err.msg);
    if (ranks_any(!ok) || !share_bodies(b, rank, size))
        return 0;
    if (b->n_all == 0) {
        if (rank == 0)
            fprintf(stderr, "orrery-nbody: %s: no particles\n", o->ic);
        return 0;
    }
    return 1;
}

/* Opens the scene on every process, rendering together when there are
 * several; 0 (NULL renderer) without a scene, else an exit status. */
static int open_renderer(const options *o, int size, orrery_renderer **r)
{
    char msg[1024];
    int code = 0;
    if (o->scene && orrery_open(r, o->scene, o->sets, o->nsets, msg, sizeof msg) != ORRERY_OK) {
        fprintf(stderr, "orrery-nbody: %s\n", msg);
        code = 2;
    }
    if (!code && *r && size > 1 && ranks_render_together(*r) != ORRERY_OK) {
        fprintf(stderr, "orrery-nbody: %s\n", orrery_error(*r));
        code = 1;
    }
    return ranks_any(code) && !code ? 1 : code;
}

int main(int argc, char **argv)
{
    int rank, size;
    ranks_start(&argc, &argv, &rank, &size);
    options o;
    if (!parse_args(argc, argv, &o)) {
        ranks_finish();
        return 2;
    }
    o.quiet |= rank != 0; /* rank 0 reports for all */
    bodies b = {0};
    orrery_renderer *r = NULL;
    int code = start_bodies(&o, rank, size, &b) ? open_renderer(&o, size, &r) : 1;
    if (code) {
        orrery_close(r);
        free_bodies(&b);
        ranks_finish();
        return code;
    }
    if (!o.quiet)
        printf("%zu bodies from %s on %d process%s, t = %g, dt = %g, eps = %g, theta = %g\n", b.n_all, o.ic, size,
               size > 1 ? "es" : "", b.time, o.dt, o.eps, o.theta);
    bh_tree tree = {0};
    double interactions, t_gravity = 0, t_render = 0, seconds;
    t_gravity += gravity(&tree, &b, &o, &interactions);
    long frames = 0;
    if (r && (code = render(r, &b, frames++, &seconds)) == 0)
        t_render += seconds;
    for (long step = 1; step <= o.steps && code == 0; step++) {
        kick(&b, 0.5 * o.dt);
        if (drift(&b, o.dt) != 0) {
            code = 1;
            break;
        }
        double tg = gravity(&tree, &b, &o, &interactions);
        t_gravity += tg;
        kick(&b, 0.5 * o.dt);
        double tr = 0;
        if (r && step % o.render_every == 0 && (code = render(r, &b, frames++, &tr)) == 0)
            t_render += tr;
        if (!o.quiet)
            printf("step %ld  t = %.4f  gravity %.3f s (%.3g interactions/s)  render %.3f s\n", step, b.time, tg,
                   interactions / (tg > 0 ? tg : 1e-9), tr);
    }
    if (!o.quiet && code == 0) {
        printf("gravity %.2f s over %ld force evaluations; rendering %.2f s over %ld frames\n", t_gravity,
               o.steps + 1, t_render, frames);
        if (r && frames > 0)
            printf("rendering per frame = %.1f%% of gravity per step\n",
                   100.0 * (t_render / frames) / (t_gravity / (double)(o.steps + 1)));
    }
    orrery_close(r);
    bh_free(&tree);
    free_bodies(&b);
    ranks_finish();
    return code ? 1 : 0;
}
