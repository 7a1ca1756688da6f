/* Values of NumPy arrays into chunks (npy_values.h). */
#include "source/readers/npy_values.h"

#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/bytes.h"

#include "source/readers/mass_policy.h"

/* One stored value's bits, in its byte order, sign-extended for a signed
 * integer narrower than 8 bytes. */
static uint64_t raw_at(const npy_column *c, const unsigned char *p)
{
    uint64_t u = 0;
    for (int i = 0; i < c->size; i++)
        u |= (uint64_t)p[c->big ? c->size - 1 - i : i] << (8 * i);
    if (c->kind == NPY_INT && c->size < 8 && (u >> (8 * c->size - 1) & 1))
        u |= ~(uint64_t)0 << (8 * c->size);
    return u;
}

/* One stored value as a double (integers of up to 8 bytes, floats). */
static double value_at(const npy_column *c, const unsigned char *p)
{
    uint64_t u = raw_at(c, p);
    if (c->kind == NPY_FLOAT && c->size == 4) {
        uint32_t w = (uint32_t)u;
        float f;
        memcpy(&f, &w, sizeof f);
        return f;
    }
    if (c->kind == NPY_FLOAT) {
        double d;
        memcpy(&d, &u, sizeof d);
        return d;
    }
    return c->kind == NPY_INT ? (double)(int64_t)u : (double)u;
}

/* An integer column's value exactly (ids beyond 2^53 stay exact). */
static int64_t integer_at(const npy_column *c, const unsigned char *p, int *negative)
{
    uint64_t u = raw_at(c, p);
    *negative = c->kind == NPY_INT && (int64_t)u < 0;
    return (int64_t)u;
}

static int role_of(const char *name)
{
    static const struct {
        const char *name;
        int role;
    } roles[] = {{"x", NPY_R_X},   {"y", NPY_R_Y}, {"z", NPY_R_Z},   {"mass", NPY_R_MASS},
                 {"m", NPY_R_MASS}, {"h", NPY_R_H}, {"id", NPY_R_ID}, {"type", NPY_R_TYPE}};
    for (size_t i = 0; i < sizeof roles / sizeof roles[0]; i++)
        if (strcmp(name, roles[i].name) == 0)
            return roles[i].role;
    return name[0] ? NPY_R_EXTRA : NPY_R_SKIP;
}

orr_status npy_assign_roles(const char *what, const char *thing, const char *positions, const npy_column *col,
                            int n, int *role, int *slot, orr_source_info *info, const orr_source_options *opt,
                            orr_error *err)
{
    int seen[NPY_R_EXTRA] = {0};
    for (int i = 0; i < n; i++) {
        const npy_column *c = &col[i];
        int r = c->kind == NPY_PAD ? NPY_R_SKIP : role_of(c->name);
        if (r < NPY_R_EXTRA && seen[r]++)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: %s '%s': a second %s column", what, thing, c->name,
                            r == NPY_R_MASS ? "mass (mass or m)" : c->name);
        if ((r == NPY_R_ID || r == NPY_R_TYPE) && c->kind == NPY_FLOAT)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: %s '%s' holds floats; %s are integers", what, thing, c->name,
                            r == NPY_R_ID ? "ids" : "types");
        if (r == NPY_R_EXTRA && (!orr_source_wants_field(opt, c->name) || info->nextra >= ORR_MAX_EXTRA_FIELDS))
            r = NPY_R_SKIP;
        slot[i] = -1;
        if (r == NPY_R_EXTRA) {
            slot[i] = info->nextra;
            snprintf(info->extra_names[info->nextra++], ORR_FIELD_NAME_MAX, "%s", c->name);
        }
        role[i] = r;
    }
    if (!seen[NPY_R_X] || !seen[NPY_R_Y] || !seen[NPY_R_Z])
        return orr_fail(err, ORR_ERR_FORMAT, "%s: no %s '%s' (positions are %s)", what, thing,
                        !seen[NPY_R_X] ? "x" : !seen[NPY_R_Y] ? "y" : "z", positions);
    info->has_h = seen[NPY_R_H];
    info->has_id = seen[NPY_R_ID];
    info->has_type = seen[NPY_R_TYPE];
    return ORR_OK;
}

