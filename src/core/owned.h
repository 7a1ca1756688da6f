/* Owned strings: the file and folder names of the settings structs (a
 * scene's input.file, output.dir, psf.file, ...) and the scene's own path
 * and folder are heap strings the struct owns, so that a scene is not
 * mostly empty ORR_PATH_MAX buffers (docs/architecture.md).
 *
 * The convention: a field is a `char *`, NULL when unset, never "" (setting
 * "" unsets it). Each struct that holds such fields owns them alone: its
 * free function frees them, and a copy of the struct duplicates them (a
 * struct assignment followed by orr_owned_dup_all: orr_owned_copy, which the
 * structs' copy functions do), so no two structs share a string and none is
 * freed twice. A struct that is zeroed (calloc, memset, = {0}) holds none
 * and may be freed or copied into. */
#ifndef ORR_CORE_OWNED_H
#define ORR_CORE_OWNED_H

#include <stddef.h>

#include "core/error.h"

/* Sets *field to a copy of value (NULL or "": unset), freeing what it held. */
orr_status orr_owned_set(char **field, const char *value, orr_error *err);

/* Frees *field and sets it to NULL. */
void orr_owned_free(char **field);

/* After a struct assignment, the n fields (pointers copied from the source
 * struct) are replaced by copies of their own. Every field is replaced even
 * when one fails (out of memory), left NULL then, so the struct never
 * shares a string with its source. */
orr_status orr_owned_dup_all(char **const *fields, int n, orr_error *err);

/* *dst = *src (size bytes) for a struct whose n owned strings are at
 * fields, the addresses of the fields inside dst: dst's strings are freed
 * first, and src's copied after, so the two share none. Nothing is done
 * when dst is src. Each struct's _copy is this over its list of strings. */
orr_status orr_owned_copy(void *dst, const void *src, size_t size, char **const *fields, int n, orr_error *err);

/* orr_owned_free on each of the n fields. */
void orr_owned_free_all(char **const *fields, int n);

/* The string, or "" when unset: for messages and comparisons. */
static inline const char *orr_owned_text(const char *s) { return s ? s : ""; }

#endif
