/* The .npy header (npy_header.h): the preamble, then the dict literal. */
#include "source/readers/npy_header.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bytes.h"

static const unsigned char npy_magic[6] = {0x93, 'N', 'U', 'M', 'P', 'Y'};

int npy_has_magic(const unsigned char *head, size_t n)
{
    return n >= sizeof npy_magic && memcmp(head, npy_magic, sizeof npy_magic) == 0;
}

int npy_parse_preamble(const unsigned char *head, size_t n, npy_header *h, char *why, size_t size)
{
    memset(h, 0, sizeof *h);
    if (!npy_has_magic(head, n) || n < NPY_PREAMBLE_V1) {
        snprintf(why, size, "no .npy magic (\\x93NUMPY and a version)");
        return 0;
    }
    h->version = head[6];
    if (h->version < 1 || h->version > 3) {
        snprintf(why, size, "format version %d.%d (versions 1 to 3 are read)", head[6], head[7]);
        return 0;
    }
    if (h->version == 1) {
        h->header_len = (size_t)head[8] | (size_t)head[9] << 8;
        h->data_offset = NPY_PREAMBLE_V1 + (int64_t)h->header_len;
        return 1;
    }
    if (n < NPY_PREAMBLE_V2) {
        snprintf(why, size, "the file ends inside its preamble");
        return 0;
    }
    uint32_t len = (uint32_t)head[8] | (uint32_t)head[9] << 8 | (uint32_t)head[10] << 16 | (uint32_t)head[11] << 24;
    if (len > NPY_MAX_HEADER) {
        snprintf(why, size, "a header of %u bytes (at most %u are read)", len, NPY_MAX_HEADER);
        return 0;
    }
    h->header_len = len;
    h->data_offset = NPY_PREAMBLE_V2 + (int64_t)len;
    return 1;
}

/* ---- the dict literal: a tree of values in a fixed pool ---- */

#define NPY_MAX_NODES 1024
#define NPY_MAX_DEPTH 6

typedef enum { V_STRING, V_INT, V_TRUE, V_FALSE, V_NONE, V_TUPLE, V_LIST, V_DICT } vkind;

typedef struct vnode {
    vkind kind;
    const char *text; /* V_STRING: the characters between the quotes */
    size_t len;
    long long num;    /* V_INT */
    int first, next;  /* containers: first child; every node: next sibling (-1: none) */
    int count;        /* containers: children (a dict: keys and values alternate) */
} vnode;

typedef struct parser {
    const char *start, *p, *end;
    vnode node[NPY_MAX_NODES];
    int nnodes;
    char *why;
    size_t why_size;
} parser;

static int fail(parser *ps, const char *what)
{
    snprintf(ps->why, ps->why_size, "header dict: %s at character %ld", what, (long)(ps->p - ps->start) + 1);
    return -1;
}

static void skip_blanks(parser *ps)
{
    while (ps->p < ps->end && (*ps->p == ' ' || *ps->p == '\t' || *ps->p == '\n' || *ps->p == '\r'))
        ps->p++;
}

static int new_node(parser *ps, vkind kind)
{
    if (ps->nnodes >= NPY_MAX_NODES)
        return fail(ps, "too many values");
    vnode *v = &ps->node[ps->nnodes];
    memset(v, 0, sizeof *v);
    v->kind = kind;
    v->first = v->next = -1;
    return ps->nnodes++;
}

static int parse_value(parser *ps, int depth);

static int parse_string(parser *ps)
{
    char quote = *ps->p++;
    const char *start = ps->p;
    while (ps->p < ps->end && *ps->p != quote) {
        if (*ps->p == '\\' || (unsigned char)*ps->p < 0x20)
            return fail(ps, "an escape or control character in a string");
        ps->p++;
    }
    if (ps->p >= ps->end)
        return fail(ps, "an unterminated string");
    int k = new_node(ps, V_STRING);
    if (k >= 0) {
        ps->node[k].text = start;
        ps->node[k].len = (size_t)(ps->p - start);
    }
    ps->p++;
    return k;
}