orr_status npy_store(const char *what, const npy_column *col, int role, int slot, orr_chunk *c, size_t at,
                     const unsigned char *p, int64_t row, orr_error *err)
{
    int negative = 0;
    switch (role) {
    case NPY_R_X: c->x[at] = (float)value_at(col, p); break;
    case NPY_R_Y: c->y[at] = (float)value_at(col, p); break;
    case NPY_R_Z: c->z[at] = (float)value_at(col, p); break;
    case NPY_R_MASS: {
        double m = value_at(col, p);
        const char *problem = orr_mass_problem(m);
        if (problem)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": mass %g %s", what, row, m, problem);
        c->mass[at] = (float)m;
        break;
    }
    case NPY_R_H: {
        double h = value_at(col, p);
        if (!(h >= 0) || isinf(h))
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": h = %g is not finite and non-negative", what,
                            row, h);
        c->h[at] = (float)h;
        break;
    }
    case NPY_R_ID:
        c->id[at] = (uint64_t)integer_at(col, p, &negative);
        if (negative)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": id %" PRId64 " is negative", what, row,
                            (int64_t)c->id[at]);
        break;
    case NPY_R_TYPE: {
        int64_t t = integer_at(col, p, &negative);
        if (negative || t > 5)
            return orr_fail(err, ORR_ERR_FORMAT, "%s: row %" PRId64 ": type %" PRId64 " is not from 0 to 5", what,
                            row, t);
        c->type[at] = (uint8_t)t;
        break;
    }
    case NPY_R_EXTRA: c->extra[slot].data[at] = (float)value_at(col, p); break;
    default: break;
    }
    return ORR_OK;
}

double npy_value(const npy_column *col, const unsigned char *p) { return value_at(col, p); }

float *npy_float_target(int role, int slot, orr_chunk *c)
{
    switch (role) {
    case NPY_R_X: return c->x;
    case NPY_R_Y: return c->y;
    case NPY_R_Z: return c->z;
    case NPY_R_MASS: return c->mass;
    case NPY_R_H: return c->h;
    case NPY_R_EXTRA: return c->extra[slot].data;
    default: return NULL;
    }
}

/* Whether a value may go into the chunk as it is for its role: any
 * position or field; a mass by the mass policy; h finite, not negative. */
static inline int plain_ok(int role, double v)
{
    if (role == NPY_R_MASS)
        return v >= 0 && v <= FLT_MAX && !(v > 0 && (float)v == 0.0f);
    if (role == NPY_R_H)
        return v >= 0 && v <= DBL_MAX;
    return 1;
}

/* Typed loops, one per stored size, so the compiler sees plain loads. */
static size_t copy_f32(int role, const unsigned char *base, size_t stride, size_t k, float *out)
{
    if (stride == sizeof(float) && role != NPY_R_MASS && role != NPY_R_H) {
        memcpy(out, base, k * sizeof(float));
        return k;
    }
    for (size_t i = 0; i < k; i++) {
        float f;
        memcpy(&f, base + i * stride, sizeof f);
        if (!plain_ok(role, f))
            return i;
        out[i] = f;
    }
    return k;
}

static size_t copy_f64(int role, const unsigned char *base, size_t stride, size_t k, float *out)
{
    for (size_t i = 0; i < k; i++) {
        double d;
        memcpy(&d, base + i * stride, sizeof d);
        if (!plain_ok(role, d))
            return i;
        out[i] = (float)d;
    }
    return k;
}

size_t npy_copy_native_floats(const npy_column *col, int role, const unsigned char *base, size_t stride, size_t k,
                              float *out)
{
    if (!out || col->kind != NPY_FLOAT || col->big != orr_host_big_endian())
        return 0;
    return col->size == 4 ? copy_f32(role, base, stride, k, out) : copy_f64(role, base, stride, k, out);
}

void npy_defaults(const orr_source_info *info, int has_mass, orr_chunk *c, size_t at, size_t k, int64_t row)
{
    for (size_t i = 0; i < k; i++) {
        if (!has_mass)
            c->mass[at + i] = 1.0f;
        if (!info->has_id)
            c->id[at + i] = (uint64_t)(row + (int64_t)i);
        if (!info->has_type)
            c->type[at + i] = 0;
    }
}

orr_status npy_fill_chunk(orr_source *src, const orr_share *share, size_t block, int64_t *row,
                          npy_block_fn read_block, orr_error *err)
{
    orr_chunk *c = &src->chunk;
    if (*row < share->lo[0])
        *row = share->lo[0];
    c->first_index = (uint64_t)*row;
    while (c->n < c->capacity && *row < share->hi[0]) {
        size_t k = c->capacity - c->n;
        if (k > block)
            k = block;
        if ((int64_t)k > share->hi[0] - *row)
            k = (size_t)(share->hi[0] - *row);
        orr_status s = read_block(src, k, err);
        if (s)
            return s;
        c->n += k;
        *row += (int64_t)k;
    }
    return ORR_OK;
}
