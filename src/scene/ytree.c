#include "scene/ytree.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <yaml.h>

/* Scenes are a few levels deep; the limit only stops hostile input from
 * exhausting the stack through the recursive descent below. */
#define YT_MAX_DEPTH 64

typedef struct parse_ctx {
    yaml_parser_t parser;
    const char *text; /* the input, to look at the character an error points to */
    size_t len;
    const char *origin;
    int with_lines;
    orr_error *err;
} parse_ctx;

/* ---- nodes ---- */

static yt_node *node_new(yt_kind kind, const char *origin, int line, orr_error *err)
{
    yt_node *n = orr_calloc(1, sizeof *n, "a YAML node", err);
    if (n) {
        n->kind = kind;
        n->origin = origin;
        n->line = line;
    }
    return n;
}

void yt_free(yt_node *n)
{
    if (!n)
        return;
    for (size_t i = 0; i < n->n; i++) {
        if (n->kind == YT_MAPPING) {
            free(n->entries[i].key);
            yt_free(n->entries[i].value);
        } else if (n->kind == YT_SEQUENCE) {
            yt_free(n->items[i]);
        }
    }
    free(n->entries);
    free(n->items);
    free(n->text);
    free(n);
}

static char *copy_text(const char *text, size_t len, orr_error *err)
{
    char *s = orr_malloc(len + 1, "YAML text", err);
    if (s) {
        memcpy(s, text, len);
        s[len] = '\0';
    }
    return s;
}

/* Makes room for one more child in a mapping or sequence. */
static orr_status node_reserve(yt_node *n, orr_error *err)
{
    if (n->n < n->cap)
        return ORR_OK;
    size_t cap = n->cap ? 2 * n->cap : 8;
    if (n->kind == YT_MAPPING) {
        yt_entry *e = realloc(n->entries, cap * sizeof *e);
        if (!e)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory growing a YAML mapping");
        n->entries = e;
    } else {
        yt_node **items = realloc(n->items, cap * sizeof *items);
        if (!items)
            return orr_fail(err, ORR_ERR_NOMEM, "out of memory growing a YAML list");
        n->items = items;
    }
    n->cap = cap;
    return ORR_OK;
}

/* Appends key: value to a mapping, taking ownership of both (also on error). */
static orr_status map_append(yt_node *map, char *key, int line, const char *origin, yt_node *value,
                             orr_error *err)
{
    orr_status st = node_reserve(map, err);
    if (st != ORR_OK) {
        free(key);
        yt_free(value);
        return st;
    }
    map->entries[map->n++] = (yt_entry){key, line, origin, value};
    return ORR_OK;
}

int yt_is_null(const yt_node *n)
{
    if (n->kind != YT_SCALAR || n->quoted)
        return 0;
    return n->text[0] == '\0' || strcmp(n->text, "~") == 0 || strcasecmp(n->text, "null") == 0;
}

const char *yt_describe(const yt_node *n, char *buf, size_t size)
{
    if (n->kind == YT_MAPPING)
        return "a mapping";
    if (n->kind == YT_SEQUENCE)
        return "a list";
    if (yt_is_null(n))
        return "nothing";
    /* Long values are cut so that the message stays readable. */
    if (strlen(n->text) > 60)
        snprintf(buf, size, "'%.57s...'", n->text);
    else
        snprintf(buf, size, "'%s'", n->text);
    return buf;
}

yt_node *yt_new_scalar(const char *text, int quoted, const char *origin, int line, orr_error *err)
{
    yt_node *n = node_new(YT_SCALAR, origin, line, err);
    if (!n)
        return NULL;
    n->quoted = quoted;
    n->text = copy_text(text, strlen(text), err);
    if (!n->text) {
        yt_free(n);
        return NULL;
    }
    return n;
}

/* ---- parsing ---- */

static int mark_line(const parse_ctx *c, yaml_mark_t mark)
{
    return c->with_lines ? (int)mark.line + 1 : 0;
}

/* "origin:line: " or "origin: " for messages about a place in the text. */
static void where(const parse_ctx *c, int line, char *buf, size_t size)
{
    if (line > 0)
        snprintf(buf, size, "%s:%d: ", c->origin, line);
    else
        snprintf(buf, size, "%s: ", c->origin);
}

