/* orrery-nbody: an example N-body code that renders itself in-situ.
 *
 * A tree code (quadrupole moments, walks shared by groups of nearby
 * particles, per-component Plummer softening, kick-drift-kick leapfrog,
 * OpenMP; qtree.h) evolving the built-in Milky Way-Andromeda model (or one
 * galaxy alone) or a Gadget snapshot (e.g. GADGET-2's galaxy-merger initial conditions), which
 * hands its particles to orrery (orrery.h) every few steps, so a scene's
 * dome master, panorama or flat views are rendered while it runs, with no
 * snapshot written: the method of Dubinski's paper. It reports the cost of
 * rendering as a fraction of the cost of gravity. docs/insitu.md. It can
 * also write Gadget-layout HDF5 snapshots every K steps and resume a run
 * from the newest bit for bit (snapshot.h, docs/nbody.md).
 *
 * Built as orrery-nbody-mpi (ranks_mpi.c), it runs on MPI ranks: each rank
 * reads and owns a contiguous slice of the particles, every rank builds the
 * tree over all positions (gathered from every rank each step) and computes
 * the forces on its own slice, and the ranks render together, each handing
 * over only its own particles (orrery_use_mpi). That replicated tree holds
 * every position on every rank; with --decompose each rank holds only its
 * own particles, a piece of a Peano-Hilbert curve, and exchanges the parts
 * of the trees the others need (domain.h).
 *
 * Units are those of the model and of GADGET-2's examples: kpc, 1e10 solar
 * masses, km/s, so G = 43007.1 and the time unit is 0.978 Gyr. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "orrery.h"
#include "bodies.h"
#include "domain.h"
#include "ranks.h"
#include "source/models/model.h"
#include "source/partition.h"
#include "source/source.h"
#include "core/atomic.h"
#include "core/digest.h"
#include "phase_mix.h"
#include "qtree.h"
#include "snapshot.h"
#include "tracer_ring.h"

#define G_KPC_KMS 43007.1
/* The longest --dt accepted: one time unit, 0.978 Gyr, nearly five times
 * the Sun's orbital period (0.21 Gyr); a longer step follows no orbit in a galaxy. */
#define DT_MAX 1.0
/* A tracer is lighter than this fraction of the mean particle mass. */
#define TRACER_MASS_FRACTION 1e-3
#define TRACER_NEIGHBOURS_MAX 256
/* The longest --phase-mix accepted: two time units, 14 of the Sun's
 * epicycles; mixing longer changes nothing more. */
#define PHASE_MIX_MAX 2.0


typedef struct options {
    const char *ic;        /* "model" or a snapshot file */
    long long particles;   /* model particles */
    double separation;     /* model separation, kpc */
    int galaxies;          /* model: ORR_MODEL_PAIR, _MW or _M31 */
    double disc_q;         /* model: the discs' Toomre Q */
    double m31_weight;     /* model: M31's particles over the Milky Way's of the same kind */
    double phase_mix;      /* a new run's disc stars moved along their orbits for up to this long (phase_mix.h) */
    const char *model_option; /* the first of the model's options given (--particles ... --m31-weight), or NULL */
    const char *scene;     /* rendered in-situ; NULL: no rendering */
    const char *sets[32];
    int nsets;
    long steps;
    double dt, eps, eps_halo, theta;
    double eta;            /* block time steps' accuracy; 0: one global step --dt */
    double dt_min;         /* block time steps are never shorter (0: down to dt / 2^MAX_LEVEL) */
    int eps_halo_given;    /* --eps-halo given; else it is 2 x --eps */
    long render_every, report_every;
    double progress;       /* seconds between progress lines on stderr; 0: none */
    long tracer_neighbours; /* tracers' softening: their k-th neighbour's distance; 0: as stars */
    long tracer_ring;      /* tracers' pull averaged over this many points around their galaxy; 0: off */
    long tracer_mirror;    /* 1: half the ring's points mirrored across the disc's plane (tracer_ring.h) */
    int tracer_start;      /* a new run's ring tracers started on the ring's circular orbit (1) or as given (0);
                            * -1: not said (circular with --tracer-ring) */
    int quiet;
    long snapshot_every;      /* 0: no snapshots */
    const char *snapshot_every_text; /* as given */
    const char *snapshot_dir; /* NULL: --resume's folder */
    const char *resume_dir;   /* NULL: a new run */
    /* Given on the command line; on a resume the others are the run's own. */
    int ic_given, dt_given, eps_given, theta_given, snapshot_every_given, eta_given, tracer_neighbours_given;
    int dt_min_given, tracer_ring_given, tracer_mirror_given;
    int decompose;         /* each MPI rank holds its own particles only (domain.h) */
} options;

static const char usage[] =
    "usage: orrery-nbody [--ic model|SNAPSHOT] [--particles N] [--separation KPC]\n"
    "                    [--galaxies pair|mw|m31] [--disc-q Q] [--m31-weight W]\n"
    "                    [--phase-mix T]\n"
    "                    [--steps N] [--dt DT] [--eta ETA] [--dt-min DT] [--eps EPS]\n"
    "                    [--eps-halo EPS] [--theta THETA] [--tracer-neighbours K]\n"
    "                    [--tracer-ring K [--tracer-mirror]] [--tracer-start circular|given]\n"
    "                    [--scene SCENE.yaml [--set KEY=VALUE ...] [--render-every K]]\n"
    "                    [--report-every K] [--snapshot-every K --snapshot-dir DIR]\n"
    "                    [--resume DIR] [--progress SECONDS] [--decompose] [--quiet]\n"
    "\n"
    "Evolves N bodies with a tree code (quadrupole moments, group walks) and renders\n"
    "SCENE in-situ every K steps (frame = step / K), reporting rendering time against\n"
    "gravity time, and energy, momentum and the structure of an isolated galaxy.\n"
    "Units: kpc, 1e10 Msun, km/s (time unit 0.978 Gyr). docs/nbody.md.\n"
    "\n"
    "  --ic model|FILE    initial conditions: the built-in MW-M31 model (default) or any\n"
    "                     snapshot orrery reads (e.g. GADGET-2's galaxy_littleendian.dat);\n"
    "                     the model's options below (--particles to --m31-weight) are\n"
    "                     errors with a FILE or --resume, which bring their own particles\n"
    "  --particles N      model particles (default 100000)\n"
    "  --separation KPC   model separation (default 780)\n"
    "  --galaxies WHICH   model: both (pair, default), or the Milky Way (mw) or M31 alone\n"
    "  --disc-q Q         model: the discs' Toomre Q (default 1.5)\n"
    "  --m31-weight W     model, pair: each of M31's particles weighs W times the Milky\n"
    "                     Way's of the same kind, so the Milky Way gets more of the N\n"
    "                     particles (default 1; from 1/64 to 64; docs/model.md)\n"
    "  --phase-mix T      before a new run, move every disc star along its orbit in its\n"
    "                     galaxy's axisymmetric pull for a time from 0 to T drawn from\n"
    "                     its id, so the disc starts in a steady state instead of\n"
    "                     breathing (default 0: off; at most 2; 0.5 is 3.5 of the\n"
    "                     Sun's epicycles; docs/nbody.md)\n"
    "  --steps N          leapfrog steps of --dt (default 100)\n"
    "  --dt DT            time step (default 0.001, about 1 Myr; with --eta the longest)\n"
    "  --eta ETA          block time steps: particle i takes the longest step dt / 2^k\n"
    "                     (k <= 10) at most sqrt(2 ETA eps_i / |a_i|) (Gadget-2's\n"
    "                     criterion; 0.025 there; a longer step than its last only\n"
    "                     when it wants twice it), and gets forces only when its step\n"
    "                     ends (default: one global step --dt for all; at the films'\n"
    "                     --eps 0.2, --dt 0.008 --eta 0.25 --dt-min 0.002 takes 0.6 of\n"
    "                     the CPU of --dt 0.002, for a smaller energy error)\n"
    "  --dt-min DT        with --eta, no step shorter than DT (the shortest dt / 2^k at\n"
    "                     least DT; Gadget-2's MinSizeTimestep; default: none); tracers\n"
    "                     (below) then always take that shortest step\n"
    "  --eps EPS          Plummer softening of stars, black holes and gas, kpc (default 0.05)\n"
    "  --eps-halo EPS     Plummer softening of dark-matter (type 1) particles (default 2 x --eps)\n"
    "  --theta THETA      opening angle, 0 to 1 (default 0.7: 99% of forces within 1%)\n"
    "  --tracer-neighbours K  tracers (particles lighter than 1/1000 of the mean, e.g.\n"
    "                     the model's Sun) feel forces softened at the distance of their\n"
    "                     K-th nearest other particle, found anew every step (default\n"
    "                     32; 0: softened as stars)\n"
    "  --tracer-ring K    tracers feel their galaxy's pull averaged over K points on the\n"
    "                     ring through them about its axis (centred on the nearest black\n"
    "                     hole's stars), plus its centre's own acceleration: no torque\n"
    "                     from spirals or bar, so they keep their radius; the tree's pull\n"
    "                     while another black hole is within twice their distance of\n"
    "                     their own (default 0: off; 2 to 256; docs/nbody.md)\n"
    "  --tracer-mirror    with --tracer-ring K (K even): every other point of the ring\n"
    "                     is reflected across the galaxy's disc plane and its pull\n"
    "                     reflected back, so tracers feel a galaxy the same above and\n"
    "                     below its plane: its bending and warps do not lift them\n"
    "                     (default: off; a resume keeps the run's own)\n"
    "  --tracer-start HOW a new run's ring tracers start on the circular orbit of the\n"
    "                     ring's pull at their place, sqrt(R a_R) about their galaxy's\n"
    "                     axis and its stars' mean velocity (circular: the default with\n"
    "                     --tracer-ring), or as the initial conditions give them (given)\n"
    "  --report-every K   energy, momentum and structure every K steps (default 10)\n"
    "  --progress SECONDS a progress line on stderr at most every SECONDS (default 10;\n"
    "                     0: none), also with --quiet: step, time, energy error,\n"
    "                     particle-steps per second, time left\n"
    "  --scene FILE       the scene rendered in-situ (its input.* keys are not used)\n"
    "  --set KEY=VALUE    override a scene key (repeatable)\n"
    "  --render-every K   render every K-th step (default 1)\n"
    "  --snapshot-every K write DIR/snapshot_NNNN.hdf5 (Gadget-layout HDF5, which orrery\n"
    "                     renders) at step 0 and every K steps; each is written to a\n"
    "                     temporary name and renamed when complete\n"
    "  --snapshot-dir DIR where snapshots go (created if missing; default: --resume's DIR)\n"
    "  --resume DIR       continue from DIR's newest snapshot, bit for bit as if never\n"
    "                     stopped: its time and step, and its --dt, --eta, --dt-min,\n"
    "                     --eps, --eps-halo, --theta and --snapshot-every unless given;\n"
    "                     --steps counts from the start of the run, not of the resume\n"
    "  --decompose        each MPI rank holds only its own particles: a piece of a\n"
    "                     Peano-Hilbert curve, the particles moved between ranks every\n"
    "                     step; forces from each rank's tree and what the others send\n"
    "                     of theirs; snapshots one file a rank (snapshot_NNNN.R.hdf5)\n"
    "On MPI ranks, rank 0 writes the snapshots (gathered from every rank), and on a\n"
    "resume every rank reads the snapshot and keeps an even share of it; with\n"
    "--decompose each rank writes and reads its own files instead.\n";

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A number, or NaN (which every check below refuses) when it is not one. */
static double parse_number(const char *v)
{
    char *end;
    double d = strtod(v, &end);
    return end == v || *end ? NAN : d;
}

/* A whole number, or -1 (which the checks refuse) when it is not one. */
static long parse_count(const char *v)
{
    char *end;
    long n = strtol(v, &end, 10);
    return end == v || *end ? -1 : n;
}

static int parse_galaxies(const char *v, int *out)
{
    if ((*out = orr_model_galaxies_named(v)) >= 0)
        return 1;
    fprintf(stderr, "orrery-nbody: --galaxies %s: expected " ORR_MODEL_GALAXIES_WORDS "\n", v);
    return 0;
}

static int parse_tracer_start(const char *v, int *out)
{
    if (strcmp(v, "circular") == 0 || strcmp(v, "given") == 0) {
        *out = v[0] == 'c';
        return 1;
    }
    fprintf(stderr, "orrery-nbody: --tracer-start %s: expected circular or given\n", v);
    return 0;
}

