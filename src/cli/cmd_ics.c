/* orrery ics --zeldovich -o FILE [--grid N] [--box L] [--z Z] [--seed S]
 *            [--truncate K] [--evolve [--z-start Z] [--pm-steps N] [--pm-grid M]]
 *            [--omega-m X] [--omega-lambda X] [--omega-b X] [--h X]
 *            [--sigma8 X] [--ns X] */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "core/numbers.h"
#include "source/models/pm.h"
#include "source/models/zeldovich.h"
#include "source/writers/zeldovich_hdf5.h"

static const char ics_help[] =
    "usage: orrery ics --zeldovich -o FILE.hdf5 [--grid N] [--box MPC_H] [--z Z] [--seed S] [--truncate K]\n"
    "                  [--evolve [--z-start Z] [--pm-steps N] [--pm-grid M] [--progress SECONDS]]\n"
    "                  [--omega-m X] [--omega-lambda X] [--omega-b X] [--h X] [--sigma8 X] [--ns X]\n"
    "\n"
    "Writes cosmological initial conditions: N^3 dark-matter particles displaced\n"
    "from a grid by the Zel'dovich approximation, from a Gaussian random field\n"
    "with the Eisenstein & Hu (1998) no-wiggle LCDM power spectrum, as an HDF5\n"
    "snapshot in the Gadget layout (Mpc/h, km/s, 1e10 Msun/h). See\n"
    "docs/dark-universe.md.\n"
    "\n"
    "  --zeldovich           the method (the only one so far; required)\n"
    "  -o, --output FILE     where to write (required)\n"
    "  --grid N              particles per side, even, 2 to 512 (default 64)\n"
    "  --box L               box side in Mpc/h (default 100)\n"
    "  --z Z                 redshift of the particles (default 0)\n"
    "  --seed S              random seed (default 1); the same seed and grid give the same box\n"
    "  --truncate K          truncated Zel'dovich: P(k) times exp(-k^2/K^2), K in h/Mpc\n"
    "                        (about the non-linear wavenumber; default 0: none)\n"
    "  --evolve              start at --z-start and evolve to --z with a particle-mesh\n"
    "                        gravity code, so that filaments and halos form\n"
    "  --z-start Z           with --evolve: the redshift of the Zel'dovich start (default 24)\n"
    "  --pm-steps N          with --evolve: kick-drift-kick steps, even in a (default 40)\n"
    "  --pm-grid M           with --evolve: force mesh cells per side, even, 2 to 1024\n"
    "                        (default twice --grid, at most 1024)\n"
    "  --progress SECONDS    with --evolve: a progress line on stderr at most every\n"
    "                        SECONDS (default 10; 0: none): step, z, momentum balance,\n"
    "                        particle-steps per second, time left\n"
    "  --omega-m, --omega-lambda, --omega-b, --h, --sigma8, --ns\n"
    "                        cosmology (default Planck 2018: 0.315 0.685 0.049 0.674 0.811 0.965)\n"
    "  -h, --help            this text\n";

enum {
    OPT_ZELDOVICH = 256, OPT_GRID, OPT_SEED, OPT_BOX, OPT_Z, OPT_TRUNCATE,
    OPT_OMEGA_M, OPT_OMEGA_LAMBDA, OPT_OMEGA_B, OPT_H, OPT_SIGMA8, OPT_NS,
    OPT_EVOLVE, OPT_Z_START, OPT_PM_STEPS, OPT_PM_GRID, OPT_PROGRESS,
};

