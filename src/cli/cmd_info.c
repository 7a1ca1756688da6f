/* orrery info FILE [--format FORMAT] */
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "source/source.h"

static const char info_help[] =
    "usage: orrery info FILE [--format FORMAT]\n"
    "\n"
    "Reads every particle of FILE and prints its format, time, header entries\n"
    "(units; for HDF5 every dataset of the particle groups with its shape, the\n"
    "field names it gives and its units; an .npz archive's scalars), particle\n"
    "count per type, fields, position bounds and total mass.\n"
    "\n"
    "  --format FORMAT   auto (default: detect from the contents) or a format name\n"
    "                    (listed below)\n"
    "  -h, --help        this text\n";

typedef struct summary {
    uint64_t n, n_nonfinite;
    uint64_t per_type[256];
    double mass_per_type[256];
    double lo[3], hi[3];
    double mass, mass_min, mass_max;
} summary;

static void summary_init(summary *s)
{
    memset(s, 0, sizeof *s);
    for (int k = 0; k < 3; k++) {
        s->lo[k] = DBL_MAX;
        s->hi[k] = -DBL_MAX;
    }
    s->mass_min = DBL_MAX;
    s->mass_max = -DBL_MAX;
}

static void summary_add(summary *s, const orr_chunk *c)
{
    for (size_t i = 0; i < c->n; i++) {
        const float p[3] = {c->x[i], c->y[i], c->z[i]};
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            s->n_nonfinite++;
        } else {
            for (int k = 0; k < 3; k++) {
                s->lo[k] = fmin(s->lo[k], p[k]);
                s->hi[k] = fmax(s->hi[k], p[k]);
            }
        }
        s->per_type[c->type[i]]++;
        s->mass_per_type[c->type[i]] += c->mass[i];
        s->mass += c->mass[i];
        s->mass_min = fmin(s->mass_min, c->mass[i]);
        s->mass_max = fmax(s->mass_max, c->mass[i]);
    }
    s->n += c->n;
}

static void print_summary(const orr_source_info *info, const summary *s)
{
    printf("file:       %s\n", info->path);
    printf("format:     %s\n", info->format);
    printf("time:       %.10g\n", info->time);
    for (int i = 0; i < info->nheader; i++)
        printf("  %-24s %s\n", info->header[i].key, info->header[i].value);
    printf("particles:  %llu\n", (unsigned long long)s->n);
    if (info->has_type)
        for (int t = 0; t < 256; t++)
            if (s->per_type[t])
                printf("  type %d:   %llu particles, mass %.9g\n", t, (unsigned long long)s->per_type[t],
                       s->mass_per_type[t]);
    printf("fields:     x y z mass%s%s%s", info->has_h ? " h" : "", info->has_id ? " id" : "",
           info->has_type ? " type" : "");
    for (int i = 0; i < info->nextra; i++)
        printf(" %s", info->extra_names[i]);
    printf("\n");
    if (s->n > s->n_nonfinite) {
        static const char axis[3] = {'x', 'y', 'z'};
        for (int k = 0; k < 3; k++)
            printf("%c range:    [%.9g, %.9g]\n", axis[k], s->lo[k], s->hi[k]);
    }
    if (s->n_nonfinite)
        printf("non-finite positions: %llu particles\n", (unsigned long long)s->n_nonfinite);
    if (s->n)
        printf("mass:       total %.9g (per particle %.9g to %.9g)\n", s->mass, s->mass_min, s->mass_max);
}

static const struct option info_options[] = {
    {"format", required_argument, NULL, 'f'},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

int cmd_info(int argc, char **argv)
{
    const char *path = NULL, *format = "auto", *value;
    int code;
    cli_options_begin();
    while ((code = cli_next_option("info", argc, argv, "h", info_options, &value)) != -1) {
        if (code == 'h') {
            fputs(info_help, stdout);
            printf("\nformats: %s\n", orr_source_format_names());
            return EXIT_OK;
        } else if (code == 'f') {
            format = value;
        } else if (code != CLI_OPERAND) {
            return EXIT_USAGE;
        } else if (path) {
            return cli_usage_error("info", "one file at a time (got '%s' and '%s')", path, value);
        } else {
            path = value;
        }
    }
    if (!path)
        return cli_usage_error("info", "no file given");
    orr_error err = {0};
    orr_source *src = NULL;
    summary s;
    summary_init(&s);
    orr_source_options opt = {.format = format, .chunk_size = (size_t)1 << 20};
    orr_status st = orr_source_open_file(path, &opt, &src, &err);
    while (!st) {
        const orr_chunk *c;
        if ((st = orr_source_next(src, &c, &err)) || c->n == 0)
            break;
        summary_add(&s, c);
    }
    if (!st)
        print_summary(&src->info, &s);
    orr_source_close(src);
    return st ? cli_report_error(&err) : EXIT_OK;
}
