/* orrery model -o FILE [--particles N] [--seed S] [--separation KPC] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "source/model.h"
#include "source/text_writer.h"

static const char model_help[] =
    "usage: orrery model -o FILE [--particles N] [--seed S] [--separation KPC]\n"
    "\n"
    "Writes the built-in Milky Way-Andromeda model as a text table (columns\n"
    "x y z mass id type vx vy vz r E0; kpc, 1e10 Msun, km/s) that 'orrery render'\n"
    "and 'orrery info' read. Scenes can also use the model directly with\n"
    "input.model.name: mw-m31, without a file. See docs/model.md.\n"
    "\n"
    "  -o, --output FILE     where to write (required)\n"
    "  --particles N         particles in all, markers included (default 200000; 100 to 2e9)\n"
    "  --seed S              random seed (default 1); the same seed gives the same model\n"
    "  --separation KPC      distance between the galaxy centres (default 780, today's)\n"
    "  -h, --help            this text\n";

int cmd_model(int argc, char **argv)
{
    orr_model_params params = {200000, 1, 780.0, ORR_MODEL_PAIR, 0};
    const char *out = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            fputs(model_help, stdout);
            return EXIT_OK;
        }
        int takes_value = strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0 || strcmp(a, "--particles") == 0 ||
                          strcmp(a, "--seed") == 0 || strcmp(a, "--separation") == 0;
        if (!takes_value)
            return cli_usage_error("model", "unknown argument '%s'", a);
        if (i + 1 >= argc)
            return cli_usage_error("model", "%s needs a value", a);
        const char *v = argv[++i];
        long long n;
        if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            out = v;
        } else if (strcmp(a, "--particles") == 0) {
            if (!cli_parse_count(v, 100, ORR_MODEL_PARTICLES_MAX, &n))
                return cli_usage_error("model", "--particles %s: expected a whole number from 100 to %lld", v,
                                       (long long)ORR_MODEL_PARTICLES_MAX);
            params.particles = n;
        } else if (strcmp(a, "--seed") == 0) {
            if (!cli_parse_count(v, 0, 9007199254740992LL, &n))
                return cli_usage_error("model", "--seed %s: expected a whole number >= 0", v);
            params.seed = (uint64_t)n;
        } else {
            char *end;
            double d = strtod(v, &end);
            if (end == v || *end || !(d > 0 && d < 1e6))
                return cli_usage_error("model", "--separation %s: expected a distance in kpc above 0", v);
            params.separation_kpc = d;
        }
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
