#include "core/keys.h"

#include <stdarg.h>
#include <stdio.h>

#include "core/limits.h"

int orr_key_given(const orr_keys *keys, const char *key)
{
    char prefix[8];
    return keys && keys->locate(keys->ctx, key, prefix, sizeof prefix);
}

orr_status orr_fail_key_prefix(const orr_keys *keys, const char *key, orr_error *err, const char *what)
{
    char prefix[ORR_PATH_MAX + 32] = "";
    if (keys)
        keys->locate(keys->ctx, key, prefix, sizeof prefix);
    return orr_fail_prefix(err, "%s%s", prefix, what);
}

orr_status orr_fail_key(const orr_keys *keys, const char *key, orr_error *err, const char *fmt, ...)
{
    char prefix[ORR_PATH_MAX + 32] = ""; /* room for a scene's path; orr_fail cuts the message to size */
    char text[ORR_ERROR_MSG_MAX];
    if (keys)
        keys->locate(keys->ctx, key, prefix, sizeof prefix);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return orr_fail(err, ORR_ERR_USAGE, "%s%s", prefix, text);
}
