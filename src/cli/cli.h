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

/* Prints "orrery: error: <message>" to stderr and returns the exit code for it. */
int cli_report_error(const orr_error *err);
/* Prints "orrery: error: <message> (see 'orrery <command> --help')" to
 * stderr, the one-line form of docs/cli.md; returns EXIT_USAGE. */
int cli_usage_error(const char *command, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Parses a whole number (accepts forms like 1e6) from min to max; returns
 * 1 and *out, 0 when it is not one in the range, -1 when it is NaN. */
int cli_parse_count(const char *text, long long min, long long max, long long *out);
/* The value of a whole-number option, or the usage error naming option and
 * range ("not a number" for a NaN): EXIT_OK or EXIT_USAGE. */
int cli_count_option(const char *command, const char *option, const char *text, long long min, long long max,
                     long long *out);

/* Options: getopt_long over a command's arguments (argv[0] is the command's
 * name), so --output=DIR, -oDIR, --output DIR, bundled short options and
 * "--" all work as in other GNU tools. Operands (a scene file) may come
 * anywhere, in order. cli_next_option returns the short letter or the long
 * option's val, CLI_OPERAND with the operand in *value, -1 at the end, or
 * CLI_BAD after printing the usage error (unknown option, missing value). */
enum { CLI_OPERAND = 1, CLI_BAD = '?' };
struct option;
void cli_options_begin(void);
int cli_next_option(const char *command, int argc, char **argv, const char *shorts, const struct option *longs,
                    const char **value);

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

/* --timings: each rendered frame's stage times added up (and, for a run,
 * a line a frame), then printed as a table on stdout. */
typedef struct cli_timings {
    int per_frame_lines;
    orr_stage_times total;
} cli_timings;
/* An orr_animation_options.timed callback; user is a cli_timings. */
void cli_timings_frame(void *user, long frame, const orr_stage_times *t);
void cli_timings_print(const cli_timings *ct);

/* On SIGINT, SIGTERM and SIGHUP: removes the temporary files of outputs
 * being written, then dies of the signal. */
void cli_clean_up_on_signals(void);

#endif
