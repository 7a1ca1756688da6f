/* orrery ics --zeldovich -o FILE [--grid N] [--box L] [--z Z] [--seed S]
 *            [--truncate K] [--omega-m X] [--omega-lambda X] [--omega-b X] [--h X]
 *            [--sigma8 X] [--ns X] */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "core/numbers.h"
#include "source/zeldovich.h"

static const char ics_help[] =
    "usage: orrery ics --zeldovich -o FILE.hdf5 [--grid N] [--box MPC_H] [--z Z] [--seed S] [--truncate K]\n"
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
    "  --omega-m, --omega-lambda, --omega-b, --h, --sigma8, --ns\n"
    "                        cosmology (default Planck 2018: 0.315 0.685 0.049 0.674 0.811 0.965)\n"
    "  -h, --help            this text\n";

enum {
    OPT_ZELDOVICH = 256, OPT_GRID, OPT_SEED, OPT_BOX, OPT_Z, OPT_TRUNCATE,
    OPT_OMEGA_M, OPT_OMEGA_LAMBDA, OPT_OMEGA_B, OPT_H, OPT_SIGMA8, OPT_NS,
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

/* One option; EXIT_OK, -1 after --help, or a usage error. */
static int take_option(int code, const char *v, orr_zeldovich_params *p, const char **out, int *zeldovich)
{
    long long n;
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
        *zeldovich = 1;
        return EXIT_OK;
    case 'o':
        *out = v;
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

int cmd_ics(int argc, char **argv)
{
    orr_zeldovich_params p = {.cosmo = orr_cosmology_default(), .grid = 64, .box = 100, .redshift = 0, .seed = 1};
    const char *out = NULL, *value;
    int zeldovich = 0, code;
    cli_options_begin();
    while ((code = cli_next_option("ics", argc, argv, "ho:", ics_options, &value)) != -1) {
        int st = take_option(code, value, &p, &out, &zeldovich);
        if (st != EXIT_OK)
            return st < 0 ? EXIT_OK : st;
    }
    if (!zeldovich)
        return cli_usage_error("ics", "give the method: --zeldovich (the only one so far)");
    if (!out)
        return cli_usage_error("ics", "no output file given (-o FILE.hdf5)");
    orr_error err = {0};
    orr_zeldovich z;
    orr_status st = orr_zeldovich_generate(&p, &z, &err);
    if (st == ORR_ERR_USAGE)
        return cli_usage_error("ics", "%s", err.msg);
    if (!st)
        st = orr_zeldovich_write_hdf5(&z, out, &err);
    if (st) {
        orr_zeldovich_free(&z);
        return cli_report_error(&err);
    }
    printf("wrote %lld particles to %s: box %g Mpc/h, z = %g, D(a) = %.4f, f = %.4f, rms displacement %.3g Mpc/h "
           "(%.3g cells), particle mass %.4g e10 Msun/h\n",
           (long long)z.n, out, z.box, z.redshift, z.growth, z.rate, z.rms_displacement,
           z.rms_displacement / (z.box / z.grid), z.particle_mass);
    orr_zeldovich_free(&z);
    return EXIT_OK;
}