static const struct option ics_options[] = {
    {"zeldovich", no_argument, NULL, OPT_ZELDOVICH},
    {"output", required_argument, NULL, 'o'},
    {"grid", required_argument, NULL, OPT_GRID},
    {"seed", required_argument, NULL, OPT_SEED},
    {"box", required_argument, NULL, OPT_BOX},
    {"z", required_argument, NULL, OPT_Z},
    {"truncate", required_argument, NULL, OPT_TRUNCATE},
    {"omega-m", required_argument, NULL, OPT_OMEGA_M},
    {"omega-lambda", required_argument, NULL, OPT_OMEGA_LAMBDA},
    {"omega-b", required_argument, NULL, OPT_OMEGA_B},
    {"h", required_argument, NULL, OPT_H},
    {"sigma8", required_argument, NULL, OPT_SIGMA8},
    {"ns", required_argument, NULL, OPT_NS},
    {"evolve", no_argument, NULL, OPT_EVOLVE},
    {"z-start", required_argument, NULL, OPT_Z_START},
    {"pm-steps", required_argument, NULL, OPT_PM_STEPS},
    {"pm-grid", required_argument, NULL, OPT_PM_GRID},
    {"progress", required_argument, NULL, OPT_PROGRESS},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

/* The box and cosmology options that take a number: where each goes. */
static double *number_option(int code, orr_zeldovich_params *p)
{
    switch (code) {
    case OPT_BOX: return &p->box;
    case OPT_Z: return &p->redshift;
    case OPT_TRUNCATE: return &p->truncate;
    case OPT_OMEGA_M: return &p->cosmo.omega_m;
    case OPT_OMEGA_LAMBDA: return &p->cosmo.omega_lambda;
    case OPT_OMEGA_B: return &p->cosmo.omega_b;
    case OPT_H: return &p->cosmo.h;
    case OPT_SIGMA8: return &p->cosmo.sigma8;
    case OPT_NS: return &p->cosmo.n_s;
    default: return NULL;
    }
}

/* The option's name as typed in full, for messages. */
static const char *option_name(int code)
{
    for (const struct option *o = ics_options; o->name; o++)
        if (o->val == code)
            return o->name;
    return "?";
}

/* What the command line asks for. */
typedef struct ics_request {
    orr_zeldovich_params p;
    const char *out;
    int zeldovich, evolve;
    double z_start;
    int pm_steps, pm_grid;      /* pm_grid 0: twice the particle grid */
    double progress;            /* seconds between progress lines; 0: none */
    const char *pm_only;        /* a PM option given (named in the error without --evolve) */
} ics_request;

/* The particle-mesh options: EXIT_OK, or a usage error naming the option. */
static int take_pm_option(int code, const char *v, ics_request *r)
{
    long long n;
    r->pm_only = code == OPT_Z_START    ? "--z-start"
                 : code == OPT_PM_STEPS ? "--pm-steps"
                 : code == OPT_PROGRESS ? "--progress"
                                        : "--pm-grid";
    if (code == OPT_PROGRESS) {
        if (!orr_parse_double(v, &r->progress) || !(r->progress >= 0 && r->progress < 1e9))
            return cli_usage_error("ics", "--progress %s: expected seconds, at least 0 (0: no progress lines)", v);
        return EXIT_OK;
    }
    if (code == OPT_Z_START) {
        if (!orr_parse_double(v, &r->z_start) || !(r->z_start > 0 && r->z_start < 1e4))
            return cli_usage_error("ics", "--z-start %s: expected a redshift above 0 and below 1e4", v);
        return EXIT_OK;
    }
    if (code == OPT_PM_STEPS) {
        if (cli_count_option("ics", "--pm-steps", v, 1, ORR_PM_STEPS_MAX, &n) != EXIT_OK)
            return EXIT_USAGE;
        r->pm_steps = (int)n;
        return EXIT_OK;
    }
    if (cli_parse_count(v, 2, ORR_PM_MESH_MAX, &n) <= 0 || n % 2)
        return cli_usage_error("ics", "--pm-grid %s: expected an even whole number from 2 to %d", v, ORR_PM_MESH_MAX);
    r->pm_grid = (int)n;
    return EXIT_OK;
}

/* One option; EXIT_OK, -1 after --help, or a usage error. */
static int take_option(int code, const char *v, ics_request *r)
{
    long long n;
    orr_zeldovich_params *p = &r->p;
    double *number = number_option(code, p);
    if (number) {
        if (!orr_parse_double(v, number))
            return cli_usage_error("ics", "--%s %s: expected a number", option_name(code), v);
        return EXIT_OK;
    }
    switch (code) {
    case 'h':
        fputs(ics_help, stdout);
        return -1;
    case OPT_ZELDOVICH:
        r->zeldovich = 1;
        return EXIT_OK;
    case OPT_EVOLVE:
        r->evolve = 1;
        return EXIT_OK;
    case OPT_Z_START:
    case OPT_PM_STEPS:
    case OPT_PM_GRID:
    case OPT_PROGRESS:
        return take_pm_option(code, v, r);
    case 'o':
        r->out = v;
        return EXIT_OK;
    case OPT_GRID:
        if (cli_parse_count(v, 2, ORR_ZELDOVICH_GRID_MAX, &n) <= 0 || n % 2)
            return cli_usage_error("ics", "--grid %s: expected an even whole number from 2 to %d", v,
                                   ORR_ZELDOVICH_GRID_MAX);
        p->grid = (int)n;
        return EXIT_OK;
    case OPT_SEED:
        if (cli_count_option("ics", "--seed", v, 0, 9007199254740992LL, &n) != EXIT_OK)
            return EXIT_USAGE;
        p->seed = (uint64_t)n;
        return EXIT_OK;
    case CLI_OPERAND:
        return cli_usage_error("ics", "unexpected argument '%s' (the output is -o FILE)", v);
    default:
        return EXIT_USAGE;
    }
}

/* The options taken together; EXIT_OK or a usage error. */
static int check_request(ics_request *r)
{
    if (!r->zeldovich)
        return cli_usage_error("ics", "give the method: --zeldovich (the only one so far)");
    if (!r->out)
        return cli_usage_error("ics", "no output file given (-o FILE.hdf5)");
    if (r->pm_only && !r->evolve)
        return cli_usage_error("ics", "%s: only with --evolve", r->pm_only);
    if (r->evolve && !(r->p.redshift >= 0))
        return cli_usage_error("ics", "--z %g: expected a redshift from 0 (the end of the run)", r->p.redshift);
    if (r->evolve && !(r->z_start > r->p.redshift))
        return cli_usage_error("ics", "--z-start %g: expected a redshift above --z %g (the end of the run)",
                               r->z_start, r->p.redshift);
    if (!r->pm_grid) {
        int twice = 2 * r->p.grid;
        r->pm_grid = twice < ORR_PM_MESH_MAX ? twice : ORR_PM_MESH_MAX;
    }
    return EXIT_OK;
}

/* When progress lines are due (at most every `every` seconds). */
typedef struct pm_progress {
    double every, last;
    int64_t particles;
} pm_progress;

/* A progress line of the particle mesh on stderr: the step, the redshift,
 * the momentum balance (the PM's conservation check: it has no energy
 * check), particle-steps per second and the time left at that rate. */
static void pm_progress_line(void *user, int done, int steps, double a, double momentum, double seconds)
{
    pm_progress *p = user;
    if (p->every <= 0 || seconds - p->last < p->every || done == steps)
        return;
    p->last = seconds;
    double rate = done / fmax(seconds, 1e-9);
    long left = (long)((steps - done) / rate + 0.5);
    fprintf(stderr, "particle mesh: step %d of %d  z = %.3f  |sum p| / sum |p| = %.2g  %.3g particle-steps/s  %ld:%02ld left\n",
            done, steps, 1 / a - 1, momentum, rate * (double)p->particles, left / 60, left % 60);
}

/* Generates the box (at --z-start when evolving, then the PM to --z). */
static orr_status make_box(const ics_request *r, orr_zeldovich *z, orr_error *err)
{
    orr_zeldovich_params p = r->p;
    if (r->evolve)
        p.redshift = r->z_start;
    orr_status st = orr_zeldovich_generate(&p, z, err);
    if (st || !r->evolve)
        return st;
    printf("Zel'dovich start at z = %g: D(a) = %.4f, rms displacement %.3g Mpc/h\n", z->redshift, z->growth,
           z->rms_displacement);
    pm_progress progress = {r->progress, 0, z->n};
    orr_pm_params pm = {.a_end = 1 / (1 + r->p.redshift), .steps = r->pm_steps, .mesh = r->pm_grid,
                        .progress = pm_progress_line, .progress_user = &progress};
    orr_pm_report rep;
    st = orr_pm_evolve(z, &pm, &rep, err);
    if (!st)
        printf("particle mesh: %d steps on a %d³ mesh to z = %g in %.1f s; total momentum %.2g of the sum of "
               "|p|, mesh mass off by %.2g at most\n",
               pm.steps, pm.mesh, z->redshift, rep.wall_seconds, rep.momentum, rep.mesh_mass);
    return st;
}

/* The box's net velocity (equal masses: the mean of the velocities, in
 * km/s) against their rms: the box is in its centre-of-mass frame when the
 * first is round-off of the second. */
static void net_velocity(const orr_zeldovich *z, double *net, double *rms)
{
    double sum[3] = {0, 0, 0}, sum2 = 0;
    for (int64_t i = 0; i < z->n; i++)
        for (int d = 0; d < 3; d++) {
            sum[d] += z->vel[3 * i + d];
            sum2 += (double)z->vel[3 * i + d] * z->vel[3 * i + d];
        }
    double n = z->n > 0 ? (double)z->n : 1;
    *net = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) / n;
    *rms = sqrt(sum2 / n);
}

