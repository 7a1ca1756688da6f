#include "source/arrays.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct arrays_state {
    orr_particle_arrays a;
    unsigned type_mask;
    size_t next; /* the next particle to read */
    /* Where each extra field of the chunk comes from. */
    const orr_array *extra_from[ORR_MAX_EXTRA_FIELDS];
} arrays_state;

static double element(const orr_array *a, size_t i)
{
    size_t stride = a->stride ? a->stride : (a->type == ORR_F64 ? sizeof(double) : sizeof(float));
    const char *p = (const char *)a->data + i * stride;
    if (a->type == ORR_F64) {
        double v;
        memcpy(&v, p, sizeof v);
        return v;
    }
    float v;
    memcpy(&v, p, sizeof v);
    return v;
}

static uint64_t id_of(const orr_particle_arrays *a, size_t i)
{
    if (!a->id)
        return a->id_offset + i;
    uint64_t v;
    memcpy(&v, (const char *)a->id + i * (a->id_stride ? a->id_stride : sizeof(uint64_t)), sizeof v);
    return v;
}

static uint8_t type_of(const orr_particle_arrays *a, size_t i)
{
    return a->type ? a->type[i * (a->type_stride ? a->type_stride : 1)] : 0;
}

/* Column copies of elements [first, first + n) into the chunk: a packed
 * float array is a memcpy, the others a plain conversion loop. */
static void copy_column(float *restrict out, const orr_array *a, size_t first, size_t n)
{
    size_t size = a->type == ORR_F64 ? sizeof(double) : sizeof(float);
    size_t stride = a->stride ? a->stride : size;
    const char *p = (const char *)a->data + first * stride;
    if (a->type == ORR_F32 && stride == sizeof(float)) {
        memcpy(out, p, n * sizeof(float));
    } else if (a->type == ORR_F64 && stride == sizeof(double)) {
        const double *restrict d = (const double *)(const void *)p;
        for (size_t i = 0; i < n; i++)
            out[i] = (float)d[i];
    } else {
        for (size_t i = 0; i < n; i++)
            out[i] = (float)element(a, first + i);
    }
}

/* The next n particles, all taken (no type selection): column by column. */
static void copy_all(arrays_state *st, orr_chunk *c, size_t n)
{
    const orr_particle_arrays *a = &st->a;
    const size_t first = st->next;
    copy_column(c->x, &a->x, first, n);
    copy_column(c->y, &a->y, first, n);
    copy_column(c->z, &a->z, first, n);
    if (a->mass.data) {
        copy_column(c->mass, &a->mass, first, n);
    } else {
        const float m = (float)a->mass_value;
        for (size_t i = 0; i < n; i++)
            c->mass[i] = m;
    }
    if (a->id && (a->id_stride == 0 || a->id_stride == sizeof(uint64_t)))
        memcpy(c->id, (const uint64_t *)a->id + first, n * sizeof *c->id);
    else
        for (size_t i = 0; i < n; i++)
            c->id[i] = id_of(a, first + i);
    if (!a->type)
        memset(c->type, 0, n);
    else if (a->type_stride <= 1)
        memcpy(c->type, a->type + first, n);
    else
        for (size_t i = 0; i < n; i++)
            c->type[i] = type_of(a, first + i);
    if (c->h)
        copy_column(c->h, &a->h, first, n);
    for (int k = 0; k < c->nextra; k++)
        copy_column(c->extra[k].data, st->extra_from[k], first, n);
    st->next += n;
}

static orr_status arrays_next(orr_source *src, orr_error *err)
{
    (void)err;
    arrays_state *st = src->state;
    const orr_particle_arrays *a = &st->a;
    orr_chunk *c = &src->chunk;
    c->first_index = st->next;
    /* Every particle taken: no selection, or no types and type 0 selected. */
    if (!st->type_mask || (!a->type && (st->type_mask & 1u))) {
        size_t left = a->n - st->next;
        c->n = left < c->capacity ? left : c->capacity;
        copy_all(st, c, c->n);
        return ORR_OK;
    }
    size_t n = 0;
    for (; st->next < a->n && n < c->capacity; st->next++) {
        size_t i = st->next;
        uint8_t t = type_of(a, i);
        if (t > 31 || !(st->type_mask & (1u << t)))
            continue;
        c->x[n] = (float)element(&a->x, i);
        c->y[n] = (float)element(&a->y, i);
        c->z[n] = (float)element(&a->z, i);
        c->mass[n] = a->mass.data ? (float)element(&a->mass, i) : (float)a->mass_value;
        c->id[n] = id_of(a, i);
        c->type[n] = t;
        if (c->h)
            c->h[n] = (float)element(&a->h, i);
        for (int k = 0; k < c->nextra; k++)
            c->extra[k].data[n] = (float)element(st->extra_from[k], i);
        n++;
    }
    c->n = n;
    return ORR_OK;
}

