/* The source a snapshot sequence hands out at a time: the particles of the
 * two snapshots around it matched by id and interpolated, linearly or by
 * cubic Hermite (sequence.h, sequence_internal.h). */
#include "source/sequence_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct seq_cursor {
    orr_sequence *seq;
    unsigned long generation;
    const snapshot *a, *b; /* b NULL: snapshot a exactly */
    double dt, s;
    int hermite;
    size_t ia, ib;         /* where the walk over a and b (both in id order) is */
    uint64_t emitted;
    int nyield;
    int yield[ORR_MAX_EXTRA_FIELDS]; /* indices into a's extras, in the chunk's order */
} seq_cursor;

static orr_status cursor_check(const orr_source *src, orr_error *err)
{
    const seq_cursor *cur = src->state;
    if (cur->generation != cur->seq->generation)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: this source is stale: the sequence has since been moved to another time", src->info.path);
    return ORR_OK;
}

/* The standard cubic Hermite basis on [0, 1]. */
static void hermite_basis(double s, double h[4])
{
    double s2 = s * s, s3 = s2 * s;
    h[0] = 2 * s3 - 3 * s2 + 1; /* h00: x0 */
    h[1] = s3 - 2 * s2 + s;     /* h10: dt v0 */
    h[2] = -2 * s3 + 3 * s2;    /* h01: x1 */
    h[3] = s3 - s2;             /* h11: dt v1 */
}

/* The later position x1 of a particle at x0 before, as seen from x0: in a
 * periodic box (box > 0) its nearest image, so that a particle that wrapped
 * through a face is interpolated through that face. */
static double later_image(double x0, double x1, double box)
{
    return box > 0 ? x0 + (x1 - x0) - box * round((x1 - x0) / box) : x1;
}

/* An interpolated coordinate back into [0, box) (box > 0), where the
 * snapshots keep their particles, and to float. */
static float wrap_coordinate(double x, double box)
{
    if (!(box > 0))
        return (float)x;
    float f = (float)(x - box * floor(x / box));
    return f < (float)box ? f : 0.0f; /* x a hair below a multiple of box rounds up to it */
}

/* Writes particle (i of a, j of b) into slot k of the chunk. */
static void emit_pair(const seq_cursor *cur, orr_chunk *c, size_t k, size_t i, size_t j)
{
    const snapshot *a = cur->a, *b = cur->b;
    const float *pa[3] = {a->x, a->y, a->z}, *pb[3] = {b->x, b->y, b->z};
    float *out[3] = {c->x, c->y, c->z};
    const double s = cur->s, box = cur->seq->opt.box;
    double h[4];
    if (cur->hermite)
        hermite_basis(s, h);
    for (int d = 0; d < 3; d++) {
        const double x0 = pa[d][i], x1 = later_image(x0, pb[d][j], box);
        double x;
        if (cur->hermite)
            x = h[0] * x0 + h[1] * cur->dt * a->extra[a->vel[d]][i] + h[2] * x1 +
                h[3] * cur->dt * b->extra[b->vel[d]][j];
        else
            x = (1 - s) * x0 + s * x1;
        out[d][k] = wrap_coordinate(x, box);
    }
    if (c->h)
        c->h[k] = (float)((1 - s) * a->h[i] + s * b->h[j]);
}

static void emit_common(const seq_cursor *cur, orr_chunk *c, size_t k, size_t i)
{
    const snapshot *a = cur->a;
    c->mass[k] = a->mass[i];
    c->id[k] = a->id[i];
    c->type[k] = a->type[i];
    for (int e = 0; e < cur->nyield; e++)
        c->extra[e].data[k] = a->extra[cur->yield[e]][i];
}

