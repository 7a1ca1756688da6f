/* A snapshot of the sequence read into memory and sorted by id, and the two
 * slots that keep the snapshots a time needs resident (sequence_internal.h). */
#include "source/sequence_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/radix.h"

void orr_seq_snapshot_free(snapshot *sn)
{
    free(sn->x);
    free(sn->y);
    free(sn->z);
    free(sn->mass);
    free(sn->h);
    free(sn->id);
    free(sn->type);
    for (int e = 0; e < sn->nextra; e++)
        free(sn->extra[e]);
    memset(sn, 0, sizeof *sn);
    sn->index = -1;
}

static orr_status snapshot_reserve(snapshot *sn, size_t cap, orr_error *err)
{
    float **floats[] = {&sn->x, &sn->y, &sn->z, &sn->mass};
    for (size_t i = 0; i < sizeof floats / sizeof floats[0]; i++) {
        float *p = realloc(*floats[i], cap * sizeof(float));
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
        *floats[i] = p;
    }
    if (sn->h) {
        float *p = realloc(sn->h, cap * sizeof(float));
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
        sn->h = p;
    }
    for (int e = 0; e < sn->nextra; e++) {
        float *p = realloc(sn->extra[e], cap * sizeof(float));
        if (!p)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
        sn->extra[e] = p;
    }
    uint64_t *id = realloc(sn->id, cap * sizeof *id);
    if (id)
        sn->id = id;
    uint8_t *type = id ? realloc(sn->type, cap) : NULL;
    if (!type)
        return orr_fail(err, ORR_ERR_NOMEM, "out of memory for a snapshot of %zu particles", cap);
    sn->type = type;
    return ORR_OK;
}

static void snapshot_describe(snapshot *sn, const orr_source_info *info)
{
    sn->has_id = info->has_id;
    sn->has_type = info->has_type;
    sn->h_support = info->h_support;
    snprintf(sn->mass_unit, sizeof sn->mass_unit, "%s", info->mass_unit);
    snprintf(sn->length_unit, sizeof sn->length_unit, "%s", info->length_unit);
    sn->nextra = info->nextra;
    for (int v = 0; v < NVEL; v++)
        sn->vel[v] = -1;
    for (int e = 0; e < info->nextra; e++) {
        snprintf(sn->names[e], ORR_FIELD_NAME_MAX, "%s", info->extra_names[e]);
        for (int v = 0; v < NVEL; v++)
            if (strcmp(sn->names[e], VEL_NAMES[v]) == 0)
                sn->vel[v] = e;
    }
}

/* Appends the wanted particles of chunk c. */
static orr_status snapshot_append(snapshot *sn, const orr_chunk *c, const orr_source_options *opt, size_t *cap,
                                  orr_error *err)
{
    const float *fields[ORR_MAX_EXTRA_FIELDS];
    for (int e = 0; e < sn->nextra; e++)
        fields[e] = orr_chunk_field(c, sn->names[e]);
    for (size_t i = 0; i < c->n; i++) {
        if (!orr_source_wants_type(opt, c->type[i]))
            continue;
        if (sn->n == *cap) {
            *cap = *cap ? 2 * *cap : 1024;
            orr_status st = snapshot_reserve(sn, *cap, err);
            if (st)
                return st;
        }
        size_t j = sn->n++;
        sn->x[j] = c->x[i];
        sn->y[j] = c->y[i];
        sn->z[j] = c->z[i];
        sn->mass[j] = c->mass[i];
        sn->id[j] = c->id[i];
        sn->type[j] = c->type[i];
        if (sn->h)
            sn->h[j] = c->h ? c->h[i] : 0.0f;
        for (int e = 0; e < sn->nextra; e++)
            sn->extra[e][j] = fields[e] ? fields[e][i] : 0.0f;
    }
    return ORR_OK;
}

/* Reorders a float array by keys (scratch holds n floats). */
static void permute_floats(float *v, float *scratch, const orr_radix_item *keys, size_t n)
{
    for (size_t i = 0; i < n; i++)
        scratch[i] = v[keys[i].index];
    memcpy(v, scratch, n * sizeof *v);
}

/* Sorts the snapshot by id (two arrays of 16-byte keys while it runs, the
 * second reused as scratch for reordering the fields), and rejects
 * duplicate ids. */
