/* Shared pieces of the command-line tool. Exit codes: 0 success, 1 runtime
 * failure, 2 usage error (bad option, bad scene). */
#ifndef ORR_CLI_CLI_H
#define ORR_CLI_CLI_H

#include <stdint.h>

#include "core/error.h"
#include "render/render.h"

enum { EXIT_OK = 0, EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

/* Set by orrery-mpi (src/mpi/orrery_mpi.c) before a command runs: the MPI
 * ranks that render together. NULL in the plain `orrery`. */
extern const orr_parallel *cli_parallel;

int cmd_render(int argc, char **argv);
int cmd_compose(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_model(int argc, char **argv);
int cmd_ics(int argc, char **argv);
int cmd_path(int argc, char **argv);
int cmd_video(int argc, char **argv);

/* Prints "orrery: <message>" to stderr and returns the exit code for it. */
int cli_report_error(const orr_error *err);
/* Prints "orrery <command>: <message>" and a hint to stderr; returns EXIT_USAGE. */
int cli_usage_error(const char *command, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Parses a positive whole number (accepts forms like 1e6); returns 0 when bad. */
int cli_parse_count(const char *text, long long min, long long max, long long *out);

/* Progress on stderr: a line rewritten in place on a terminal, a plain line
 * every 10% otherwise. */
typedef struct cli_progress {
    int enabled, tty;
    double start, last;
    int last_decile;
} cli_progress;
void cli_progress_init(cli_progress *p, int enabled);
void cli_progress_update(void *user, uint64_t done, int64_t total);
void cli_progress_finish(cli_progress *p);
double cli_now(void);

/* On SIGINT, SIGTERM and SIGHUP: removes the temporary files of outputs
 * being written, then dies of the signal. */
void cli_clean_up_on_signals(void);

#endif