static orr_status arrays_rewind(orr_source *src, orr_error *err)
{
    (void)err;
    ((arrays_state *)src->state)->next = 0;
    return ORR_OK;
}

static void arrays_close(orr_source *src)
{
    free(src->state);
    src->state = NULL;
}

static const orr_source_ops arrays_ops = {.next = arrays_next, .rewind = arrays_rewind, .close = arrays_close};

static int valid_array(const orr_array *a) { return a->type == ORR_F32 || a->type == ORR_F64; }

/* Checks the arrays and lists the extra fields: velocities, then the named ones. */
static orr_status collect_fields(arrays_state *st, const char *what, const char **names, int *nextra,
                                 orr_error *err)
{
    const orr_particle_arrays *a = &st->a;
    if (!a->x.data || !a->y.data || !a->z.data)
        return orr_fail(err, ORR_ERR_USAGE, "%s: the positions x, y, z are required", what);
    const orr_array *all[] = {&a->x, &a->y, &a->z, &a->mass, &a->h, &a->vx, &a->vy, &a->vz};
    static const char *const all_names[] = {"x", "y", "z", "mass", "h", "vx", "vy", "vz"};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; k++)
        if (all[k]->data && !valid_array(all[k]))
            return orr_fail(err, ORR_ERR_USAGE, "%s: array %s has an unknown element type %d (ORR_F32 or ORR_F64)",
                            what, all_names[k], (int)all[k]->type);
    if (a->nfields < 0 || a->nfields > ORR_ARRAYS_MAX_FIELDS)
        return orr_fail(err, ORR_ERR_USAGE, "%s: %d named fields; at most %d", what, a->nfields,
                        ORR_ARRAYS_MAX_FIELDS);
    int n = 0;
    const orr_array *vel[3] = {&a->vx, &a->vy, &a->vz};
    for (int k = 0; k < 3; k++)
        if (vel[k]->data) {
            names[n] = all_names[5 + k];
            st->extra_from[n++] = vel[k];
        }
    for (int k = 0; k < a->nfields; k++) {
        const char *name = a->field_names[k];
        if (!name || !name[0] || strlen(name) >= ORR_FIELD_NAME_MAX)
            return orr_fail(err, ORR_ERR_USAGE, "%s: field %d has no name or one longer than %d characters", what, k,
                            ORR_FIELD_NAME_MAX - 1);
        if (!a->fields[k].data || !valid_array(&a->fields[k]))
            return orr_fail(err, ORR_ERR_USAGE, "%s: field %s has no data or an unknown element type", what, name);
        names[n] = name;
        st->extra_from[n++] = &a->fields[k];
    }
    *nextra = n;
    return ORR_OK;
}

orr_status orr_arrays_source_open(const orr_particle_arrays *a, const char *what, size_t chunk_size,
                                  unsigned type_mask, orr_source **out, orr_error *err)
{
    *out = NULL;
    orr_source *src = orr_source_new("arrays", what, &arrays_ops, sizeof(arrays_state), err);
    if (!src)
        return ORR_ERR_NOMEM;
    arrays_state *st = src->state;
    st->a = *a;
    st->type_mask = type_mask;
    const char *names[ORR_MAX_EXTRA_FIELDS];
    int nextra = 0;
    orr_status s = collect_fields(st, what, names, &nextra, err);
    size_t cap = chunk_size < a->n ? chunk_size : (a->n ? a->n : 1);
    if (!s)
        s = orr_chunk_alloc(&src->chunk, cap, a->h.data != NULL, names, nextra, err);
    if (s) {
        orr_source_close(src);
        return s;
    }
    orr_source_info *info = &src->info;
    info->count = (int64_t)a->n;
    info->time = a->time;
    info->has_h = a->h.data != NULL;
    info->has_id = a->id != NULL;
    info->has_type = a->type != NULL;
    info->h_support = 2.0;
    info->nextra = nextra;
    for (int k = 0; k < nextra; k++)
        snprintf(info->extra_names[k], sizeof info->extra_names[k], "%s", names[k]);
    *out = src;
    return ORR_OK;
}
