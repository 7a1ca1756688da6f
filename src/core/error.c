#include "core/error.h"
#include "core/numbers.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

orr_status orr_fail(orr_error *err, orr_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        orr_vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

orr_status orr_fail_prefix(orr_error *err, const char *fmt, ...)
{
    if (!err)
        return ORR_ERR_INTERNAL;
    char prefix[ORR_ERROR_MSG_MAX];
    char old[ORR_ERROR_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    orr_vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    memcpy(old, err->msg, sizeof old);
    /* Both parts fit separately; a combined message too long is cut short. */
    size_t len = strlen(prefix);
    if (len >= sizeof err->msg)
        len = sizeof err->msg - 1;
    memcpy(err->msg, prefix, len);
    size_t room = sizeof err->msg - 1 - len;
    size_t rest = strlen(old);
    if (rest > room)
        rest = room;
    memcpy(err->msg + len, old, rest);
    err->msg[len + rest] = '\0';
    return err->code;
}

void orr_error_clear(orr_error *err)
{
    if (err) {
        err->code = ORR_OK;
        err->msg[0] = '\0';
    }
}

void *orr_malloc(size_t size, const char *what, orr_error *err)
{
    void *p = malloc(size ? size : 1);
    if (!p)
        orr_fail(err, ORR_ERR_NOMEM, "out of memory allocating %zu bytes for %s", size, what);
    return p;
}

void *orr_calloc(size_t count, size_t size, const char *what, orr_error *err)
{
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p)
        orr_fail(err, ORR_ERR_NOMEM, "out of memory allocating %zu x %zu bytes for %s",
                 count, size, what);
    return p;
}