static orr_status syntax_error(parse_ctx *c)
{
    const yaml_parser_t *p = &c->parser;
    const char *problem = p->problem ? p->problem : "unknown error";
    if (p->error == YAML_MEMORY_ERROR)
        return orr_fail(c->err, ORR_ERR_NOMEM, "%s: out of memory while reading YAML", c->origin);
    if (p->error == YAML_READER_ERROR)
        return orr_fail(c->err, ORR_ERR_USAGE, "%s: YAML read error: %s (at byte %zu)", c->origin, problem,
                        p->problem_offset);
    char context[160] = "";
    if (p->context && c->with_lines)
        snprintf(context, sizeof context, " (%s at line %zu)", p->context, p->context_mark.line + 1);
    else if (p->context)
        snprintf(context, sizeof context, " (%s)", p->context);
    /* YAML forbids tabs in indentation, and libyaml's message does not say so. */
    const char *hint = p->problem_mark.index < c->len && c->text[p->problem_mark.index] == '\t'
                           ? "; indent with spaces, not tabs"
                           : "";
    if (c->with_lines)
        return orr_fail(c->err, ORR_ERR_USAGE, "%s:%zu:%zu: YAML syntax error: %s%s%s", c->origin,
                        p->problem_mark.line + 1, p->problem_mark.column + 1, problem, context, hint);
    return orr_fail(c->err, ORR_ERR_USAGE, "%s: YAML syntax error: %s%s%s", c->origin, problem, context, hint);
}

static orr_status next_event(parse_ctx *c, yaml_event_t *ev)
{
    if (!yaml_parser_parse(&c->parser, ev))
        return syntax_error(c);
    return ORR_OK;
}

static orr_status parse_node(parse_ctx *c, const yaml_event_t *ev, int depth, yt_node **out);

static orr_status parse_scalar(parse_ctx *c, const yaml_event_t *ev, yt_node **out)
{
    const char *value = (const char *)ev->data.scalar.value;
    size_t len = ev->data.scalar.length;
    char at[ORR_ERROR_MSG_MAX];
    if (memchr(value, '\0', len)) {
        where(c, mark_line(c, ev->start_mark), at, sizeof at);
        return orr_fail(c->err, ORR_ERR_USAGE, "%svalue contains a NUL character", at);
    }
    yt_node *n = node_new(YT_SCALAR, c->origin, mark_line(c, ev->start_mark), c->err);
    if (!n)
        return ORR_ERR_NOMEM;
    n->quoted = ev->data.scalar.style != YAML_PLAIN_SCALAR_STYLE;
    n->text = copy_text(value, len, c->err);
    if (!n->text) {
        yt_free(n);
        return ORR_ERR_NOMEM;
    }
    *out = n;
    return ORR_OK;
}

/* Reads "key: value" pairs until the end of the mapping. */
static orr_status parse_mapping_body(parse_ctx *c, yt_node *map, int depth)
{
    for (;;) {
        yaml_event_t kev, vev;
        orr_status st = next_event(c, &kev);
        if (st != ORR_OK)
            return st;
        if (kev.type == YAML_MAPPING_END_EVENT) {
            yaml_event_delete(&kev);
            return ORR_OK;
        }
        int line = mark_line(c, kev.start_mark);
        if (kev.type != YAML_SCALAR_EVENT) {
            /* A list or mapping used as a key ("? [a, b]: c") cannot name anything. */
            yaml_event_delete(&kev);
            char at[ORR_ERROR_MSG_MAX];
            where(c, line, at, sizeof at);
            return orr_fail(c->err, ORR_ERR_USAGE, "%skeys must be plain words, not lists or mappings", at);
        }
        char *key = copy_text((const char *)kev.data.scalar.value, kev.data.scalar.length, c->err);
        yaml_event_delete(&kev);
        if (!key)
            return ORR_ERR_NOMEM;
        st = next_event(c, &vev);
        if (st != ORR_OK) {
            free(key);
            return st;
        }
        yt_node *value = NULL;
        st = parse_node(c, &vev, depth + 1, &value);
        yaml_event_delete(&vev);
        if (st != ORR_OK) {
            free(key);
            return st;
        }
        st = map_append(map, key, line, c->origin, value, c->err);
        if (st != ORR_OK)
            return st;
    }
}

