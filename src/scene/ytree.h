/* A small YAML tree for the scene parser: mappings, sequences and scalars,
 * each remembering where it came from (the file and line, or the --set
 * argument) so that errors found later, while binding the tree to the scene
 * struct, can still point at the text the user wrote. libyaml's own document
 * API is not used because its nodes cannot be edited by overrides and share
 * one origin. */
#ifndef ORR_SCENE_YTREE_H
#define ORR_SCENE_YTREE_H

#include <stddef.h>

#include "core/error.h"

typedef enum {
    YT_SCALAR,
    YT_MAPPING,
    YT_SEQUENCE,
} yt_kind;

typedef struct yt_node yt_node;

typedef struct yt_entry {
    char *key;
    int line;           /* line of the key; 0 when it came from an override */
    const char *origin; /* borrowed: the file path or "--set key=value" */
    yt_node *value;
} yt_entry;

struct yt_node {
    yt_kind kind;
    int line;           /* 1-based line; 0 for nodes from an override (one line) */
    const char *origin; /* borrowed, must outlive the tree */
    char *text;         /* scalar: its text (never NULL) */
    int quoted;         /* scalar: written quoted or as a block literal, so never null */
    size_t n, cap;
    yt_entry *entries;  /* mapping: n entries in document order (duplicates kept) */
    yt_node **items;    /* sequence: n items */
};

/* Parses one YAML document from text[0..len). with_lines = 0 records line 0
 * on every node (for override values, which are a single argument). An empty
 * stream gives *out = NULL and ORR_OK. Syntax errors are ORR_ERR_USAGE and
 * read "origin:line:col: YAML syntax error: ..." (without line and column
 * when with_lines is 0). */
orr_status yt_parse(const char *text, size_t len, const char *origin, int with_lines, yt_node **out,
                    orr_error *err);

/* A new scalar node holding a copy of text; NULL (with err set) when out of memory. */
yt_node *yt_new_scalar(const char *text, int quoted, const char *origin, int line, orr_error *err);

/* Frees a node and everything below it; n may be NULL. */
void yt_free(yt_node *n);

/* A scalar with no value: plain "", "~" or "null". */
int yt_is_null(const yt_node *n);

/* "a mapping", "a list", "nothing" or the quoted scalar text, for messages;
 * uses buf (of size size) when it needs to. */
const char *yt_describe(const yt_node *n, char *buf, size_t size);

/* Sets value at a dotted key path below the mapping root ("camera.fov"),
 * creating (or replacing non-mapping nodes with) mappings along the way, and
 * replacing any value already there. Takes ownership of value, also on error.
 * The path must have no empty part; the caller checks that. */
orr_status yt_set_path(yt_node *root, const char *dotted, yt_node *value, const char *origin,
                       orr_error *err);

/* The first entry of mapping map with this key, or NULL (also when map is
 * not a mapping). */
const yt_entry *yt_find(const yt_node *map, const char *key);

/* Removes the first entry with this key from mapping map and returns its
 * value, which the caller then owns; NULL when there is none. */
yt_node *yt_detach(yt_node *map, const char *key);

/* A deep copy of n (origins stay borrowed); NULL (with err set) when out of memory. */
yt_node *yt_clone(const yt_node *n, orr_error *err);

/* Merges mapping src into mapping dst: a key in both whose values are
 * mappings is merged key by key; any other value of src (scalar or list)
 * replaces dst's, keeping src's origin and line. An empty value in src
 * ("camera:" with nothing below) leaves a mapping of dst as it is, as an
 * empty section does everywhere else. src must have no duplicate keys (the
 * caller checks): the second would silently win. */
orr_status yt_merge(yt_node *dst, const yt_node *src, orr_error *err);

/* The tree below mapping root as "key.path=value" lines in document order
 * (nested mappings as dotted keys; lists and mappings within them on one
 * line, as [a, b] and {key: value}), each ending in '\n'. A new string the
 * caller frees; NULL (with err set) when out of memory. */
char *yt_settings_text(const yt_node *root, orr_error *err);

/* The tree below mapping root as a YAML document that yt_parse reads back
 * as the same tree: mappings in block style (two spaces an indent), lists
 * and the mappings inside them in flow style ([a, b], {key: value}), a
 * scalar plain where its text reads back the same, else double-quoted with
 * YAML's escapes, and null as ~. A new string the caller frees; NULL (with
 * err set) when out of memory. */
char *yt_yaml_text(const yt_node *root, orr_error *err);

#endif
