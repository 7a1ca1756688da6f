#include "particles/chunk.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

orr_status orr_chunk_alloc(orr_chunk *c, size_t capacity, int with_h,
                           const char *const *extra_names, int nextra, orr_error *err)
{
    memset(c, 0, sizeof *c);
    if (nextra < 0 || nextra > ORR_MAX_EXTRA_FIELDS)
        return orr_fail(err, ORR_ERR_USAGE, "%d extra particle fields requested; at most %d are supported",
                        nextra, ORR_MAX_EXTRA_FIELDS);
    if (capacity == 0 || capacity > ((size_t)1 << 32))
        return orr_fail(err, ORR_ERR_USAGE, "chunk size %zu is out of range (1 to 2^32 particles)", capacity);
    c->capacity = capacity;
    c->x = orr_malloc(capacity * sizeof(float), "particle x", err);
    c->y = orr_malloc(capacity * sizeof(float), "particle y", err);
    c->z = orr_malloc(capacity * sizeof(float), "particle z", err);
    c->mass = orr_malloc(capacity * sizeof(float), "particle mass", err);
    c->id = orr_malloc(capacity * sizeof(uint64_t), "particle id", err);
    c->type = orr_calloc(capacity, sizeof(uint8_t), "particle type", err);
    int ok = c->x && c->y && c->z && c->mass && c->id && c->type;
    if (with_h) {
        c->h = orr_malloc(capacity * sizeof(float), "smoothing length", err);
        ok = ok && c->h;
    }
    for (int i = 0; i < nextra && ok; i++) {
        strncpy(c->extra[i].name, extra_names[i], ORR_FIELD_NAME_MAX - 1);
        c->extra[i].data = orr_malloc(capacity * sizeof(float), extra_names[i], err);
        c->nextra = i + 1;
        ok = c->extra[i].data != NULL;
    }
    if (!ok) {
        orr_chunk_free(c);
        return ORR_ERR_NOMEM;
    }
    return ORR_OK;
}

void orr_chunk_free(orr_chunk *c)
{
    free(c->x);
    free(c->y);
    free(c->z);
    free(c->mass);
    free(c->h);
    free(c->id);
    free(c->type);
    for (int i = 0; i < c->nextra; i++)
        free(c->extra[i].data);
    memset(c, 0, sizeof *c);
}

float *orr_chunk_field(const orr_chunk *c, const char *name)
{
    if (strcmp(name, "x") == 0) return c->x;
    if (strcmp(name, "y") == 0) return c->y;
    if (strcmp(name, "z") == 0) return c->z;
    if (strcmp(name, "mass") == 0) return c->mass;
    if (strcmp(name, "h") == 0) return c->h;
    for (int i = 0; i < c->nextra; i++)
        if (strcmp(c->extra[i].name, name) == 0)
            return c->extra[i].data;
    return NULL;
}

long orr_chunk_first_nonfinite(const orr_chunk *c, size_t start)
{
    for (size_t i = start; i < c->n; i++)
        if (!isfinite(c->x[i]) || !isfinite(c->y[i]) || !isfinite(c->z[i]))
            return (long)i;
    return -1;
}

void orr_chunk_remove(orr_chunk *c, size_t i)
{
    size_t last = c->n - 1;
    c->x[i] = c->x[last];
    c->y[i] = c->y[last];
    c->z[i] = c->z[last];
    c->mass[i] = c->mass[last];
    c->id[i] = c->id[last];
    c->type[i] = c->type[last];
    if (c->h)
        c->h[i] = c->h[last];
    for (int k = 0; k < c->nextra; k++)
        c->extra[k].data[i] = c->extra[k].data[last];
    c->n = last;
}
