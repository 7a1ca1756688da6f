#include "source/arrays.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The chunk hands out the caller's arrays themselves where they are packed
 * floats (or packed ids and types): no copy. The renderer only reads a
 * source's chunks, so the const the caller gave them keeps its promise.
 * Other arrays are converted into the chunk's own buffers (kept in `own`,
 * restored before the chunk is freed). */
typedef struct arrays_state {
    orr_particle_arrays a;
    unsigned type_mask;
    size_t next; /* the next particle to read */
    orr_chunk own; /* the chunk's own buffers */
    /* Where each extra field of the chunk comes from. */
    const orr_array *extra_from[ORR_MAX_EXTRA_FIELDS];
} arrays_state;

static size_t element_size(const orr_array *a) { return a->type == ORR_F64 ? sizeof(double) : sizeof(float); }

static double element(const orr_array *a, size_t i)
{
    size_t stride = a->stride ? a->stride : element_size(a);
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

/* 1 when p may be read as an array of elements of this alignment. */
static int aligned(const void *p, size_t alignment) { return (uintptr_t)p % alignment == 0; }

/* Elements [first, first + n) of a column as floats: the caller's array
 * itself when it is packed, aligned floats, otherwise converted into own. */
static float *column(float *own, const orr_array *a, size_t first, size_t n)
{
    size_t stride = a->stride ? a->stride : element_size(a);
    const char *p = (const char *)a->data + first * stride;
    if (a->type == ORR_F32 && stride == sizeof(float) && aligned(p, _Alignof(float)))
        return (float *)(uintptr_t)p; /* read only: see arrays_state */
    if (a->type == ORR_F64 && stride == sizeof(double) && aligned(p, _Alignof(double))) {
        const double *restrict d = (const double *)(const void *)p;
        for (size_t i = 0; i < n; i++)
            own[i] = (float)d[i];
    } else {
        for (size_t i = 0; i < n; i++)
            own[i] = (float)element(a, first + i);
    }
    return own;
}

/* The next n particles, all taken (no type selection): column by column,
 * the caller's arrays themselves where they can be. A constant mass and
 * absent types are in the own buffers from the start. */
static void take_all(arrays_state *st, orr_chunk *c, size_t n)
{
    const orr_particle_arrays *a = &st->a;
    const orr_chunk *own = &st->own;
    const size_t first = st->next;
    c->x = column(own->x, &a->x, first, n);
    c->y = column(own->y, &a->y, first, n);
    c->z = column(own->z, &a->z, first, n);
    c->mass = a->mass.data ? column(own->mass, &a->mass, first, n) : own->mass;
    if (a->id && (a->id_stride == 0 || a->id_stride == sizeof(uint64_t)) && aligned(a->id, _Alignof(uint64_t))) {
        c->id = (uint64_t *)(uintptr_t)(a->id + first);
    } else {
        for (size_t i = 0; i < n; i++)
            c->id[i] = id_of(a, first + i);
    }
    if (a->type && a->type_stride <= 1)
        c->type = (uint8_t *)(uintptr_t)(a->type + first);
    else if (a->type)
        for (size_t i = 0; i < n; i++)
            c->type[i] = type_of(a, first + i);
    if (c->h)
        c->h = column(own->h, &a->h, first, n);
    for (int k = 0; k < c->nextra; k++)
        c->extra[k].data = column(own->extra[k].data, st->extra_from[k], first, n);
    st->next += n;
}

/* Points the chunk back at its own buffers. */
static void own_buffers(arrays_state *st, orr_chunk *c)
{
    c->x = st->own.x, c->y = st->own.y, c->z = st->own.z, c->mass = st->own.mass, c->h = st->own.h;
    c->id = st->own.id, c->type = st->own.type;
    for (int k = 0; k < c->nextra; k++)
        c->extra[k].data = st->own.extra[k].data;
}

static orr_status arrays_next(orr_source *src, orr_error *err)
{
    (void)err;
    arrays_state *st = src->state;
    const orr_particle_arrays *a = &st->a;
    orr_chunk *c = &src->chunk;
    c->first_index = st->next;
    own_buffers(st, c);
    /* Every particle taken: no selection, or no types and type 0 selected. */
    if (!st->type_mask || (!a->type && (st->type_mask & 1u))) {
        size_t left = a->n - st->next;
        c->n = left < c->capacity ? left : c->capacity;
        take_all(st, c, c->n);
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
    if (src->state)
        own_buffers(src->state, &src->chunk); /* what orr_source_close frees */
    free(src->state);
    src->state = NULL;
}

static const orr_source_ops arrays_ops = {.next = arrays_next, .rewind = arrays_rewind, .close = arrays_close};

static int valid_array(const orr_array *a) { return a->type == ORR_F32 || a->type == ORR_F64; }

/* The arrays every caller may give, and their names in messages. */
enum { NSTANDARD = 8 };
static const char *const standard_names[NSTANDARD] = {"x", "y", "z", "mass", "h", "vx", "vy", "vz"};

static void standard_arrays(const orr_particle_arrays *a, const orr_array *all[NSTANDARD])
{
    const orr_array *list[NSTANDARD] = {&a->x, &a->y, &a->z, &a->mass, &a->h, &a->vx, &a->vy, &a->vz};
    memcpy(all, list, sizeof list);
}

/* Checks one array's stride: 0 (packed) or at least an element, and n
 * elements of it that end inside the address space. Strides are unsigned
 * byte counts, so a negative stride (a reversed NumPy view) arrives as a
 * huge one that wraps around. A broadcast array (NumPy's stride 0) cannot
 * be told from a packed one: the caller must copy it out (docs/insitu.md). */
static orr_status check_stride(const char *what, const char *name, const void *data, size_t stride, size_t size,
                               size_t n, orr_error *err)
{
    if (!data || n == 0)
        return ORR_OK;
    if (stride != 0 && stride < size)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: array %s has a stride of %zu bytes, less than its %zu-byte elements: the elements "
                        "would overlap (0 means packed; a broadcast array must be copied out first)",
                        what, name, stride, size);
    size_t step = stride ? stride : size;
    uintptr_t room = UINTPTR_MAX - (uintptr_t)data; /* bytes from data to the end of the address space */
    if (room < size - 1 || (n - 1) > (room - (size - 1)) / step)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: array %s: %zu elements %zu bytes apart would run past the end of memory (strides are "
                        "unsigned byte counts: a negative stride must be made positive, e.g. by a copy)",
                        what, name, n, step);
    return ORR_OK;
}

/* Checks every array's stride (check_stride), ids and types included. */
static orr_status check_strides(const orr_particle_arrays *a, const char *what, orr_error *err)
{
    const orr_array *all[NSTANDARD];
    standard_arrays(a, all);
    orr_status s = ORR_OK;
    for (int k = 0; !s && k < NSTANDARD; k++)
        s = check_stride(what, standard_names[k], all[k]->data, all[k]->stride, element_size(all[k]), a->n, err);
    for (int k = 0; !s && k < a->nfields; k++)
        s = check_stride(what, a->field_names[k], a->fields[k].data, a->fields[k].stride,
                         element_size(&a->fields[k]), a->n, err);
    if (!s)
        s = check_stride(what, "id", a->id, a->id_stride, sizeof(uint64_t), a->n, err);
    if (!s)
        s = check_stride(what, "type", a->type, a->type_stride, sizeof(uint8_t), a->n, err);
    return s;
}

/* Checks the arrays and lists the extra fields: velocities, then the named ones. */
static orr_status collect_fields(arrays_state *st, const char *what, const char **names, int *nextra,
                                 orr_error *err)
{
    const orr_particle_arrays *a = &st->a;
    if (!a->x.data || !a->y.data || !a->z.data)
        return orr_fail(err, ORR_ERR_USAGE, "%s: the positions x, y, z are required", what);
    const orr_array *all[NSTANDARD];
    standard_arrays(a, all);
    for (int k = 0; k < NSTANDARD; k++)
        if (all[k]->data && !valid_array(all[k]))
            return orr_fail(err, ORR_ERR_USAGE, "%s: array %s has an unknown element type %d (ORR_F32 or ORR_F64)",
                            what, standard_names[k], (int)all[k]->type);
    if (a->nfields < 0 || a->nfields > ORR_ARRAYS_MAX_FIELDS)
        return orr_fail(err, ORR_ERR_USAGE, "%s: %d named fields; at most %d", what, a->nfields,
                        ORR_ARRAYS_MAX_FIELDS);
    int n = 0;
    const orr_array *vel[3] = {&a->vx, &a->vy, &a->vz};
    for (int k = 0; k < 3; k++)
        if (vel[k]->data) {
            names[n] = standard_names[5 + k];
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
    return check_strides(a, what, err);
}

/* The caller's struct_size (orrery.h): 0 or this library's size. A
 * different size is a caller compiled against another orrery.h, whose
 * fields would be read from the wrong places. */
static orr_status check_struct_size(const orr_particle_arrays *a, const char *what, orr_error *err)
{
    if (a->struct_size == 0 || a->struct_size == sizeof *a)
        return ORR_OK;
    return orr_fail(err, ORR_ERR_USAGE,
                    "%s: orr_particle_arrays.struct_size is %zu, but this liborrery's orr_particle_arrays is %zu "
                    "bytes (orrery.h API version %d): the caller was built against another orrery.h; set "
                    "struct_size = sizeof(orr_particle_arrays) and rebuild against this library's header",
                    what, a->struct_size, sizeof *a, ORRERY_API_VERSION);
}

orr_status orr_arrays_source_open(const orr_particle_arrays *a, const char *what, size_t chunk_size,
                                  unsigned type_mask, orr_source **out, orr_error *err)
{
    *out = NULL;
    orr_status size_ok = check_struct_size(a, what, err);
    if (size_ok)
        return size_ok;
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
    st->own = src->chunk;
    /* A constant mass and absent types never change: written once. */
    if (!a->mass.data)
        for (size_t i = 0; i < cap; i++)
            st->own.mass[i] = (float)a->mass_value;
    if (!a->type)
        memset(st->own.type, 0, cap);
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