static int parse_number(parser *ps)
{
    int neg = *ps->p == '-';
    if (neg)
        ps->p++;
    long long v = 0;
    const char *start = ps->p;
    while (ps->p < ps->end && *ps->p >= '0' && *ps->p <= '9') {
        if (v > (INT64_MAX - 9) / 10)
            return fail(ps, "a number too large");
        v = v * 10 + (*ps->p++ - '0');
    }
    if (ps->p == start)
        return fail(ps, "a '-' without digits");
    if (ps->p < ps->end && *ps->p == 'L') /* Python 2's long integers, in old files */
        ps->p++;
    int k = new_node(ps, V_INT);
    if (k >= 0)
        ps->node[k].num = neg ? -v : v;
    return k;
}

static int parse_word(parser *ps)
{
    static const struct {
        const char *word;
        vkind kind;
    } words[] = {{"True", V_TRUE}, {"False", V_FALSE}, {"None", V_NONE}};
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++) {
        size_t n = strlen(words[i].word);
        if ((size_t)(ps->end - ps->p) >= n && memcmp(ps->p, words[i].word, n) == 0) {
            ps->p += n;
            return new_node(ps, words[i].kind);
        }
    }
    return fail(ps, "an unexpected character");
}

/* A tuple, list or dict: children separated by ',' (a dict's by ':' and
 * ','), a trailing ',' allowed. */
static int parse_container(parser *ps, vkind kind, char close, int depth)
{
    if (depth > NPY_MAX_DEPTH)
        return fail(ps, "values nested too deep");
    ps->p++;
    int k = new_node(ps, kind), last = -1;
    while (k >= 0) {
        skip_blanks(ps);
        if (ps->p < ps->end && *ps->p == close) {
            ps->p++;
            return k;
        }
        int child = parse_value(ps, depth + 1);
        if (child < 0)
            return -1;
        if (last < 0)
            ps->node[k].first = child;
        else
            ps->node[last].next = child;
        last = child;
        ps->node[k].count++;
        skip_blanks(ps);
        char sep = kind == V_DICT && ps->node[k].count % 2 ? ':' : ',';
        if (ps->p < ps->end && *ps->p == sep)
            ps->p++;
        else if (ps->p >= ps->end || *ps->p != close)
            return fail(ps, kind == V_DICT ? "a missing ':' or ','" : "a missing ','");
    }
    return -1;
}

static int parse_value(parser *ps, int depth)
{
    skip_blanks(ps);
    if (ps->p >= ps->end)
        return fail(ps, "the end of the header where a value was due");
    char c = *ps->p;
    if (c == '\'' || c == '"')
        return parse_string(ps);
    if (c == '-' || (c >= '0' && c <= '9'))
        return parse_number(ps);
    if (c == '(')
        return parse_container(ps, V_TUPLE, ')', depth);
    if (c == '[')
        return parse_container(ps, V_LIST, ']', depth);
    if (c == '{')
        return parse_container(ps, V_DICT, '}', depth);
    return parse_word(ps);
}

/* ---- from the tree to the header ---- */

static int is_string(const vnode *v, const char *s)
{
    return v->kind == V_STRING && v->len == strlen(s) && memcmp(v->text, s, v->len) == 0;
}

static const vnode *child(const parser *ps, const vnode *v, int i)
{
    int k = v->first;
    while (k >= 0 && i-- > 0)
        k = ps->node[k].next;
    return k >= 0 ? &ps->node[k] : NULL;
}

/* A dtype string ('<f4', '|u1', '|V8') into col; 0 with why. */
static int parse_dtype(const vnode *v, npy_column *col, char *why, size_t size)
{
    char s[16];
    if (v->kind != V_STRING || v->len < 3 || v->len >= sizeof s) {
        snprintf(why, size, "a dtype that is not a simple type string such as '<f4'");
        return 0;
    }
    memcpy(s, v->text, v->len);
    s[v->len] = '\0';
    char order = s[0], kind = s[1];
    char *end;
    long n = strtol(s + 2, &end, 10);
    int ok_order = order == '<' || order == '>' || order == '|' || order == '=';
    if (!ok_order || *end || n < 1 || n > 1 << 20 || s[2] < '0' || s[2] > '9') {
        snprintf(why, size, "dtype '%s' is not a simple type string such as '<f4'", s);
        return 0;
    }
    col->size = (int)n;
    col->big = order == '>' || (order == '=' && orr_host_big_endian());
    if (kind == 'V') {
        col->kind = NPY_PAD;
        return 1;
    }
    col->kind = kind == 'f' ? NPY_FLOAT : kind == 'i' ? NPY_INT : kind == 'u' ? NPY_UINT : NPY_PAD;
    int size_ok = kind == 'f' ? n == 4 || n == 8 : n == 1 || n == 2 || n == 4 || n == 8;
    if (col->kind == NPY_PAD || !size_ok || (n > 1 && order == '|')) {
        snprintf(why, size, "dtype '%s': only float32, float64 and integers of 1 to 8 bytes are read", s);
        return 0;
    }
    return 1;
}

