/* See gadget_writer.h. Bytes go through a small buffer in the file's byte
 * order, whatever the host's. */
#include "gadget_writer.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#define GW_BUF 65536

typedef struct emitter {
    FILE *fp;
    int big;
    int failed;
    size_t n;
    unsigned char buf[GW_BUF];
} emitter;

static void flush(emitter *e)
{
    if (e->n && fwrite(e->buf, 1, e->n, e->fp) != e->n)
        e->failed = 1;
    e->n = 0;
}

/* Appends the size low bytes of v in the file's byte order. */
static void put_uint(emitter *e, uint64_t v, int size)
{
    if (e->n + (size_t)size > GW_BUF)
        flush(e);
    for (int i = 0; i < size; i++) {
        int shift = 8 * (e->big ? size - 1 - i : i);
        e->buf[e->n++] = (unsigned char)(v >> shift);
    }
}

static void put_i32(emitter *e, int32_t v)
{
    put_uint(e, (uint32_t)v, 4);
}

static void put_f64(emitter *e, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    put_uint(e, u, 8);
}

static void put_real(emitter *e, double v, int dbl)
{
    if (dbl) {
        put_f64(e, v);
    } else {
        float f = (float)v;
        uint32_t u;
        memcpy(&u, &f, 4);
        put_uint(e, u, 4);
    }
}

static void put_bytes(emitter *e, const void *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        put_uint(e, ((const unsigned char *)p)[i], 1);
}

/* The record start: the label record in SnapFormat 2, then the marker. */
static int begin_block(emitter *e, const gw_spec *s, const char *label, uint64_t bytes)
{
    if (bytes > UINT32_MAX - 8)
        return -1;
    if (s->snapformat == 2) {
        char l[4] = {' ', ' ', ' ', ' '};
        memcpy(l, label, strlen(label) < 4 ? strlen(label) : 4);
        put_i32(e, 8);
        put_bytes(e, l, 4);
        put_uint(e, bytes + 8, 4);
        put_i32(e, 8);
    }
    put_uint(e, bytes, 4);
    return 0;
}

static void write_header(emitter *e, const gw_spec *s)
{
    begin_block(e, s, "HEAD", 256);
    for (int t = 0; t < 6; t++)
        put_i32(e, s->npart[t]);
    for (int t = 0; t < 6; t++)
        put_f64(e, s->massarr[t]);
    put_f64(e, s->time);
    put_f64(e, s->redshift);
    put_i32(e, s->flag_sfr);
    put_i32(e, s->flag_feedback);
    for (int t = 0; t < 6; t++)
        put_uint(e, s->npart_total[t], 4);
    put_i32(e, s->flag_cooling);
    put_i32(e, s->num_files);
    put_f64(e, s->box_size);
    put_f64(e, s->omega0);
    put_f64(e, s->omega_lambda);
    put_f64(e, s->hubble_param);
    put_i32(e, 0); /* flag_stellarage */
    put_i32(e, 0); /* flag_metals */
    for (int t = 0; t < 6; t++)
        put_uint(e, s->npart_total_high[t], 4);
    put_i32(e, 0); /* flag_entropy_instead_u */
    for (int i = 196; i < 256; i++)
        put_uint(e, 0, 1);
    put_uint(e, 256, 4);
}

typedef enum { F_POS, F_VEL, F_ID, F_MASS, F_U, F_RHO, F_HSML, F_POT } gw_field;

/* Whether particle of type t belongs in the block. */
static int in_block(const gw_spec *s, gw_field f, int t)
{
    if (f == F_MASS)
        return s->massarr[t] == 0;
    if (f == F_U || f == F_RHO || f == F_HSML)
        return t == 0;
    return 1;
}

static void put_value(emitter *e, const gw_spec *s, gw_field f, const gw_particle *p)
{
    int dbl = s->double_precision;
    switch (f) {
    case F_POS: for (int k = 0; k < 3; k++) put_real(e, p->pos[k], dbl); break;
    case F_VEL: for (int k = 0; k < 3; k++) put_real(e, p->vel[k], dbl); break;
    case F_ID: put_uint(e, p->id, s->id64 ? 8 : 4); break;
    case F_MASS: put_real(e, p->mass, dbl); break;
    case F_U: put_real(e, p->u, dbl); break;
    case F_RHO: put_real(e, p->rho, dbl); break;
    case F_HSML: put_real(e, p->hsml, dbl); break;
    case F_POT: put_real(e, p->pot, dbl); break;
    }
}

static int write_block(emitter *e, const gw_spec *s, gw_field f, const char *label, int ncomp, int size,
                       gw_particle_fn fn, void *user)
{
    uint64_t count = 0;
    for (int t = 0; t < 6; t++)
        if (in_block(s, f, t))
            count += (uint64_t)s->npart[t];
    if (f == F_MASS && count == 0)
        return 0;
    uint64_t bytes = count * (uint64_t)ncomp * (uint64_t)size;
    if (begin_block(e, s, label, bytes) != 0)
        return -1;
    uint64_t i = 0;
    for (int t = 0; t < 6; t++)
        for (int32_t j = 0; j < s->npart[t]; j++, i++) {
            if (!in_block(s, f, t))
                continue;
            gw_particle p;
            memset(&p, 0, sizeof p);
            fn(user, i, t, &p);
            put_value(e, s, f, &p);
        }
    put_uint(e, bytes, 4);
    return 0;
}

int gw_write(const char *path, const gw_spec *s, gw_particle_fn fn, void *user)
{
    static emitter e; /* 64 KiB: not on the stack */
    memset(&e, 0, sizeof e);
    e.big = s->big_endian;
    e.fp = fopen(path, "wb");
    if (!e.fp)
        return -1;
    int real = s->double_precision ? 8 : 4;
    int ok = 1;
    write_header(&e, s);
    ok = ok && write_block(&e, s, F_POS, "POS", 3, real, fn, user) == 0;
    if (s->blocks & GW_VEL)
        ok = ok && write_block(&e, s, F_VEL, "VEL", 3, real, fn, user) == 0;
    if (s->blocks & GW_ID)
        ok = ok && write_block(&e, s, F_ID, "ID", 1, s->id64 ? 8 : 4, fn, user) == 0;
    ok = ok && write_block(&e, s, F_MASS, "MASS", 1, real, fn, user) == 0;
    if (s->npart[0] > 0) {
        if (s->blocks & GW_U)
            ok = ok && write_block(&e, s, F_U, "U", 1, real, fn, user) == 0;
        if (s->blocks & GW_RHO)
            ok = ok && write_block(&e, s, F_RHO, "RHO", 1, real, fn, user) == 0;
        if (s->blocks & GW_HSML)
            ok = ok && write_block(&e, s, F_HSML, "HSML", 1, real, fn, user) == 0;
    }
    if (s->blocks & GW_POT)
        ok = ok && write_block(&e, s, F_POT, "POT", 1, real, fn, user) == 0;
    flush(&e);
    int closed = fclose(e.fp) == 0;
    if (!ok) {
        errno = EINVAL;
        return -1;
    }
    return e.failed || !closed ? -1 : 0;
}