static orr_status seq_next(orr_source *src, orr_error *err)
{
    orr_status st = cursor_check(src, err);
    if (st)
        return st;
    seq_cursor *cur = src->state;
    orr_chunk *c = &src->chunk;
    const snapshot *a = cur->a, *b = cur->b;
    c->first_index = cur->emitted;
    size_t k = 0;
    while (k < c->capacity && cur->ia < a->n) {
        size_t i = cur->ia;
        if (!b) {
            c->x[k] = a->x[i];
            c->y[k] = a->y[i];
            c->z[k] = a->z[i];
            if (c->h)
                c->h[k] = a->h[i];
            emit_common(cur, c, k++, i);
            cur->ia++;
            continue;
        }
        if (cur->ib >= b->n)
            break;
        size_t j = cur->ib;
        if (a->id[i] < b->id[j]) {
            cur->ia++;
        } else if (a->id[i] > b->id[j]) {
            cur->ib++;
        } else {
            emit_pair(cur, c, k, i, j);
            emit_common(cur, c, k++, i);
            cur->ia++;
            cur->ib++;
        }
    }
    c->n = k;
    cur->emitted += k;
    return ORR_OK;
}

static orr_status seq_rewind(orr_source *src, orr_error *err)
{
    orr_status st = cursor_check(src, err);
    if (st)
        return st;
    seq_cursor *cur = src->state;
    cur->ia = cur->ib = 0;
    cur->emitted = 0;
    return ORR_OK;
}

static void seq_close(orr_source *src)
{
    /* Only the cursor: the snapshots belong to the sequence, which keeps
     * them for the next frame. orr_source_close frees the chunk. */
    free(src->state);
    src->state = NULL;
}

static const orr_source_ops SEQ_OPS = {.next = seq_next, .rewind = seq_rewind, .close = seq_close};

static int has_velocities(const snapshot *sn) { return sn->vel[0] >= 0 && sn->vel[1] >= 0 && sn->vel[2] >= 0; }

/* Whether the pair [a, b] is interpolated with Hermite; an error when the
 * scene asks for hermite and a file has no velocities. */
static orr_status choose_hermite(const orr_sequence *seq, const snapshot *a, const snapshot *b, int *hermite,
                                 orr_error *err)
{
    *hermite = 0;
    if (seq->opt.interpolation == ORR_INTERP_LINEAR)
        return ORR_OK;
    const snapshot *lacking = !has_velocities(a) ? a : !has_velocities(b) ? b : NULL;
    if (lacking && seq->opt.interpolation == ORR_INTERP_HERMITE)
        return orr_fail(err, ORR_ERR_USAGE,
                        "%s: has no velocities (vx, vy, vz), which interpolation: hermite needs; use linear",
                        seq->paths[lacking->index]);
    *hermite = lacking == NULL;
    return ORR_OK;
}

/* Counts the particles of a and b with and without a partner. */
static void count_matches(const snapshot *a, const snapshot *b, orr_sequence_stats *stats)
{
    size_t i = 0, j = 0;
    int64_t both = 0;
    while (i < a->n && j < b->n) {
        if (a->id[i] < b->id[j])
            i++;
        else if (a->id[i] > b->id[j])
            j++;
        else {
            both++;
            i++;
            j++;
        }
    }
    stats->matched = both;
    stats->only_earlier = (int64_t)a->n - both;
    stats->only_later = (int64_t)b->n - both;
}

/* Which of a's extra fields the caller gets. */
static void choose_yield(const orr_sequence *seq, seq_cursor *cur)
{
    cur->nyield = 0;
    for (int e = 0; e < cur->a->nextra; e++) {
        int wanted = seq->ncaller < 0;
        for (int f = 0; f < seq->ncaller && !wanted; f++)
            wanted = strcmp(seq->field_store[f], cur->a->names[e]) == 0;
        if (wanted)
            cur->yield[cur->nyield++] = e;
    }
}