static orr_status parse_sequence_body(parse_ctx *c, yt_node *seq, int depth)
{
    for (;;) {
        yaml_event_t ev;
        orr_status st = next_event(c, &ev);
        if (st != ORR_OK)
            return st;
        if (ev.type == YAML_SEQUENCE_END_EVENT) {
            yaml_event_delete(&ev);
            return ORR_OK;
        }
        yt_node *item = NULL;
        st = parse_node(c, &ev, depth + 1, &item);
        yaml_event_delete(&ev);
        if (st == ORR_OK && (st = node_reserve(seq, c->err)) != ORR_OK)
            yt_free(item);
        if (st != ORR_OK)
            return st;
        seq->items[seq->n++] = item;
    }
}

/* Builds the node that starts with event ev (which the caller deletes). */
static orr_status parse_node(parse_ctx *c, const yaml_event_t *ev, int depth, yt_node **out)
{
    int line = mark_line(c, ev->start_mark);
    char at[ORR_ERROR_MSG_MAX];
    where(c, line, at, sizeof at);
    if (depth > YT_MAX_DEPTH)
        return orr_fail(c->err, ORR_ERR_USAGE, "%sYAML nested more than %d levels deep", at, YT_MAX_DEPTH);
    switch (ev->type) {
    case YAML_SCALAR_EVENT:
        return parse_scalar(c, ev, out);
    case YAML_ALIAS_EVENT:
        /* Aliases would make one node appear under several keys, and its line
         * number would then point at the anchor, not the use: not worth it. */
        return orr_fail(c->err, ORR_ERR_USAGE, "%sYAML aliases (*%s) are not supported in scenes", at,
                        (const char *)ev->data.alias.anchor);
    case YAML_MAPPING_START_EVENT:
    case YAML_SEQUENCE_START_EVENT: {
        int is_map = ev->type == YAML_MAPPING_START_EVENT;
        yt_node *n = node_new(is_map ? YT_MAPPING : YT_SEQUENCE, c->origin, line, c->err);
        if (!n)
            return ORR_ERR_NOMEM;
        orr_status st = is_map ? parse_mapping_body(c, n, depth) : parse_sequence_body(c, n, depth);
        if (st != ORR_OK) {
            yt_free(n);
            return st;
        }
        *out = n;
        return ORR_OK;
    }
    default:
        return orr_fail(c->err, ORR_ERR_INTERNAL, "%sunexpected YAML event %d", at, (int)ev->type);
    }
}

/* Expects an event of the given type and discards it. */
static orr_status expect_event(parse_ctx *c, yaml_event_type_t type, yaml_event_t *ev)
{
    orr_status st = next_event(c, ev);
    if (st != ORR_OK)
        return st;
    if (ev->type == type)
        return ORR_OK;
    yaml_event_delete(ev);
    return orr_fail(c->err, ORR_ERR_INTERNAL, "%s: unexpected YAML event %d (wanted %d)", c->origin,
                    (int)ev->type, (int)type);
}

/* The body of yt_parse, once the parser is set up: STREAM-START, then either
 * STREAM-END (an empty file) or exactly one document. */
static orr_status parse_stream(parse_ctx *c, yt_node **out)
{
    yaml_event_t ev;
    orr_status st = expect_event(c, YAML_STREAM_START_EVENT, &ev);
    if (st != ORR_OK)
        return st;
    yaml_event_delete(&ev);
    if ((st = next_event(c, &ev)) != ORR_OK)
        return st;
    yaml_event_type_t type = ev.type;
    yaml_event_delete(&ev);
    if (type == YAML_STREAM_END_EVENT)
        return ORR_OK; /* nothing but comments and blank lines */
    if (type != YAML_DOCUMENT_START_EVENT)
        return orr_fail(c->err, ORR_ERR_INTERNAL, "%s: unexpected YAML event %d", c->origin, (int)type);

    if ((st = next_event(c, &ev)) != ORR_OK)
        return st;
    yt_node *root = NULL;
    st = parse_node(c, &ev, 0, &root);
    yaml_event_delete(&ev);
    if (st == ORR_OK && (st = expect_event(c, YAML_DOCUMENT_END_EVENT, &ev)) == ORR_OK) {
        yaml_event_delete(&ev);
        st = next_event(c, &ev);
        if (st == ORR_OK) {
            if (ev.type != YAML_STREAM_END_EVENT) {
                char at[ORR_ERROR_MSG_MAX];
                where(c, mark_line(c, ev.start_mark), at, sizeof at);
                st = orr_fail(c->err, ORR_ERR_USAGE, "%sa scene is one YAML document, but a second one starts here",
                              at);
            }
            yaml_event_delete(&ev);
        }
    }
    if (st != ORR_OK) {
        yt_free(root);
        return st;
    }
    *out = root;
    return ORR_OK;
}

