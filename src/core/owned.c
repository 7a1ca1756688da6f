#include "core/owned.h"

#include <stdlib.h>
#include <string.h>

/* A copy of s, or NULL with err set. */
static char *duplicate(const char *s, orr_error *err)
{
    size_t size = strlen(s) + 1;
    char *copy = orr_malloc(size, "a file name", err);
    if (copy)
        memcpy(copy, s, size);
    return copy;
}

orr_status orr_owned_set(char **field, const char *value, orr_error *err)
{
    char *copy = NULL;
    if (value && value[0] && !(copy = duplicate(value, err)))
        return ORR_ERR_NOMEM; /* *field keeps what it held */
    free(*field);
    *field = copy;
    return ORR_OK;
}

void orr_owned_free(char **field)
{
    free(*field);
    *field = NULL;
}

orr_status orr_owned_dup_all(char **const *fields, int n, orr_error *err)
{
    orr_status st = ORR_OK;
    for (int i = 0; i < n; i++) {
        char *shared = *fields[i];
        *fields[i] = NULL;
        if (shared && !(*fields[i] = duplicate(shared, st ? NULL : err)))
            st = ORR_ERR_NOMEM;
    }
    return st;
}

orr_status orr_owned_copy(void *dst, const void *src, size_t size, char **const *fields, int n, orr_error *err)
{
    if (dst == src)
        return ORR_OK;
    orr_owned_free_all(fields, n);
    memcpy(dst, src, size); /* shares src's strings until each is duplicated */
    return orr_owned_dup_all(fields, n, err);
}

void orr_owned_free_all(char **const *fields, int n)
{
    for (int i = 0; i < n; i++)
        orr_owned_free(fields[i]);
}
