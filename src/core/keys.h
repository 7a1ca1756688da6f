/* Where a stage's settings came from, for the stage's own checks
 * (orr_X_prepare): whether a key was given, and where, so that a message
 * about it starts "file:line: " as the scene's other messages do. The
 * scene supplies it (scene/scene_check.c, from the marks its binder
 * records); a program that fills a stage's settings itself passes NULL:
 * then no key counts as given and messages start with no place. */
#ifndef ORR_CORE_KEYS_H
#define ORR_CORE_KEYS_H

#include <stddef.h>

#include "core/error.h"

typedef struct orr_keys {
    const void *ctx;
    /* Whether key was given; writes into prefix "origin:line: " (or
     * "origin: ") where it was set, else "path: " of the scene; key NULL
     * asks for that. */
    int (*locate)(const void *ctx, const char *key, char *prefix, size_t size);
} orr_keys;

/* Whether the scene gave key (0 when keys is NULL). */
int orr_key_given(const orr_keys *keys, const char *key);

/* Fails with ORR_ERR_USAGE and the formatted text, after the place of key
 * (or, key NULL or not given, of the scene). */
orr_status orr_fail_key(const orr_keys *keys, const char *key, orr_error *err, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Puts the place of key (or of the scene) and what before the message
 * err already holds; returns its code. */
orr_status orr_fail_key_prefix(const orr_keys *keys, const char *key, orr_error *err, const char *what);

#endif