/* Each bad value is named, with what it must be. */
static int check_options(const options *o)
{
    const char *bad = NULL;
    char why[512] = "";
    if (!(o->dt > 0) || !isfinite(o->dt))
        bad = "--dt", snprintf(why, sizeof why, "%g: the time step must be a number above 0", o->dt);
    else if (o->dt > DT_MAX)
        bad = "--dt", snprintf(why, sizeof why, "%g: longer than %g time unit (%.3g Gyr): no orbit could be followed",
                               o->dt, DT_MAX, 0.978 * DT_MAX);
    else if (o->eta_given && (!(o->eta > 0) || !isfinite(o->eta)))
        bad = "--eta", snprintf(why, sizeof why, "%g: the time-step accuracy must be a number above 0 (Gadget-2: 0.025)",
                                o->eta);
    else if (o->dt_min_given && (!(o->dt_min > 0) || !(o->dt_min <= o->dt)))
        bad = "--dt-min", snprintf(why, sizeof why, "%g: the shortest block step must be above 0 and at most --dt %g",
                                   o->dt_min, o->dt);
    else if (!(o->eps > 0) || !isfinite(o->eps))
        bad = "--eps", snprintf(why, sizeof why, "%g: the softening must be a length above 0 (kpc)", o->eps);
    else if (!(o->eps_halo > 0) || !isfinite(o->eps_halo))
        bad = "--eps-halo", snprintf(why, sizeof why, "%g: the softening must be a length above 0 (kpc)", o->eps_halo);
    else if (!(o->theta > 0 && o->theta <= 1))
        bad = "--theta", snprintf(why, sizeof why, "%g: the opening angle must be above 0 and at most 1", o->theta);
    else if (!(o->disc_q > 0) || !isfinite(o->disc_q))
        bad = "--disc-q", snprintf(why, sizeof why, "%g: Toomre's Q must be above 0", o->disc_q);
    else if (!(o->m31_weight >= 1.0 / ORR_MODEL_M31_WEIGHT_MAX && o->m31_weight <= ORR_MODEL_M31_WEIGHT_MAX))
        bad = "--m31-weight", snprintf(why, sizeof why, "%g: expected how many times the Milky Way's particles each "
                                       "of M31's weighs, from %g to %g", o->m31_weight,
                                       1.0 / ORR_MODEL_M31_WEIGHT_MAX, ORR_MODEL_M31_WEIGHT_MAX);
    else if (!(o->phase_mix >= 0 && o->phase_mix <= PHASE_MIX_MAX))
        bad = "--phase-mix", snprintf(why, sizeof why, "%g: expected a time from 0 (off) to %g time units", o->phase_mix,
                                      PHASE_MIX_MAX);
    else if (o->phase_mix > 0 && o->resume_dir)
        bad = "--phase-mix", snprintf(why, sizeof why, "mixes a new run's discs before its first step: not with "
                                                       "--resume (the snapshot's discs are as the run left them)");
    else if (o->steps < 0)
        bad = "--steps", snprintf(why, sizeof why, "%ld: must be at least 0", o->steps);
    else if (o->render_every < 1)
        bad = "--render-every", snprintf(why, sizeof why, "%ld: must be at least 1", o->render_every);
    else if (!(o->progress >= 0) || !isfinite(o->progress))
        bad = "--progress", snprintf(why, sizeof why, "%g: expected seconds, at least 0 (0: no progress lines)",
                                     o->progress);
    else if (o->tracer_neighbours < 0 || o->tracer_neighbours > TRACER_NEIGHBOURS_MAX)
        bad = "--tracer-neighbours", snprintf(why, sizeof why, "%ld: expected 0 (off) to %d", o->tracer_neighbours,
                                              TRACER_NEIGHBOURS_MAX);
    else if (o->tracer_ring != 0 && (o->tracer_ring < 2 || o->tracer_ring > RING_POINTS_MAX))
        bad = "--tracer-ring", snprintf(why, sizeof why, "%ld: expected 0 (off) or 2 to %d points", o->tracer_ring,
                                        RING_POINTS_MAX);
    else if (o->tracer_mirror && (!o->tracer_ring || o->tracer_ring % 2))
        bad = "--tracer-mirror", snprintf(why, sizeof why, "needs --tracer-ring K with K even: it mirrors every other "
                                                           "point (K = %ld)", o->tracer_ring);
    else if (o->tracer_start > 0 && !o->tracer_ring)
        bad = "--tracer-start", snprintf(why, sizeof why, "circular: the circular speed is the ring's pull: needs "
                                                          "--tracer-ring K");
    else if (o->report_every < 1)
        bad = "--report-every", snprintf(why, sizeof why, "%ld: must be at least 1", o->report_every);
    else if (o->particles < 100)
        bad = "--particles", snprintf(why, sizeof why, "%lld: the model needs at least 100", o->particles);
    else if (o->snapshot_every < 0)
        bad = "--snapshot-every",
        snprintf(why, sizeof why, "%s: expected a whole number of steps, at least 1", o->snapshot_every_text);
    else if (o->snapshot_every > 0 && !o->snapshot_dir && !o->resume_dir)
        bad = "--snapshot-every", snprintf(why, sizeof why, "needs --snapshot-dir DIR (where to write them)");
    else if (o->resume_dir && o->ic_given)
        bad = "--resume", snprintf(why, sizeof why, "%s: the initial conditions are the snapshot's: not with --ic",
                                   o->resume_dir);
    else if (o->model_option && (o->resume_dir || strcmp(o->ic, "model") != 0))
        bad = o->model_option,
        snprintf(why, sizeof why, "shapes the built-in model: not with %s %s, whose particles are the run's",
                 o->resume_dir ? "--resume" : "--ic", o->resume_dir ? o->resume_dir : o->ic);
    if (bad)
        fprintf(stderr, "orrery-nbody: %s %s\n", bad, why);
    return bad == NULL;
}

/* The model's options shape the built-in model only: given with a file
 * or a resumed run's snapshots they would change nothing, so they are an
 * error there (check_options), named by the first given. */
static void note_model_option(options *o, const char *name)
{
    if (!o->model_option)
        o->model_option = name;
}

