#include "scene/scene_bind.h"
#include "core/numbers.h"
#include "core/owned.h"

#include "scene/scene_colour.h"
#include "scene/scene_keys.h"
#include "scene/scene_sequence.h"
#include "scene/scene_path.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define PATH_MAX_LEN SCENE_KEY_PATH_MAX

void scene_loc_prefix(const char *origin, int line, char *buf, size_t size)
{
    if (line > 0)
        snprintf(buf, size, "%s:%d: ", origin, line);
    else
        snprintf(buf, size, "%s: ", origin);
}

/* ---- messages ---- */

/* The short name keeps the binder's many messages readable. */
#define fail_at scene_fail_at

orr_status scene_fail_at(orr_error *err, const char *origin, int line, const char *fmt, ...)
{
    char prefix[ORR_ERROR_MSG_MAX];
    char text[ORR_ERROR_MSG_MAX];
    scene_loc_prefix(origin, line, prefix, sizeof prefix);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return orr_fail(err, ORR_ERR_USAGE, "%s%s", prefix, text);
}

/* The value's description for "expected ..., got <what>" messages. */
#define GOT(node) yt_describe((node), got_buf, sizeof got_buf)

/* ---- scalar conversions (no messages; the callers know the key) ---- */

/* "nan", "-inf", ".inf", "Infinity", ...: words people use for non-finite numbers. */
static int is_nonfinite_word(const char *t)
{
    if (*t == '+' || *t == '-')
        t++;
    if (*t == '.')
        t++;
    return strcasecmp(t, "nan") == 0 || strcasecmp(t, "inf") == 0 || strcasecmp(t, "infinity") == 0;
}

/* "nan", ".NaN", "-nan": the words for not-a-number. */
static int is_nan_word(const char *t)
{
    if (*t == '+' || *t == '-')
        t++;
    if (*t == '.')
        t++;
    return strcasecmp(t, "nan") == 0;
}

/* Returns 1 and *v for a finite decimal number, -1 for a number that is not
 * finite (1e999, nan, .inf), 0 for anything else. Only digits, signs, '.' and
 * 'e' are let through to strtod (in the C locale: core/numbers.h), which keeps out its hex, nan and inf forms,
 * and the whole text must be used, which keeps out trailing junk. */
static int parse_number(const char *t, double *v)
{
    if (is_nonfinite_word(t))
        return -1;
    if (t[0] == '\0' || strspn(t, "0123456789+-.eE") != strlen(t) || !strpbrk(t, "0123456789"))
        return 0;
    char *end;
    *v = orr_strtod(t, &end);
    if (*end != '\0')
        return 0;
    return isfinite(*v) ? 1 : -1;
}

/* Integers: plain digits (the full long long range), or a number such as
 * 2e9 or 1.0 whose value is a whole number exactly representable in a double.
 * Returns 1 and *v, 0 when not an integer, -1 when too large. */
static int parse_integer(const char *t, long long *v)
{
    const char *digits = (*t == '+' || *t == '-') ? t + 1 : t;
    if (*digits && strspn(digits, "0123456789") == strlen(digits)) {
        errno = 0;
        *v = strtoll(t, NULL, 10);
        return errno == ERANGE ? -1 : 1;
    }
    double d;
    int ok = parse_number(t, &d);
    if (ok <= 0)
        return ok;
    if (d != floor(d))
        return 0;
    if (fabs(d) > 9007199254740992.0) /* 2^53: beyond it doubles skip integers */
        return -1;
    *v = (long long)d;
    return 1;
}

static int parse_bool(const char *t, int *v)
{
    static const char *const yes[] = {"true", "yes", "on"};
    static const char *const no[] = {"false", "no", "off"};
    for (int i = 0; i < 3; i++) {
        if (strcasecmp(t, yes[i]) == 0) {
            *v = 1;
            return 1;
        }
        if (strcasecmp(t, no[i]) == 0) {
            *v = 0;
            return 1;
        }
    }
    return 0;
}

static int in_bounds(const key_spec *k, double v)
{
    if ((k->bounds & HAS_LO) && ((k->bounds & LO_OPEN) ? !(v > k->lo) : !(v >= k->lo)))
        return 0;
    if ((k->bounds & HAS_HI) && ((k->bounds & HI_OPEN) ? !(v < k->hi) : !(v <= k->hi)))
        return 0;
    return 1;
}