/* The last k with times[k] <= t (t within the range). */
static int bracket(const orr_sequence *seq, double t)
{
    int lo = 0, hi = seq->n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (seq->times[mid] <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static orr_status make_source(orr_sequence *seq, seq_cursor *proto, double time, orr_source **out, orr_error *err)
{
    char what[ORR_PATH_MAX];
    snprintf(what, sizeof what, "sequence %.1000s ... %.1000s at time %.17g", seq->paths[0], seq->paths[seq->n - 1],
             time);
    orr_source *src = orr_source_new("sequence", what, &SEQ_OPS, sizeof(seq_cursor), err);
    if (!src)
        return ORR_ERR_NOMEM;
    seq_cursor *cur = src->state;
    *cur = *proto;
    choose_yield(seq, cur);
    const snapshot *a = cur->a, *b = cur->b;
    orr_source_info *info = &src->info;
    info->count = b ? seq->stats.matched : (int64_t)a->n;
    info->time = time;
    info->has_h = a->h && (!b || b->h);
    info->has_id = a->has_id;
    info->has_type = a->has_type;
    info->h_support = a->h_support;
    /* Units both snapshots agree on (a file's, unknown in the other: none). */
    if (!b || strcmp(a->mass_unit, b->mass_unit) == 0)
        snprintf(info->mass_unit, sizeof info->mass_unit, "%s", a->mass_unit);
    if (!b || strcmp(a->length_unit, b->length_unit) == 0)
        snprintf(info->length_unit, sizeof info->length_unit, "%s", a->length_unit);
    info->nextra = cur->nyield;
    const char *names[ORR_MAX_EXTRA_FIELDS];
    for (int e = 0; e < cur->nyield; e++) {
        snprintf(info->extra_names[e], ORR_FIELD_NAME_MAX, "%s", a->names[cur->yield[e]]);
        names[e] = info->extra_names[e];
    }
    orr_source_add_header(info, "snapshots", "%d, times %.17g to %.17g", seq->n, seq->times[0], seq->times[seq->n - 1]);
    if (seq->opt.box > 0)
        orr_source_add_header(info, "BoxSize", "%.17g", seq->opt.box);
    orr_source_add_header(info, "earlier", "%s", seq->paths[a->index]);
    if (b) {
        orr_source_add_header(info, "later", "%s", seq->paths[b->index]);
        orr_source_add_header(info, "interpolation", "%s", cur->hermite ? "hermite" : "linear");
        orr_source_add_header(info, "dropped", "%lld only in the earlier, %lld only in the later",
                              (long long)seq->stats.only_earlier, (long long)seq->stats.only_later);
    }
    /* No larger than the particles there are: a frame allocates its chunk anew. */
    size_t capacity = seq->opt.source.chunk_size;
    if (info->count >= 0 && (uint64_t)info->count < capacity)
        capacity = info->count > 0 ? (size_t)info->count : 1;
    orr_status st = orr_chunk_alloc(&src->chunk, capacity, info->has_h, names, cur->nyield, err);
    if (st) {
        orr_source_close(src);
        return st;
    }
    *out = src;
    return ORR_OK;
}

orr_status orr_sequence_source_at(orr_sequence *seq, double time, orr_source **out, orr_error *err)
{
    *out = NULL;
    seq->generation++; /* sources handed out earlier may read evicted snapshots: retire them */
    double t0 = seq->times[0], t1 = seq->times[seq->n - 1];
    if (!(time >= t0 && time <= t1))
        return orr_fail(err, ORR_ERR_USAGE, "sequence: time %.17g is outside the snapshots' times, %.17g (%s) to %.17g (%s)",
                        time, t0, seq->paths[0], t1, seq->paths[seq->n - 1]);
    int k = bracket(seq, time);
    seq_cursor proto;
    memset(&proto, 0, sizeof proto);
    proto.seq = seq;
    proto.generation = seq->generation;
    snapshot *a = NULL, *b = NULL;
    orr_status st;
    if (seq->times[k] == time) {
        st = orr_seq_require(seq, k, -1, &a, &b, err);
        if (st)
            return st;
        seq->stats.matched = (int64_t)a->n;
        seq->stats.only_earlier = seq->stats.only_later = 0;
        seq->stats.hermite = 0;
    } else {
        st = orr_seq_require(seq, k, k + 1, &a, &b, err);
        if (!st)
            st = choose_hermite(seq, a, b, &proto.hermite, err);
        if (st)
            return st;
        count_matches(a, b, &seq->stats);
        seq->stats.hermite = proto.hermite;
        proto.dt = seq->times[k + 1] - seq->times[k];
        proto.s = (time - seq->times[k]) / proto.dt;
    }
    proto.a = a;
    proto.b = b;
    return make_source(seq, &proto, time, out, err);
}