/* One field of a structured dtype: (name, dtype) or (name, dtype, shape). */
static int parse_field(const parser *ps, const vnode *f, npy_column *col, char *why, size_t size)
{
    const vnode *name = f->kind == V_TUPLE ? child(ps, f, 0) : NULL;
    const vnode *type = f->kind == V_TUPLE ? child(ps, f, 1) : NULL;
    if (!name || !type || name->kind != V_STRING || f->count > 3) {
        snprintf(why, size, "a field of the dtype that is not (name, type)");
        return 0;
    }
    if (name->len >= sizeof col->name) {
        snprintf(why, size, "a field name of %zu characters (at most %zu)", name->len, sizeof col->name - 1);
        return 0;
    }
    memcpy(col->name, name->text, name->len);
    col->name[name->len] = '\0';
    if (f->count == 3) {
        snprintf(why, size, "field '%s' is a sub-array: give each component a field of its own (x, y, z)", col->name);
        return 0;
    }
    if (!parse_dtype(type, col, why, size))
        return 0;
    if (col->kind == NPY_PAD && col->name[0]) {
        snprintf(why, size, "field '%s' is not a number", col->name);
        return 0;
    }
    return 1;
}

/* The columns of a structured dtype, packed in order as numpy writes them. */
static int parse_fields(const parser *ps, const vnode *list, npy_header *h, char *why, size_t size)
{
    if (list->count < 1 || list->count > NPY_MAX_COLUMNS) {
        snprintf(why, size, "a dtype of %d fields (1 to %d are read)", list->count, NPY_MAX_COLUMNS);
        return 0;
    }
    size_t offset = 0;
    for (int i = 0; i < list->count; i++) {
        npy_column *col = &h->col[i];
        if (!parse_field(ps, child(ps, list, i), col, why, size))
            return 0;
        col->offset = offset;
        offset += (size_t)col->size;
    }
    h->ncolumns = list->count;
    h->record = offset;
    return 1;
}

/* The shape: (N,) for a structured array, (N, 3) for a plain one. */
static int parse_shape(const parser *ps, const vnode *shape, npy_header *h, char *why, size_t size)
{
    int want = h->structured ? 1 : 2;
    const vnode *n = shape && shape->kind == V_TUPLE ? child(ps, shape, 0) : NULL;
    const vnode *k = want == 2 && n ? child(ps, shape, 1) : NULL;
    int ok = n && shape->count == want && n->kind == V_INT && n->num >= 0 && (want == 1 || (k && k->kind == V_INT));
    if (!ok || (k && k->num != 3)) {
        snprintf(why, size, "%s", h->structured ? "a structured array must have shape (N,)"
                                                : "a plain array must have shape (N, 3), positions: for more "
                                                  "columns, save a structured array with named fields");
        return 0;
    }
    h->rows = n->num;
    if (h->record && h->rows > (INT64_MAX - h->data_offset) / (int64_t)h->record) {
        snprintf(why, size, "shape (%lld, ...) is too large", (long long)h->rows);
        return 0;
    }
    return 1;
}

/* A plain (N, 3) array: columns x, y, z of one type. */
static int plain_columns(const vnode *descr, npy_header *h, char *why, size_t size)
{
    static const char *const names[3] = {"x", "y", "z"};
    npy_column col = {0};
    if (!parse_dtype(descr, &col, why, size))
        return 0;
    if (col.kind != NPY_FLOAT) {
        snprintf(why, size, "a plain array of positions must hold floats");
        return 0;
    }
    for (int i = 0; i < 3; i++) {
        h->col[i] = col;
        snprintf(h->col[i].name, sizeof h->col[i].name, "%s", names[i]);
        h->col[i].offset = (size_t)i * (size_t)col.size;
    }
    h->ncolumns = 3;
    h->record = 3 * (size_t)col.size;
    return 1;
}