/* "1 to 65536", "must be > 0", "must be > 0 and <= 100". */
static void describe_bounds(const key_spec *k, char *buf, size_t size)
{
    const int lo_closed = (k->bounds & HAS_LO) && !(k->bounds & LO_OPEN);
    const int hi_closed = (k->bounds & HAS_HI) && !(k->bounds & HI_OPEN);
    if (lo_closed && hi_closed) {
        snprintf(buf, size, "%g to %g", k->lo, k->hi);
        return;
    }
    char lo[48] = "", hi[48] = "";
    if (k->bounds & HAS_LO)
        snprintf(lo, sizeof lo, "%s %g", (k->bounds & LO_OPEN) ? ">" : ">=", k->lo);
    if (k->bounds & HAS_HI)
        snprintf(hi, sizeof hi, "%s %g", (k->bounds & HI_OPEN) ? "<" : "<=", k->hi);
    snprintf(buf, size, "must be %s%s%s", lo, (lo[0] && hi[0]) ? " and " : "", hi);
}

/* ---- binding values ---- */

typedef struct bind_ctx {
    void *target;           /* the orr_scene or dome_profile being filled */
    const char *dir;        /* the scene's folder, for K_PATH values */
    const key_table *table;
    scene_marks *marks;
    orr_error *err;
} bind_ctx;

/* Where a value's messages point: the key that holds it, or a list item. */
typedef struct value_at {
    const char *origin;
    int line;
    const char *path; /* "camera.position", "camera.position[1]" */
} value_at;

static void *field(const bind_ctx *c, const key_spec *k) { return (char *)c->target + k->offset; }

/* The scalar text of a value, or an error when it is a list, mapping or null. */
static orr_status want_scalar(const bind_ctx *c, const value_at *at, const yt_node *n, const char *what,
                              const char **text)
{
    char got_buf[96];
    if (n->kind != YT_SCALAR || yt_is_null(n))
        return fail_at(c->err, at->origin, at->line, "%s: expected %s, got %s", at->path, what, GOT(n));
    *text = n->text;
    return ORR_OK;
}

static orr_status get_number(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n,
                             double *v)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "a number", &t);
    if (st != ORR_OK)
        return st;
    int ok = parse_number(t, v);
    if (ok <= 0)
        return fail_at(c->err, at->origin, at->line, "%s: expected a %snumber, got '%s'", at->path,
                       ok < 0 ? "finite " : "", t);
    if (k && !in_bounds(k, *v)) {
        char range[128];
        describe_bounds(k, range, sizeof range);
        return fail_at(c->err, at->origin, at->line, "%s: %s is out of range (%s)", at->path, t, range);
    }
    return ORR_OK;
}

static orr_status get_integer(const bind_ctx *c, const value_at *at, const yt_node *n, long long lo,
                              long long hi, long long *v)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "an integer", &t);
    if (st != ORR_OK)
        return st;
    int ok = parse_integer(t, v);
    if (is_nan_word(t)) /* not "out of range": NaN is no number at all */
        return fail_at(c->err, at->origin, at->line, "%s: expected an integer, got '%s', which is not a number",
                       at->path, t);
    if (ok == 0)
        return fail_at(c->err, at->origin, at->line, "%s: expected an integer, got '%s'", at->path, t);
    if (ok < 0 || *v < lo || *v > hi)
        return fail_at(c->err, at->origin, at->line, "%s: %s is out of range (%lld to %lld)", at->path, t, lo,
                       hi);
    return ORR_OK;
}

/* What a K_FILENAME key names instead of a path, for its '/' message: the
 * folder of each is set elsewhere. */
static const char *filename_hint(const char *key)
{
    if (strcmp(key, "camera.dome") == 0)
        return "a dome profile's name, e.g. flat-180, found in the domes folders; see docs/scenes.md#dome-profiles";
    if (strcmp(key, "output.image") == 0)
        return "a file extension such as tif or jpg; the folder is output.dir";
    return "the folder is output.dir";
}

