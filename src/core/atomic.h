/* Files are written to a temporary name in the target directory and renamed
 * into place only when complete, so an interrupted run never leaves a
 * truncated output under its final name. A frame's outputs go further: they
 * are all written to temporary names first and renamed together
 * (orr_output_batch), so a failure part-way leaves none of the new ones.
 *
 * Temporary names are ".orrery-tmp-HOST-PID-N-NAME" (HOST: 8 hex digits of
 * the host name's hash, PID: the writing process, N: a counter), so that a
 * later run can tell which ones belong to a process that is gone and remove
 * them (orr_remove_stale_temporaries), and a signal handler can remove the
 * ones still open (orr_remove_live_temporaries). docs/output.md. */
#ifndef ORR_CORE_ATOMIC_H
#define ORR_CORE_ATOMIC_H

#include "core/error.h"
#include "core/limits.h"

#define ORR_TEMP_PREFIX ".orrery-tmp-"

typedef struct orr_atomic_file {
    char final_path[ORR_PATH_MAX];
    char temp_path[ORR_PATH_MAX]; /* "<dir>/.orrery-tmp-HOST-PID-N-<name>", created empty */
    int live_slot;                /* its entry in the list a signal handler removes, or -1 */
} orr_atomic_file;

/* Creates the temporary file beside final_path. Fails with a message naming
 * the directory when it cannot be written, and when final_path is an
 * existing folder (a file could never be renamed over it). */
orr_status orr_atomic_begin(orr_atomic_file *af, const char *final_path, orr_error *err);
/* Renames the temporary file to the final name. */
orr_status orr_atomic_commit(orr_atomic_file *af, orr_error *err);
/* Removes the temporary file (safe to call after a failed commit). */
void orr_atomic_abort(orr_atomic_file *af);

/* Removes every temporary file this process has begun and not yet committed
 * or aborted. Async-signal-safe: for a SIGINT/SIGTERM handler, which should
 * then re-raise the signal. */
void orr_remove_live_temporaries(void);

/* Removes from dir the temporary files of processes of this host that no
 * longer run (a killed earlier run). Files of running processes, of other
 * hosts (a shared folder) and anything not named like ours are kept.
 * Returns how many were removed; a folder that cannot be read gives 0. */
int orr_remove_stale_temporaries(const char *dir);

/* All of a frame's outputs: each is written to its temporary name, and
 * orr_output_batch_commit renames them all once every one is written. */
typedef struct orr_output_batch {
    int n, cap;
    orr_atomic_file **files; /* each allocated on its own: the paths handed out stay put */
} orr_output_batch;

void orr_output_batch_init(orr_output_batch *b);
/* Reserves final_path in the batch; *write_path is the temporary file to
 * write it to (valid until commit or abort). Two outputs of one batch may
 * not share a final path. */
orr_status orr_output_batch_add(orr_output_batch *b, const char *final_path, const char **write_path,
                                orr_error *err);
/* Renames every output into place, in the order added, and empties the
 * batch. Should a rename fail part-way (the disk or folder changed under
 * the run), the outputs renamed before it stay, the rest are removed, and
 * the message says which. */
orr_status orr_output_batch_commit(orr_output_batch *b, orr_error *err);
/* Removes every temporary file of the batch and empties it. */
void orr_output_batch_abort(orr_output_batch *b);
/* In err's message, names each output by its final path instead of the
 * temporary one a writer was given: what the user asked for. */
void orr_output_batch_name_finals(const orr_output_batch *b, orr_error *err);

/* Checks that directory dir exists (creating it, and the folders above it,
 * when missing) and that a file can be created in it. */
orr_status orr_check_output_dir(const char *dir, orr_error *err);

#endif
