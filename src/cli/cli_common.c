/* The pieces every command shares: error reporting, number parsing, the
 * clock and the particle progress line (also linked into orrery-mpi). */
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"
#include "core/numbers.h"
#include "core/atomic.h"

int cli_report_error(const orr_error *err)
{
    fprintf(stderr, "orrery: error: %s\n", err->msg[0] ? err->msg : "unknown error");
    return err->code == ORR_ERR_USAGE ? EXIT_USAGE : EXIT_RUNTIME;
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "orrery: error: %s (see 'orrery %s --help')\n", msg, command);
    return EXIT_USAGE;
}

int cli_parse_count(const char *text, long long min, long long max, long long *out)
{
    char *end;
    double v = orr_strtod(text, &end);
    if (end == text || *end != '\0')
        return 0;
    if (isnan(v))
        return -1;
    /* The range first: the cast below is defined only within it. */
    if (!(v >= (double)min && v <= (double)max) || v != (double)(long long)v)
        return 0;
    *out = (long long)v;
    return 1;
}

int cli_count_option(const char *command, const char *option, const char *text, long long min, long long max,
                     long long *out)
{
    int ok = cli_parse_count(text, min, max, out);
    if (ok > 0)
        return EXIT_OK;
    return cli_usage_error(command, "%s %s: %sexpected a whole number from %lld to %lld", option, text,
                           ok < 0 ? "not a number; " : "", min, max);
}

/* Set once getopt_long has returned -1: the rest of argv are operands
 * (those after "--"), and getopt_long must not look at them again. */
static int options_ended;

void cli_options_begin(void)
{
    optind = 0; /* glibc: start afresh (a command may be parsed more than once in a test) */
    opterr = 0; /* the messages are ours, in the one-line form */
    options_ended = 0;
}

/* Whether arg is "--NAME=..." for a long option NAME that takes no value
 * and whose val is code: getopt_long's other reason for '?'. */
static int given_needless_value(const char *arg, const struct option *longs, int code)
{
    const char *eq = strchr(arg, '=');
    if (strncmp(arg, "--", 2) != 0 || !eq)
        return 0;
    for (const struct option *o = longs; o->name; o++)
        if (o->has_arg == no_argument && o->val == code && strlen(o->name) == (size_t)(eq - arg - 2) &&
            strncmp(o->name, arg + 2, (size_t)(eq - arg - 2)) == 0)
            return 1;
    return 0;
}

/* The option getopt_long has just refused, as the user wrote it. A short
 * option refused inside a bundle (-xq) leaves optind on its element, so
 * only optopt is trusted for those. */
static void bad_option(const char *command, int code, char **argv, const struct option *longs)
{
    const char *arg = argv[optind - 1];
    if (code == ':')
        cli_usage_error(command, "option '%s' needs a value", arg);
    else if (optopt && given_needless_value(arg, longs, optopt))
        cli_usage_error(command, "option '%.*s' takes no value", (int)strcspn(arg, "="), arg);
    else if (optopt > 0 && optopt < 256)
        cli_usage_error(command, "unknown option '-%c'", optopt);
    else
        cli_usage_error(command, "unknown option '%s'", arg);
}

int cli_next_option(const char *command, int argc, char **argv, const char *shorts, const struct option *longs,
                    const char **value)
{
    /* "-": operands are returned in order, as option 1; ":": a missing
     * value is told apart from an unknown option. */
    char spec[64];
    snprintf(spec, sizeof spec, "-:%s", shorts);
    *value = NULL;
    if (!options_ended) {
        int code = getopt_long(argc, argv, spec, longs, NULL);
        if (code == '?' || code == ':') {
            bad_option(command, code, argv, longs);
            return CLI_BAD;
        }
        if (code != -1) {
            *value = optarg;
            return code;
        }
        options_ended = 1;
    }
    if (optind >= argc)
        return -1;
    *value = argv[optind++]; /* an operand after "--" */
    return CLI_OPERAND;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_init(cli_progress *p, int enabled)
{
    p->enabled = enabled;
    p->tty = isatty(STDERR_FILENO);
    p->start = p->last = cli_now();
    p->last_decile = 0;
}

void cli_progress_update(void *user, uint64_t done, int64_t total)
{
    cli_progress *p = user;
    if (!p->enabled)
        return;
    double now = cli_now();
    double rate = done / (now - p->start > 1e-9 ? now - p->start : 1e-9);
    if (p->tty) {
        if (now - p->last < 0.2)
            return;
        p->last = now;
        if (total > 0)
            fprintf(stderr, "\r  %llu / %lld particles (%.0f%%), %.3g particles/s, %.0f s left   ",
                    (unsigned long long)done, (long long)total, 100.0 * done / total, rate,
                    (total - (double)done) / (rate > 0 ? rate : 1));
        else
            fprintf(stderr, "\r  %llu particles, %.3g particles/s   ", (unsigned long long)done, rate);
        return;
    }
    if (total > 0) {
        int decile = (int)(10.0 * done / total);
        if (decile > p->last_decile && decile < 10) {
            p->last_decile = decile;
            fprintf(stderr, "  %d%%: %llu of %lld particles, %.3g particles/s\n", 10 * decile,
                    (unsigned long long)done, (long long)total, rate);
        }
    }
}

void cli_progress_finish(cli_progress *p)
{
    if (p->enabled && p->tty && cli_now() - p->start >= 0.2)
        fprintf(stderr, "\r%80s\r", "");
}

/* ---- interruptions ---- */

static void remove_temporaries_and_die(int sig)
{
    orr_remove_live_temporaries();
    signal(sig, SIG_DFL);
    raise(sig); /* die of the signal, so the shell and a parent see it */
}

void cli_clean_up_on_signals(void)
{
    const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = remove_temporaries_and_die;
        sigemptyset(&sa.sa_mask);
        struct sigaction old;
        /* A signal the caller chose to ignore (nohup) stays ignored. */
        if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler != SIG_IGN)
            sigaction(sigs[i], &sa, NULL);
    }
}
