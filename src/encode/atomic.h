/* Files are written to a temporary name in the target directory and renamed
 * into place only when complete, so an interrupted run never leaves a
 * truncated output under its final name. */
#ifndef ORR_ENCODE_ATOMIC_H
#define ORR_ENCODE_ATOMIC_H

#include "core/error.h"
#include "source/source.h" /* ORR_PATH_MAX */

typedef struct orr_atomic_file {
    char final_path[ORR_PATH_MAX];
    char temp_path[ORR_PATH_MAX]; /* "<dir>/.<name>.tmp-XXXXXX", created empty */
} orr_atomic_file;

/* Creates the temporary file beside final_path. Fails with a message naming
 * the directory when it cannot be written. */
orr_status orr_atomic_begin(orr_atomic_file *af, const char *final_path, orr_error *err);
/* Renames the temporary file to the final name. */
orr_status orr_atomic_commit(orr_atomic_file *af, orr_error *err);
/* Removes the temporary file (safe to call after a failed commit). */
void orr_atomic_abort(orr_atomic_file *af);

/* Checks that directory dir exists (creating it, and the folders above it,
 * when missing)
 * and that a file can be created in it. */
orr_status orr_check_output_dir(const char *dir, orr_error *err);

#endif