static int parse_args(int argc, char **argv, options *o)
{
    *o = (options){.ic = "model", .particles = 100000, .separation = 780, .disc_q = ORR_MODEL_DISC_Q_DEFAULT, .m31_weight = 1,
                   .steps = 100, .dt = 0.001, .eps = 0.05, .theta = 0.7, .render_every = 1,
                   .report_every = 10, .progress = 10, .tracer_neighbours = 32, .tracer_start = -1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int has_value = 1;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(usage, stdout);
            exit(0);
        } else if (strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
            has_value = 0;
        } else if (strcmp(a, "--decompose") == 0) {
            o->decompose = 1;
            has_value = 0;
        } else if (strcmp(a, "--tracer-mirror") == 0) {
            o->tracer_mirror = 1;
            o->tracer_mirror_given = 1;
            has_value = 0;
        } else if (!v) {
            fprintf(stderr, "orrery-nbody: %s needs a value\n", a);
            return 0;
        } else if (strcmp(a, "--ic") == 0) {
            o->ic = v;
            o->ic_given = 1;
        } else if (strcmp(a, "--snapshot-every") == 0) {
            o->snapshot_every = parse_count(v);
            o->snapshot_every = o->snapshot_every ? o->snapshot_every : -1; /* 0 is not a period */
            o->snapshot_every_text = v;
            o->snapshot_every_given = 1;
        } else if (strcmp(a, "--snapshot-dir") == 0) {
            o->snapshot_dir = v;
        } else if (strcmp(a, "--resume") == 0) {
            o->resume_dir = v;
        } else if (strcmp(a, "--particles") == 0) {
            o->particles = atoll(v);
            note_model_option(o, a);
        } else if (strcmp(a, "--separation") == 0) {
            o->separation = atof(v);
            note_model_option(o, a);
        } else if (strcmp(a, "--galaxies") == 0) {
            if (!parse_galaxies(v, &o->galaxies))
                return 0;
            note_model_option(o, a);
        } else if (strcmp(a, "--disc-q") == 0) {
            o->disc_q = parse_number(v);
            note_model_option(o, a);
        } else if (strcmp(a, "--m31-weight") == 0) {
            o->m31_weight = parse_number(v);
            note_model_option(o, a);
        } else if (strcmp(a, "--phase-mix") == 0) {
            o->phase_mix = parse_number(v);
        } else if (strcmp(a, "--eps-halo") == 0) {
            o->eps_halo = parse_number(v);
            o->eps_halo_given = 1;
        } else if (strcmp(a, "--tracer-neighbours") == 0) {
            o->tracer_neighbours = parse_count(v);
            o->tracer_neighbours_given = 1;
        } else if (strcmp(a, "--tracer-ring") == 0) {
            o->tracer_ring = parse_count(v);
            o->tracer_ring_given = 1;
        } else if (strcmp(a, "--tracer-start") == 0) {
            if (!parse_tracer_start(v, &o->tracer_start))
                return 0;
        } else if (strcmp(a, "--progress") == 0) {
            o->progress = parse_number(v);
        } else if (strcmp(a, "--report-every") == 0) {
            o->report_every = atol(v);
        } else if (strcmp(a, "--steps") == 0) {
            o->steps = atol(v);
        } else if (strcmp(a, "--dt") == 0) {
            o->dt = parse_number(v);
            o->dt_given = 1;
        } else if (strcmp(a, "--eta") == 0) {
            o->eta = parse_number(v);
            o->eta_given = 1;
        } else if (strcmp(a, "--dt-min") == 0) {
            o->dt_min = parse_number(v);
            o->dt_min_given = 1;
        } else if (strcmp(a, "--eps") == 0) {
            o->eps = parse_number(v);
            o->eps_given = 1;
        } else if (strcmp(a, "--theta") == 0) {
            o->theta = parse_number(v);
            o->theta_given = 1;
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
    if (!o->eps_halo_given)
        o->eps_halo = 2.0 * o->eps;
    return check_options(o);
}

static int alloc_bodies(bodies *b, size_t n)
{
    b->n = n;
    b->pos = malloc(3 * n * sizeof *b->pos);
    b->vel = malloc(3 * n * sizeof *b->vel);
    b->acc = calloc(3 * n, sizeof *b->acc);
    b->pot = calloc(n ? n : 1, sizeof *b->pot);
    b->mass = malloc(n * sizeof *b->mass);
    b->id = malloc(n * sizeof *b->id);
    b->type = malloc(n * sizeof *b->type);
    return b->pos && b->vel && b->acc && b->pot && b->mass && b->id && b->type;
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
    free(b->pot);
    free(b->eps_all);
    free(b->tracers);
    free(b->mass);
    free(b->id);
    free(b->type);
    free(b->level);
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
 * whole: a file reader that can reads only it (source/readers/share.h); the model
 * is made in chunks of one share each, so chunk r is rank r's. */
static orr_status open_share(const options *o, int rank, int size, orr_source **out, orr_error *err)
{
    orr_source *src = NULL;
    orr_status st;
    if (strcmp(o->ic, "model") == 0) {
        orr_model_params mp = {o->particles, 1, o->separation, o->galaxies, o->disc_q, 0, 0, o->m31_weight};
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

/* ---- tracers: a quiet Sun ----------------------------------------------- */

/* The tracers: particles far lighter than the mean (the model's Sun, one
 * solar mass among particles of 10^5 or more), whose own gravity does not
 * matter but whose path does (the in-situ camera rides on the Sun). */
static int find_tracers(bodies *b)
{
    double total = 0;
    for (size_t i = 0; i < b->n_all; i++)
        total += b->mass_all[i];
    double light = b->tracer_mass = TRACER_MASS_FRACTION * total / (double)(b->n_all ? b->n_all : 1);
    b->ntracers = 0;
    for (size_t i = 0; i < b->n_all; i++)
        b->ntracers += b->mass_all[i] < light;
    b->tracers = malloc((b->ntracers + 1) * sizeof *b->tracers);
    if (!b->tracers)
        return 0;
    b->ntracers = 0;
    for (size_t i = 0; i < b->n_all; i++)
        if (b->mass_all[i] < light)
            b->tracers[b->ntracers++] = i;
    return 1;
}

/* The distance from particle t to its k-th nearest particle that is not a
 * tracer (every particle looked at: O(N) for each of the few tracers). */
static double neighbour_distance(const bodies *b, size_t t, int k)
{
    double heap[TRACER_NEIGHBOURS_MAX];
    nearest_non_tracers(b->pos_all, b->mass_all, b->n_all, b->tracer_mass, &b->pos_all[3 * t], k, heap);
    return isfinite(heap[0]) ? sqrt(heap[0]) : 0; /* fewer than k others: as stars */
}

/* Softens each tracer's forces at the local particle spacing: its
 * softening is sqrt(2) times the distance r_k of its k-th nearest
 * particle, so that with the pair rule eps^2 = (eps_i^2 + eps_j^2) / 2 it
 * feels every particle softened over at least r_k (never less than
 * --eps). Particle noise (single passing halo particles of
 * 10^5-10^6 solar masses) then no longer kicks it about, while the
 * galaxy's smooth pull, on scales well above r_k, is unchanged: the
 * paper's large softening of the bulge's black hole, for the same reason.
 * The same on every rank (all positions are everywhere). */
static void soften_tracers(bodies *b, const options *o)
{
    if (!o->tracer_neighbours || !b->ntracers)
        return;
    for (size_t j = 0; j < b->ntracers; j++) {
        size_t t = b->tracers[j];
        double r = neighbour_distance(b, t, (int)o->tracer_neighbours);
        b->eps_all[t] = fmax(o->eps, sqrt(2.0) * r);
    }
}

/* What is wrong with particle i's numbers (a position or velocity that is
 * not finite, a mass that is not finite or negative), or NULL; which
 * component in *axis. */
static const char *bad_numbers(const bodies *b, size_t i, int *axis)
{
    for (*axis = 0; *axis < 3; ++*axis) {
        if (!isfinite(b->pos[3 * i + *axis]))
            return "position";
        if (!isfinite(b->vel[3 * i + *axis]))
            return "velocity";
    }
    *axis = 0;
    return isfinite(b->mass[i]) && b->mass[i] >= 0 ? NULL : "mass";
}

/* Whether every particle of this process can be evolved; else an error
 * naming the file, the first bad particle and its field. */
static int check_bodies(const bodies *b, const char *file)
{
    for (size_t i = 0; i < b->n; i++) {
        int axis;
        const char *what = bad_numbers(b, i, &axis);
        if (!what)
            continue;
        double v = strcmp(what, "mass") == 0 ? b->mass[i]
                   : what[0] == 'p'           ? b->pos[3 * i + axis]
                                              : b->vel[3 * i + axis];
        fprintf(stderr, "orrery-nbody: %s: particle id %llu (type %d): %s%s = %g: cannot evolve it (%s)\n", file,
                (unsigned long long)b->id[i], b->type[i], what,
                strcmp(what, "mass") == 0 ? "" : (const char *[]){" x", " y", " z"}[axis], v,
                strcmp(what, "mass") == 0 ? "a mass must be finite and at least 0" : "it must be finite");
        return 0;
    }
    return 1;
}

/* Gives every process every position and mass: the slices in rank order,
 * this process's at b->first. */
static int share_bodies(bodies *b, const options *o, int rank, int size)
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
    b->eps_all = malloc((b->n_all + 1) * sizeof *b->eps_all);
    int failed = !pos_all || !mass_all || !b->eps_all;
    if (failed)
        fprintf(stderr, "orrery-nbody: out of memory for %zu positions\n", b->n_all);
    if (ranks_any(failed)) { /* before the gathers, which every process must join */
        free(pos_all);
        free(mass_all);
        return 0;
    }
    memcpy(pos_all + 3 * b->first, b->pos, 3 * b->n * sizeof *b->pos);
    memcpy(mass_all + b->first, b->mass, b->n * sizeof *b->mass);
    for (size_t i = 0; i < b->n; i++) /* dark matter (type 1) has its own softening */
        b->eps_all[b->first + i] = b->type[i] == ORR_MODEL_TYPE_HALO ? o->eps_halo : o->eps;
    free(b->pos);
    free(b->mass);
    b->pos_all = pos_all;
    b->mass_all = mass_all;
    b->pos = pos_all + 3 * b->first;
    b->mass = mass_all + b->first;
    return ranks_gather(b->pos_all, 3, b->counts) == 0 && ranks_gather(b->mass_all, 1, b->counts) == 0 &&
           ranks_gather(b->eps_all, 1, b->counts) == 0 && find_tracers(b);
}

/* --decompose: each process keeps its own particles, which are moved to
 * the ranks of their pieces of the Peano-Hilbert curve (domain.h); the
 * tracers' mass limit from the exact total mass. */
static int own_bodies(bodies *b, const options *o, int rank, int size)
{
#ifdef __GLIBC__
    /* Large blocks mapped and unmapped, always: glibc otherwise raises its
     * threshold after the first large free, and the exchanges' buffers,
     * freed, stay in the process beside the tree (25 MB a rank at 10^6 on
     * 4 ranks). */
    mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
    b->decomposed = 1;
    b->counts = calloc((size_t)size, sizeof *b->counts);
    if (!b->counts || ranks_counts(b->n, b->counts) != 0)
        return 0;
    b->n_all = b->first = 0;
    for (int r = 0; r < size; r++)
        b->n_all += b->counts[r];
    double e[4];
    if (domain_mass_momentum(b, e) != 0)
        return 0;
    b->tracer_mass = TRACER_MASS_FRACTION * e[0] / (double)(b->n_all ? b->n_all : 1);
    if (ranks_any(b->level != NULL) && !b->level && !(b->level = calloc(b->n + 1, 1))) /* records alike on every rank */
        return 0;
    return domain_migrate(b, o->eps, o->eps_halo, rank, size) == 0;
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

/* The accelerations and potentials of this process's particles, from a
 * tree built anew over all: for all (active NULL), or for the particles with
 * active[i] set within a block step. The tree is built anew at every
 * sub-step, not kept with its cells' moments moved to the new positions (as
 * it was until issue 42): a group's particles drift apart over a long step,
 * so a moved tree's interaction lists grew to 3 times a new one's within a
 * step of 0.008 and the sub-steps cost far more than a build saves
 * (docs/nbody.md). The tracers' softening is renewed with the full
 * computations only. */
static void ring_tracers(bodies *b, const options *o, const unsigned char *active, int rank, int size);

static double gravity(qt_tree *t, bodies *b, const options *o, const unsigned char *active, double *interactions,
                      int rank, int size)
{
    double t0 = now();
    if (b->decomposed) {
        int failed = !active && o->tracer_neighbours && domain_soften_tracers(b, (int)o->tracer_neighbours, o->eps,
                                                                              rank, size) != 0;
        domain_stats stats;
        if (failed || (*interactions = domain_gravity(t, b, G_KPC_KMS, o->theta, active, rank, size, &stats)) < 0) {
            fprintf(stderr, "orrery-nbody: out of memory in the tree\n");
            exit(1);
        }
        if (!active)
            b->imported_cells = stats.cells, b->imported_particles = stats.particles;
        ring_tracers(b, o, active, rank, size);
        return now() - t0;
    }
    if (!active)
        soften_tracers(b, o);
    if (qt_build(t, b->pos_all, b->mass_all, b->eps_all, b->n_all) != 0 ||
        (*interactions = qt_accelerations_masked(t, G_KPC_KMS, o->theta, b->first, b->n, active, b->acc, b->pot)) <
            0) {
        fprintf(stderr, "orrery-nbody: out of memory in the tree\n");
        exit(1);
    }
    ring_tracers(b, o, active, rank, size);
    return now() - t0;
}

/* Sums (or, with take_min, the least) of every process's values (v[0 ..
 * k)), through the gather: each process puts its k values at its rank's
 * row. */
static int reduce_over_ranks(double *v, int k, int rank, int size, int take_min)
{
    double *all = calloc((size_t)(size * k), sizeof *all);
    size_t *counts = malloc((size_t)size * sizeof *counts);
    int ok = all && counts;
    if (ok) {
        for (int r = 0; r < size; r++)
            counts[r] = 1;
        memcpy(all + (size_t)rank * k, v, (size_t)k * sizeof *v);
        ok = ranks_gather(all, (size_t)k, counts) == 0;
        for (int j = 0; ok && j < k; j++) {
            v[j] = take_min ? INFINITY : 0;
            for (int r = 0; r < size; r++)
                v[j] = take_min ? fmin(v[j], all[(size_t)r * k + j]) : v[j] + all[(size_t)r * k + j];
        }
    }
    free(all);
    free(counts);
    return ok;
}

/* ---- tracers' rings: no torque from spirals or bar (tracer_ring.h) ------ */

/* A host's stars lie within RING_SPIN_TIMES the tracer's distance from its
 * black hole (at least RING_SPIN_MIN kpc). */
#define RING_SPIN_TIMES 2.0
#define RING_SPIN_MIN 5.0
#define RING_ROW 6

/* Every process's rows (per doubles each; this process's nown of them in
 * own) on every process, in rank order, into *all (allocated; *nall rows). */
static int gather_rows(const double *own, size_t nown, int per, int rank, int size, double **all, size_t *nall)
{
    size_t *counts = malloc((size_t)size * sizeof *counts), before = 0;
    *all = NULL;
    if (!counts || ranks_counts(nown, counts) != 0) {
        free(counts);
        return 0;
    }
    *nall = 0;
    for (int r = 0; r < size; r++) {
        before += r < rank ? counts[r] : 0;
        *nall += counts[r];
    }
    free(counts);
    *all = calloc(*nall * (size_t)per + 1, sizeof **all);
    if (!*all)
        return 0;
    memcpy(*all + before * (size_t)per, own, nown * (size_t)per * sizeof *own);
    return *nall == 0 || reduce_over_ranks(*all, (int)(*nall * (size_t)per), rank, size, 0);
}

/* This process's index of the j-th tracer it knows (b->tracers holds every
 * process's tracers in the run's order unless decomposed), or SIZE_MAX
 * when another process owns it. */
static size_t own_tracer(const bodies *b, size_t j)
{
    size_t t = b->tracers[j];
    if (b->decomposed)
        return t;
    return t >= b->first && t < b->first + b->n ? t - b->first : SIZE_MAX;
}

/* The tracers this process owns (x, y, z, eps, rank, its index here: RING_ROW
 * doubles) and its black holes (x, y, z), each list then gathered over every
 * process. */
static int ring_lists(const bodies *b, int rank, int size, double **tracers, size_t *nt, double **holes, size_t *nh)
{
    const double *eps = b->eps_all + (b->decomposed ? 0 : b->first);
    size_t nmine = 0, nholes = 0;
    for (size_t i = 0; i < b->n; i++)
        nholes += b->type[i] == ORR_MODEL_TYPE_BH;
    double *mine = malloc((b->ntracers + nholes + 1) * RING_ROW * sizeof *mine);
    *tracers = *holes = NULL;
    if (ranks_any(!mine)) {
        free(mine);
        return 0;
    }
    for (size_t j = 0; j < b->ntracers; j++) {
        size_t i = own_tracer(b, j);
        if (i == SIZE_MAX)
            continue;
        double row[RING_ROW] = {b->pos[3 * i], b->pos[3 * i + 1], b->pos[3 * i + 2], eps[i], (double)rank, (double)i};
        memcpy(&mine[RING_ROW * nmine++], row, sizeof row);
    }
    int ok = gather_rows(mine, nmine, RING_ROW, rank, size, tracers, nt);
    nholes = 0;
    for (size_t i = 0; i < b->n; i++)
        if (b->type[i] == ORR_MODEL_TYPE_BH)
            memcpy(&mine[3 * nholes++], &b->pos[3 * i], 3 * sizeof *mine);
    ok = ok && gather_rows(mine, nholes, 3, rank, size, holes, nh);
    free(mine);
    return ok;
}

/* Whether some process's tracer gets forces now (active NULL: all do). */
static int tracer_active(const bodies *b, const unsigned char *active)
{
    int any = !active;
    for (size_t j = 0; !any && j < b->ntracers; j++) {
        size_t i = own_tracer(b, j);
        any = i != SIZE_MAX && active[i];
    }
    return ranks_any(any);
}

static double distance(const double a[3], const double b[3])
{
    return sqrt(ring_distance2(a, b));
}

/* The black hole in holes (nh of them) nearest x. */
static const double *nearest_hole(const double *holes, size_t nh, const double x[3])
{
    const double *best = holes;
    for (size_t h = 1; h < nh; h++)
        if (distance(&holes[3 * h], x) < distance(best, x))
            best = &holes[3 * h];
    return best;
}

/* Whether a black hole other than host lies within radius of it: another
 * galaxy passing through the tracer's own. */
static int another_hole_within(const double *holes, size_t nh, const double *host, double radius)
{
    for (size_t h = 0; h < nh; h++)
        if (&holes[3 * h] != host && distance(&holes[3 * h], host) < radius)
            return 1;
    return 0;
}

/* Stars' sums (ring_star_sums, of the per-particle vectors vec: the
 * accelerations or the velocities) within radius of about, over every
 * process. */
static int star_sums(const bodies *b, const double *vec, const double about[3], double radius, int rank, int size,
                     double s[RING_SUMS])
{
    memset(s, 0, RING_SUMS * sizeof *s);
    ring_star_sums(b->pos, vec, b->mass, b->type, b->n, b->tracer_mass, about, radius, s);
    return reduce_over_ranks(s, RING_SUMS, rank, size, 0);
}

/* The host of a tracer (tracer_ring.h): the stars within radius, centred
 * twice on their centre of mass from the black hole start; its axis n the
 * one its disc's particles are thinnest along (its bulge's when it has no
 * disc particles); with v_host, the same stars' mean velocity too. Returns
 * 0 when a sum failed; *found 0 when no stars were there. */
static int ring_frame(const bodies *b, const double start[3], double radius, int rank, int size, double c[3],
                      double n[3], double a_host[3], double *v_host, int *found)
{
    double s[RING_SUMS], centre[3] = {start[0], start[1], start[2]}, c_again[3];
    *found = 0;
    for (int pass = 0; pass < 2; pass++) {
        if (!star_sums(b, b->acc, centre, radius, rank, size, s))
            return 0;
        if (!ring_host(s, c, a_host))
            return 1;
        if (pass == 1 && v_host && (!star_sums(b, b->vel, centre, radius, rank, size, s) ||
                                    !ring_host(s, c_again, v_host)))
            return 0;
        memcpy(centre, c, sizeof centre);
    }
    for (uint8_t which = ORR_MODEL_TYPE_DISC; which <= ORR_MODEL_TYPE_BULGE && !*found; which++) {
        double m2[6] = {0};
        ring_shape_sum(b->pos, b->mass, b->type, b->n, which, c, radius, m2);
        if (!reduce_over_ranks(m2, 6, rank, size, 0))
            return 0;
        *found = ring_axis(m2, n);
    }
    return 1;
}

/* The galaxy of one tracer (row: ring_lists'): the stars within
 * RING_SPIN_TIMES its distance from the nearest black hole (ring_frame;
 * v_host as there). While another black hole is inside that sphere (a
 * galaxy passing through, or merging) there is no one axis to average
 * about: *found 0, as when there are no stars about its black hole. */
static int tracer_host(const bodies *b, const double *row, const double *holes, size_t nh, int rank, int size,
                       double c[3], double n[3], double a_host[3], double *v_host, int *found)
{
    const double *host = nearest_hole(holes, nh, row);
    double radius = fmax(RING_SPIN_MIN, RING_SPIN_TIMES * distance(row, host));
    *found = 0;
    return another_hole_within(holes, nh, host, radius) ||
           ring_frame(b, host, radius, rank, size, c, n, a_host, v_host, found);
}

/* The ring's pull on one tracer (row: ring_lists'), set on the process
 * that owns it when it is active (active NULL: all are). Without one
 * galaxy about it (tracer_host) the tracer keeps the tree's pull: the true
 * dynamics of an encounter. */
static int ring_one(bodies *b, const options *o, const double *row, const double *holes, size_t nh,
                    const unsigned char *active, int rank, int size)
{
    double c[3], n[3], a_host[3], pts[3 * RING_POINTS_MAX], acc[3 * RING_POINTS_MAX] = {0};
    int found, k = (int)o->tracer_ring;
    if (!tracer_host(b, row, holes, nh, rank, size, c, n, a_host, NULL, &found))
        return 0;
    if (!found)
        return 1; /* the tree's pull stays */
    ring_points(c, n, row, k, (int)o->tracer_mirror, pts);
    const double *eps = b->eps_all + (b->decomposed ? 0 : b->first);
    ring_pulls(b->pos, b->mass, eps, b->n, b->tracer_mass, row[3], pts, k, G_KPC_KMS, acc);
    if (!reduce_over_ranks(acc, 3 * k, rank, size, 0))
        return 0;
    size_t i = (size_t)row[5];
    if ((int)row[4] == rank && (!active || active[i]))
        ring_average(n, a_host, acc, k, (int)o->tracer_mirror, &b->acc[3 * i]);
    return 1;
}

/* With --tracer-ring: every tracer's pull replaced by its ring's, after the
 * tree's forces. Collective; exits when a sum fails or there is no black
 * hole to centre a ring on. */
static void ring_tracers(bodies *b, const options *o, const unsigned char *active, int rank, int size)
{
    double *tracers, *holes;
    size_t nt, nh;
    if (!o->tracer_ring || !tracer_active(b, active)) /* a block sub-step without a tracer's step ending */
        return;
    int ok = ring_lists(b, rank, size, &tracers, &nt, &holes, &nh);
    if (ok && nt && !nh) {
        if (rank == 0)
            fprintf(stderr, "orrery-nbody: --tracer-ring %ld: no black hole (type %d particle) to centre a "
                            "tracer's ring on\n", o->tracer_ring, ORR_MODEL_TYPE_BH);
        exit(1);
    }
    for (size_t t = 0; ok && t < nt; t++)
        ok = ring_one(b, o, &tracers[RING_ROW * t], holes, nh, active, rank, size);
    free(tracers);
    free(holes);
    if (!ok) {
        fprintf(stderr, "orrery-nbody: --tracer-ring: out of memory or MPI failed\n");
        exit(1);
    }
}

/* One tracer started on its ring's circular orbit (ring_circular_velocity)
 * by the process that owns it, after a force computation gave it the
 * ring's pull. Into said (summed over processes, as only the owner adds
 * to it): 1 when started, its speed about its galaxy before and after,
 * its distance from the axis and its height from the disc's plane. */
#define START_SAID 5
static int start_one(bodies *b, const double *row, const double *holes, size_t nh, int rank, int size,
                     double said[START_SAID])
{
    double c[3], n[3], a_host[3], v_host[3];
    int found;
    memset(said, 0, START_SAID * sizeof *said);
    if (!tracer_host(b, row, holes, nh, rank, size, c, n, a_host, v_host, &found))
        return 0;
    size_t i = (size_t)row[5];
    if (found && (int)row[4] == rank) {
        double *x = &b->pos[3 * i], *v = &b->vel[3 * i], was[3], now[3], d[3];
        const double zero[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            was[k] = v[k] - v_host[k], d[k] = x[k] - c[k];
        if (ring_circular_velocity(c, n, a_host, v_host, x, &b->acc[3 * i], v, v)) {
            for (int k = 0; k < 3; k++)
                now[k] = v[k] - v_host[k];
            double z = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            said[0] = 1;
            said[1] = distance(was, zero);
            said[2] = distance(now, zero);
            said[3] = sqrt(fmax(0.0, ring_distance2(x, c) - z * z));
            said[4] = z;
        }
    }
    return reduce_over_ranks(said, START_SAID, rank, size, 0);
}

/* --tracer-start circular (the default with --tracer-ring), at the start of
 * a new run, after the first force computation: every ring tracer moved
 * onto the circular orbit of the pull it will feel, which the particles
 * realise (softened at its spacing) rather than the smooth model the
 * initial conditions were drawn from; its place is kept. Says so for each.
 * Collective; 0 when a sum failed. */
static int start_tracers(bodies *b, const options *o, int rank, int size)
{
    double *tracers, *holes;
    size_t nt, nh;
    if (!(o->tracer_start < 0 ? o->tracer_ring > 0 : o->tracer_start))
        return 1;
    int ok = ring_lists(b, rank, size, &tracers, &nt, &holes, &nh);
    for (size_t t = 0; ok && nh && t < nt; t++) {
        double said[START_SAID];
        ok = start_one(b, &tracers[RING_ROW * t], holes, nh, rank, size, said);
        if (ok && !o->quiet && said[0] > 0)
            printf("tracer %zu started on its ring's circular orbit: %.2f km/s about its galaxy (was %.2f) at "
                   "R = %.3f kpc, %+.3f kpc from its disc's plane\n",
                   t, said[2], said[1], said[3], said[4]);
        else if (ok && !o->quiet)
            printf("tracer %zu kept as given: no one galaxy about it, no inward pull, or no turning about "
                   "its galaxy's axis\n", t);
    }
    free(tracers);
    free(holes);
    return ok;
}

/* ---- discs phase-mixed before the run (--phase-mix, phase_mix.h) ------ */

/* The stars within this distance of a black hole give its galaxy's centre,
 * axis and velocity (ring_frame). */
#define PHASE_MIX_FRAME_RADIUS 20.0

/* A galaxy's frame: its centre, in-plane axes e[0], e[1], axis e[2], and
 * its stars' mean velocity. */
typedef struct galaxy_frame {
    double c[3], e[3][3], v[3];
    int found;
} galaxy_frame;

static int find_galaxy_frame(const bodies *b, const double hole[3], int rank, int size, galaxy_frame *g)
{
    double a_host[3], *n = g->e[2];
    if (!ring_frame(b, hole, PHASE_MIX_FRAME_RADIUS, rank, size, g->c, n, a_host, g->v, &g->found))
        return 0;
    if (g->found) { /* any two unit vectors perpendicular to the axis and each other */
        const double t[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
        double *e0 = g->e[0];
        ring_cross(t, n, e0);
        const double len = sqrt(e0[0] * e0[0] + e0[1] * e0[1] + e0[2] * e0[2]);
        for (int k = 0; k < 3; k++)
            e0[k] /= len;
        ring_cross(n, e0, g->e[1]);
    }
    return 1;
}

/* x - origin in the frame's axes. */
static void into_frame(const galaxy_frame *g, const double *x, const double origin[3], double out[3])
{
    for (int a = 0; a < 3; a++)
        out[a] = g->e[a][0] * (x[0] - origin[0]) + g->e[a][1] * (x[1] - origin[1]) + g->e[a][2] * (x[2] - origin[2]);
}

static void out_of_frame(const galaxy_frame *g, const double in[3], const double origin[3], double *x)
{
    for (int k = 0; k < 3; k++)
        x[k] = origin[k] + in[0] * g->e[0][k] + in[1] * g->e[1][k] + in[2] * g->e[2][k];
}

/* Which galaxy particle i belongs to: the nearest black hole's. */
static size_t galaxy_of(const bodies *b, size_t i, const double *holes, size_t nh)
{
    return (size_t)(nearest_hole(holes, nh, &b->pos[3 * i]) - holes) / 3;
}

/* Every massive particle of every galaxy as rings about its axis, summed
 * over the processes. */
static int galaxy_rings(const bodies *b, const galaxy_frame *g, const double *holes, size_t nh, int rank, int size,
                        pm_rings *rings)
{
    const double *eps = b->eps_all + (b->decomposed ? 0 : b->first);
    for (size_t i = 0; i < b->n; i++) {
        const size_t k = galaxy_of(b, i, holes, nh);
        if (bodies_is_tracer(b, i) || !g[k].found)
            continue;
        double y[3];
        into_frame(&g[k], &b->pos[3 * i], g[k].c, y);
        pm_rings_add(&rings[k], sqrt(y[0] * y[0] + y[1] * y[1]), y[2], b->mass[i], eps[i]);
    }
    for (size_t k = 0; k < nh; k++)
        if (!reduce_over_ranks(rings[k].sum, PM_BINS_U * PM_BINS_V * PM_BIN_SUMS, rank, size, 0))
            return 0;
    return 1;
}

/* This process's disc stars, each along its orbit in its galaxy's field
 * for its own time (pm_mix_time). Returns how many moved. */
static double mix_own_discs(bodies *b, const galaxy_frame *g, const pm_field *fields, const double *holes, size_t nh,
                            double T)
{
    double moved = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : moved)
    for (long li = 0; li < (long)b->n; li++) {
        const size_t i = (size_t)li, k = galaxy_of(b, i, holes, nh);
        if (b->type[i] != ORR_MODEL_TYPE_DISC || bodies_is_tracer(b, i) || !g[k].found)
            continue;
        double x[3], v[3];
        into_frame(&g[k], &b->pos[3 * i], g[k].c, x);
        into_frame(&g[k], &b->vel[3 * i], g[k].v, v);
        pm_follow(&fields[k], x, v, pm_mix_time(b->id[i], T));
        out_of_frame(&g[k], x, g[k].c, &b->pos[3 * i]);
        out_of_frame(&g[k], v, g[k].v, &b->vel[3 * i]);
        moved += 1;
    }
    return moved;
}

/* --phase-mix T: every galaxy's disc stars moved along their orbits in its
 * axisymmetric pull (phase_mix.h), then every process's positions shared.
 * Says why when it fails. */
static int phase_mix_discs(bodies *b, const options *o, int rank, int size)
{
    double *tracers, *holes;
    size_t nt, nh;
    if (!(o->phase_mix > 0))
        return 1;
    if (!ring_lists(b, rank, size, &tracers, &nt, &holes, &nh)) {
        fprintf(stderr, "orrery-nbody: --phase-mix: out of memory or MPI failed\n");
        return 0;
    }
    free(tracers);
    if (!nh) {
        if (rank == 0)
            fprintf(stderr, "orrery-nbody: --phase-mix %g: %s has no black hole (type %d particle) to centre a "
                            "galaxy on\n", o->phase_mix, o->ic, ORR_MODEL_TYPE_BH);
        free(holes);
        return 0;
    }
    galaxy_frame *g = calloc(nh, sizeof *g);
    pm_rings *rings = calloc(nh, sizeof *rings);
    pm_field *fields = malloc(nh * sizeof *fields);
    int ok = !ranks_any(!g || !rings || !fields);
    for (size_t k = 0; ok && k < nh; k++)
        ok = find_galaxy_frame(b, &holes[3 * k], rank, size, &g[k]);
    ok = ok && galaxy_rings(b, g, holes, nh, rank, size, rings);
    for (size_t k = 0; ok && k < nh; k++)
        if (g[k].found)
            pm_field_build(&fields[k], &rings[k], G_KPC_KMS, o->eps);
    double moved = ok ? mix_own_discs(b, g, fields, holes, nh, o->phase_mix) : 0;
    ok = ok && reduce_over_ranks(&moved, 1, rank, size, 0) &&
         (b->decomposed || ranks_gather(b->pos_all, 3, b->counts) == 0);
    if (!ok)
        fprintf(stderr, "orrery-nbody: --phase-mix: out of memory or MPI failed\n");
    if (ok && !o->quiet)
        printf("phase mixing: %.0f disc stars moved along their orbits in their galaxy's axisymmetric pull for up to "
               "%g (%.3g Gyr) each\n", moved, o->phase_mix, 0.978 * o->phase_mix);
    free(holes);
    free(g);
    free(rings);
    free(fields);
    return ok;
}

/* Kinetic and potential energy (W = 1/2 sum m phi), momentum and the
 * centre of mass, over every process's particles: e[0] K, e[1] W, e[2..4]
 * P, e[5..7] the sum of m x, e[8] the mass. */
#define N_SUMS 9
static int energies(const bodies *b, int rank, int size, double e[N_SUMS])
{
    memset(e, 0, N_SUMS * sizeof *e);
    for (size_t i = 0; i < b->n; i++) {
        const double *v = &b->vel[3 * i];
        e[0] += 0.5 * b->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        e[1] += 0.5 * b->mass[i] * b->pot[i];
        for (int k = 0; k < 3; k++) {
            e[2 + k] += b->mass[i] * v[k];
            e[5 + k] += b->mass[i] * b->pos[3 * i + k];
        }
        e[8] += b->mass[i];
    }
    return reduce_over_ranks(e, N_SUMS, rank, size, 0);
}

/* The centre of mass of every process's particles. */
static int centre_of_mass(const bodies *b, int rank, int size, double c[3])
{
    double e[N_SUMS];
    if (!energies(b, rank, size, e))
        return 0;
    for (int k = 0; k < 3; k++)
        c[k] = e[8] > 0 ? e[5 + k] / e[8] : 0;
    return 1;
}

/* The mass-weighted mean velocity of all particles, summed in the run's
 * order on every process (their velocities gathered once), so it is the
 * same to the last bit on any number of ranks; mass in *total. */
static int mean_velocity(const bodies *b, double vmean[3], double *total)
{
    if (b->decomposed) { /* summed exactly in fixed point (domain.h): the same on any number of ranks */
        double e[4];
        if (domain_mass_momentum(b, e) != 0)
            return 0;
        for (int k = 0; k < 3; k++)
            vmean[k] = e[0] > 0 ? e[1 + k] / e[0] : 0;
        *total = e[0];
        return 1;
    }
    double *all = malloc((3 * b->n_all + 1) * sizeof *all);
    int ok = all != NULL;
    if (ranks_any(!ok)) {
        free(all);
        return 0;
    }
    memcpy(all + 3 * b->first, b->vel, 3 * b->n * sizeof *b->vel);
    ok = ranks_gather(all, 3, b->counts) == 0;
    double p[3] = {0, 0, 0}, m = 0;
    for (size_t i = 0; ok && i < b->n_all; i++) {
        for (int k = 0; k < 3; k++)
            p[k] += b->mass_all[i] * all[3 * i + k];
        m += b->mass_all[i];
    }
    for (int k = 0; k < 3; k++)
        vmean[k] = m > 0 ? p[k] / m : 0;
    *total = m;
    free(all);
    return ok;
}

/* Starts a new run in the frame of its centre of mass: takes the mean
 * velocity off every particle, so the system does not drift (a model
 * drawn particle by particle carries a net momentum from its sampling,
 * 2 km/s for 2000 particles). Positions are left where the initial
 * conditions put them (the model's Milky Way at the origin). Says what it
 * took off and what is left. */
static int to_centre_of_mass_frame(bodies *b, int quiet)
{
    double v[3], left[3], m;
    if (!mean_velocity(b, v, &m))
        return 0;
    for (size_t i = 0; i < b->n; i++)
        for (int k = 0; k < 3; k++)
            b->vel[3 * i + k] -= v[k];
    if (!mean_velocity(b, left, &m))
        return 0;
    if (!quiet)
        printf("centre-of-mass frame: took off a net velocity of %.3g km/s (|P| = %.3g); left: %.2g km/s\n",
               sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), m * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]),
               sqrt(left[0] * left[0] + left[1] * left[1] + left[2] * left[2]));
    return 1;
}

/* ---- how an isolated galaxy holds together (one process) -------------- */

typedef struct structure {
    double zrms;      /* rms height of disc particles 3-10 kpc from the centre (cylindrical) */
    double disc_half; /* median cylindrical radius of the disc particles */
    double bulge_half; /* median radius of the bulge particles */
    double sun_R, sun_z;
    double sun_eps;   /* the Sun's softening (a tracer's: soften_tracers) */
    int has_sun;
} structure;

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, size_t n)
{
    if (!n)
        return NAN;
    qsort(v, n, sizeof *v, compare_double);
    return v[n / 2];
}

/* Centre (centre of mass of the stars: disc and bulge) and the disc's
 * plane (normal along the disc particles' angular momentum), so the
 * figures follow a galaxy that drifts or tilts a little. */
static void disc_frame(const bodies *b, double c[3], double nrm[3])
{
    double m = 0, cv[3] = {0, 0, 0}, L[3] = {0, 0, 0};
    memset(c, 0, 3 * sizeof *c);
    for (size_t i = 0; i < b->n; i++)
        if (b->type[i] == ORR_MODEL_TYPE_DISC || b->type[i] == ORR_MODEL_TYPE_BULGE) {
            m += b->mass[i];
            for (int k = 0; k < 3; k++) {
                c[k] += b->mass[i] * b->pos[3 * i + k];
                cv[k] += b->mass[i] * b->vel[3 * i + k];
            }
        }
    for (int k = 0; k < 3; k++) {
        c[k] = m > 0 ? c[k] / m : 0;
        cv[k] = m > 0 ? cv[k] / m : 0;
    }
    for (size_t i = 0; i < b->n; i++)
        if (b->type[i] == ORR_MODEL_TYPE_DISC) {
            double x[3], v[3];
            for (int k = 0; k < 3; k++) {
                x[k] = b->pos[3 * i + k] - c[k];
                v[k] = b->vel[3 * i + k] - cv[k];
            }
            L[0] += b->mass[i] * (x[1] * v[2] - x[2] * v[1]);
            L[1] += b->mass[i] * (x[2] * v[0] - x[0] * v[2]);
            L[2] += b->mass[i] * (x[0] * v[1] - x[1] * v[0]);
        }
    double l = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
    for (int k = 0; k < 3; k++)
        nrm[k] = l > 0 ? L[k] / l : (k == 2);
}

/* Height and cylindrical radius of particle i in the frame (c, nrm). */
static void cylindrical(const bodies *b, size_t i, const double c[3], const double nrm[3], double *R, double *z)
{
    double x[3] = {b->pos[3 * i] - c[0], b->pos[3 * i + 1] - c[1], b->pos[3 * i + 2] - c[2]};
    *z = x[0] * nrm[0] + x[1] * nrm[1] + x[2] * nrm[2];
    double r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    *R = sqrt(fmax(0.0, r2 - *z * *z));
}

static int structure_of(const bodies *b, structure *s)
{
    double c[3], nrm[3];
    disc_frame(b, c, nrm);
    double *disc = malloc((b->n + 1) * sizeof *disc), *bulge = malloc((b->n + 1) * sizeof *bulge);
    if (!disc || !bulge) {
        free(disc);
        free(bulge);
        return 0;
    }
    size_t nd = 0, nb = 0, nz = 0;
    double z2 = 0;
    memset(s, 0, sizeof *s);
    for (size_t i = 0; i < b->n; i++) {
        double R, z;
        cylindrical(b, i, c, nrm, &R, &z);
        if (b->type[i] == ORR_MODEL_TYPE_DISC) {
            disc[nd++] = R;
            if (R >= 3.0 && R <= 10.0) {
                z2 += z * z;
                nz++;
            }
        } else if (b->type[i] == ORR_MODEL_TYPE_BULGE) {
            bulge[nb++] = sqrt(R * R + z * z);
        } else if (b->type[i] == ORR_MODEL_TYPE_SUN) {
            s->sun_R = R;
            s->sun_z = z;
            s->sun_eps = b->eps_all[b->first + i];
            s->has_sun = 1;
        }
    }
    s->zrms = nz ? sqrt(z2 / (double)nz) : NAN;
    s->disc_half = median(disc, nd);
    s->bulge_half = median(bulge, nb);
    free(disc);
    free(bulge);
    return 1;
}

/* The Sun's position into sun[0 .. 3) and sun[3] = 1, when some rank
 * holds one (--decompose: each rank holds its own particles). */
static int sun_position(const bodies *b, int rank, int size, double sun[4])
{
    for (size_t i = 0; i < b->n && !sun[3]; i++)
        if (b->type[i] == ORR_MODEL_TYPE_SUN) {
            memcpy(sun, &b->pos[3 * i], 3 * sizeof *sun);
            sun[3] = 1;
        }
    return reduce_over_ranks(sun, 4, rank, size, 0);
}

/* --decompose: the least and most particles a rank holds, and imported at
 * the last full force computation, over the ranks (rank 0 says). */
static int say_domains(const bodies *b, int rank, int size)
{
    double least[3] = {(double)b->n, (double)b->imported_cells, (double)b->imported_particles};
    double most[3] = {least[0], least[1], least[2]};
    if (ranks_extreme(least, 3, 0) != 0 || ranks_extreme(most, 3, 1) != 0)
        return 0;
    if (rank == 0)
        printf("domains: %d rank%s %.0f-%.0f particles each of %zu, and imported %.0f-%.0f cells and %.0f-%.0f "
               "particles of the others at the last full force computation\n",
               size, size > 1 ? "s hold" : " holds", least[0], most[0], b->n_all, least[1], most[1], least[2], most[2]);
    return 1;
}

/* One line of figures: energy and its drift from the start, momentum, how
 * far the centre of mass has moved from c0 (where it was at step 0), and
 * (one process, a galaxy's discs) the structure. 0, or 1 when the energy
 * is no longer a number (the run has blown up: said on every process). */
static int report(const bodies *b, int rank, int size, double e0, const double c0[3], long step, int quiet)
{
    double e[N_SUMS];
    if (!energies(b, rank, size, e))
        return 1;
    double E = e[0] + e[1];
    if (!isfinite(E)) {
        if (rank == 0)
            fprintf(stderr, "orrery-nbody: step %ld, t = %g: the energy is %g: the run has blown up (is --dt too long?)\n",
                    step, b->time, E);
        return 1;
    }
    double sun[4] = {0, 0, 0, 0}; /* --decompose: the Sun's position, from the rank that holds it (all join) */
    if (b->decomposed && !sun_position(b, rank, size, sun))
        return 1;
    if (quiet)
        return 0;
    double d[3];
    for (int k = 0; k < 3; k++)
        d[k] = (e[8] > 0 ? e[5 + k] / e[8] : 0) - c0[k];
    printf("report t = %.4f  E = %.6e  dE/|E0| = %+.2e  2K/|W| = %.3f  |P| = %.3g  drift %.3g kpc", b->time, E,
           (E - e0) / fabs(e0), 2 * e[0] / fabs(e[1]), sqrt(e[2] * e[2] + e[3] * e[3] + e[4] * e[4]),
           sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    structure s;
    if (size == 1 && structure_of(b, &s) && isfinite(s.disc_half)) {
        printf("  disc z_rms(3-10 kpc) = %.4f  disc R_half = %.3f  bulge r_half = %.3f", s.zrms, s.disc_half,
               s.bulge_half);
        if (s.has_sun)
            printf("  Sun R = %.3f z = %+.3f eps = %.3f", s.sun_R, s.sun_z, s.sun_eps);
    }
    if (sun[3] > 0)
        printf("  Sun at (%.4f, %.4f, %.4f)", sun[0], sun[1], sun[2]);
    printf("\n");
    fflush(stdout);
    return 0;
}

/* Total energy now (every process). */
static double total_energy(const bodies *b, int rank, int size)
{
    double e[N_SUMS];
    return energies(b, rank, size, e) ? e[0] + e[1] : NAN;
}

/* The step particle i (of this process) wants by Gadget-2's criterion,
 * dt_i = sqrt(2 eta eps_i / |a_i|) (Springel 2005, MNRAS 364, 1105, eq. 34):
 * a fraction of the time to fall through its own softening length. */
static double wanted_step(const bodies *b, size_t i, double eta)
{
    const double *a = &b->acc[3 * i];
    double amag = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return amag > 0 ? sqrt(2 * eta * b->eps_all[b->first + i] / amag) : INFINITY;
}

/* The share of this process's particles for which a step dt is longer than
 * the criterion with eta: how honest one global step is. */
static double share_wanting_shorter(const bodies *b, double dt, double eta)
{
    size_t shorter = 0;
    for (size_t i = 0; i < b->n; i++)
        shorter += wanted_step(b, i, eta) < dt;
    return b->n ? (double)shorter / (double)b->n : 0.0;
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
    return b->decomposed ? 0 : ranks_gather(b->pos_all, 3, b->counts);
}

/* ---- block time steps --------------------------------------------------- */

/* Each particle's step is dt / 2^k, k = 0 .. MAX_LEVEL, counted in integer
 * ticks of dt / 2^MAX_LEVEL, so a step of --dt is TICKS ticks and steps
 * nest: a particle's step always starts at a multiple of its length. */
#define MAX_LEVEL 10
#define TICKS (1L << MAX_LEVEL)

typedef struct blocks {
    long min_ticks;        /* the shortest step (--dt-min) */
    long *end;             /* the tick each particle's step ends at (within a step of --dt) */
    unsigned char *active; /* whose step ends now: they get forces and kicks */
    double forces;         /* particle forces computed so far (every process) */
    long substeps;         /* force computations (tree builds) so far */
} blocks;

/* The block steps' arrays; b->level is kept when a snapshot gave it, else
 * every particle starts on the longest step (so its first step is the
 * criterion's). */
static int alloc_blocks(blocks *k, bodies *b, const options *o)
{
    k->min_ticks = 1;
    while (k->min_ticks < TICKS && (double)k->min_ticks * (o->dt / TICKS) < o->dt_min * (1 - 1e-12))
        k->min_ticks *= 2;
    k->end = malloc((b->n + 1) * sizeof *k->end);
    k->active = malloc(b->n + 1);
    if (!b->level)
        b->level = calloc(b->n + 1, 1);
    return k->end && k->active && b->level;
}

/* The block steps' arrays for the particles a migration left on this
 * rank, all at the end of their steps (TICKS). */
static int resize_blocks(blocks *k, const bodies *b)
{
    long *end = realloc(k->end, (b->n + 1) * sizeof *end);
    if (end)
        k->end = end;
    unsigned char *active = realloc(k->active, b->n + 1);
    if (active)
        k->active = active;
    for (size_t i = 0; end && i < b->n; i++)
        k->end[i] = TICKS;
    return end && active;
}

static void free_blocks(blocks *k)
{
    free(k->end);
    free(k->active);
}

static long ticks_of(uint8_t level)
{
    return TICKS >> level;
}

/* The longest step of the hierarchy, in ticks, that is at most the wanted
 * one (but not shorter than least) and may start at tick T (T a multiple
 * of it, so the steps stay nested); at least one tick. */
static long step_ticks(double want, double dt, long T, long least)
{
    long s = TICKS;
    while (s > 1 && (((double)s * (dt / TICKS) > want && s > least) || T % s != 0))
        s >>= 1;
    return s;
}

/* The step a particle whose last step was `last` ticks takes at tick T
 * when it wants `want`: shorter at once when it wants a shorter one, but
 * longer only when it wants at least twice the longer step. A step chosen
 * from the acceleration at its start only is not time-symmetric; without
 * this margin a particle near a boundary between two steps flips between
 * them and the energy error grows steadily (docs/nbody.md). */
static long next_ticks(double want, double dt, long T, long last, long least)
{
    long s = step_ticks(want, dt, T, least);
    if (s <= last)
        return s;
    long longer = step_ticks(0.5 * want, dt, T, least);
    return longer > last ? longer : last;
}

/* The step particle i wants: a tracer the shortest the run takes when
 * --dt-min sets one. The criterion would give the Sun, softened at the
 * local spacing (0.4-0.6 kpc), steps twice the stars' shortest, and in the
 * short film's block-step runs its height from the disc's plane then grew
 * to 0.27 kpc, where the global step's stayed within 0.1 (docs/nbody.md,
 * "Tracers on the shortest step"). A tracer costs nothing: it has no
 * gravity of its own. */
static double step_wanted(const bodies *b, size_t i, const options *o)
{
    if (o->dt_min > 0 && bodies_is_tracer(b, i))
        return 0;
    return wanted_step(b, i, o->eta);
}

/* Opens the step of particle i at tick T: its length from its acceleration
 * now and its last step, and the first half kick. */
static void open_step(bodies *b, blocks *k, size_t i, long T, const options *o)
{
    const double tick = o->dt / TICKS;
    long s = next_ticks(step_wanted(b, i, o), o->dt, T, ticks_of(b->level[i]), k->min_ticks);
    uint8_t level = 0;
    while (ticks_of(level) > s)
        level++;
    b->level[i] = level;
    k->end[i] = T + s;
    for (int c = 0; c < 3; c++)
        b->vel[3 * i + c] += b->acc[3 * i + c] * (0.5 * (double)s * tick);
}

/* The second half kick of particle i's step, with its new acceleration. */
static void close_step(bodies *b, size_t i, const options *o)
{
    const double tick = o->dt / TICKS;
    for (int c = 0; c < 3; c++)
        b->vel[3 * i + c] += b->acc[3 * i + c] * (0.5 * (double)ticks_of(b->level[i]) * tick);
}

/* The next tick at which some particle's step ends, over every process. */
static long next_end(const blocks *k, size_t n, int rank, int size)
{
    double next = (double)TICKS;
    for (size_t i = 0; i < n; i++)
        next = fmin(next, (double)k->end[i]);
    return reduce_over_ranks(&next, 1, rank, size, 1) ? (long)next : -1;
}

/* One step of --dt in block steps (kick-drift-kick for each particle with
 * its own step): everyone starts synchronised, with accelerations, and
 * ends so; between, every particle is drifted to each tick where some
 * step ends (positions stay synchronised, so one tree over all serves),
 * and only the particles whose step ends get forces and kicks. With every
 * particle on the longest step it is the global step exactly. 0 or an
 * exit status; the tree time in *seconds. */
static int block_step(qt_tree *tree, bodies *b, const options *o, blocks *k, int rank, int size, double *seconds)
{
    const double tick = o->dt / TICKS, t0 = b->time;
    for (size_t i = 0; i < b->n; i++)
        open_step(b, k, i, 0, o);
    for (long T = 0; T < TICKS;) {
        long next = next_end(k, b->n, rank, size);
        if (next <= T || drift(b, (double)(next - T) * tick) != 0)
            return 1;
        T = next;
        /* Every particle's step ends at the end of the step of --dt: the
         * particles move to their ranks then, with their levels. */
        if (T == TICKS && b->decomposed &&
            (domain_migrate(b, o->eps, o->eps_halo, rank, size) != 0 || ranks_any(!resize_blocks(k, b))))
            return 1;
        double active = 0, interactions;
        for (size_t i = 0; i < b->n; i++)
            active += (k->active[i] = k->end[i] == T);
        *seconds += gravity(tree, b, o, T == TICKS ? NULL : k->active, &interactions, rank, size);
        k->forces += active; /* this process's; summed over processes when reported */
        k->substeps++;
        for (size_t i = 0; i < b->n; i++)
            if (k->active[i]) {
                close_step(b, i, o);
                if (T < TICKS)
                    open_step(b, k, i, T, o);
            }
    }
    b->time = t0 + o->dt; /* as the global step has it, whatever the ticks' rounding */
    return 0;
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

/* Takes over the particles a snapshot read gave (one process). */
static int adopt_particles(bodies *b, nb_particles *p)
{
    b->n = p->n;
    b->pos = p->pos;
    b->vel = p->vel;
    b->mass = p->mass;
    b->id = p->id;
    b->type = p->type;
    b->level = p->level;
    b->nfields = p->nfields;
    memcpy(b->field_name, p->field_name, sizeof b->field_name);
    memcpy(b->field, p->field, sizeof b->field);
    memset(p, 0, sizeof *p); /* b owns them now */
    b->acc = calloc(3 * b->n + 3, sizeof *b->acc);
    b->pot = calloc(b->n + 1, sizeof *b->pot);
    return b->acc && b->pot;
}

/* A setting of the resumed run: the command line's when given (said, when
 * it differs, since the run then no longer continues bit for bit), else
 * the run's own. */
static void take_setting(const char *name, int given, double *value, double stored, int quiet)
{
    if (!given)
        *value = stored;
    else if (*value != stored && !quiet)
        printf("note: resuming with %s %g where the run used %g\n", name, *value, stored);
}

static void take_run_settings(options *o, const nb_run_state *rs)
{
    double every = (double)o->snapshot_every;
    take_setting("--dt", o->dt_given, &o->dt, rs->dt, o->quiet);
    take_setting("--eps", o->eps_given, &o->eps, rs->eps, o->quiet);
    take_setting("--eps-halo", o->eps_halo_given || o->eps_given, &o->eps_halo, rs->eps_halo, o->quiet);
    take_setting("--theta", o->theta_given, &o->theta, rs->theta, o->quiet);
    take_setting("--eta", o->eta_given, &o->eta, rs->eta, o->quiet);
    take_setting("--dt-min", o->dt_min_given, &o->dt_min, rs->dt_min, o->quiet);
    double k = (double)o->tracer_neighbours;
    take_setting("--tracer-neighbours", o->tracer_neighbours_given, &k, (double)rs->tracer_neighbours, o->quiet);
    o->tracer_neighbours = (long)k;
    double ring = (double)o->tracer_ring;
    take_setting("--tracer-ring", o->tracer_ring_given, &ring, (double)rs->tracer_ring, o->quiet);
    o->tracer_ring = (long)ring;
    double mirror = (double)o->tracer_mirror;
    take_setting("--tracer-mirror", o->tracer_mirror_given, &mirror, (double)rs->tracer_mirror, o->quiet);
    o->tracer_mirror = (long)mirror;
    take_setting("--snapshot-every", o->snapshot_every_given, &every, (double)rs->snapshot_every, o->quiet);
    o->snapshot_every = (long)every;
}

/* Keeps particles first .. first + count - 1 of p, moved to the start of
 * its arrays. */
static void keep_slice(nb_particles *p, size_t first, size_t count)
{
    memmove(p->pos, p->pos + 3 * first, 3 * count * sizeof *p->pos);
    memmove(p->vel, p->vel + 3 * first, 3 * count * sizeof *p->vel);
    memmove(p->mass, p->mass + first, count * sizeof *p->mass);
    memmove(p->id, p->id + first, count * sizeof *p->id);
    memmove(p->type, p->type + first, count * sizeof *p->type);
    if (p->level)
        memmove(p->level, p->level + first, count * sizeof *p->level);
    for (int f = 0; f < p->nfields; f++)
        memmove(p->field[f], p->field[f] + first, count * sizeof *p->field[f]);
    p->n = count;
}

/* Whether every block-step level a snapshot keeps is one a run takes (at
 * most MAX_LEVEL); the first that is not is an error naming it. */
static int levels_valid(const nb_particles *p, const char *path)
{
    for (size_t i = 0; p->level && i < p->n; i++)
        if (p->level[i] > MAX_LEVEL) {
            fprintf(stderr,
                    "orrery-nbody: --resume %s: particle id %" PRIu64
                    ": OrreryNbodyStepLevel = %d: a block step's level is at most %d\n",
                    path, p->id[i], p->level[i], MAX_LEVEL);
            return 0;
        }
    return 1;
}

/* The particles and state of the newest snapshot in --resume's folder;
 * on MPI ranks every rank reads it and keeps an even slice of the run's
 * order (the forces do not depend on the slicing, only on that order). */
static int resume_bodies(options *o, bodies *b, nb_run_state *rs, int rank, int size)
{
    static char path[4096];
    orr_error err = {0};
    nb_particles p;
    long newest = nb_snapshot_newest(o->resume_dir, &err);
    if (newest >= 0 && nb_snapshot_path(path, sizeof path, o->resume_dir, newest) != 0)
        newest = -1, snprintf(err.msg, sizeof err.msg, "the folder's name is too long");
    if (newest < 0 || nb_snapshot_read(path, &p, rs, &err) != ORR_OK) {
        fprintf(stderr, "orrery-nbody: --resume %s: %s\n", o->resume_dir, err.msg);
        return 0;
    }
    if (!levels_valid(&p, path)) {
        nb_particles_free(&p);
        return 0;
    }
    size_t share = p.n / (size_t)size, extra = p.n % (size_t)size, r = (size_t)rank;
    keep_slice(&p, r * share + (r < extra ? r : extra), share + (r < extra));
    if (!adopt_particles(b, &p)) {
        fprintf(stderr, "orrery-nbody: %s: out of memory\n", path);
        return 0;
    }
    b->time = rs->time;
    o->ic = path;
    take_run_settings(o, rs);
    return 1;
}

/* --decompose: the newest complete set of snapshot files in --resume's
 * folder, rank r reading files r, r + size, ... (any number of files on
 * any number of ranks: the particles then move to their ranks' pieces of
 * the curve, domain_migrate). A rank with no file reads the state only. */
static int resume_own(options *o, bodies *b, nb_run_state *rs, int rank, int size)
{
    static char path[4096];
    orr_error err = {0};
    nb_particles mine = {0};
    int nfiles = 0, ok = 1;
    long newest = nb_snapshot_newest_set(o->resume_dir, &nfiles, &err);
    if (newest < 0 || nb_snapshot_part_path(path, sizeof path, o->resume_dir, newest, 0, nfiles) != 0 ||
        (rank >= nfiles && nb_snapshot_read_state(path, rs, &mine, &err) != ORR_OK)) {
        fprintf(stderr, "orrery-nbody: --resume %s: %s\n", o->resume_dir, err.msg[0] ? err.msg : "no snapshot");
        return 0;
    }
    for (int part = rank; ok && part < nfiles; part += size) {
        nb_particles p;
        nb_run_state s;
        ok = nb_snapshot_part_path(path, sizeof path, o->resume_dir, newest, part, nfiles) == 0 &&
             nb_snapshot_read(path, &p, &s, &err) == ORR_OK;
        if (!ok) {
            fprintf(stderr, "orrery-nbody: --resume %s: %s\n", o->resume_dir, err.msg);
        } else if (s.nfiles != nfiles || (part != rank && s.step != rs->step)) {
            fprintf(stderr, "orrery-nbody: --resume %s: %s: step %ld of a snapshot in %d files, not step %ld of %d: "
                            "files of different runs\n", o->resume_dir, path, s.step, s.nfiles, rs->step, nfiles);
            nb_particles_free(&p);
            ok = 0;
        } else {
            ok = levels_valid(&p, path);
            if (part == rank)
                *rs = s;
            if (!ok || nb_particles_append(&mine, &p) != 0) {
                if (ok)
                    fprintf(stderr, "orrery-nbody: %s: out of memory, or fields unlike the set's first file's\n", path);
                ok = 0;
            }
        }
    }
    if (ok && !adopt_particles(b, &mine)) { /* a rank with no file: none, but the set's fields (records alike) */
        fprintf(stderr, "orrery-nbody: %s: out of memory\n", path);
        ok = 0;
    }
    nb_particles_free(&mine);
    if (!ok)
        return 0;
    b->time = rs->time;
    o->ic = path;
    take_run_settings(o, rs);
    return 1;
}

/* Loads this process's particles (or a resumed run's) and shares the
 * positions; whether every process succeeded (each prints its own error). */
static int start_bodies(options *o, int rank, int size, bodies *b, nb_run_state *rs)
{
    orr_error err = {0};
    int ok;
    if (o->resume_dir) {
        ok = o->decompose ? resume_own(o, b, rs, rank, size) : resume_bodies(o, b, rs, rank, size);
    } else if (!(ok = load_bodies(o, rank, size, b, &err) == ORR_OK)) {
        fprintf(stderr, "orrery-nbody: %s\n", err.msg);
    }
    ok = ok && check_bodies(b, o->ic);
    if (ranks_any(!ok) || !(o->decompose ? own_bodies(b, o, rank, size) : share_bodies(b, o, rank, size)))
        return 0;
    if (b->n_all == 0) {
        if (rank == 0)
            fprintf(stderr, "orrery-nbody: %s: no particles\n", o->ic);
        return 0;
    }
    if (o->resume_dir && o->decompose && rs->total && rs->total != b->n_all) {
        if (rank == 0)
            fprintf(stderr, "orrery-nbody: --resume %s: the files hold %zu particles, their headers %llu\n",
                    o->resume_dir, b->n_all, (unsigned long long)rs->total);
        return 0;
    }
    return 1;
}

/* Where snapshots go: --snapshot-dir, else --resume's folder. */
static const char *snapshot_dir(const options *o)
{
    return o->snapshot_dir ? o->snapshot_dir : o->resume_dir;
}

/* Before the run: a folder that takes the snapshots (created if missing;
 * what a killed run left there under temporary names removed), checked by
 * rank 0, which writes them. 0, or an exit status (on every rank). */
static int prepare_snapshots(const options *o, int rank)
{
    int code = 0;
    orr_error err = {0};
    if (rank == 0 && o->snapshot_every && orr_check_output_dir(snapshot_dir(o), &err) != ORR_OK) {
        fprintf(stderr, "orrery-nbody: --snapshot-dir %s: %s\n", snapshot_dir(o), err.msg);
        code = 1;
    }
    if (rank == 0 && !code && o->snapshot_every)
        orr_remove_stale_temporaries(snapshot_dir(o));
    return ranks_any(code) ? 1 : 0;
}

/* Every process's particles in the run's order, on every process (the
 * gather is an all-gather; positions and masses are there already), for
 * rank 0 to write. Ids travel as two exact 32-bit halves. */
static int gather_particles(const bodies *b, nb_particles *all)
{
    size_t n = b->n_all, mine = b->first;
    *all = (nb_particles){.n = n, .pos = b->pos_all, .mass = b->mass_all, .nfields = b->nfields};
    memcpy(all->field_name, b->field_name, sizeof all->field_name);
    all->vel = malloc(3 * (n + 1) * sizeof *all->vel);
    all->id = malloc((n + 1) * sizeof *all->id);
    all->type = malloc(n + 1);
    all->level = b->level ? malloc(n + 1) : NULL;
    double *rows = malloc(3 * (n + 1) * sizeof *rows);
    int ok = all->vel && all->id && all->type && rows && (all->level || !b->level);
    for (int f = 0; f < b->nfields; f++)
        ok &= (all->field[f] = malloc((n + 1) * sizeof(float))) != NULL;
    if (ranks_any(!ok)) {
        free(rows);
        return 0;
    }
    memcpy(all->vel + 3 * mine, b->vel, 3 * b->n * sizeof *b->vel);
    ok = ranks_gather(all->vel, 3, b->counts) == 0;
    for (size_t i = 0; i < b->n; i++) {
        rows[3 * (mine + i)] = (double)(b->id[i] >> 32);
        rows[3 * (mine + i) + 1] = (double)(b->id[i] & 0xffffffffu);
        rows[3 * (mine + i) + 2] = b->type[i];
    }
    ok = ok && ranks_gather(rows, 3, b->counts) == 0;
    for (size_t i = 0; ok && i < n; i++) {
        all->id[i] = (uint64_t)rows[3 * i] << 32 | (uint64_t)rows[3 * i + 1];
        all->type[i] = (uint8_t)rows[3 * i + 2];
    }
    if (all->level) {
        for (size_t i = 0; i < b->n; i++)
            rows[mine + i] = b->level[i];
        ok = ok && ranks_gather(rows, 1, b->counts) == 0;
        for (size_t i = 0; ok && i < n; i++)
            all->level[i] = (uint8_t)rows[i];
    }
    for (int f = 0; ok && f < b->nfields; f++) {
        for (size_t i = 0; i < b->n; i++)
            rows[mine + i] = b->field[f][i];
        ok = ranks_gather(rows, 1, b->counts) == 0;
        for (size_t i = 0; ok && i < n; i++)
            all->field[f][i] = (float)rows[i];
    }
    free(rows);
    return ok;
}

/* The arrays gather_particles made (positions and masses are the run's). */
static void free_gathered(nb_particles *all)
{
    all->pos = all->mass = NULL;
    nb_particles_free(all);
}

/* Writes snapshot s->number of p into the snapshot folder; 0 or 1. */
static int write_file(const nb_particles *p, const nb_run_state *s, const options *o)
{
    char path[4096];
    orr_error err = {0};
    if (nb_snapshot_path(path, sizeof path, snapshot_dir(o), s->number) != 0)
        snprintf(err.msg, sizeof err.msg, "%s: the folder's name is too long", snapshot_dir(o));
    else if (nb_snapshot_write(path, p, s, &err) == ORR_OK) {
        if (!o->quiet)
            printf("snapshot %s  step %ld  t = %.4f\n", path, s->step, s->time);
        return 0;
    }
    fprintf(stderr, "orrery-nbody: %s\n", err.msg);
    return 1;
}

/* --decompose: each rank writes its own particles as file `rank` of the
 * snapshot's set (snapshot_NNNN.R.hdf5; one file on one rank), the
 * header's totals over all. Each file is renamed when complete; a run
 * killed mid-way may leave some of a set's files, which a resume passes
 * over (nb_snapshot_newest_set). 0 or 1, on every rank. */
static int write_own_snapshot(const bodies *b, nb_run_state *s, const options *o, int rank, int size)
{
    uint64_t totals[NB_SNAPSHOT_TYPES] = {0};
    for (size_t i = 0; i < b->n; i++)
        totals[b->type[i] < NB_SNAPSHOT_TYPES ? b->type[i] : 0]++;
    if (ranks_sum_u64(totals, NB_SNAPSHOT_TYPES) != 0)
        return 1;
    nb_particles p = {.n = b->n, .pos = b->pos, .vel = b->vel, .mass = b->mass, .id = b->id, .type = b->type,
                      .level = b->level, .nfields = b->nfields};
    memcpy(p.field_name, b->field_name, sizeof p.field_name);
    memcpy(p.field, b->field, sizeof p.field);
    s->nfiles = size;
    s->type_totals = totals;
    char path[4096];
    orr_error err = {0};
    int failed = 0;
    if (nb_snapshot_part_path(path, sizeof path, snapshot_dir(o), s->number, rank, size) != 0)
        failed = 1, snprintf(err.msg, sizeof err.msg, "%s: the folder's name is too long", snapshot_dir(o));
    else
        failed = nb_snapshot_write(path, &p, s, &err) != ORR_OK;
    if (failed)
        fprintf(stderr, "orrery-nbody: %s\n", err.msg);
    else if (!o->quiet)
        printf("snapshot %s (and the other ranks' files)  step %ld  t = %.4f\n", path, s->step, s->time);
    return ranks_any(failed) ? 1 : 0;
}

/* Snapshot number of the run at step (and time b->time), written by rank
 * 0 (gathered from every rank first when there are several); 0 or 1, on
 * every rank. */
static int write_snapshot(const bodies *b, const options *o, long step, long number, double e0, const double c0[3],
                          int rank, int size)
{
    nb_particles p = {.n = b->n, .pos = b->pos, .vel = b->vel, .mass = b->mass, .id = b->id, .type = b->type,
                      .level = b->level, .nfields = b->nfields};
    memcpy(p.field_name, b->field_name, sizeof p.field_name);
    memcpy(p.field, b->field, sizeof p.field);
    int failed = size > 1 && !b->decomposed && !gather_particles(b, &p);
    nb_run_state s = {.time = b->time, .step = step, .number = number, .e0 = e0, .centre0 = {c0[0], c0[1], c0[2]},
                      .dt = o->dt, .eps = o->eps, .eps_halo = o->eps_halo, .theta = o->theta, .eta = o->eta,
                      .dt_min = o->dt_min,
                      .snapshot_every = o->snapshot_every, .tracer_neighbours = o->tracer_neighbours,
                      .tracer_ring = o->tracer_ring, .tracer_mirror = o->tracer_mirror};
    if (b->decomposed)
        return write_own_snapshot(b, &s, o, rank, size);
    if (!failed && rank == 0)
        failed = write_file(&p, &s, o);
    if (size > 1)
        free_gathered(&p);
    return ranks_any(failed) ? 1 : 0;
}

/* ---- the ranks agree on the run ---- */

/* Bytes of a file read for its fingerprint: its size and its start, where
 * a snapshot's header is (a scene is read whole). */
#define FINGERPRINT_BYTES 65536

/* The command line's fingerprint: each argument with its terminator. */
static uint64_t args_fingerprint(int argc, char **argv)
{
    uint64_t h = ORR_DIGEST_START;
    for (int i = 1; i < argc; i++)
        h = orr_digest(h, argv[i], strlen(argv[i]) + 1);
    return h;
}

/* A file's fingerprint: its size and its first FINGERPRINT_BYTES bytes; a
 * file that cannot be read gets its own (the error is reported where it is
 * read), and no file (NULL) 0. */
static uint64_t file_fingerprint(const char *path)
{
    if (!path)
        return 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return orr_digest_text(ORR_DIGEST_START, "unreadable");
    unsigned char buf[4096]; /* read in pieces: no allocation that could fail on one rank only */
    uint64_t h = ORR_DIGEST_START;
    size_t got, total = 0;
    while (total < FINGERPRINT_BYTES && (got = fread(buf, 1, sizeof buf, f)) > 0) {
        h = orr_digest(h, buf, got);
        total += got;
    }
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    h = orr_digest(h, &size, sizeof size);
    fclose(f);
    return h;
}

/* Whether every rank's fingerprints mine[0 .. n) equal rank 0's; if not,
 * rank 0 says which rank differs first in what[k], and it is an error on
 * every rank. Ranks that ran different commands or read different files
 * (a node with another copy of the scene) would otherwise simulate
 * different particles together, or wait for each other forever. */
static int ranks_agree(const uint64_t *mine, const char *const *what, int n, int rank, int size)
{
    uint64_t *all = malloc((size_t)size * (size_t)n * sizeof *all);
    int ok = all != NULL;
    if (ranks_any(!ok) || ranks_allgather_u64(mine, n, all) != 0) {
        free(all);
        return 0;
    }
    for (int r = 1; r < size && ok; r++)
        for (int k = 0; k < n && ok; k++)
            if (all[(size_t)r * n + k] != all[k]) {
                if (rank == 0)
                    fprintf(stderr,
                            "orrery-nbody: rank %d's %s differs from rank 0's: every rank must run the same "
                            "command on the same files\n",
                            r, what[k]);
                ok = 0;
            }
    free(all);
    return ok;
}

/* The command lines agree: checked before they are parsed, so that a rank
 * whose arguments are refused does not leave the others waiting. 0 or 2. */
static int check_ranks_args(int argc, char **argv, int rank, int size)
{
    const uint64_t mine = args_fingerprint(argc, argv);
    const char *what = "command line";
    return size == 1 || ranks_agree(&mine, &what, 1, rank, size) ? 0 : 2;
}

/* The scene file and the initial conditions' file agree. 0 or 2. */
static int check_ranks_files(const options *o, int rank, int size)
{
    if (size == 1)
        return 0;
    char scene[ORR_PATH_MAX + 32], ic[ORR_PATH_MAX + 32];
    snprintf(scene, sizeof scene, "scene file %s", o->scene ? o->scene : "");
    snprintf(ic, sizeof ic, "initial conditions %s", o->ic_given ? o->ic : "");
    const uint64_t mine[2] = {file_fingerprint(o->scene), file_fingerprint(o->ic_given ? o->ic : NULL)};
    const char *what[2] = {scene, ic};
    return ranks_agree(mine, what, 2, rank, size) ? 0 : 2;
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

/* The run's state between steps. */
typedef struct run {
    long step, frame, snapshot;
    double e0, t_gravity, t_render;
    double c0[3]; /* the centre of mass at step 0 */
    long first_step;            /* the step this process started (or resumed) at */
    double started, progressed; /* wall clock then, and at the last progress line */
} run;

/* "1:02:03" (or "2:03") for a number of seconds. */
static const char *clock_text(char *buf, size_t size, double seconds)
{
    long s = isfinite(seconds) && seconds > 0 ? (long)(seconds + 0.5) : 0;
    if (s >= 3600)
        snprintf(buf, size, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else
        snprintf(buf, size, "%ld:%02ld", s / 60, s % 60);
    return buf;
}

/* Every --progress seconds of wall clock (as rank 0 counts them, so every
 * rank joins the energy sum), one line on stderr: the step, the simulated
 * time, the energy error, particle-steps per second and the time left at
 * that rate. 0, or 1 when the ranks fail. */
static int progress(const bodies *b, const options *o, run *u, int rank, int size)
{
    double t = now();
    if (!ranks_any(rank == 0 && o->progress > 0 && t - u->progressed >= o->progress))
        return 0;
    double e[N_SUMS];
    if (!energies(b, rank, size, e))
        return 1;
    u->progressed = t;
    double done = (double)(u->step - u->first_step), rate = done / fmax(t - u->started, 1e-9);
    char left[32];
    if (rank == 0)
        fprintf(stderr, "progress: step %ld of %ld  t = %.4f (%.1f Myr)  dE/|E0| = %+.2e  %.3g particle-steps/s  %s left\n",
                u->step, o->steps, b->time, b->time * 978.0, (e[0] + e[1] - u->e0) / fabs(u->e0),
                rate * (double)b->n_all, clock_text(left, sizeof left, (double)(o->steps - u->step) / rate));
    return 0;
}

/* What comes after a step (or the start): a frame, a report, a snapshot;
 * 0 or an exit status. */
static int after_step(orrery_renderer *r, const bodies *b, const options *o, run *u, int rank, int size)
{
    double tr = 0;
    int code = 0;
    if (r && u->step % o->render_every == 0 && (code = render(r, b, u->frame++, &tr)) == 0)
        u->t_render += tr;
    if (u->step > 0 && !o->quiet) /* ends the step's line */
        printf("render %.3f s\n", tr);
    if (!code && u->step > 0)
        code = progress(b, o, u, rank, size);
    if (u->step % o->report_every == 0 || u->step == o->steps)
        code = report(b, rank, size, u->e0, u->c0, u->step, o->quiet) ? 1 : code;
    if (!code && o->snapshot_every && u->step % o->snapshot_every == 0)
        code = write_snapshot(b, o, u->step, u->snapshot++, u->e0, u->c0, rank, size);
    return code;
}

/* One kick-drift-kick step of --dt, in block steps with --eta; 0 or an
 * exit status. */
static int leapfrog_step(qt_tree *tree, bodies *b, const options *o, run *u, blocks *k, int rank, int size)
{
    if (o->eta > 0) {
        double tg = 0, forces = k->forces;
        long substeps = k->substeps;
        if (block_step(tree, b, o, k, rank, size, &tg) != 0)
            return 1;
        u->t_gravity += tg;
        u->step++;
        if (!o->quiet)
            printf("step %ld  t = %.4f  gravity %.3f s (%ld force computations, %.3g particle forces here)  ", u->step,
                   b->time, tg, k->substeps - substeps, k->forces - forces);
        return 0;
    }
    double interactions;
    kick(b, 0.5 * o->dt);
    if (drift(b, o->dt) != 0)
        return 1;
    if (b->decomposed && domain_migrate(b, o->eps, o->eps_halo, rank, size) != 0)
        return 1;
    double tg = gravity(tree, b, o, NULL, &interactions, rank, size);
    u->t_gravity += tg;
    kick(b, 0.5 * o->dt);
    u->step++;
    if (!o->quiet)
        printf("step %ld  t = %.4f  gravity %.3f s (%.3g interactions/s)  ", u->step, b->time, tg,
               interactions / (tg > 0 ? tg : 1e-9));
    return 0;
}

int main(int argc, char **argv)
{
    int rank, size;
    ranks_start(&argc, &argv, &rank, &size);
    options o;
    if (check_ranks_args(argc, argv, rank, size) || !parse_args(argc, argv, &o) ||
        check_ranks_files(&o, rank, size)) {
        ranks_finish();
        return 2;
    }
    o.quiet |= rank != 0; /* rank 0 reports for all */
    bodies b = {0};
    orrery_renderer *r = NULL;
    nb_run_state resumed = {0};
    int code = prepare_snapshots(&o, rank);
    if (!code)
        code = start_bodies(&o, rank, size, &b, &resumed) ? 0 : 1;
    if (!code && o.resume_dir) /* its --snapshot-every may be the run's own */
        code = prepare_snapshots(&o, rank);
    if (!code)
        code = open_renderer(&o, size, &r);
    if (code) {
        orrery_close(r);
        free_bodies(&b);
        ranks_finish();
        return code;
    }
    if (!o.quiet)
        printf("%zu bodies from %s on %d process%s, t = %g, dt = %g, eps = %g, theta = %g\n", b.n_all, o.ic, size,
               size > 1 ? "es" : "", b.time, o.dt, o.eps, o.theta);
    qt_tree tree = {0};
    double interactions;
    run u = {0};
    blocks blk = {0};
    if (o.eta <= 0) { /* a resumed run's levels, when it goes on with one global step */
        free(b.level);
        b.level = NULL;
    }
    if (o.eta > 0 && ranks_any(!alloc_blocks(&blk, &b, &o))) {
        fprintf(stderr, "orrery-nbody: out of memory for the block time steps\n");
        code = 1;
    }
    if (!code && !o.resume_dir && !phase_mix_discs(&b, &o, rank, size))
        code = 1;
    if (!code && !o.resume_dir && !to_centre_of_mass_frame(&b, o.quiet))
        code = 1;
    u.t_gravity = code ? 0 : gravity(&tree, &b, &o, NULL, &interactions, rank, size);
    if (!code && !o.resume_dir && !start_tracers(&b, &o, rank, size)) {
        fprintf(stderr, "orrery-nbody: --tracer-start: out of memory or MPI failed\n");
        code = 1;
    }
    if (!code && o.resume_dir) { /* the state after step resumed.step: its frame, report and snapshot are done */
        u = (run){resumed.step, resumed.step / o.render_every + 1, resumed.number + 1, resumed.e0, u.t_gravity, 0,
                  {resumed.centre0[0], resumed.centre0[1], resumed.centre0[2]}, 0, 0, 0};
        if (!resumed.has_centre0 && centre_of_mass(&b, rank, size, u.c0) && !o.quiet)
            printf("note: the snapshot does not say where the centre of mass started: the drift is reported from "
                   "where it is now\n");
        if (!o.quiet)
            printf("resumed at step %ld, t = %.4f\n", u.step, b.time);
    } else if (!code) {
        u.e0 = total_energy(&b, rank, size);
        code = centre_of_mass(&b, rank, size, u.c0) ? 0 : 1;
        if (!o.quiet)
            printf("time step: %.2f%% of this process's particles want a shorter one than dt = %g by "
                   "sqrt(2 x 0.025 eps / |a|)\n",
                   100.0 * share_wanting_shorter(&b, o.dt, 0.025), o.dt);
        code = code ? code : after_step(r, &b, &o, &u, rank, size);
    }
    long start = u.step, frame0 = o.resume_dir ? u.frame : 0;
    u.first_step = u.step;
    u.started = u.progressed = now();
    while (u.step < o.steps && code == 0)
        if ((code = leapfrog_step(&tree, &b, &o, &u, &blk, rank, size)) == 0)
            code = after_step(r, &b, &o, &u, rank, size);
    if (!o.quiet && code == 0) {
        long frames = u.frame - frame0, steps = u.step - start;
        printf("gravity %.3f s over %ld force evaluations; rendering %.2f s over %ld frames\n", u.t_gravity,
               (o.eta > 0 ? blk.substeps : steps) + 1, u.t_render, frames);
        if (r && frames > 0)
            printf("rendering per frame = %.1f%% of gravity per step\n",
                   100.0 * (u.t_render / (double)frames) / (u.t_gravity / (double)(steps + 1)));
    }
    double forces = blk.forces; /* every process's */
    if (code == 0 && o.eta > 0 && !reduce_over_ranks(&forces, 1, rank, size, 0))
        code = 1;
    if (!o.quiet && code == 0 && o.eta > 0) {
        printf("block steps: %ld force computations, %.4g particle forces = %.3f per particle and step of dt\n",
               blk.substeps, forces, forces / (double)b.n_all / (double)(u.step - start > 0 ? u.step - start : 1));
    }
    if (code == 0 && b.decomposed && !say_domains(&b, rank, size))
        code = 1;
    free_blocks(&blk);
    orrery_close(r);
    qt_free(&tree);
    free_bodies(&b);
    ranks_finish();
    return code ? 1 : 0;
}