orr_status yt_parse(const char *text, size_t len, const char *origin, int with_lines, yt_node **out,
                    orr_error *err)
{
    parse_ctx c = {.text = text, .len = len, .origin = origin, .with_lines = with_lines, .err = err};
    *out = NULL;
    if (!yaml_parser_initialize(&c.parser))
        return orr_fail(err, ORR_ERR_NOMEM, "%s: cannot initialise the YAML parser", origin);
    yaml_parser_set_input_string(&c.parser, (const unsigned char *)text, len);
    orr_status st = parse_stream(&c, out);
    yaml_parser_delete(&c.parser);
    return st;
}

/* ---- overrides ---- */

static yt_entry *map_find(yt_node *map, const char *key)
{
    for (size_t i = 0; i < map->n; i++)
        if (strcmp(map->entries[i].key, key) == 0)
            return &map->entries[i];
    return NULL;
}

/* Puts value under key in map, replacing what was there; the key then counts
 * as written by the override, so later errors about it name the override. */
static orr_status map_put(yt_node *map, const char *key, yt_node *value, const char *origin, orr_error *err)
{
    yt_entry *e = map_find(map, key);
    if (e) {
        yt_free(e->value);
        e->value = value;
        e->origin = origin;
        e->line = 0;
        return ORR_OK;
    }
    char *k = copy_text(key, strlen(key), err);
    if (!k) {
        yt_free(value);
        return ORR_ERR_NOMEM;
    }
    return map_append(map, k, 0, origin, value, err);
}

/* The mapping under key in map, made (or put in place of a scalar or list) when needed. */
static yt_node *child_mapping(yt_node *map, const char *key, const char *origin, orr_error *err)
{
    yt_entry *e = map_find(map, key);
    if (e && e->value->kind == YT_MAPPING)
        return e->value;
    yt_node *child = node_new(YT_MAPPING, origin, 0, err);
    if (!child || map_put(map, key, child, origin, err) != ORR_OK)
        return NULL;
    return child;
}

orr_status yt_set_path(yt_node *root, const char *dotted, yt_node *value, const char *origin,
                       orr_error *err)
{
    char *path = copy_text(dotted, strlen(dotted), err);
    if (!path) {
        yt_free(value);
        return ORR_ERR_NOMEM;
    }
    yt_node *map = root;
    char *part = path;
    char *dot;
    while ((dot = strchr(part, '.')) != NULL) {
        *dot = '\0';
        map = child_mapping(map, part, origin, err);
        if (!map) {
            free(path);
            yt_free(value);
            return err ? err->code : ORR_ERR_NOMEM;
        }
        part = dot + 1;
    }
    orr_status st = map_put(map, part, value, origin, err);
    free(path);
    return st;
}

/* ---- views: lookup, copying and merging ---- */

const yt_entry *yt_find(const yt_node *map, const char *key)
{
    if (!map || map->kind != YT_MAPPING)
        return NULL;
    return map_find((yt_node *)map, key);
}

yt_node *yt_detach(yt_node *map, const char *key)
{
    yt_entry *e = map && map->kind == YT_MAPPING ? map_find(map, key) : NULL;
    if (!e)
        return NULL;
    yt_node *value = e->value;
    free(e->key);
    size_t i = (size_t)(e - map->entries);
    memmove(&map->entries[i], &map->entries[i + 1], (map->n - i - 1) * sizeof *e);
    map->n--;
    return value;
}

