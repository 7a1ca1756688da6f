/* The pieces every command shares: error reporting, number parsing, the
 * clock and the particle progress line (also linked into orrery-mpi). */
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli/cli.h"
#include "encode/atomic.h"

int cli_report_error(const orr_error *err)
{
    fprintf(stderr, "orrery: error: %s\n", err->msg[0] ? err->msg : "unknown error");
    return err->code == ORR_ERR_USAGE ? EXIT_USAGE : EXIT_RUNTIME;
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "orrery %s: ", command);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(see 'orrery %s --help')\n", command);
    va_end(ap);
    return EXIT_USAGE;
}

int cli_parse_count(const char *text, long long min, long long max, long long *out)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !(v >= (double)min && v <= (double)max) || v != (double)(long long)v)
        return 0;
    *out = (long long)v;
    return 1;
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
