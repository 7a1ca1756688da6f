/* The table of a scene's keys (internal to src/scene): for each key its
 * type, the field of orr_scene it is stored in (of the stage's settings
 * struct the scene holds, scene.h), its bounds or its words. scene_bind.c
 * binds YAML values through it; the table itself is scene_keys.c, one line
 * per key. The keys of a dome profile (domes/NAME.yaml) have a table too. */
#ifndef ORR_SCENE_SCENE_KEYS_H
#define ORR_SCENE_SCENE_KEYS_H

#include <stddef.h>

#include "core/names.h"
#include "scene/scene.h"

typedef enum {
    K_STRING,   /* any non-empty text */
    K_FILENAME, /* non-empty text without '/' */
    K_PATH,     /* a file path, resolved against the scene's folder */
    K_NUMBER,   /* double, finite, within the bounds */
    K_AUTO,     /* double within the bounds, or the word auto (stored as 0) */
    K_RUN,      /* double within the bounds, or the word run (stored as 0, sets the has_* flag) */
    K_INT,      /* int within ilo..ihi */
    K_LLONG,    /* long long within ilo..ihi */
    K_U64,      /* uint64_t within ilo..ihi (ilo >= 0) */
    K_BOOL,     /* int 0 / 1 */
    K_ENUM,     /* a word that parse_word accepts, stored as text (a reader's or a model's name) */
    K_NAMED,    /* a word of an orr_named table, its value stored in an int-sized field */
    K_VEC3,     /* orr_vec3 from [x, y, z] */
    K_QUAT,     /* orr_quat from [w, x, y, z] */
    K_TYPES,    /* unsigned bit mask from a list of particle types 0..5 */
    K_POPULATIONS, /* colour.populations: a list of mappings (scene_colour.c) */
    K_TINT,        /* colour.tint.path: a list of temperatures (scene_colour.c) */
    K_LAYERS,      /* compose.layers: a list of mappings (scene_colour.c) */
    K_SEQ_FILES,   /* input.sequence.files: a list of paths (scene_sequence.c) */
    K_ID,       /* uint64_t, the full range: a particle id */
    K_LB,       /* double[2] from [l, b], degrees: l any finite number, b in [-90, 90] */
    K_PAIR,     /* double[2] from [a, b], any finite numbers */
    K_KEYFRAMES, /* camera.path.keyframes: a list of mappings (scene_path.c) */
} key_type;

/* Bounds of K_NUMBER, K_AUTO and K_RUN. */
enum {
    HAS_LO = 1,
    LO_OPEN = 2, /* the bound itself is excluded */
    HAS_HI = 4,
    HI_OPEN = 8,
};

typedef struct key_spec {
    const char *key;
    key_type type;
    size_t offset, size;          /* the field in the target (orr_scene or dome_profile) */
    int owned;                    /* K_STRING, K_PATH: the field is an owned char * (core/owned.h) holding at
                                   * most size - 1 characters, not a char[size] */
    double lo, hi;                /* K_NUMBER, K_AUTO, K_RUN: with the bounds flags */
    unsigned bounds;
    long long ilo, ihi;           /* integers: inclusive range */
    int (*parse_word)(orr_scene *s, const char *word); /* K_ENUM: 1 when accepted (scene keys only) */
    const char *(*choices)(void); /* K_ENUM: the accepted words, for messages */
    const orr_named *names;       /* K_NAMED: the stage's table of words and values */
    int names_shown;              /* K_NAMED: list only the first this many words after "one of:" (0: all) */
    const char *names_note;       /* ...and the others after the value, under this label ("sky maps") */
    int has_flag;                 /* a has_* flag to set when the key is present */
    size_t flag_offset;
} key_spec;

/* A table of keys, and where its keys are documented (for unknown-key messages). */
typedef struct key_table {
    const key_spec *keys;
    size_t n;
    const char *doc;
} key_table;

extern const key_table scene_key_table;        /* a scene's keys, into an orr_scene */
extern const key_table scene_profile_key_table; /* a dome profile's, into a dome_profile */

/* Longest dotted path the binder builds; longer keys cannot be in the table. */
#define SCENE_KEY_PATH_MAX 128

/* The key of that path, or NULL. */
const key_spec *scene_find_key(const key_table *t, const char *path);

/* Whether path is a section: a proper prefix of some key, up to a dot ("input.model"). */
int scene_is_section(const key_table *t, const char *path);

/* The closest key or section to an unknown path, for "did you mean", in
 * buf ("" when none is close). */
void scene_suggest_key(const key_table *t, const char *path, char *buf, size_t size);

#endif