int cmd_ics(int argc, char **argv)
{
    ics_request r = {.p = {.cosmo = orr_cosmology_default(), .grid = 64, .box = 100, .redshift = 0, .seed = 1},
                     .z_start = 24, .pm_steps = 40, .progress = 10};
    const char *value;
    int code;
    cli_options_begin();
    while ((code = cli_next_option("ics", argc, argv, "ho:", ics_options, &value)) != -1) {
        int st = take_option(code, value, &r);
        if (st != EXIT_OK)
            return st < 0 ? EXIT_OK : st;
    }
    int bad = check_request(&r);
    if (bad)
        return bad;
    orr_error err = {0};
    orr_zeldovich z;
    orr_status st = make_box(&r, &z, &err);
    if (st == ORR_ERR_USAGE) {
        orr_zeldovich_free(&z);
        return cli_usage_error("ics", "%s", err.msg);
    }
    if (!st)
        st = orr_zeldovich_write_hdf5(&z, r.out, &err);
    if (st) {
        orr_zeldovich_free(&z);
        return cli_report_error(&err);
    }
    printf("wrote %lld particles to %s: box %g Mpc/h, z = %g, D(a) = %.4f, f = %.4f, rms displacement %.3g Mpc/h "
           "(%.3g cells), particle mass %.4g e10 Msun/h\n",
           (long long)z.n, r.out, z.box, z.redshift, z.growth, z.rate, z.rms_displacement,
           z.rms_displacement / (z.box / z.grid), z.particle_mass);
    double net, rms;
    net_velocity(&z, &net, &rms);
    printf("centre-of-mass frame: net velocity %.2g km/s, %.2g of the rms velocity %.3g km/s\n", net,
           rms > 0 ? net / rms : 0, rms);
    orr_zeldovich_free(&z);
    return EXIT_OK;
}
