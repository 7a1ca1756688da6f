/* Error reporting for the library: functions return an orr_status and fill an
 * orr_error with a message that names the file, field and what was wrong.
 * The library never prints on its own behalf and never calls exit(); the CLI
 * decides what to do with an error. */
#ifndef ORR_CORE_ERROR_H
#define ORR_CORE_ERROR_H

#include <stddef.h>

typedef enum {
    ORR_OK = 0,
    ORR_ERR_USAGE = 2,   /* bad scene, bad option, bad value: the user's input */
    ORR_ERR_IO = 3,      /* a file could not be opened, read or written */
    ORR_ERR_FORMAT = 4,  /* a file was read but its contents are wrong */
    ORR_ERR_DATA = 5,    /* the particles themselves are unusable (NaN, ...) */
    ORR_ERR_NOMEM = 6,
    ORR_ERR_INTERNAL = 7,
    ORR_ERR_CANCELLED = 8 /* the caller asked the work to stop (orrery_cancel) */
} orr_status;

#define ORR_ERROR_MSG_MAX 1024

typedef struct orr_error {
    orr_status code;
    char msg[ORR_ERROR_MSG_MAX];
} orr_error;

/* Records code and a printf-style message in err (which may be NULL) and
 * returns code, so callers can write `return orr_fail(err, ORR_ERR_IO, ...)`. */
orr_status orr_fail(orr_error *err, orr_status code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Prefixes an existing message with more context ("scene.yaml: " + msg). */
orr_status orr_fail_prefix(orr_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

void orr_error_clear(orr_error *err);

/* Allocation helpers that report failures through err with the size asked. */
void *orr_malloc(size_t size, const char *what, orr_error *err);
void *orr_calloc(size_t count, size_t size, const char *what, orr_error *err);

#endif
