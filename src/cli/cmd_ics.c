/* orrery ics --zeldovich -o FILE [--grid N] [--box L] [--z Z] [--seed S]
 *            [--truncate K] [--omega-m X] [--omega-lambda X] [--omega-b X] [--h X]
 *            [--sigma8 X] [--ns X] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
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

static int is_option(const char *a, const char *name)
{
    return strcmp(a, name) == 0;
}

/* The cosmology and box options that take a number. */
static double *number_option(const char *a, orr_zeldovich_params *p)
{
    if (is_option(a, "--box"))
        return &p->box;
    if (is_option(a, "--z"))
        return &p->redshift;
    if (is_option(a, "--truncate"))
        return &p->truncate;
    if (is_option(a, "--omega-m"))
        return &p->cosmo.omega_m;
    if (is_option(a, "--omega-lambda"))
        return &p->cosmo.omega_lambda;
    if (is_option(a, "--omega-b"))
        return &p->cosmo.omega_b;
    if (is_option(a, "--h"))
        return &p->cosmo.h;
    if (is_option(a, "--sigma8"))
        return &p->cosmo.sigma8;
    if (is_option(a, "--ns"))
        return &p->cosmo.n_s;
    return NULL;
}

int cmd_ics(int argc, char **argv)
{
    orr_zeldovich_params p = {.cosmo = orr_cosmology_default(), .grid = 64, .box = 100, .redshift = 0, .seed = 1};
    const char *out = NULL;
    int zeldovich = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (is_option(a, "-h") || is_option(a, "--help")) {
            fputs(ics_help, stdout);
            return EXIT_OK;
        }
        if (is_option(a, "--zeldovich")) {
            zeldovich = 1;
            continue;
        }
        double *number = number_option(a, &p);
        int takes_value = number || is_option(a, "-o") || is_option(a, "--output") || is_option(a, "--grid") ||
                          is_option(a, "--seed");
        if (!takes_value)
            return cli_usage_error("ics", "unknown argument '%s'", a);
        if (i + 1 >= argc)
            return cli_usage_error("ics", "%s needs a value", a);
        const char *v = argv[++i];
        long long n;
        if (is_option(a, "-o") || is_option(a, "--output")) {
            out = v;
        } else if (is_option(a, "--grid")) {
            if (!cli_parse_count(v, 2, ORR_ZELDOVICH_GRID_MAX, &n) || n % 2)
                return cli_usage_error("ics", "--grid %s: expected an even whole number from 2 to %d", v,
                                       ORR_ZELDOVICH_GRID_MAX);
            p.grid = (int)n;
        } else if (is_option(a, "--seed")) {
            if (!cli_parse_count(v, 0, 9007199254740992LL, &n))
                return cli_usage_error("ics", "--seed %s: expected a whole number >= 0", v);
            p.seed = (uint64_t)n;
        } else {
            char *end;
            double d = strtod(v, &end);
            if (end == v || *end)
                return cli_usage_error("ics", "%s %s: expected a number", a, v);
            *number = d;
        }
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