static orr_status bind_text(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, k->type == K_PATH ? "a file path" : "a string", &t);
    if (st != ORR_OK)
        return st;
    if (t[0] == '\0')
        return fail_at(c->err, at->origin, at->line, "%s: must not be empty", at->path);
    if (k->type == K_FILENAME && strchr(t, '/'))
        return fail_at(c->err, at->origin, at->line, "%s: '%s' must be a file name, without '/' (%s)", at->path, t,
                       filename_hint(k->key));
    /* A newline or other control character (a YAML block scalar keeps its
     * last newline) would end up in file names and FITS cards unseen. */
    for (const unsigned char *p = (const unsigned char *)t; k->type == K_FILENAME && *p; p++)
        if (*p < 0x20 || *p == 0x7f)
            return fail_at(c->err, at->origin, at->line,
                           "%s: a file name without control characters is needed, but character %zu of %zu is "
                           "byte 0x%02x%s", at->path, (size_t)(p - (const unsigned char *)t) + 1, strlen(t), *p,
                           *p == '\n' ? " (a newline: a YAML block scalar, | or >, keeps its last one; write "
                                         "the value on the key's line)" : "");
    /* Paths in the scene are relative to its folder, so a scene and its data
     * can move together; a --set path (line 0) was typed in a shell, so it
     * stays relative to the working directory like any other argument. "-"
     * (standard input) is no path. */
    const int from_scene = at->line > 0;
    char path[ORR_PATH_MAX]; /* an owned field's text before it is copied */
    char *out = k->owned ? path : field(c, k);
    size_t size = k->owned ? sizeof path : k->size;
    int len;
    if (k->type == K_PATH && from_scene && t[0] != '/' && strcmp(c->dir, ".") != 0 && strcmp(t, "-") != 0)
        len = snprintf(out, size, "%s/%s", c->dir, t);
    else
        len = snprintf(out, size, "%s", t);
    if (len < 0 || (size_t)len >= k->size)
        return fail_at(c->err, at->origin, at->line, "%s: '%.60s...' is too long (at most %zu characters)",
                       at->path, t, k->size - 1);
    return k->owned ? orr_owned_set((char **)field(c, k), path, c->err) : ORR_OK;
}

static orr_status bind_enum(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    char got_buf[96];
    /* Only the scene table has words, so the target is an orr_scene. */
    if (n->kind == YT_SCALAR && !yt_is_null(n) && k->parse_word((orr_scene *)c->target, n->text))
        return ORR_OK;
    return fail_at(c->err, at->origin, at->line, "%s: expected one of: %s, got %s", at->path, k->choices(),
                   GOT(n));
}

/* The words of a K_NAMED key for its message: the first names_shown after
 * "one of:" (all without names_shown), the others in a note after the value. */
static void named_words(const key_spec *k, char *shown, size_t shown_size, char *note, size_t note_size)
{
    note[0] = '\0';
    if (k->names_shown <= 0) {
        orr_named_list(k->names, shown, shown_size);
        return;
    }
    orr_named first[16] = {{NULL, 0}};
    for (int i = 0; i < k->names_shown && i < 15 && k->names[i].name; i++)
        first[i] = k->names[i];
    orr_named_list(first, shown, shown_size);
    char rest[160];
    snprintf(note, note_size, " (%s: %s)", k->names_note, orr_named_list(k->names + k->names_shown, rest, sizeof rest));
}

static orr_status bind_named(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    int v;
    if (k->size != sizeof v)
        return orr_fail(c->err, ORR_ERR_INTERNAL, "%s: the key's field is not int-sized", at->path);
    if (n->kind == YT_SCALAR && !yt_is_null(n) && orr_named_value(k->names, n->text, &v)) {
        memcpy(field(c, k), &v, sizeof v);
        return ORR_OK;
    }
    char words[160], note[200], got_buf[96];
    named_words(k, words, sizeof words, note, sizeof note);
    return fail_at(c->err, at->origin, at->line, "%s: expected one of: %s, got %s%s", at->path, words, GOT(n), note);
}

static orr_status bind_bool(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "true or false", &t);
    if (st != ORR_OK)
        return st;
    int v;
    if (!parse_bool(t, &v))
        return fail_at(c->err, at->origin, at->line, "%s: expected true or false, got '%s'", at->path, t);
    memcpy(field(c, k), &v, sizeof v);
    return ORR_OK;
}

/* Particle ids: plain digits up to 2^64 - 1 (ids near the top of the range
 * are real: some codes hash them), or any integer form get_integer takes. */
static orr_status bind_id(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const char *t = NULL;
    orr_status st = want_scalar(c, at, n, "a particle id (an integer >= 0)", &t);
    if (st != ORR_OK)
        return st;
    const char *digits = t[0] == '+' ? t + 1 : t;
    uint64_t id;
    if (digits[0] && strspn(digits, "0123456789") == strlen(digits)) {
        errno = 0;
        unsigned long long v = strtoull(digits, NULL, 10);
        if (errno == ERANGE) /* unsigned long long is 64 bits wide on every platform we build on */
            return fail_at(c->err, at->origin, at->line, "%s: %s is out of range (0 to %llu)", at->path, t,
                           (unsigned long long)UINT64_MAX);
        id = (uint64_t)v;
    } else {
        long long v;
        if ((st = get_integer(c, at, n, 0, LLONG_MAX, &v)) != ORR_OK)
            return st;
        id = (uint64_t)v;
    }
    memcpy(field(c, k), &id, sizeof id);
    return ORR_OK;
}