/* An .npz member's shape: () a scalar, (N,), or (N, k) for a plain
 * array; sets rows, ndim and, for a plain array, the columns. */
static int parse_any_shape(const parser *ps, const vnode *shape, const vnode *descr, npy_header *h, char *why,
                           size_t size)
{
    const vnode *n = shape && shape->kind == V_TUPLE ? child(ps, shape, 0) : NULL;
    const vnode *k = n ? child(ps, shape, 1) : NULL;
    int ok = shape && shape->kind == V_TUPLE && shape->count <= 2 && (!n || (n->kind == V_INT && n->num >= 0)) &&
             (!k || (k->kind == V_INT && k->num >= 1 && k->num <= NPY_MAX_COLUMNS));
    if (!ok || (h->structured && shape->count != 1)) {
        snprintf(why, size, h->structured ? "a structured array must have shape (N,)"
                                          : "an array must have shape (), (N,) or (N, k) with k from 1 to %d",
                 NPY_MAX_COLUMNS);
        return 0;
    }
    h->ndim = shape->count;
    h->rows = n ? n->num : 1;
    if (!h->structured) {
        npy_column col = {0};
        if (!parse_dtype(descr, &col, why, size))
            return 0;
        if (col.kind == NPY_PAD) {
            snprintf(why, size, "an array of void records: not numbers");
            return 0;
        }
        h->ncolumns = k ? (int)k->num : 1;
        for (int i = 0; i < h->ncolumns; i++) {
            h->col[i] = col;
            h->col[i].offset = (size_t)i * (size_t)col.size;
        }
        h->record = (size_t)h->ncolumns * (size_t)col.size;
        h->fortran = h->fortran && h->ncolumns > 1;
    }
    if (h->record && h->rows > (INT64_MAX - h->data_offset) / (int64_t)h->record) {
        snprintf(why, size, "shape (%lld, ...) is too large", (long long)h->rows);
        return 0;
    }
    return 1;
}

int npy_parse_dict(const char *text, size_t len, npy_header *h, char *why, size_t size)
{
    parser *ps = calloc(1, sizeof *ps);
    if (!ps) {
        snprintf(why, size, "out of memory reading the header");
        return 0;
    }
    ps->start = ps->p = text;
    ps->end = text + len;
    ps->why = why;
    ps->why_size = size;
    int root = parse_value(ps, 0);
    const vnode *dict = root >= 0 ? &ps->node[root] : NULL, *descr = NULL, *fortran = NULL, *shape = NULL;
    int ok = dict != NULL;
    if (ok && dict->kind != V_DICT) {
        snprintf(why, size, "the header is not a dict");
        ok = 0;
    }
    for (int i = 0; ok && i + 1 < dict->count; i += 2) {
        const vnode *key = child(ps, dict, i), *value = child(ps, dict, i + 1);
        if (is_string(key, "descr"))
            descr = value;
        else if (is_string(key, "fortran_order"))
            fortran = value;
        else if (is_string(key, "shape"))
            shape = value;
    }
    if (ok && (!descr || !fortran || !shape)) {
        snprintf(why, size, "the header dict lacks 'descr', 'fortran_order' or 'shape'");
        ok = 0;
    }
    if (ok) {
        h->structured = descr->kind == V_LIST;
        /* Order matters only to a 2-D array: a structured one is 1-D. */
        h->fortran = fortran->kind == V_TRUE && descr->kind != V_LIST;
        if (h->structured)
            ok = parse_fields(ps, descr, h, why, size);
        else if (!h->any_shape)
            ok = plain_columns(descr, h, why, size);
    }
    if (ok && h->any_shape)
        ok = parse_any_shape(ps, shape, descr, h, why, size);
    else if (ok) {
        ok = parse_shape(ps, shape, h, why, size);
        h->ndim = h->structured ? 1 : 2;
    }
    free(ps);
    return ok;
}