static orr_status snapshot_sort(snapshot *sn, const char *path, orr_error *err)
{
    size_t n = sn->n;
    int sorted = 1;
    for (size_t i = 1; i < n && sorted; i++)
        sorted = sn->id[i - 1] < sn->id[i];
    if (sorted)
        return ORR_OK; /* snapshots are often written in id order */
    orr_radix_item *buf = orr_malloc(2 * n * sizeof *buf, "sorting a snapshot by id", err);
    if (!buf)
        return ORR_ERR_NOMEM;
    for (size_t i = 0; i < n; i++)
        buf[i] = (orr_radix_item){sn->id[i], i};
    orr_radix_item *keys = orr_radix_sort(buf, buf + n, n); /* stable: duplicate ids end side by side */
    void *scratch = keys == buf ? (void *)(buf + n) : (void *)buf;
    orr_status st = ORR_OK;
    for (size_t i = 1; i < n && !st; i++)
        if (keys[i].key == keys[i - 1].key)
            st = orr_fail(err, ORR_ERR_DATA, "%s: particle id %llu appears more than once; a sequence matches "
                          "particles by id, so ids must be unique", path, (unsigned long long)keys[i].key);
    if (!st) {
        float *arrays[4 + 1 + ORR_MAX_EXTRA_FIELDS] = {sn->x, sn->y, sn->z, sn->mass, sn->h};
        for (int e = 0; e < sn->nextra; e++)
            arrays[5 + e] = sn->extra[e];
        for (int a = 0; a < 5 + sn->nextra; a++)
            if (arrays[a])
                permute_floats(arrays[a], scratch, keys, n);
        uint8_t *ts = scratch;
        for (size_t i = 0; i < n; i++)
            ts[i] = sn->type[keys[i].index];
        memcpy(sn->type, ts, n);
        for (size_t i = 0; i < n; i++)
            sn->id[i] = keys[i].key;
    }
    free(buf);
    return st;
}

/* Bytes a loaded snapshot holds. */
static double snapshot_bytes(const snapshot *sn)
{
    return (double)sn->n * (double)(4 * sizeof(float) + sizeof(uint64_t) + 1 +
                                    (sn->h ? sizeof(float) : 0) + (size_t)sn->nextra * sizeof(float));
}

static orr_status check_memory(const orr_sequence *seq, int k, const snapshot *other, const orr_source_info *info,
                               orr_error *err)
{
    if (info->count < 0)
        return ORR_OK; /* unknown until read: checked after reading */
    double mine = (double)info->count * (double)orr_seq_bytes_per_particle(info);
    double theirs = other->index >= 0 ? snapshot_bytes(other) : 0;
    if (mine + theirs <= seq->opt.max_memory)
        return ORR_OK;
    return orr_fail(err, ORR_ERR_USAGE,
                    "sequence: %s needs about %.2f GiB in memory next to the %.2f GiB already held, more than "
                    "input.sequence.max_memory (%.2f GiB)",
                    seq->paths[k], gib(mine), gib(theirs), gib(seq->opt.max_memory));
}

static orr_status load_snapshot(orr_sequence *seq, int k, snapshot *sn, const snapshot *other, orr_error *err)
{
    orr_seq_snapshot_free(sn);
    orr_source *src = NULL;
    orr_status st = orr_seq_open_file(seq, k, &src, err);
    if (!st)
        st = check_memory(seq, k, other, &src->info, err);
    size_t cap = 0;
    if (!st) {
        snapshot_describe(sn, &src->info);
        if (src->info.has_h && !(sn->h = malloc(sizeof(float))))
            st = orr_fail(err, ORR_ERR_NOMEM, "out of memory");
        cap = src->info.count > 0 ? (size_t)src->info.count : 0;
        if (!st && cap)
            st = snapshot_reserve(sn, cap, err);
    }
    while (!st) {
        const orr_chunk *c;
        st = orr_source_next(src, &c, err);
        if (st || c->n == 0)
            break;
        st = snapshot_append(sn, c, &seq->opt.source, &cap, err);
    }
    orr_source_close(src);
    if (!st && snapshot_bytes(sn) + (other->index >= 0 ? snapshot_bytes(other) : 0) > seq->opt.max_memory)
        st = orr_fail(err, ORR_ERR_USAGE, "sequence: %s takes %.2f GiB in memory, more than input.sequence.max_memory "
                      "(%.2f GiB) allows beside the snapshot already held", seq->paths[k], gib(snapshot_bytes(sn)),
                      gib(seq->opt.max_memory));
    if (!st)
        st = snapshot_sort(sn, seq->paths[k], err);
    if (st) {
        orr_seq_snapshot_free(sn);
        return st;
    }
    sn->index = k;
    seq->stats.loads++;
    return ORR_OK;
}

/* Makes snapshots a and b (b = -1: none) resident, reading only those not
 * held already and evicting only what is in the way, so that time stepping
 * forward reads every snapshot once. */
orr_status orr_seq_require(orr_sequence *seq, int a, int b, snapshot **sa, snapshot **sb, orr_error *err)
{
    int want[2] = {a, b};
    snapshot *got[2] = {NULL, NULL};
    for (int w = 0; w < 2; w++)
        for (int i = 0; i < 2; i++)
            if (want[w] >= 0 && seq->slot[i].index == want[w])
                got[w] = &seq->slot[i];
    for (int w = 0; w < 2; w++) {
        if (want[w] < 0 || got[w])
            continue;
        /* A slot that holds neither wanted snapshot. */
        snapshot *free_slot = NULL;
        for (int i = 0; i < 2 && !free_slot; i++)
            if (&seq->slot[i] != got[0] && &seq->slot[i] != got[1])
                free_slot = &seq->slot[i];
        snapshot *other = free_slot == &seq->slot[0] ? &seq->slot[1] : &seq->slot[0];
        if (other != got[0] && other != got[1])
            orr_seq_snapshot_free(other); /* not needed either: free it before reading, to keep the peak low */
        orr_status st = load_snapshot(seq, want[w], free_slot, other, err);
        if (st)
            return st;
        got[w] = free_slot;
    }
    *sa = got[0];
    *sb = got[1];
    return ORR_OK;
}