static orr_status bind_integer(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    long long v;
    orr_status st = get_integer(c, at, n, k->ilo, k->ihi, &v);
    if (st != ORR_OK)
        return st;
    if (k->type == K_INT) {
        int i = (int)v; /* the range check above keeps it within int */
        memcpy(field(c, k), &i, sizeof i);
    } else if (k->type == K_U64) {
        uint64_t u = (uint64_t)v; /* ilo >= 0 */
        memcpy(field(c, k), &u, sizeof u);
    } else {
        memcpy(field(c, k), &v, sizeof v);
    }
    return ORR_OK;
}

static orr_status bind_number(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double v = 0; /* "auto": the stretch takes its white from a percentile */
    const int is_auto = n->kind == YT_SCALAR && strcmp(n->text, "auto") == 0;
    if (k->type == K_AUTO && !is_auto && (n->kind != YT_SCALAR || parse_number(n->text, &v) == 0)) {
        char got_buf[96];
        return fail_at(c->err, at->origin, at->line, "%s: expected a number or auto, got %s", at->path, GOT(n));
    }
    if (k->type != K_AUTO || !is_auto) {
        orr_status st = get_number(c, k, at, n, &v);
        if (st != ORR_OK)
            return st;
    }
    memcpy(field(c, k), &v, sizeof v);
    return ORR_OK;
}

/* A number, or the word run: the value then follows the frame's place in
 * the run (0 at the first frame, 1 at the last), which the renderer reads
 * from the int the table's RUN_FLAG names: 1 for run, 0 for a number, so
 * that a --set number overrides a file's run and the other way round. */
static orr_status bind_run(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    const int is_run = n->kind == YT_SCALAR && strcmp(n->text, "run") == 0;
    double v = 0;
    if (!is_run) {
        double probe;
        if (n->kind != YT_SCALAR || parse_number(n->text, &probe) == 0) {
            char got_buf[96];
            return fail_at(c->err, at->origin, at->line, "%s: expected a number or run, got %s", at->path,
                           GOT(n));
        }
        orr_status st = get_number(c, k, at, n, &v);
        if (st != ORR_OK)
            return st;
    }
    memcpy(field(c, k), &v, sizeof v);
    memcpy((char *)c->target + k->flag_offset, &is_run, sizeof is_run);
    return ORR_OK;
}