/* Copies the children of a mapping or sequence into an empty node of the same kind. */
static orr_status clone_children(yt_node *copy, const yt_node *n, orr_error *err)
{
    for (size_t i = 0; i < n->n; i++) {
        const yt_node *child = n->kind == YT_MAPPING ? n->entries[i].value : n->items[i];
        yt_node *child_copy = yt_clone(child, err);
        if (!child_copy)
            return ORR_ERR_NOMEM;
        if (n->kind == YT_SEQUENCE) {
            if (node_reserve(copy, err) != ORR_OK) {
                yt_free(child_copy);
                return ORR_ERR_NOMEM;
            }
            copy->items[copy->n++] = child_copy;
            continue;
        }
        const yt_entry *e = &n->entries[i];
        char *key = copy_text(e->key, strlen(e->key), err);
        if (!key) {
            yt_free(child_copy);
            return ORR_ERR_NOMEM;
        }
        orr_status st = map_append(copy, key, e->line, e->origin, child_copy, err);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

yt_node *yt_clone(const yt_node *n, orr_error *err)
{
    if (n->kind == YT_SCALAR)
        return yt_new_scalar(n->text, n->quoted, n->origin, n->line, err);
    yt_node *copy = node_new(n->kind, n->origin, n->line, err);
    if (!copy)
        return NULL;
    if (clone_children(copy, n, err) != ORR_OK) {
        yt_free(copy);
        return NULL;
    }
    return copy;
}

/* Puts a copy of src's entry e in place of dst's entry d, or appends it when d is NULL. */
static orr_status merge_replace(yt_node *dst, yt_entry *d, const yt_entry *e, orr_error *err)
{
    yt_node *copy = yt_clone(e->value, err);
    if (!copy)
        return ORR_ERR_NOMEM;
    if (d) {
        yt_free(d->value);
        d->value = copy;
        d->origin = e->origin;
        d->line = e->line;
        return ORR_OK;
    }
    char *key = copy_text(e->key, strlen(e->key), err);
    if (!key) {
        yt_free(copy);
        return ORR_ERR_NOMEM;
    }
    return map_append(dst, key, e->line, e->origin, copy, err);
}

orr_status yt_merge(yt_node *dst, const yt_node *src, orr_error *err)
{
    for (size_t i = 0; i < src->n; i++) {
        const yt_entry *e = &src->entries[i];
        yt_entry *d = map_find(dst, e->key);
        orr_status st = ORR_OK;
        if (d && d->value->kind == YT_MAPPING && e->value->kind == YT_MAPPING)
            st = yt_merge(d->value, e->value, err);
        else if (!(d && d->value->kind == YT_MAPPING && yt_is_null(e->value)))
            st = merge_replace(dst, d, e, err);
        if (st != ORR_OK)
            return st;
    }
    return ORR_OK;
}

/* ---- writing the tree as text ---- */

/* Appends text to a growing buffer; a failed allocation leaves ok = 0. */
typedef struct text_buf {
    char *text;
    size_t len, cap;
    int ok;
} text_buf;

static void put(text_buf *b, const char *text)
{
    size_t n = strlen(text);
    if (!b->ok)
        return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 1024;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *t = realloc(b->text, cap);
        if (!t) {
            b->ok = 0;
            return;
        }
        b->text = t;
        b->cap = cap;
    }
    memcpy(b->text + b->len, text, n + 1);
    b->len += n;
}

/* ---- scalars as YAML reads them back (yt_yaml_text) ---- */

/* Whether text reads back as the same plain scalar wherever it stands (a
 * key, a value, a flow list): letters, digits and punctuation without YAML
 * meaning, starting with none of YAML's indicators ("-", "..." and the
 * like), except a sign or point before a number. */
static int plain_safe(const char *t)
{
    const unsigned char *u = (const unsigned char *)t;
    if (!isalnum(u[0]) && u[0] != '_' && u[0] != '/' &&
        !(strchr("+-.", u[0]) && u[0] && (isdigit(u[1]) || (u[1] == '.' && isdigit(u[2])))))
        return 0;
    for (; *u; u++)
        if (!isalnum(*u) && !strchr("_.+-/", *u))
            return 0;
    return 1;
}

/* text in double quotes, with YAML's escapes for what a quoted scalar may
 * not hold as it is; bytes of UTF-8 pass unchanged. */
static void put_quoted(text_buf *b, const char *text)
{
    put(b, "\"");
    for (const unsigned char *u = (const unsigned char *)text; *u; u++) {
        char c[8] = {(char)*u, '\0'};
        if (*u == '"' || *u == '\\')
            snprintf(c, sizeof c, "\\%c", *u);
        else if (*u == '\n')
            snprintf(c, sizeof c, "\\n");
        else if (*u < 0x20 || *u == 0x7f)
            snprintf(c, sizeof c, "\\x%02x", *u);
        put(b, c);
    }
    put(b, "\"");
}

/* A scalar as yt_parse would read it back: the same text, null or not. */
static void put_scalar(text_buf *b, const yt_node *n)
{
    if (!n->quoted && yt_is_null(n))
        put(b, "~");
    else if (!n->quoted && plain_safe(n->text))
        put(b, n->text);
    else
        put_quoted(b, n->text);
}

static void put_key(text_buf *b, const char *key)
{
    if (plain_safe(key))
        put(b, key);
    else
        put_quoted(b, key);
}

/* A value on one line: a scalar, [a, b] for a list, {k: v} for a mapping
 * inside a list; scalars and keys as their text (quote = 0, the settings
 * lines) or as YAML reads them back (quote = 1, yt_yaml_text). */
static void put_inline(text_buf *b, const yt_node *n, int quote)
{
    if (n->kind == YT_SCALAR) {
        if (quote)
            put_scalar(b, n);
        else
            put(b, n->text);
        return;
    }
    put(b, n->kind == YT_SEQUENCE ? "[" : "{");
    for (size_t i = 0; i < n->n; i++) {
        if (i)
            put(b, ", ");
        if (n->kind == YT_MAPPING) {
            if (quote)
                put_key(b, n->entries[i].key);
            else
                put(b, n->entries[i].key);
            put(b, ": ");
        }
        put_inline(b, n->kind == YT_SEQUENCE ? n->items[i] : n->entries[i].value, quote);
    }
    put(b, n->kind == YT_SEQUENCE ? "]" : "}");
}

static void put_lines(text_buf *b, const yt_node *map, const char *prefix)
{
    for (size_t i = 0; i < map->n; i++) {
        const yt_entry *e = &map->entries[i];
        size_t len = strlen(prefix) + strlen(e->key) + 2;
        char *key = malloc(len);
        if (!key) {
            b->ok = 0;
            return;
        }
        snprintf(key, len, "%s%s%s", prefix, prefix[0] ? "." : "", e->key);
        if (e->value->kind == YT_MAPPING && e->value->n > 0) {
            put_lines(b, e->value, key);
        } else {
            put(b, key);
            put(b, "=");
            put_inline(b, e->value, 0);
            put(b, "\n");
        }
        free(key);
    }
}

char *yt_settings_text(const yt_node *root, orr_error *err)
{
    text_buf b = {NULL, 0, 0, 1};
    put(&b, "");
    if (root && root->kind == YT_MAPPING)
        put_lines(&b, root, "");
    if (!b.ok) {
        free(b.text);
        orr_fail(err, ORR_ERR_NOMEM, "out of memory for the scene's settings text");
        return NULL;
    }
    return b.text;
}

/* ---- the tree as a YAML document ---- */

/* A mapping in block style, its entries indent spaces in; mappings below
 * it nest, lists stay on one line. */
static void put_block(text_buf *b, const yt_node *map, int indent)
{
    for (size_t i = 0; i < map->n; i++) {
        const yt_entry *e = &map->entries[i];
        for (int k = 0; k < indent; k++)
            put(b, " ");
        put_key(b, e->key);
        put(b, ":");
        if (e->value->kind == YT_MAPPING && e->value->n > 0) {
            put(b, "\n");
            put_block(b, e->value, indent + 2);
            continue;
        }
        put(b, " ");
        put_inline(b, e->value, 1);
        put(b, "\n");
    }
}

char *yt_yaml_text(const yt_node *root, orr_error *err)
{
    text_buf b = {NULL, 0, 0, 1};
    put(&b, "");
    if (root && root->kind == YT_MAPPING)
        put_block(&b, root, 0);
    if (!b.ok) {
        free(b.text);
        orr_fail(err, ORR_ERR_NOMEM, "out of memory for the scene as YAML");
        return NULL;
    }
    return b.text;
}
