/* orrery model -o FILE [--particles N] [--seed S] [--separation KPC] [--galaxies pair|mw|m31] [--disc-q Q]
 *               [--m31-weight W] */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "core/numbers.h"
#include "source/models/model.h"
#include "source/writers/text_writer.h"

static const char model_help[] =
    "usage: orrery model -o FILE [--particles N] [--seed S] [--separation KPC]\n"
    "                    [--galaxies pair|mw|m31] [--disc-q Q] [--m31-weight W]\n"
    "\n"
    "Writes the built-in Milky Way-Andromeda model (or one galaxy alone) as a\n"
    "text table (columns x y z mass id type vx vy vz r E0 ez; kpc, 1e10 Msun, km/s;\n"
    "r and E0 the distance from the galaxy's centre and the binding energy, ez a\n"
    "disc star's vertical energy over sigma_z^2 (0 off the discs), all at the start)\n"
    "that 'orrery render' and 'orrery info' read. Scenes can also use the model\n"
    "directly with input.model.name: mw-m31, without a file (the options below are\n"
    "its keys input.model.particles, .seed, .separation, .galaxies, .disc_q,\n"
    ".m31_weight).\n"
    "See docs/model.md.\n"
    "\n"
    "  -o, --output FILE     where to write (required)\n"
    "  --particles N         particles in all, markers included (default 200000; 100 to 2e9)\n"
    "  --seed S              random seed (default 1); the same seed gives the same model\n"
    "  --separation KPC      distance between the galaxy centres (default 780, today's;\n"
    "                        the pair only)\n"
    "  --galaxies WHICH      pair: both on their approach orbit (default); mw: the Milky\n"
    "                        Way alone with the Sun; m31: Andromeda alone (each at rest\n"
    "                        at the origin)\n"
    "  --disc-q Q            the discs' Toomre Q at 2.43 scale lengths (default 1.5;\n"
    "                        above 0, at most 100; below 1 a disc is unstable)\n"
    "  --m31-weight W        the pair: each of M31's particles weighs W times the Milky\n"
    "                        Way's of the same kind, so the Milky Way gets more of the\n"
    "                        particles (default 1; 1/64 to 64)\n"
    "  -h, --help            this text\n";

enum { OPT_PARTICLES = 256, OPT_SEED, OPT_SEPARATION, OPT_GALAXIES, OPT_DISC_Q, OPT_M31_WEIGHT };

static const struct option model_options[] = {
    {"output", required_argument, NULL, 'o'},        {"particles", required_argument, NULL, OPT_PARTICLES},
    {"seed", required_argument, NULL, OPT_SEED},     {"separation", required_argument, NULL, OPT_SEPARATION},
    {"galaxies", required_argument, NULL, OPT_GALAXIES},  {"disc-q", required_argument, NULL, OPT_DISC_Q},
    {"m31-weight", required_argument, NULL, OPT_M31_WEIGHT},
    {"help", no_argument, NULL, 'h'},                {NULL, 0, NULL, 0},
};

/* One option; EXIT_OK, -1 after --help, or a usage error. */
static int take_option(int code, const char *v, orr_model_params *params, const char **out)
{
    long long n;
    double d;
    switch (code) {
    case 'h':
        fputs(model_help, stdout);
        return -1;
    case 'o':
        *out = v;
        return EXIT_OK;
    case OPT_PARTICLES:
        if (cli_count_option("model", "--particles", v, 100, ORR_MODEL_PARTICLES_MAX, &n) != EXIT_OK)
            return EXIT_USAGE;
        params->particles = n;
        return EXIT_OK;
    case OPT_SEED:
        if (cli_count_option("model", "--seed", v, 0, 9007199254740992LL, &n) != EXIT_OK)
            return EXIT_USAGE;
        params->seed = (uint64_t)n;
        return EXIT_OK;
    case OPT_SEPARATION:
        if (!orr_parse_double(v, &d) || !(d > 0 && d < 1e6))
            return cli_usage_error("model", "--separation %s: expected a distance in kpc above 0 (and below 1e6)", v);
        params->separation_kpc = d;
        return EXIT_OK;
    case OPT_GALAXIES:
        if ((params->galaxies = orr_model_galaxies_named(v)) < 0)
            return cli_usage_error("model", "--galaxies %s: expected " ORR_MODEL_GALAXIES_WORDS, v);
        return EXIT_OK;
    case OPT_DISC_Q:
        if (!orr_parse_double(v, &d) || !(d > 0 && d <= ORR_MODEL_DISC_Q_MAX))
            return cli_usage_error("model", "--disc-q %s: expected the discs' Toomre Q, above 0 and at most %g", v,
                                   ORR_MODEL_DISC_Q_MAX);
        params->disc_q = d;
        return EXIT_OK;
    case OPT_M31_WEIGHT:
        if (!orr_parse_double(v, &d) || !(d >= 1.0 / ORR_MODEL_M31_WEIGHT_MAX && d <= ORR_MODEL_M31_WEIGHT_MAX))
            return cli_usage_error("model", "--m31-weight %s: expected how many times the Milky Way's particles each "
                                   "of M31's weighs, from %g to %g", v, 1.0 / ORR_MODEL_M31_WEIGHT_MAX,
                                   ORR_MODEL_M31_WEIGHT_MAX);
        params->m31_weight = d;
        return EXIT_OK;
    case CLI_OPERAND:
        return cli_usage_error("model", "unexpected argument '%s' (the output is -o FILE)", v);
    default:
        return EXIT_USAGE;
    }
}

int cmd_model(int argc, char **argv)
{
    orr_model_params params = {200000, 1, 780.0, ORR_MODEL_PAIR, 0, 0, 0, 0};
    const char *out = NULL, *value;
    int code;
    cli_options_begin();
    while ((code = cli_next_option("model", argc, argv, "ho:", model_options, &value)) != -1) {
        int st = take_option(code, value, &params, &out);
        if (st != EXIT_OK)
            return st < 0 ? EXIT_OK : st;
    }
    if (!out)
        return cli_usage_error("model", "no output file given (-o FILE)");
    orr_error err = {0};
    orr_source *src = NULL;
    orr_status st = orr_model_source_open(&params, 1 << 20, &src, &err);
    if (!st)
        st = orr_text_write_source(src, out, &err);
    orr_source_close(src);
    if (st)
        return cli_report_error(&err);
    printf("wrote %lld particles to %s\n", params.particles, out);
    return EXIT_OK;
}