/* The n numbers of a list value ([x, y, z] or [w, x, y, z]). */
static orr_status get_numbers(const bind_ctx *c, const value_at *at, const yt_node *n, size_t count,
                              const char *form, double *out)
{
    char got_buf[96];
    if (n->kind != YT_SEQUENCE)
        return fail_at(c->err, at->origin, at->line, "%s: expected a list of %zu numbers %s, got %s", at->path,
                       count, form, GOT(n));
    if (n->n != count)
        return fail_at(c->err, at->origin, at->line, "%s: expected a list of %zu numbers %s, got a list of %zu",
                       at->path, count, form, n->n);
    for (size_t i = 0; i < count; i++) {
        char path[PATH_MAX_LEN + 24]; /* room for "[index]" of any size_t */
        snprintf(path, sizeof path, "%s[%zu]", at->path, i);
        const yt_node *item = n->items[i];
        value_at item_at = {item->origin, item->line ? item->line : at->line, path};
        orr_status st = get_number(c, NULL, &item_at, item, &out[i]);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

static orr_status bind_vector(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double v[4];
    if (k->type == K_VEC3) {
        orr_status st = get_numbers(c, at, n, 3, "[x, y, z]", v);
        if (st != ORR_OK)
            return st;
        orr_vec3 vec = {v[0], v[1], v[2]};
        memcpy(field(c, k), &vec, sizeof vec);
    } else {
        orr_status st = get_numbers(c, at, n, 4, "[w, x, y, z]", v);
        if (st != ORR_OK)
            return st;
        orr_quat q = {v[0], v[1], v[2], v[3]};
        memcpy(field(c, k), &q, sizeof q);
    }
    return ORR_OK;
}

/* [l, b] in degrees: l wraps around, so any finite value is fine; b is a latitude. */
static orr_status bind_lb(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double lb[2];
    orr_status st = get_numbers(c, at, n, 2, "[l, b] in degrees", lb);
    if (st != ORR_OK)
        return st;
    if (!(lb[1] >= -90 && lb[1] <= 90)) {
        const yt_node *b = n->items[1];
        return fail_at(c->err, b->origin, b->line ? b->line : at->line,
                       "%s[1]: %s is out of range (-90 to 90: b is a latitude)", at->path, b->text);
    }
    memcpy(field(c, k), lb, sizeof lb);
    return ORR_OK;
}

static orr_status bind_pair(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    double ab[2];
    orr_status st = get_numbers(c, at, n, 2, "[first, last]", ab);
    if (st == ORR_OK)
        memcpy(field(c, k), ab, sizeof ab);
    return st;
}

/* input.types: a list of types 0..5 (or one type alone) to a bit mask. */
static orr_status bind_types(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    char got_buf[96];
    const yt_node *const *items = &n;
    size_t count = 1;
    if (n->kind == YT_SEQUENCE) {
        items = (const yt_node *const *)n->items;
        count = n->n;
    } else if (n->kind != YT_SCALAR || yt_is_null(n)) {
        return fail_at(c->err, at->origin, at->line, "%s: expected a list of particle types 0 to 5, got %s",
                       at->path, GOT(n));
    }
    if (count == 0)
        return fail_at(c->err, at->origin, at->line, "%s: the list is empty; give at least one particle type",
                       at->path);
    unsigned mask = 0;
    for (size_t i = 0; i < count; i++) {
        char path[PATH_MAX_LEN + 24]; /* room for "[index]" of any size_t */
        if (n->kind == YT_SEQUENCE)
            snprintf(path, sizeof path, "%s[%zu]", at->path, i);
        else
            snprintf(path, sizeof path, "%s", at->path);
        value_at item_at = {items[i]->origin, items[i]->line ? items[i]->line : at->line, path};
        long long t;
        orr_status st = get_integer(c, &item_at, items[i], 0, 5, &t);
        if (st != ORR_OK)
            return st;
        mask |= 1u << t;
    }
    memcpy(field(c, k), &mask, sizeof mask);
    return ORR_OK;
}

static orr_status bind_value(const bind_ctx *c, const key_spec *k, const value_at *at, const yt_node *n)
{
    switch (k->type) {
    case K_STRING:
    case K_FILENAME:
    case K_PATH: return bind_text(c, k, at, n);
    case K_NUMBER:
    case K_AUTO: return bind_number(c, k, at, n);
    case K_RUN: return bind_run(c, k, at, n);
    case K_INT:
    case K_LLONG:
    case K_U64: return bind_integer(c, k, at, n);
    case K_BOOL: return bind_bool(c, k, at, n);
    case K_ENUM: return bind_enum(c, k, at, n);
    case K_NAMED: return bind_named(c, k, at, n);
    case K_VEC3:
    case K_QUAT: return bind_vector(c, k, at, n);
    case K_TYPES: return bind_types(c, k, at, n);
    case K_POPULATIONS: return scene_bind_populations(c->target, at->origin, at->line, at->path, n, c->err);
    case K_TINT: return scene_bind_tint(c->target, at->origin, at->line, at->path, n, c->err);
    case K_LAYERS: return scene_bind_layers(c->target, at->origin, at->line, at->path, n, c->err);
    case K_SEQ_FILES: return scene_bind_sequence_files(c->target, at->origin, at->line, at->path, n, c->err);
    case K_ID: return bind_id(c, k, at, n);
    case K_LB: return bind_lb(c, k, at, n);
    case K_PAIR: return bind_pair(c, k, at, n);
    case K_KEYFRAMES: return scene_bind_keyframes(c->target, at->origin, at->line, at->path, n, c->err);
    }
    return orr_fail(c->err, ORR_ERR_INTERNAL, "%s: unknown key type %d", k->key, (int)k->type);
}

/* ---- walking the tree ---- */

static orr_status bind_mapping(const bind_ctx *c, const yt_node *map, const char *prefix);

/* Checks a key on its own: not empty, no dots (nesting is written as
 * mappings, so "camera.fov:" in a file would silently bypass the duplicate
 * check), and not already used in the same mapping. */
static orr_status check_key(const bind_ctx *c, const yt_node *map, size_t i, const char *prefix)
{
    const yt_entry *e = &map->entries[i];
    const char *sep = prefix[0] ? "." : "";
    if (e->key[0] == '\0')
        return fail_at(c->err, e->origin, e->line, "empty key%s%s", prefix[0] ? " in " : "", prefix);
    if (strchr(e->key, '.'))
        return fail_at(c->err, e->origin, e->line,
                       "key '%s%s%s' contains a '.'; write nested keys as indented mappings", prefix, sep, e->key);
    for (size_t j = 0; j < i; j++) {
        const yt_entry *first = &map->entries[j];
        if (strcmp(first->key, e->key) == 0)
            return fail_at(c->err, e->origin, e->line, "duplicate key '%s%s%s' (first set at line %d)", prefix,
                           sep, e->key, first->line);
    }
    return ORR_OK;
}

static orr_status unknown_key(const bind_ctx *c, const yt_entry *e, const char *path)
{
    char hint[PATH_MAX_LEN];
    scene_suggest_key(c->table, path, hint, sizeof hint);
    if (hint[0])
        return fail_at(c->err, e->origin, e->line, "unknown key '%s' (did you mean '%s'?)", path, hint);
    return fail_at(c->err, e->origin, e->line, "unknown key '%s' (see %s for the keys)", path, c->table->doc);
}

static orr_status bind_entry(const bind_ctx *c, const yt_entry *e, const char *path)
{
    const key_spec *k = scene_find_key(c->table, path);
    if (k) {
        value_at at = {e->origin, e->line, path};
        orr_status st = bind_value(c, k, &at, e->value);
        if (st != ORR_OK)
            return st;
        c->marks->loc[k - c->table->keys] = (scene_loc){e->origin, e->line};
        if (k->has_flag) {
            int one = 1;
            memcpy((char *)c->target + k->flag_offset, &one, sizeof one);
        }
        return ORR_OK;
    }
    if (!scene_is_section(c->table, path))
        return unknown_key(c, e, path);
    if (e->value->kind == YT_MAPPING)
        return bind_mapping(c, e->value, path);
    if (yt_is_null(e->value))
        return ORR_OK; /* "camera:" with every key commented out */
    char got_buf[96];
    return fail_at(c->err, e->origin, e->line, "%s: expected a mapping of %s.* keys, got %s", path, path,
                   GOT(e->value));
}

static orr_status bind_mapping(const bind_ctx *c, const yt_node *map, const char *prefix)
{
    for (size_t i = 0; i < map->n; i++) {
        const yt_entry *e = &map->entries[i];
        orr_status st = check_key(c, map, i, prefix);
        if (st != ORR_OK)
            return st;
        char path[PATH_MAX_LEN];
        int len = snprintf(path, sizeof path, "%s%s%s", prefix, prefix[0] ? "." : "", e->key);
        if (len < 0 || (size_t)len >= sizeof path)
            return fail_at(c->err, e->origin, e->line, "unknown key '%.60s...' (too long)", path);
        st = bind_entry(c, e, path);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

orr_status scene_bind(orr_scene *s, const yt_node *root, scene_marks *marks, orr_error *err)
{
    memset(marks, 0, sizeof *marks);
    bind_ctx c = {s, s->dir, &scene_key_table, marks, err};
    return bind_mapping(&c, root, "");
}

orr_status dome_profile_bind(dome_profile *p, const yt_node *root, orr_error *err)
{
    scene_marks marks; /* a profile's keys have no checks across them */
    bind_ctx c = {p, ".", &scene_profile_key_table, &marks, err};
    memset(&marks, 0, sizeof marks);
    return bind_mapping(&c, root, "");
}

static int locate_key(const void *ctx, const char *key, char *prefix, size_t size)
{
    const scene_keyed *k = ctx;
    const scene_loc *loc = key ? scene_mark(k->m, key) : NULL;
    scene_loc_prefix(loc ? loc->origin : k->s->path, loc ? loc->line : 0, prefix, size);
    return loc != NULL;
}

orr_keys scene_keys(const scene_keyed *k) { return (orr_keys){k, locate_key}; }

orr_status scene_fail_key(const orr_scene *s, const scene_marks *m, const char *key, orr_error *err,
                          const char *fmt, ...)
{
    char prefix[ORR_PATH_MAX + 32]; /* room for s->path; orr_fail cuts the message to size */
    char text[ORR_ERROR_MSG_MAX];
    const scene_loc *loc = scene_mark(m, key);
    scene_loc_prefix(loc ? loc->origin : s->path, loc ? loc->line : 0, prefix, sizeof prefix);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return orr_fail(err, ORR_ERR_USAGE, "%s%s", prefix, text);
}
